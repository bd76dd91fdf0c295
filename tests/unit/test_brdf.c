/* BRDF: Beckmann, Fresnel, KS specular, rho_dt — against closed forms and brute force. */
#include <criterion/criterion.h>
#include <math.h>

#include "core/dm_brdf.h"
#include "core/dm_math.h"

/* Independent Beckmann, straight from the formula in long double. */
static long double beckmann_ref(long double c, long double m)
{
    long double c2 = c * c;
    return expl((c2 - 1.0L) / (c2 * m * m)) / (m * m * c2 * c2);
}

/* ∫ D(h) (N·H) dω_h by a midpoint rule in θ_h (no substitution); n points on [0, π/2]. */
static double normalisation(double m, int n)
{
    double sum = 0.0, h = DM_PI_2 / n;
    for (int i = 0; i < n; ++i) {
        double th = (i + 0.5) * h;
        sum += dm_beckmann(cos(th), m) * cos(th) * sin(th);
    }
    return DM_2PI * sum * h;
}

/* Tolerance: the midpoint rule with 400k steps has error ~h²/24·max|f''| ≪ 1e-6 relative
 * for m ≥ 0.05 (the lobe spans ≥ 1000 steps); the answer is exactly π by construction. */
Test(beckmann, normalised_to_pi)
{
    const double ms[] = {0.05, 0.1, 0.3, 0.6, 1.0};
    for (int k = 0; k < 5; ++k) {
        double v = normalisation(ms[k], 400000);
        cr_expect(fabs(v - DM_PI) < 1e-6 * DM_PI, "m=%g: integral %.9f, expected pi", ms[k], v);
    }
}

Test(beckmann, matches_formula)
{
    for (int i = 1; i <= 100; ++i)
        for (int j = 1; j <= 100; ++j) {
            double c = i / 100.0, m = j / 100.0;
            long double ref = beckmann_ref(c, m);
            double d = dm_beckmann(c, m);
            /* 1e-12 relative: both are one exp of the same argument in ≥ double precision. */
            cr_assert(fabsl(d - ref) <= 1e-12L * ref + 1e-300L, "c=%g m=%g: %g vs %Lg", c, m, d, ref);
        }
}

Test(beckmann, hard_case_c_zero)
{
    const double ms[] = {0.0, 1e-4, 0.05, 0.3, 1.0};
    for (int k = 0; k < 5; ++k) {
        cr_expect_eq(dm_beckmann(0.0, ms[k]), 0.0);
        cr_expect_eq(dm_beckmann_f(0.0f, (float)ms[k]), 0.0f);
    }
}

Test(beckmann, hard_case_c_negative)
{
    cr_expect_eq(dm_beckmann(-0.5, 0.3), 0.0);
    cr_expect_eq(dm_beckmann(-1.0, 0.0), 0.0);
    cr_expect_eq(dm_beckmann(-1e-300, 1e-4), 0.0);
    cr_expect_eq(dm_beckmann_f(-0.5f, 0.3f), 0.0f);
}

Test(beckmann, hard_case_c_one)
{
    /* D(1, m) = 1/m² exactly */
    const double ms[] = {1e-3, 0.05, 0.3, 1.0};
    for (int k = 0; k < 4; ++k) {
        double d = dm_beckmann(1.0, ms[k]);
        cr_expect(fabs(d - 1.0 / (ms[k] * ms[k])) < 1e-12 * d, "m=%g: %g", ms[k], d);
    }
    cr_expect(isfinite(dm_beckmann(1.0 + 1e-9, 0.3)));
}

Test(beckmann, hard_case_m_zero)
{
    /* the m → 0 limit: 0 below c = 1, the finite stand-in for the delta at c = 1 */
    cr_expect_eq(dm_beckmann(0.5, 0.0), 0.0);
    cr_expect_eq(dm_beckmann(0.999999, 0.0), 0.0);
    cr_expect_eq(dm_beckmann(1.0, 0.0), DM_BECKMANN_D_MAX);
    cr_expect(isfinite(dm_beckmann_f(1.0f, 0.0f)));
    cr_expect_eq(dm_beckmann_f(0.5f, 0.0f), 0.0f);
    cr_expect_eq(dm_beckmann(0.5, -1.0), 0.0);
}

Test(beckmann, hard_case_m_1e4)
{
    for (int i = 0; i <= 100000; ++i) {
        double c = i / 100000.0;
        double d = dm_beckmann(c, 1e-4);
        float f = dm_beckmann_f((float)c, 1e-4f);
        cr_assert(isfinite(d) && d >= 0.0, "c=%g: %g", c, d);
        cr_assert(isfinite(f) && f >= 0.0f, "c=%g: %g (float)", c, (double)f);
    }
    cr_expect(fabs(dm_beckmann(1.0, 1e-4) - 1e8) < 1e-4);
    cr_expect(isfinite(dm_beckmann(1.0, 1e-300)), "denormal-scale m stays finite");
    cr_expect(isfinite(dm_beckmann(1e-300, 1e-4)));
}

Test(beckmann, hard_case_saturation)
{
    /* c = 1, m < 1/32: D = 1/m² > 1024, so the 8-bit texel saturates at 255 and decodes to
     * exactly 1024, the largest representable D. */
    const double ms[] = {1.0 / 33.0, 0.01, 1e-3, 1e-4, 0.0};
    for (int k = 0; k < 5; ++k) {
        uint8_t v = dm_beckmann_encode8(dm_beckmann(1.0, ms[k]));
        cr_expect_eq(v, 255, "m=%g: %d", ms[k], v);
    }
    cr_expect_eq(dm_beckmann_decode8(1.0), 1024.0);
    cr_expect_eq(dm_beckmann_encode8(NAN), 0);
    cr_expect_eq(dm_beckmann_encode8(INFINITY), 255);
}

Test(beckmann, nan_inputs_stay_finite)
{
    cr_expect(isfinite(dm_beckmann(NAN, 0.3)));
    cr_expect(isfinite(dm_beckmann(0.5, NAN)));
    cr_expect(isfinite(dm_beckmann_f(NAN, NAN)));
}

Test(beckmann, float_matches_double)
{
    /* float evaluation: ~10 ulp of float (1e-6 relative) over the range the runtime uses */
    for (int i = 1; i <= 64; ++i)
        for (int j = 4; j <= 64; ++j) {
            double c = i / 64.0, m = j / 64.0;
            double d = dm_beckmann(c, m);
            double f = dm_beckmann_f((float)c, (float)m);
            if (d < 1e-30) continue;
            cr_assert(fabs(f - d) <= 2e-5 * d, "c=%g m=%g: %g vs %g", c, m, f, d);
        }
}

Test(fresnel, schlick_endpoints)
{
    cr_expect_float_eq(dm_fresnel_schlick(1.0, 0.028), 0.028, 1e-15);
    cr_expect_float_eq(dm_fresnel_schlick(0.0, 0.028), 1.0, 1e-15);
    cr_expect_float_eq(dm_fresnel_schlick(-3.0, 0.028), 1.0, 1e-15);
    cr_expect_float_eq(dm_fresnel_schlick(2.0, 0.028), 0.028, 1e-15);
    cr_expect_float_eq(dm_fresnel_schlick(0.5, 0.028), 0.028 + 0.972 / 32.0, 1e-15);
}

Test(ks, zero_below_horizon_and_opposite)
{
    double n[3] = {0, 0, 1}, l[3] = {0, 0.6, -0.8}, v[3] = {0, 0, 1};
    cr_expect_eq(dm_ks_specular(n, l, v, 0.3, 1.0, 0.028), 0.0, "light behind: zero");
    double l2[3] = {0.6, 0, 0.8}, v2[3] = {-0.6, 0, -0.8};
    double s = dm_ks_specular(n, l2, v2, 0.3, 1.0, 0.028);
    cr_expect(isfinite(s) && s == 0.0, "V = -L has no half vector: %g", s);
    float nf[3] = {0, 0, 1}, lf[3] = {0.6f, 0, 0.8f}, vf[3] = {-0.6f, 0, -0.8f};
    cr_expect(dm_ks_specular_f(nf, lf, vf, 0.3f, 1.0f, 0.028f) == 0.0f);
}

Test(ks, grazing_is_finite)
{
    double n[3] = {0, 0, 1};
    for (int k = 0; k <= 1000; ++k) {
        double a = DM_PI_2 * k / 1000.0;
        double l[3] = {sin(a), 0, cos(a)}, v[3] = {-sin(a), 0, cos(a)};
        const double ms[] = {0.0, 1e-4, 0.05, 1.0};
        for (int j = 0; j < 4; ++j) {
            double s = dm_ks_specular(n, l, v, ms[j], 1.0, 0.028);
            cr_assert(isfinite(s) && s >= 0.0, "angle %g m %g: %g", a, ms[j], s);
        }
    }
}

Test(ks, matches_chapter_formula)
{
    /* ndotl * rho_s * D(N·H) F(H·V) / |L+V|², evaluated by hand for one configuration */
    double n[3] = {0, 0, 1}, l[3] = {0.6, 0, 0.8}, v[3] = {0, 0, 1};
    double h[3] = {0.6, 0, 1.8}, hh = 0.36 + 3.24, hl = sqrt(hh);
    double ndoth = 1.8 / hl, vdoth = 1.8 / hl;
    double expected = 0.8 * 0.5 * dm_beckmann(ndoth, 0.3) * dm_fresnel_schlick(vdoth, 0.028) / hh;
    (void)h;
    cr_expect_float_eq(dm_ks_specular(n, l, v, 0.3, 0.5, 0.028), expected, 1e-14);
}

/* Brute force rho_dt in V space: midpoint grid over θ_V ∈ [0, π/2] and φ_V ∈ [0, π]
 * (the lobe is symmetric in φ), n × 2n cells; an independent parametrisation from the
 * library's half-vector quadrature. With n = 1200 the grid resolves the m = 0.05 lobe by
 * ~40 cells (measured agreement with n = 3000: 4e-5). Near grazing (c < 0.05) the mirror
 * direction approaches V = −L, where f_KS grows like 1/|h|², and n = 1200 is off by 0.2
 * at c = 1/128, m = 0.05; there the reference uses n = 3000 (measured 3.5e-5 from the
 * library at n = 3000). */
static double rho_dt_brute(double c, double m, int n)
{
    double l[3] = {sqrt(1 - c * c), 0, c}, nn[3] = {0, 0, 1};
    double sum = 0.0, dt = DM_PI_2 / n, dp = DM_PI / (2 * n);
    for (int i = 0; i < n; ++i) {
        double th = (i + 0.5) * dt, st = sin(th), ct = cos(th);
        for (int j = 0; j < 2 * n; ++j) {
            double ph = (j + 0.5) * dp;
            double v[3] = {st * cos(ph), st * sin(ph), ct};
            /* f_KS(L, V) (N·V): the "ndotl" slot of dm_ks_specular carries N·V here */
            sum += dm_ks_specular(nn, v, l, m, 1.0, 0.028) * st;
        }
    }
    return 2.0 * sum * dt * dp;
}

Test(rho_dt, against_brute_force, .timeout = 60)
{
    const double cs[] = {1.0 / 128, 0.05, 0.2, 0.5, 0.9, 1.0};
    const double ms[] = {0.05, 0.1, 0.3, 0.6, 1.0};
    for (int a = 0; a < 6; ++a)
        for (int b = 0; b < 5; ++b) {
            double ref = rho_dt_brute(cs[a], ms[b], cs[a] < 0.05 ? 3000 : 1200);
            double got = dm_rho_dt(cs[a], ms[b], 0.028, 32); /* the bake's node count */
            cr_expect(fabs(got - ref) < 1e-3, "c=%g m=%g: %.6f vs brute %.6f", cs[a], ms[b], got, ref);
        }
}

/* At c = 0 the mirror direction is V = −L, where f_KS has a 1/|h|² singularity on the
 * horizon that a V-space grid cannot resolve. Reference: a midpoint grid over the half
 * vector (θ_h, φ_h) without the library's substitution or horizon cut; dω_V = 4 (L·H) dω_h. */
static double rho_dt_brute_half(double c, double m, int n)
{
    double sl = sqrt(1 - c * c), sum = 0.0, dt = DM_PI_2 / n, dp = DM_2PI / (2 * n);
    for (int i = 0; i < n; ++i) {
        double th = (i + 0.5) * dt, st = sin(th), ct = cos(th);
        for (int j = 0; j < 2 * n; ++j) {
            double ph = (j + 0.5) * dp;
            double ldoth = sl * st * cos(ph) + c * ct;
            double ndotv = 2 * ldoth * ct - c;
            if (ldoth <= 0 || ndotv <= 0) continue;
            double f = dm_beckmann(ct, m) * dm_fresnel_schlick(ldoth, 0.028) / (4 * ldoth * ldoth);
            sum += f * ndotv * 4 * ldoth * st;
        }
    }
    return sum * dt * dp;
}

Test(rho_dt, hard_case_grazing_c_zero, .timeout = 60)
{
    const double ms[] = {0.05, 0.3, 1.0};
    for (int b = 0; b < 3; ++b) {
        double ref = rho_dt_brute_half(0.0, ms[b], 3000);
        double got = dm_rho_dt(0.0, ms[b], 0.028, 32);
        cr_expect(isfinite(got));
        cr_expect(fabs(got - ref) < 1e-3, "m=%g: %.6f vs brute %.6f", ms[b], got, ref);
    }
}

Test(rho_dt, hard_case_m_to_zero)
{
    /* m → 0: the lobe is a mirror; ∫ D cos dω_h = π gives rho_dt → π F(c). At m = 1e-3 the
     * deviation is O(m) on F's slope, below 1e-3 for c ≥ 0.2. */
    for (int k = 2; k <= 10; ++k) {
        double c = k / 10.0;
        double lim = DM_PI * dm_fresnel_schlick(c, 0.028);
        cr_expect(fabs(dm_rho_dt(c, 0.0, 0.028, 32) - lim) < 1e-12);
        cr_expect(fabs(dm_rho_dt(c, 1e-3, 0.028, 32) - lim) < 1e-3, "c=%g: %g vs %g", c,
                  dm_rho_dt(c, 1e-3, 0.028, 32), lim);
    }
    for (int k = 0; k <= 100; ++k) {
        double v = dm_rho_dt(k / 100.0, 1e-4, 0.028, 32);
        cr_assert(isfinite(v) && v >= 0.0, "c=%g: %g", k / 100.0, v);
    }
}

Test(rho_dt, converged_at_bake_nodes)
{
    /* the bake's 32 nodes against 96: the "much finer reference", within 1e-4 */
    for (int a = 0; a <= 16; ++a)
        for (int b = 1; b <= 16; ++b) {
            double c = a / 16.0, m = b / 16.0;
            double d = fabs(dm_rho_dt(c, m, 0.028, 32) - dm_rho_dt(c, m, 0.028, 96));
            cr_expect(d < 1e-4, "c=%g m=%g: %g", c, m, d);
        }
}

Test(rho_dt, split_sum_consistency)
{
    /* f0·scale + bias is rho_dt for any f0; both parts non-negative; F0 = 1 gives scale+bias */
    for (int a = 0; a <= 8; ++a)
        for (int b = 1; b <= 8; ++b) {
            double c = a / 8.0, m = b / 8.0, s, bias;
            dm_ks_directional(c, m, 32, &s, &bias);
            cr_expect(s >= 0.0 && bias >= 0.0);
            cr_expect_float_eq(dm_rho_dt(c, m, 0.5, 32), 0.5 * s + bias, 1e-12);
            cr_expect_float_eq(dm_rho_dt(c, m, 1.0, 32), s + bias, 1e-12);
        }
}
