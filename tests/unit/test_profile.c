/* Sum-of-Gaussians profiles (core/dm_profile.h): the gems3-skin preset, evaluation,
 * normalisation to white, incremental variances and the exact blur-kernel taps. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_math.h"
#include "core/dm_profile.h"

/* ∫ lo..hi f by composite Simpson with n (even) intervals: an independent reference. */
static double simpson(double (*f)(double, const void *), const void *ctx, double lo, double hi, int n)
{
    double h = (hi - lo) / n, s = f(lo, ctx) + f(hi, ctx);
    for (int i = 1; i < n; ++i) s += (i % 2 ? 4.0 : 2.0) * f(lo + i * h, ctx);
    return s * h / 3.0;
}

static double ring_gaussian(double r, const void *ctx)
{
    double v = *(const double *)ctx;
    return DM_2PI * r * exp(-r * r / (2.0 * v)) / (DM_2PI * v); /* written out, not dm_gaussian */
}

Test(profile, gems3_each_channel_sums_to_one)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    double s[3];
    dm_profile_channel_sums(&p, s);
    /* Six 3-decimal constants that sum to 1 exactly in decimal: double rounding only. */
    for (int c = 0; c < 3; ++c) cr_assert(fabs(s[c] - 1.0) < 1e-12, "channel %d sums to %.17g", c, s[c]);
    cr_assert_eq(p.count, 6);
    cr_assert_eq(dm_profile_validate(&p, "gems3", NULL), DM_OK);
}

/* The physical ranges every reader of a profile shares (a scene's, a pack's, a file's):
 * variances up to 1e8 mm^2, weights in [0, 1], channel sums at most 1.001; a channel of no
 * weight at all is allowed (a medium that scatters none of that colour back). */
Test(profile, validate_refuses_absurd_values)
{
    struct {
        int k, c;
        double variance, weight;
        const char *expect;
    } cases[] = {
        {5, -1, 1e38, 0, "gems3: gaussians[5].variance_mm2 = 1e+38, expected a value in (0, 1e+08] mm^2"},
        {5, -1, 1.0000001e8, 0, "gaussians[5].variance_mm2 = 1e+08"},
        {0, 1, 0, 2.0, "gems3: gaussians[0].weights[1] = 2, expected a value in [0, 1]"},
        {0, 1, 0, -1e-9, "gaussians[0].weights[1] = -1e-09"},
        {0, 2, 0, 0.66, "gems3: the weights of channel 2 sum to 1.011, expected a total in [0, 1.001]"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        dm_profile p;
        dm_profile_gems3_skin(&p);
        if (cases[i].c < 0) p.variance_mm2[cases[i].k] = cases[i].variance;
        else p.weight[cases[i].k][cases[i].c] = cases[i].weight;
        dm_error err = {0};
        cr_expect_eq(dm_profile_validate(&p, "gems3", &err), DM_ERR_RANGE, "case %zu", i);
        cr_expect(strstr(err.detail, cases[i].expect), "'%s' not in: %s", cases[i].expect, err.detail);
    }
    dm_profile p;
    dm_profile_gems3_skin(&p);
    p.variance_mm2[5] = DM_PROFILE_VARIANCE_MAX_MM2;
    for (int k = 0; k < p.count; ++k) p.weight[k][2] = 0.0; /* no blue scattered back */
    p.weight[0][0] += 0.0009;                           /* 1.0009: three-decimal rounding */
    dm_error err = {0};
    cr_expect_eq(dm_profile_validate(&p, "edges", &err), DM_OK, "%s", err.detail);
}

Test(profile, each_gaussian_integrates_to_one)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    for (int k = 0; k < p.count; ++k) {
        double v = p.variance_mm2[k];
        /* [0, 40σ] holds all but e^-800 of the mass; Simpson with 20000 intervals on a
         * smooth integrand errs below 1e-12. */
        double total = simpson(ring_gaussian, &v, 0.0, 40.0 * sqrt(v), 20000);
        cr_assert(fabs(total - 1.0) < 1e-9, "gaussian %d (v %g) integrates to %.15g", k, v, total);
    }
}

Test(profile, eval_is_the_weighted_sum)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    const double rs[] = {0.0, 0.05, 0.3, 1.0, 4.0};
    for (size_t i = 0; i < sizeof rs / sizeof rs[0]; ++i) {
        double rgb[3], r = rs[i];
        dm_profile_eval(&p, r, rgb);
        for (int c = 0; c < 3; ++c) {
            double ref = 0.0;
            for (int k = 0; k < p.count; ++k)
                ref += p.weight[k][c] * exp(-r * r / (2.0 * p.variance_mm2[k])) / (DM_2PI * p.variance_mm2[k]);
            cr_assert(fabs(rgb[c] - ref) <= 1e-14 * fabs(ref), "r %g channel %d: %.17g vs %.17g", r, c, rgb[c], ref);
        }
    }
}

Test(profile, gaussian_at_r_zero)
{
    cr_assert_eq(dm_gaussian(0.5, 0.0), 1.0 / (DM_2PI * 0.5));
}

Test(profile, gaussian_at_huge_r_is_zero_not_nan)
{
    const double rs[] = {1e3, 1e10, 1e155, 1e200, 1e308, INFINITY};
    for (size_t i = 0; i < sizeof rs / sizeof rs[0]; ++i) {
        double g = dm_gaussian(0.0064, rs[i]);
        cr_assert(g == 0.0, "G(0.0064, %g) = %g, expected 0", rs[i], g);
        dm_profile p;
        dm_profile_gems3_skin(&p);
        double rgb[3];
        dm_profile_eval(&p, rs[i], rgb);
        for (int c = 0; c < 3; ++c) cr_assert(rgb[c] == 0.0 || (rs[i] == 1e3 && rgb[c] >= 0.0 && isfinite(rgb[c])));
    }
}

Test(profile, normalize_white)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    for (int k = 0; k < p.count; ++k) p.weight[k][1] *= 0.25, p.weight[k][2] *= 3.0;
    double before[3], s[3];
    cr_assert_eq(dm_profile_normalize_white(&p, before, NULL), DM_OK);
    cr_assert(fabs(before[1] - 0.25) < 1e-12 && fabs(before[2] - 3.0) < 1e-12);
    dm_profile_channel_sums(&p, s);
    for (int c = 0; c < 3; ++c) cr_assert(fabs(s[c] - 1.0) < 1e-14, "channel %d sums to %.17g", c, s[c]);
}

Test(profile, normalize_white_refuses_a_zero_channel)
{
    dm_profile p, q;
    dm_profile_gems3_skin(&p);
    for (int k = 0; k < p.count; ++k) p.weight[k][2] = 0.0;
    q = p;
    dm_error err = {0};
    cr_assert_eq(dm_profile_normalize_white(&p, NULL, &err), DM_ERR_RANGE);
    cr_assert(strstr(err.detail, "channel 2") != NULL, "%s", err.detail);
    cr_assert(memcmp(&p, &q, sizeof p) == 0, "profile changed on failure");
}

Test(profile, incremental_variances_and_passes)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    double inc[DM_PROFILE_MAX_GAUSSIANS], sum = 0.0;
    dm_profile_incremental_variances(&p, inc);
    cr_assert_eq(inc[0], 0.0064);
    cr_assert(fabs(inc[1] - 0.042) < 1e-15 && fabs(inc[5] - (7.41 - 1.99)) < 1e-15);
    for (int k = 0; k < p.count; ++k) sum += inc[k];
    /* Blurring by each increment in turn composes to the widest variance. */
    cr_assert(fabs(sum - 7.41) < 1e-14);
    cr_assert_eq(dm_profile_blur_passes(6), 10); /* DESIGN.md: 5 stages, a U and a V pass each */
    cr_assert_eq(dm_profile_blur_passes(1), 0);
    cr_assert_eq(dm_profile_blur_passes(8), 14);
}

static double normal_pdf(double x, const void *ctx)
{
    (void)ctx;
    return exp(-0.5 * x * x) / sqrt(DM_2PI);
}

Test(profile, blur_taps_against_brute_force)
{
    const int counts[] = {1, 3, 7, 13, 63};
    const double spacings[] = {0.25, 1.0, 2.0};
    for (size_t a = 0; a < 5; ++a)
        for (size_t b = 0; b < 3; ++b) {
            int n = counts[a];
            double w[DM_BLUR_TAPS_MAX], tail;
            cr_assert_eq(dm_blur_taps(n, spacings[b], 0, w, &tail, NULL), DM_OK);
            double sum = 0.0;
            for (int i = 0; i < n; ++i) {
                double o = (i - n / 2) * spacings[b];
                /* Simpson with 2000 intervals over one bin of the normal density: < 1e-14. */
                double ref = simpson(normal_pdf, NULL, o - 0.5 * spacings[b], o + 0.5 * spacings[b], 2000);
                cr_assert(fabs(w[i] - ref) < 1e-12, "%d taps, spacing %g, tap %d: %.15g vs %.15g", n, spacings[b], i,
                          w[i], ref);
                sum += w[i];
            }
            cr_assert(fabs(sum + tail - 1.0) < 1e-14, "weights %.17g + tail %.17g", sum, tail);
        }
}

Test(profile, blur_taps_match_the_chapter_table)
{
    double w[7];
    cr_assert_eq(dm_blur_taps(7, 1.0, 0, w, NULL, NULL), DM_OK);
    /* The chapter prints 3 decimals: agreement to rounding (0.0005) shows its table is
     * the bin-integrated Gaussian at 1σ spacing. */
    for (int i = 0; i < 7; ++i)
        cr_assert(fabs(w[i] - DM_BLUR_TAPS_GEMS3[i]) <= 0.0005, "tap %d: %.6f vs chapter %.3f", i, w[i],
                  DM_BLUR_TAPS_GEMS3[i]);
}

Test(profile, blur_taps_fold_tails_keeps_energy)
{
    double w[9], tail, sum = 0.0;
    cr_assert_eq(dm_blur_taps(9, 0.5, 1, w, &tail, NULL), DM_OK);
    for (int i = 0; i < 9; ++i) sum += w[i];
    cr_assert(fabs(sum - 1.0) < 1e-15, "sum %.17g", sum);
    cr_assert(tail > 0.01, "9 taps at 0.5σ cover ±2.25σ, so ~2.4%% is tail, got %g", tail);
    for (int i = 0; i < 4; ++i) cr_assert_eq(w[i], w[8 - i]);
    cr_assert_eq(dm_blur_taps(1, 1.0, 1, w, NULL, NULL), DM_OK);
    cr_assert(fabs(w[0] - 1.0) < 1e-15);
}

Test(profile, blur_taps_refuse_bad_counts_and_spacing)
{
    double w[DM_BLUR_TAPS_MAX + 2];
    dm_error err = {0};
    cr_assert_eq(dm_blur_taps(0, 1.0, 0, w, NULL, &err), DM_ERR_RANGE);
    cr_assert_eq(dm_blur_taps(6, 1.0, 0, w, NULL, &err), DM_ERR_RANGE);
    cr_assert(strstr(err.detail, "odd") != NULL, "%s", err.detail);
    cr_assert_eq(dm_blur_taps(DM_BLUR_TAPS_MAX + 2, 1.0, 0, w, NULL, &err), DM_ERR_RANGE);
    cr_assert_eq(dm_blur_taps(7, 0.0, 0, w, NULL, &err), DM_ERR_RANGE);
    cr_assert_eq(dm_blur_taps(7, NAN, 0, w, NULL, &err), DM_ERR_RANGE);
    cr_assert_eq(dm_blur_taps(7, -1.0, 0, w, NULL, &err), DM_ERR_RANGE);
}

/* Profile JSON is read strictly (core/dm_jread.h): unknown keys, at the top and in a
 * Gaussian, are refused with their JSON path; what the writers add (a fit's report) is not. */
Test(profile, json_is_read_strictly)
{
    dm_profile p;
    dm_error err = {0};
    const char *ok = "{\"format\": \"dermis-profile\", \"version\": 1, \"name\": \"x\", \"normalized\": true,"
                     " \"gaussians\": [{\"variance_mm2\": 0.5, \"incremental_variance_mm2\": 0.5,"
                     " \"weights\": [1, 1, 1]}], \"blur_passes\": 1, \"error\": {}, \"source\": {}}";
    cr_expect_eq(dm_profile_from_json(ok, "ok.json", &p, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(p.count, 1);
    cr_expect_eq(p.variance_mm2[0], 0.5);
    const char *top = "{\"gaussians\": [{\"variance_mm2\": 0.5, \"weights\": [1, 1, 1]}], \"colour\": 1}";
    cr_expect_eq(dm_profile_from_json(top, "t.json", &p, &err), DM_ERR_FORMAT);
    cr_expect(strstr(err.detail, "t.json: $.colour: unknown key") != NULL, "%s", err.detail);
    const char *inner = "{\"gaussians\": [{\"variance_mm2\": 0.5, \"weight\": [1, 1, 1]}]}";
    cr_expect_eq(dm_profile_from_json(inner, "i.json", &p, &err), DM_ERR_FORMAT);
    cr_expect(strstr(err.detail, "$.gaussians[0].weight: unknown key") != NULL, "%s", err.detail);
    const char *none = "{\"gaussians\": []}";
    cr_expect_eq(dm_profile_from_json(none, "n.json", &p, &err), DM_ERR_RANGE);
    cr_expect(strstr(err.detail, "$.gaussians: [] is not an array of 1..") != NULL, "%s", err.detail);
}

/* The one writer (dm_profile_to_json): what it writes reads back bit for bit, a name
 * with quotes and a backslash included (the pack's profile step printed names raw and
 * wrote invalid JSON for such a name), and the layout is the pack's (golden bytes). */
Test(profile, json_writer_round_trips_exactly)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    snprintf(p.name, sizeof p.name, "my \"skin\" \\ v2");
    p.weight[2][1] = 1.0 / 7.0; /* a double that needs all 17 digits (the channel still sums to <= 1) */
    char *json = NULL;
    dm_error err = {0};
    cr_assert_eq(dm_profile_to_json(&p, &json, &err), DM_OK, "%s", err.detail);
    dm_profile q;
    cr_assert_eq(dm_profile_from_json(json, "written", &q, &err), DM_OK, "%s\n%s", err.detail, json);
    cr_assert_str_eq(q.name, p.name);
    cr_assert_eq(q.count, p.count);
    for (int k = 0; k < p.count; ++k) {
        cr_assert_eq(memcmp(&q.variance_mm2[k], &p.variance_mm2[k], sizeof(double)), 0, "variance %d", k);
        cr_assert_eq(memcmp(q.weight[k], p.weight[k], sizeof p.weight[k]), 0, "weights %d", k);
    }
    free(json);

    dm_profile one = {.count = 1, .variance_mm2 = {0.25}, .weight = {{1, 0.5, 0.125}}};
    snprintf(one.name, sizeof one.name, "one");
    cr_assert_eq(dm_profile_to_json(&one, &json, &err), DM_OK, "%s", err.detail);
    cr_assert_str_eq(json, "{\"format\": \"dermis-profile\", \"version\": 1, \"name\": \"one\", \"gaussians\": [\n"
                           "  {\"variance_mm2\": 0.25, \"weights\": [1, 0.5, 0.125]}\n]}\n");
    free(json);

    one.variance_mm2[0] = -1; /* invalid: refused, nothing returned */
    json = (char *)1;
    cr_assert_eq(dm_profile_to_json(&one, &json, &err), DM_ERR_RANGE);
    cr_assert_null(json);
}
