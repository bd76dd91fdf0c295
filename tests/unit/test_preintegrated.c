/* The pre-integrated skin table (bake/dm_preintegrated.h): the flat row, symmetry, energy,
 * one Gaussian against closed forms and a brute force, the table against the brute force,
 * thread invariance, and the range checks. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include <stdio.h>

#include "../common/tmpdir.h"
#include "image/dm_exr.h"
#include "bake/dm_preintegrated.h"
#include "core/dm_math.h"

static dm_profile one_gaussian(double v)
{
    dm_profile p;
    memset(&p, 0, sizeof p);
    p.count = 1;
    p.variance_mm2[0] = v;
    p.weight[0][0] = p.weight[0][1] = p.weight[0][2] = 1.0;
    return p;
}

/* I0(a) e^(−a) by its power series (a ≤ 30 here: 120 terms converge to 1e-16). */
static double i0e(double a)
{
    double term = 1.0, sum = 1.0;
    for (int k = 1; k < 200; ++k) {
        term *= (a / 2) * (a / 2) / ((double)k * k);
        sum += term;
    }
    return sum * exp(-a);
}

Test(preintegrated, flat_row_is_lambert)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    for (int i = 0; i <= 20; ++i) {
        double c = -1.0 + i / 10.0, rgb[3];
        dm_preint_eval(&p, c, 0.0, rgb);
        for (int ch = 0; ch < 3; ++ch) cr_assert_eq(rgb[ch], fmax(0.0, c));
        /* and the limit: κ = 1e-6 /mm (r = 1 km) within 1e-9 of it, away from the kink */
        dm_preint_eval(&p, c, 1e-6, rgb);
        for (int ch = 0; ch < 3; ++ch)
            cr_assert(fabs(rgb[ch] - fmax(0.0, c)) < (fabs(c) > 0.05 ? 1e-9 : 1e-5), "c %g: %.12g", c, rgb[ch]);
    }
    dm_preint_lut lut;
    cr_assert_eq(dm_preint_bake(&p, 32, 8, 1.0, 1, &lut, NULL), DM_OK);
    for (int i = 0; i < 32; ++i)
        for (int ch = 0; ch < 3; ++ch)
            cr_assert_eq(lut.rgb[ch * 32 * 8 + i], (float)fmax(0.0, dm_preint_texel_cos(i, 32)));
    dm_preint_lut_free(&lut);
}

/* The kernel is even, so D(θ) − D(π − θ) = cos θ · C(r) with C = ∫cos x K / ∫K the same
 * for every θ (max(0, c) − max(0, −c) = c and the blur is linear); and C for a Gaussian
 * on the ring is I1(a)/I0(a)... checked here only as a constant across θ. */
Test(preintegrated, antisymmetric_part_is_a_blurred_cosine)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    for (int k = 0; k < 4; ++k) {
        double kappa = 0.1 * (1 << k), ref[3] = {0, 0, 0};
        for (int i = 1; i <= 9; ++i) {
            double c = i / 10.0, a[3], b[3];
            dm_preint_eval(&p, c, kappa, a);
            dm_preint_eval(&p, -c, kappa, b);
            for (int ch = 0; ch < 3; ++ch) {
                double ratio = (a[ch] - b[ch]) / c;
                if (i == 1) ref[ch] = ratio;
                cr_assert(fabs(ratio - ref[ch]) < 1e-12, "kappa %g c %g ch %d: %.15g vs %.15g", kappa, c, ch, ratio,
                          ref[ch]);
                cr_assert(ratio > 0.0 && ratio <= 1.0);
            }
        }
    }
}

/* ∫_{−π}^{π} D(θ) dθ = ∫ max(0, cos) = 2 for every r: the normalised blur keeps energy.
 * Simpson in θ over [0, π] (D is even in θ) with 2000 intervals; D has no kink once blurred
 * but its curvature near θ = π/2 is ~r/σ: 1e-6 is the rule's error at κ = 0.05. */
Test(preintegrated, energy_over_theta)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    static const double kappas[] = {0.05, 0.3, 1.0, 5.0};
    for (int k = 0; k < 4; ++k) {
        int n = 2000;
        double h = DM_PI / n, sum[3] = {0, 0, 0};
        for (int i = 0; i <= n; ++i) {
            double rgb[3], w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
            dm_preint_eval(&p, cos(i * h), kappas[k], rgb);
            for (int ch = 0; ch < 3; ++ch) sum[ch] += w * rgb[ch];
        }
        for (int ch = 0; ch < 3; ++ch) {
            double e = 2.0 * sum[ch] * h / 3.0;
            cr_assert(fabs(e - 2.0) < 1e-6, "kappa %g ch %d: %.12g", kappas[k], ch, e);
        }
    }
}

/* One Gaussian: at N·L = 1 with the light behind nothing (θ = 0), max(0, cos x) cuts at
 * ±π/2; at θ = π/2 ... Compare with the brute force everywhere, and the denominator with
 * its closed form 2π e^(−a) I0(a)/(2πv), a = r²/v. */
Test(preintegrated, gaussian_against_brute_force)
{
    double v = 0.5;
    dm_profile p = one_gaussian(v);
    static const double kappas[] = {0.2, 0.5, 1.0, 2.0, 10.0, 50.0};
    for (int k = 0; k < 6; ++k)
        for (int i = 0; i <= 16; ++i) {
            double c = -1.0 + i / 8.0, a[3], b[3];
            dm_preint_eval(&p, c, kappas[k], a);
            dm_preint_brute(&p, c, kappas[k], 1 << 17, b);
            /* midpoint rule with kinks: O(h²) ≈ 1e-10 at 2^17 points */
            cr_assert(fabs(a[0] - b[0]) < 1e-9, "kappa %g c %g: %.15g vs brute %.15g", kappas[k], c, a[0], b[0]);
        }
    /* D(cos θ = 1) = ∫_{−π/2}^{π/2} cos x K dx / ∫ K: at κ → ∞ (r → 0) the kernel is flat
     * over the circle and D → (1/2π)·2 = 1/π */
    double rgb[3];
    dm_preint_eval(&p, 1.0, 100.0, rgb);
    cr_assert(fabs(rgb[0] - 1.0 / DM_PI) < 1e-3, "%.9g", rgb[0]);
    /* the denominator's closed form through a two-Gaussian profile whose weights make the
     * ratio of the two normalisations visible: D_mix = (w1 N1 + w2 N2)/(w1 Z1 + w2 Z2) */
    dm_profile q;
    memset(&q, 0, sizeof q);
    q.count = 2;
    q.variance_mm2[0] = 0.5;
    q.variance_mm2[1] = 2.0;
    q.weight[0][0] = 1.0; /* R: first only */
    q.weight[1][1] = 1.0; /* G: second only */
    q.weight[0][2] = q.weight[1][2] = 1.0;
    double r = 1.0, c = 0.3, d[3];
    dm_preint_eval(&q, c, 1.0 / r, d);
    double z1 = i0e(r * r / 0.5) / 0.5, z2 = i0e(r * r / 2.0) / 2.0;
    double mix = (d[0] * z1 + d[1] * z2) / (z1 + z2);
    cr_assert(fabs(d[2] - mix) < 1e-12, "%.15g vs %.15g", d[2], mix);
}

Test(preintegrated, table_against_brute_force_and_threads)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    dm_preint_lut a, b;
    cr_assert_eq(dm_preint_bake(&p, 64, 32, 1.0, 1, &a, NULL), DM_OK);
    cr_assert_eq(dm_preint_bake(&p, 64, 32, 1.0, 3, &b, NULL), DM_OK);
    cr_assert_eq(memcmp(a.rgb, b.rgb, sizeof(float) * 3 * 64 * 32), 0);
    dm_preint_error e;
    dm_preint_lut_error(&p, &a, 3, 1 << 16, 2, &e);
    /* centres: the float rounding (6e-8) over the integral's own ~1e-10 */
    cr_assert(e.max_abs_centres < 2e-7, "%g", e.max_abs_centres);
    cr_assert(e.max_abs_bilinear > e.max_abs_centres);
    cr_assert(e.samples > 200);
    for (size_t i = 0; i < 3 * 64 * 32; ++i) cr_assert(a.rgb[i] >= 0.0f && a.rgb[i] <= 1.0f);
    dm_preint_lut_free(&a);
    dm_preint_lut_free(&b);
}

Test(preintegrated, range_checks)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    dm_preint_lut l;
    dm_error err = {0};
    cr_assert_eq(dm_preint_bake(&p, 1, 8, 1.0, 1, &l, &err), DM_ERR_RANGE);
    cr_assert_eq(dm_preint_bake(&p, 8, 8, 0.0, 1, &l, &err), DM_ERR_RANGE);
    cr_assert_eq(dm_preint_bake(&p, 8, 8, NAN, 1, &l, &err), DM_ERR_NON_FINITE);
    cr_assert_eq(dm_preint_bake(&p, 8, 8, 1e3, 1, &l, &err), DM_ERR_RANGE);
    p.count = 0;
    cr_assert_neq(dm_preint_bake(&p, 8, 8, 1.0, 1, &l, &err), DM_OK);
    cr_assert_null(l.rgb);
}

#define LUT DERMIS_BIN "/dermis-bake-lut"

Test(preintegrated, bake_lut_tool)
{
    char dir[64], cmd[512], path[160];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(cmd, sizeof cmd, LUT " -o %s --quiet --tables preintegrated --preint-size 16x8 --curvature-max 2", dir);
    cr_assert_eq(test_run(cmd, NULL), 0);
    snprintf(path, sizeof path, "%s/preintegrated.exr", dir);
    dm_exr_image img;
    dm_error err = {0};
    cr_assert_eq(dm_exr_read(path, &img, &err), DM_OK, "%s", err.detail);
    cr_assert(img.has_provenance);
    cr_expect_str_eq(dm_prov_find(&img.prov, "table")->s, "preintegrated");
    cr_expect_eq(dm_prov_find(&img.prov, "curvature_max_per_mm")->d, 2.0);
    cr_expect_str_eq(dm_prov_find(&img.prov, "profile")->s, "gems3-skin");
    cr_assert(dm_prov_find(&img.prov, "s") && dm_prov_find(&img.prov, "t") && dm_prov_find(&img.prov, "profile_hash"));
    cr_assert_eq(img.width, 16);
    cr_assert_eq(img.height, 8);
    dm_profile p;
    dm_profile_gems3_skin(&p);
    static const char *const names[3] = {"R", "G", "B"};
    for (int ch = 0; ch < 3; ++ch) {
        const float *plane = dm_exr_find(&img, names[ch]);
        cr_assert(plane);
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 16; ++i) {
                double rgb[3];
                dm_preint_eval(&p, dm_preint_texel_cos(i, 16), 2.0 * j / 7.0, rgb);
                cr_assert_eq(plane[j * 16 + i], (float)rgb[ch]);
            }
    }
    dm_exr_free(&img);
    static const char *const bad[] = {"--profile gems3-skin", "--tables preintegrated --curvature-max 0",
                                      "--tables preintegrated --preint-size 1", "--curvature-max 1",
                                      "--tables preintegrated --preint-size 5000"};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; ++k) {
        snprintf(cmd, sizeof cmd, LUT " -o %s --quiet %s 2>/dev/null", dir, bad[k]);
        cr_expect_eq(test_run(cmd, NULL), 1, "'%s' should be a usage error", bad[k]);
    }
    snprintf(cmd, sizeof cmd, LUT " -o %s --quiet --tables preintegrated --profile %s/none.json 2>/dev/null", dir, dir);
    cr_expect_eq(test_run(cmd, NULL), 2);
}
