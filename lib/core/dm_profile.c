#include "core/dm_profile.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "core/dm_input.h"
#include "core/dm_jread.h"
#include "core/dm_math.h"
#include "core/dm_sbuf.h"

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
        if (!(v > 0.0 && v <= DM_PROFILE_VARIANCE_MAX_MM2)) /* NaN too */
            return dm_fail(err, DM_ERR_RANGE, "%s: gaussians[%d].variance_mm2 = %g, expected a value in (0, %g] mm^2",
                           what, k, v, DM_PROFILE_VARIANCE_MAX_MM2);
        if (k > 0 && !(v > p->variance_mm2[k - 1]))
            return dm_fail(err, DM_ERR_RANGE,
                           "%s: gaussians[%d].variance_mm2 = %g, expected more than the previous %g (ascending)",
                           what, k, v, p->variance_mm2[k - 1]);
        for (int c = 0; c < 3; ++c)
            if (!(p->weight[k][c] >= 0.0 && p->weight[k][c] <= 1.0))
                return dm_fail(err, DM_ERR_RANGE, "%s: gaussians[%d].weights[%d] = %g, expected a value in [0, 1]",
                               what, k, c, p->weight[k][c]);
    }
    double sum[3];
    dm_profile_channel_sums(p, sum);
    for (int c = 0; c < 3; ++c)
        if (!(sum[c] <= DM_PROFILE_WEIGHT_SUM_MAX))
            return dm_fail(err, DM_ERR_RANGE, "%s: the weights of channel %d sum to %.6g, expected a total in [0, %g]",
                           what, c, sum[c], DM_PROFILE_WEIGHT_SUM_MAX);
    return DM_OK;
}

/* One Gaussian of $.gaussians: {variance_mm2, weights[3]} (incremental_variance_mm2, which
 * dermis-fit-profile writes for readers, is allowed and not read: it follows from the rest). */
static bool read_gaussian(dm_jread *c, const cJSON *e, int k, dm_profile *p)
{
    static const char *const keys[] = {"variance_mm2", "incremental_variance_mm2", "weights", NULL};
    char jp[DM_JPATH_SIZE], wp[DM_JPATH_SIZE];
    snprintf(jp, sizeof jp, "$.gaussians[%d]", k);
    if (!cJSON_IsObject(e)) return dm_jread_fail(c, DM_ERR_FORMAT, jp, e, "an object {variance_mm2, weights}");
    if (!dm_jread_keys(c, e, jp, keys)) return false;
    const cJSON *v = dm_jread_required(c, e, jp, "variance_mm2", "a number (mm^2)");
    if (!v || !dm_jread_double_opt(c, e, jp, "variance_mm2", -1e300, 1e300, &p->variance_mm2[k])) return false;
    const cJSON *w = dm_jread_required(c, e, jp, "weights", "an array of 3 numbers (R, G, B)");
    if (!w) return false;
    dm_jread_path(wp, jp, "weights");
    if (!cJSON_IsArray(w) || cJSON_GetArraySize(w) != 3)
        return dm_jread_fail(c, DM_ERR_FORMAT, wp, w, "an array of 3 numbers (R, G, B)");
    for (int ch = 0; ch < 3; ++ch) {
        const cJSON *x = cJSON_GetArrayItem(w, ch);
        if (!cJSON_IsNumber(x)) return dm_jread_fail(c, DM_ERR_FORMAT, wp, w, "an array of 3 numbers (R, G, B)");
        p->weight[k][ch] = x->valuedouble; /* double as written: ranges are dm_profile_validate's */
    }
    return true;
}

dm_result dm_profile_from_json(const char *json, const char *what, dm_profile *p, dm_error *err)
{
    cJSON *root = cJSON_Parse(json);
    dm_result r = dm_profile_from_cjson(root, what, p, err);
    cJSON_Delete(root);
    return r;
}

dm_result dm_profile_from_cjson(const cJSON *root, const char *what, dm_profile *p, dm_error *err)
{
    /* what dermis-fit-profile, dermis-pack and dm_scene_to_json write (the fit's report is
     * carried, not read) */
    static const char *const top[] = {"format", "version", "name", "normalized", "gaussians", "blur_passes",
                                      "total_reflectance_rgb", "error", "source", "provenance", NULL};
    memset(p, 0, sizeof *p);
    dm_jread c = {what, err, DM_OK};
    bool ok = cJSON_IsObject(root) ? dm_jread_keys(&c, root, "$", top)
                                   : dm_jread_fail(&c, DM_ERR_FORMAT, "$", NULL, "a JSON object (a profile)");
    const cJSON *fmt = ok ? dm_jread_get(root, "format") : NULL, *name = ok ? dm_jread_get(root, "name") : NULL;
    if (ok && fmt && !(cJSON_IsString(fmt) && strcmp(fmt->valuestring, "dermis-profile") == 0))
        ok = dm_jread_fail(&c, DM_ERR_FORMAT, "$.format", fmt, "\"dermis-profile\"");
    int version = 1;
    ok = ok && dm_jread_int_opt(&c, root, "$", "version", 1, 1, false, &version);
    if (ok && name && !cJSON_IsString(name)) ok = dm_jread_fail(&c, DM_ERR_FORMAT, "$.name", name, "a string");
    if (ok && name) snprintf(p->name, sizeof p->name, "%s", name->valuestring);
    const cJSON *g = ok ? dm_jread_required(&c, root, "$", "gaussians", "an array of {variance_mm2, weights}") : NULL;
    ok = ok && g;
    if (ok && (!cJSON_IsArray(g) || cJSON_GetArraySize(g) < 1 || cJSON_GetArraySize(g) > DM_PROFILE_MAX_GAUSSIANS)) {
        char want[96];
        snprintf(want, sizeof want, "an array of 1..%d {variance_mm2, weights}", DM_PROFILE_MAX_GAUSSIANS);
        ok = dm_jread_fail(&c, cJSON_IsArray(g) ? DM_ERR_RANGE : DM_ERR_FORMAT, "$.gaussians", g, want);
    }
    for (int k = 0; ok && k < cJSON_GetArraySize(g); ++k) {
        ok = read_gaussian(&c, cJSON_GetArrayItem(g, k), k, p);
        p->count = k + 1;
    }
    if (!ok) return c.r;
    return dm_profile_validate(p, what, err);
}

dm_result dm_profile_read(const char *path, dm_profile *p, dm_error *err)
{
    char *text = NULL;
    size_t size = 0;
    dm_result r = dm_input_read(path, DM_INPUT_JSON, &text, &size, err);
    if (r != DM_OK) return r;
    r = dm_profile_from_json(text, path, p, err);
    free(text);
    return r;
}

void dm_profile_put_gaussians(dm_sbuf *b, const dm_profile *p, const char *indent, int with_increments)
{
    double inc[DM_PROFILE_MAX_GAUSSIANS];
    dm_profile_incremental_variances(p, inc);
    dm_sbuf_put(b, "[\n");
    for (int k = 0; k < p->count; ++k) {
        dm_sbuf_put(b, "%s  {\"variance_mm2\": ", indent);
        dm_sbuf_num(b, p->variance_mm2[k]);
        if (with_increments) {
            dm_sbuf_put(b, ", \"incremental_variance_mm2\": ");
            dm_sbuf_num(b, inc[k]);
        }
        dm_sbuf_put(b, ", \"weights\": ");
        dm_sbuf_rgb(b, p->weight[k]);
        dm_sbuf_put(b, "}%s\n", k + 1 < p->count ? "," : "");
    }
    dm_sbuf_put(b, "%s]", indent);
}

dm_result dm_profile_to_json(const dm_profile *p, char **json, dm_error *err)
{
    *json = NULL;
    dm_result r = dm_profile_validate(p, "profile to write", err);
    if (r != DM_OK) return r;
    dm_sbuf b = {0};
    dm_sbuf_put(&b, "{\"format\": \"dermis-profile\", \"version\": 1, \"name\": ");
    dm_sbuf_str(&b, p->name);
    dm_sbuf_put(&b, ", \"gaussians\": ");
    dm_profile_put_gaussians(&b, p, "", 0);
    dm_sbuf_put(&b, "}\n");
    if (b.failed) {
        free(b.s);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "profile '%s': cannot build its JSON", p->name);
    }
    *json = b.s;
    return DM_OK;
}
