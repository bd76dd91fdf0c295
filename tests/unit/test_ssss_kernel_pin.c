/* The screen-space kernels pinned against their definition (core/dm_ssss_kernel.h), checked
 * here independently in double precision (issue #31: a parameter could change with every test
 * green, the checks taking the kernel's own offsets as given; issue #29: one kernel per size of
 * pixel).
 *
 * The definition, per row r at P = 0.02·2^r mm per pixel (8 rows): the centre tap at 0 weighs
 * the line-spread function L's mass over [−½, ½] pixels; each side's taps span bins of whole
 * pixels [s − ½, e + ½] outward from pixel 1, the last to infinity, and weigh L's mass over
 * them; a one-pixel bin's tap sits on its pixel; a tap at j + f inside its bin reads (1 − f) of
 * pixel j and f of j + 1, and the bin's error is the largest difference of that cumulative mass
 * from L's at the bin's inner pixel boundaries (three channels); the fit's edge_error is the
 * largest bin error, and no bin but the last could take one more pixel within it (the greedy
 * partition). Here masses by Simpson's rule (not erf) and each bin's best error by an
 * exhaustive j and a ternary search on f (not the fit's candidates).
 *
 * Tolerances: sizes to 1e-12 relative; weights to 2e-6 (float storage, Simpson's 1e-10);
 * errors to 1e-6. A row count or first size 5 % off moves the sizes; a bin boundary moved by one
 * pixel changes a weight by ≥ 1e-4 at every size here; the modelled edge (last test) bounds
 * the fit's quality. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "core/dm_profile.h"
#include "core/dm_scene.h"
#include "core/dm_ssss_kernel.h"

/* Mass of L (channel c, weights normalised) over [lo, hi] mm, hi may be INFINITY (cut at 14σ
 * of the widest, where the tail is 1e-44): composite Simpson per Gaussian, 4000 intervals. */
static double lsf_mass(const dm_profile *p, int c, double lo, double hi)
{
    double sum = 0, wsum = 0;
    for (int j = 0; j < p->count; ++j) {
        double s = sqrt(p->variance_mm2[j]), a = fmax(lo, -14 * s), b = fmin(hi, 14 * s), m = 0;
        wsum += p->weight[j][c];
        if (!(b > a)) continue;
        const int n = 4000;
        double step = (b - a) / n;
        for (int i = 0; i <= n; ++i) {
            double x = a + i * step;
            m += exp(-x * x / (2 * s * s)) * (i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0);
        }
        sum += p->weight[j][c] * m * step / 3.0 / (s * sqrt(2.0 * 3.14159265358979323846));
    }
    return wsum > 0 ? sum / wsum : 0.0;
}

/* The best error of one tap over pixels s..e (e < 0: to infinity, cut at `far`) at P mm/px. */
static double best_bin_error(const dm_profile *p, double P, int s, int e, int far)
{
    int last = e < 0 ? far : e;
    double w[3];
    for (int c = 0; c < 3; ++c) w[c] = lsf_mass(p, c, (s - 0.5) * P, e < 0 ? INFINITY : (e + 0.5) * P);
    double best = INFINITY;
    for (int j = s; j <= last; ++j) {
        double base = 0, t[3];
        for (int c = 0; c < 3; ++c) {
            if (j > s) base = fmax(base, lsf_mass(p, c, (s - 0.5) * P, (j - 0.5) * P));
            if (j + 1 < last) base = fmax(base, w[c] - lsf_mass(p, c, (s - 0.5) * P, (j + 1.5) * P));
            t[c] = lsf_mass(p, c, (s - 0.5) * P, (j + 0.5) * P);
        }
        if (base >= best) continue;
        double lo = 0, hi = j < last ? 1 : 0; /* g = 1 − f; max_c |g w − t| is convex in g */
        for (int it = 0; it < 100 && hi > lo; ++it) {
            double g1 = lo + (hi - lo) / 3, g2 = hi - (hi - lo) / 3, e1 = 0, e2 = 0;
            for (int c = 0; c < 3; ++c) e1 = fmax(e1, fabs(g1 * w[c] - t[c])), e2 = fmax(e2, fabs(g2 * w[c] - t[c]));
            if (e1 < e2) hi = g2;
            else lo = g1;
        }
        double err = base;
        for (int c = 0; c < 3 && j < last; ++c) err = fmax(err, fabs(lo * w[c] - t[c]));
        best = fmin(best, err);
    }
    return best;
}

static void check_against_definition(const dm_profile *p, const char *name, int taps)
{
    dm_ssss_kernel k;
    dm_error err = {0};
    cr_assert_eq(dm_ssss_kernel_fit(p, taps, &k, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(k.rows, 8, "%s: %d rows", name, k.rows);
    const int h = taps / 2;
    for (int r = 0; r < k.rows; ++r) {
        const double P = 0.02 * pow(2.0, r);
        cr_expect(fabs(dm_ssss_kernel_row_mm_per_px(&k, r) / P - 1) < 1e-12, "%s row %d: %.9g mm/px, expected %g",
                  name, r, dm_ssss_kernel_row_mm_per_px(&k, r), P);
        cr_expect_eq(k.offset_px[r][h], 0.0f);
        for (int c = 0; c < 3; ++c)
            cr_expect(fabs(k.weight[r][h][c] - lsf_mass(p, c, -0.5 * P, 0.5 * P)) < 2e-6, "%s row %d centre %d", name,
                      r, c);
        /* outward: each tap's bin ends at the half-integer where the cumulative mass matches */
        int s = 1;
        double worst = 0;
        for (int a = 1; a <= h; ++a) {
            const float *wt = k.weight[r][h + a];
            double rest = 0; /* past where float weights tell bins apart: nothing left to check */
            for (int c = 0; c < 3; ++c) rest = fmax(rest, lsf_mass(p, c, (s - 0.5) * P, INFINITY));
            if (rest < 2e-6) break;
            int e = -1;
            bool tail = a == h;
            for (int c = 0; c < 3 && tail; ++c)
                tail = fabs(wt[c] - lsf_mass(p, c, (s - 0.5) * P, INFINITY)) < 2e-6;
            double o = k.offset_px[r][h + a];
            int e_hi = -1;
            if (!tail) { /* the bin's end: pixels s..e whose masses the weights are (in float, a few
                          * ends may hold tiny weights alike: the one at or past the tap's pixels) */
                double best = INFINITY;
                for (int n = s; n < s + 4096; ++n) {
                    double mis = 0, m = 0;
                    for (int c = 0; c < 3; ++c) {
                        double mc = lsf_mass(p, c, (s - 0.5) * P, (n + 0.5) * P);
                        mis = fmax(mis, fabs(wt[c] - mc)), m += mc;
                    }
                    if (mis < 2e-6) {
                        e_hi = n;
                        if (mis < best && n >= ceil(o)) best = mis, e = n;
                    }
                    if (m > wt[0] + wt[1] + wt[2] + 1e-5) break;
                }
                if (e < 0) e = e_hi;
                cr_assert(e >= s, "%s row %d tap %d: no bin of whole pixels from %d holds its weights", name, r, a, s);
            }
            cr_expect(k.offset_px[r][h - a] == -k.offset_px[r][h + a]);
            if (e_hi == s) cr_expect(o == s, "%s row %d tap %d: one-pixel bin %d, tap at %.6f", name, r, a, s, o);
            cr_expect(o >= s && (e < 0 || o <= e), "%s row %d tap %d at %.4f outside its bin %d..%d", name, r, a, o, s, e);
            int far = s + 2 * (int)ceil(o - s + 1) + 8; /* the tail's best tap lies near its median */
            double be = e == s ? 0.0 : best_bin_error(p, P, s, e, far);
            worst = fmax(worst, be);
            cr_expect(be <= k.edge_error[r] + 1e-6, "%s row %d tap %d: bin error %.6f over the fit's %.6f", name, r, a,
                      be, k.edge_error[r]);
            if (e < 0) break;
            /* greedy: one more pixel would not fit (unless this was the last tap) */
            if (a < h)
                cr_expect(e_hi > e || best_bin_error(p, P, s, e + 1, 0) > k.edge_error[r] - 1e-9,
                          "%s row %d tap %d: pixels %d..%d fit within %.6f too", name, r, a, s, e + 1, k.edge_error[r]);
            s = e + 1;
        }
        cr_expect(fabs(worst - k.edge_error[r]) < 1e-6, "%s row %d: largest bin error %.7f, the fit says %.7f", name, r,
                  worst, k.edge_error[r]);
    }
}

Test(ssss_kernel_pin, skin_profile_kernel_is_its_definition)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    const int taps_list[] = DM_SCENE_SCREEN_TAPS_LIST;
    for (size_t t = 0; t < sizeof taps_list / sizeof taps_list[0]; ++t) check_against_definition(&p, "gems3-skin", taps_list[t]);
}

Test(ssss_kernel_pin, two_gaussians_kernel_is_its_definition)
{
    dm_profile p = {.count = 2, .variance_mm2 = {0.3, 4.0}, .weight = {{0.6, 0.8, 0.9}, {0.4, 0.2, 0.1}}};
    check_against_definition(&p, "two Gaussians", 17);
}
