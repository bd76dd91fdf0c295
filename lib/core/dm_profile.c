#include "core/dm_profile.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "core/dm_file.h"
#include "core/dm_math.h"

const double DM_BLUR_TAPS_GEMS3[DM_BLUR_TAPS_GEMS3_COUNT] = {0.006, 0.061, 0.242, 0.383, 0.242, 0.061, 0.006};

double dm_gaussian(double variance_mm2, double r_mm)
{
    /* exp(−x) for x ≥ 0 is in [0, 1]; r = inf gives exp(−inf) = 0, and r² overflowing to
     * inf does the same, so no guard is needed beyond the contract v > 0. */
    return exp(-(r_mm * r_mm) / (2.0 * variance_mm2)) / (DM_2PI * variance_mm2);
}

void dm_profile_eval(const dm_profile *p, double r_mm, double rgb[3])
{
    rgb[0] = rgb[1] = rgb[2] = 0.0;
    for (int k = 0; k < p->count; ++k) {
        double g = dm_gaussian(p->variance_mm2[k], r_mm);
        for (int c = 0; c < 3; ++c) rgb[c] += p->weight[k][c] * g;
    }
}

void dm_profile_channel_sums(const dm_profile *p, double sums[3])
{
    sums[0] = sums[1] = sums[2] = 0.0;
    for (int k = 0; k < p->count; ++k)
        for (int c = 0; c < 3; ++c) sums[c] += p->weight[k][c];
}

dm_result dm_profile_normalize_white(dm_profile *p, double sums_before[3], dm_error *err)
{
    double s[3];
    dm_profile_channel_sums(p, s);
    for (int c = 0; c < 3; ++c)
        if (!(s[c] > 0.0) || !isfinite(s[c]))
            return dm_fail(err, DM_ERR_RANGE, "profile '%s': channel %d weights sum to %g, expected > 0 to normalise",
                           p->name, c, s[c]);
    for (int k = 0; k < p->count; ++k)
        for (int c = 0; c < 3; ++c) p->weight[k][c] /= s[c];
    if (sums_before)
        for (int c = 0; c < 3; ++c) sums_before[c] = s[c];
    return DM_OK;
}

void dm_profile_incremental_variances(const dm_profile *p, double *out_mm2)
{
    for (int k = 0; k < p->count; ++k) out_mm2[k] = p->variance_mm2[k] - (k ? p->variance_mm2[k - 1] : 0.0);
}

int dm_profile_blur_passes(int gaussian_count)
{
    return gaussian_count > 1 ? 2 * (gaussian_count - 1) : 0;
}

/* P(X > x) for a standard normal X, accurate in the far tail (erfc, not 1 − erf). */
static double upper_tail(double x)
{
    return 0.5 * erfc(x / DM_SQRT2);
}

dm_result dm_blur_taps(int tap_count, double spacing_sigma, int fold_tails, double *weight, double *tail,
                       dm_error *err)
{
    if (tap_count < 1 || tap_count > DM_BLUR_TAPS_MAX || tap_count % 2 == 0)
        return dm_fail(err, DM_ERR_RANGE, "blur kernel: %d taps, expected an odd count in 1..%d", tap_count,
                       DM_BLUR_TAPS_MAX);
    if (!isfinite(spacing_sigma) || !(spacing_sigma > 0.0))
        return dm_fail(err, DM_ERR_RANGE, "blur kernel: tap spacing %g sigma, expected a finite value > 0",
                       spacing_sigma);
    int half = tap_count / 2;
    /* Symmetric: compute one side as differences of upper tails (no cancellation against 1). */
    for (int i = 0; i <= half; ++i) {
        double lo = (i - 0.5) * spacing_sigma, hi = (i + 0.5) * spacing_sigma;
        double w = i == 0 ? 1.0 - 2.0 * upper_tail(hi) : upper_tail(lo) - upper_tail(hi);
        weight[half + i] = weight[half - i] = w;
    }
    double t = 2.0 * upper_tail((half + 0.5) * spacing_sigma);
    if (fold_tails) {
        if (tap_count == 1) {
            weight[0] += t;
        } else {
            weight[0] += 0.5 * t;
            weight[tap_count - 1] += 0.5 * t;
        }
    }
    if (tail) *tail = t;
    return DM_OK;
}

void dm_profile_gems3_skin(dm_profile *p)
{
    static const double v[6] = {0.0064, 0.0484, 0.187, 0.567, 1.99, 7.41};
    static const double w[6][3] = {{0.233, 0.455, 0.649}, {0.100, 0.336, 0.344}, {0.118, 0.198, 0.0},
                                   {0.113, 0.007, 0.007}, {0.358, 0.004, 0.0},   {0.078, 0.0, 0.0}};
    memset(p, 0, sizeof *p);
    snprintf(p->name, sizeof p->name, "gems3-skin");
    p->count = 6;
    for (int k = 0; k < 6; ++k) {
        p->variance_mm2[k] = v[k];
        for (int c = 0; c < 3; ++c) p->weight[k][c] = w[k][c];
    }
}

dm_result dm_profile_validate(const dm_profile *p, const char *what, dm_error *err)
{
    if (p->count < 1 || p->count > DM_PROFILE_MAX_GAUSSIANS)
        return dm_fail(err, DM_ERR_RANGE, "%s: %d Gaussians, expected 1..%d", what, p->count,
                       DM_PROFILE_MAX_GAUSSIANS);
    for (int k = 0; k < p->count; ++k) {
        double v = p->variance_mm2[k];
        if (!isfinite(v) || v <= 0.0)
            return dm_fail(err, DM_ERR_RANGE, "%s: gaussians[%d].variance_mm2 = %g, expected a finite value > 0",
                           what, k, v);
        if (k > 0 && !(v > p->variance_mm2[k - 1]))
            return dm_fail(err, DM_ERR_RANGE,
                           "%s: gaussians[%d].variance_mm2 = %g, expected more than the previous %g (ascending)",
                           what, k, v, p->variance_mm2[k - 1]);
        for (int c = 0; c < 3; ++c)
            if (!isfinite(p->weight[k][c]) || p->weight[k][c] < 0.0)
                return dm_fail(err, DM_ERR_RANGE, "%s: gaussians[%d].weights[%d] = %g, expected a finite value >= 0",
                               what, k, c, p->weight[k][c]);
    }
    return DM_OK;
}

dm_result dm_profile_from_json(const char *json, const char *what, dm_profile *p, dm_error *err)
{
    memset(p, 0, sizeof *p);
    cJSON *root = cJSON_Parse(json);
    if (!cJSON_IsObject(root)) {
        cJSON_Delete(root);
        return dm_fail(err, DM_ERR_FORMAT, "%s: not a JSON object", what);
    }
    dm_result r = DM_OK;
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(root, "name");
    if (cJSON_IsString(name)) snprintf(p->name, sizeof p->name, "%s", name->valuestring);
    const cJSON *g = cJSON_GetObjectItemCaseSensitive(root, "gaussians");
    if (!cJSON_IsArray(g)) {
        r = dm_fail(err, DM_ERR_FORMAT, "%s: $.gaussians: expected an array of {variance_mm2, weights}", what);
    } else {
        int n = cJSON_GetArraySize(g);
        if (n < 1 || n > DM_PROFILE_MAX_GAUSSIANS)
            r = dm_fail(err, DM_ERR_RANGE, "%s: $.gaussians has %d entries, expected 1..%d", what, n,
                        DM_PROFILE_MAX_GAUSSIANS);
        for (int k = 0; k < n && r == DM_OK; ++k) {
            const cJSON *e = cJSON_GetArrayItem(g, k);
            const cJSON *v = cJSON_GetObjectItemCaseSensitive(e, "variance_mm2");
            const cJSON *w = cJSON_GetObjectItemCaseSensitive(e, "weights");
            if (!cJSON_IsNumber(v)) {
                r = dm_fail(err, DM_ERR_FORMAT, "%s: $.gaussians[%d].variance_mm2: expected a number", what, k);
            } else if (!cJSON_IsArray(w) || cJSON_GetArraySize(w) != 3) {
                r = dm_fail(err, DM_ERR_FORMAT, "%s: $.gaussians[%d].weights: expected an array of 3 numbers", what, k);
            } else {
                p->variance_mm2[k] = v->valuedouble;
                for (int c = 0; c < 3 && r == DM_OK; ++c) {
                    const cJSON *x = cJSON_GetArrayItem(w, c);
                    if (!cJSON_IsNumber(x))
                        r = dm_fail(err, DM_ERR_FORMAT, "%s: $.gaussians[%d].weights[%d]: expected a number", what, k, c);
                    else
                        p->weight[k][c] = x->valuedouble;
                }
            }
        }
        p->count = n;
    }
    cJSON_Delete(root);
    if (r == DM_OK) r = dm_profile_validate(p, what, err);
    return r;
}

dm_result dm_profile_read(const char *path, dm_profile *p, dm_error *err)
{
    char *text = NULL;
    size_t size = 0;
    dm_result r = dm_read_file(path, &text, &size, err);
    if (r != DM_OK) return r;
    r = dm_profile_from_json(text, path, p, err);
    free(text);
    return r;
}
