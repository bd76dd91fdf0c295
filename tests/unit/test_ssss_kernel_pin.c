/* The screen-space kernel pinned against its definition (core/dm_ssss_kernel.h), computed here
 * independently in double precision (issue #31: its range could shrink from 3σ to 2σ with
 * every test green, the existing checks taking the kernel's own offsets as given).
 *
 * The definition: taps at o_a = R·t·|t|, t = (a − h)/h, R = 3σ of the profile's widest
 * Gaussian; bins between midpoints, the end bins to ±∞; the weights the profile's line-spread
 * function (its marginal, Σ_j w_j G₁(v_j, x)) integrated over each bin, Σ_j w_j p_j[a] / Σ_j w_j
 * with p_j[a] the mass of the 1-D Gaussian j in bin a (issue #29). Here p_j by Simpson's rule
 * (not erf).
 *
 * Tolerances: offsets and range to 1e-6 relative (float storage: 6e-8); weights to 2e-6
 * absolute (float storage, Simpson's 1e-10). A 5 % change of the range
 * (2.85σ or 3.15σ) moves the offsets by 5 % and the weights by ~1e-2: far outside. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "core/dm_profile.h"
#include "core/dm_scene.h"
#include "core/dm_ssss_kernel.h"

enum { MAXT = DM_SSSS_MAX_TAPS };

/* Mass of N(0, s²) over [lo, hi] (infinite ends cut at ±12s, where the tail is 2e-33):
 * composite Simpson with 2000 intervals. */
static double gauss_mass(double s, double lo, double hi)
{
    lo = fmax(lo, -12.0 * s), hi = fmin(hi, 12.0 * s);
    if (!(hi > lo)) return 0.0;
    const int n = 2000;
    double step = (hi - lo) / n, sum = 0.0;
    for (int i = 0; i <= n; ++i) {
        double x = lo + i * step, g = exp(-x * x / (2.0 * s * s));
        sum += g * (i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0);
    }
    return sum * step / 3.0 / (s * sqrt(2.0 * 3.14159265358979323846));
}

/* The kernel by the definition above: offsets, range and per-channel weights. */
static void reference_kernel(const dm_profile *p, int taps, double off[MAXT], double *range, double w[MAXT][3])
{
    double vmax = 0.0;
    for (int j = 0; j < p->count; ++j) vmax = fmax(vmax, p->variance_mm2[j]);
    const int h = taps / 2;
    *range = 3.0 * sqrt(vmax);
    for (int a = 0; a < taps; ++a) {
        double t = (double)(a - h) / h;
        off[a] = *range * t * fabs(t);
    }
    double pm[DM_PROFILE_MAX_GAUSSIANS][MAXT];
    for (int j = 0; j < p->count; ++j)
        for (int a = 0; a < taps; ++a) {
            double lo = a == 0 ? -INFINITY : 0.5 * (off[a - 1] + off[a]);
            double hi = a == taps - 1 ? INFINITY : 0.5 * (off[a] + off[a + 1]);
            pm[j][a] = gauss_mass(sqrt(p->variance_mm2[j]), lo, hi);
        }
    for (int c = 0; c < 3; ++c) {
        double total = 0.0;
        for (int j = 0; j < p->count; ++j) total += p->weight[j][c];
        for (int a = 0; a < taps; ++a) {
            w[a][c] = 0.0;
            for (int j = 0; j < p->count; ++j) w[a][c] += p->weight[j][c] * pm[j][a] / total;
        }
    }
}

static void check_against_reference(const dm_profile *p, const char *name)
{
    const int taps_list[] = DM_SCENE_SCREEN_TAPS_LIST;
    for (size_t t = 0; t < sizeof taps_list / sizeof taps_list[0]; ++t) {
        int taps = taps_list[t];
        dm_ssss_kernel k;
        dm_error err = {0};
        cr_assert_eq(dm_ssss_kernel_fit(p, taps, &k, &err), DM_OK, "%s", err.detail);
        double off[MAXT], range, w[MAXT][3];
        reference_kernel(p, taps, off, &range, w);
        cr_expect(fabs(k.range_mm / range - 1.0) < 1e-9, "%s, %d taps: range %.6f mm, 3 sigma of the widest is %.6f mm",
                  name, taps, k.range_mm, range);
        for (int a = 0; a < taps; ++a) {
            cr_expect(fabs(k.offset_mm[a] - off[a]) <= 1e-6 * range, "%s, %d taps: tap %d at %.6f mm, expected %.6f",
                      name, taps, a, (double)k.offset_mm[a], off[a]);
            for (int c = 0; c < 3; ++c)
                cr_expect(fabs(k.weight[a][c] - w[a][c]) < 2e-6, "%s, %d taps: tap %d channel %d weight %.7f, expected %.7f",
                          name, taps, a, c, (double)k.weight[a][c], w[a][c]);
        }
    }
}

Test(ssss_kernel_pin, skin_profile_kernel_is_its_definition)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    check_against_reference(&p, "gems3-skin");
}

Test(ssss_kernel_pin, two_gaussians_kernel_is_its_definition)
{
    dm_profile p = {.count = 2, .variance_mm2 = {0.3, 4.0}, .weight = {{0.6, 0.8, 0.9}, {0.4, 0.2, 0.1}}};
    check_against_reference(&p, "two Gaussians");
}

/* The range itself, in words a reader can check: 3σ of the widest Gaussian, gems3-skin's
 * 7.41 mm² (DESIGN.md), so 3·√7.41 = 8.1664 mm; the end taps sit there. */
Test(ssss_kernel_pin, skin_range_is_three_sigma_of_the_widest)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    dm_ssss_kernel k;
    dm_error err = {0};
    cr_assert_eq(dm_ssss_kernel_fit(&p, 17, &k, &err), DM_OK, "%s", err.detail);
    cr_expect(fabs(k.range_mm - 8.1664) < 1e-3, "range %.5f mm", k.range_mm);
    cr_expect(fabs(-k.offset_mm[0] - 8.1664) < 1e-3 && fabs(k.offset_mm[16] - 8.1664) < 1e-3, "end taps %.5f, %.5f",
              (double)k.offset_mm[0], (double)k.offset_mm[16]);
}
