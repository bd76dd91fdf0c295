#include "bake/dm_profile_json.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "core/dm_file.h"

/* A growing string; on allocation failure it stays failed and later appends do nothing. */
typedef struct sbuf {
    char *s;
    size_t len, cap;
    int failed;
} sbuf;

static void put(sbuf *b, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static void put(sbuf *b, const char *fmt, ...)
{
    if (b->failed) return;
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int n = vsnprintf(b->s ? b->s + b->len : NULL, b->s ? b->cap - b->len : 0, fmt, ap);
        va_end(ap);
        if (n < 0) {
            b->failed = 1;
            return;
        }
        if (b->s && b->len + (size_t)n < b->cap) {
            b->len += (size_t)n;
            return;
        }
        size_t cap = b->cap ? b->cap : 1024;
        while (cap <= b->len + (size_t)n) cap *= 2;
        char *s = realloc(b->s, cap);
        if (!s) {
            b->failed = 1;
            return;
        }
        b->s = s;
        b->cap = cap;
    }
}

static void put_num(sbuf *b, double v)
{
    if (!isfinite(v)) {
        put(b, "null");
        return;
    }
    char num[40];
    snprintf(num, sizeof num, "%.17g", v);
    put(b, "%s", num);
}

static void put_rgb(sbuf *b, const double v[3])
{
    put(b, "[");
    for (int c = 0; c < 3; ++c) {
        if (c) put(b, ", ");
        put_num(b, v[c]);
    }
    put(b, "]");
}

static void put_str(sbuf *b, const char *s)
{
    cJSON *j = cJSON_CreateString(s ? s : "");
    char *t = j ? cJSON_PrintUnformatted(j) : NULL;
    if (t)
        put(b, "%s", t);
    else
        b->failed = 1;
    cJSON_free(t);
    cJSON_Delete(j);
}

static void put_gaussians(sbuf *b, const dm_profile *p, const char *indent, int with_increments)
{
    double inc[DM_PROFILE_MAX_GAUSSIANS];
    dm_profile_incremental_variances(p, inc);
    put(b, "[\n");
    for (int k = 0; k < p->count; ++k) {
        put(b, "%s  {\"variance_mm2\": ", indent);
        put_num(b, p->variance_mm2[k]);
        if (with_increments) {
            put(b, ", \"incremental_variance_mm2\": ");
            put_num(b, inc[k]);
        }
        put(b, ", \"weights\": ");
        put_rgb(b, p->weight[k]);
        put(b, "}%s\n", k + 1 < p->count ? "," : "");
    }
    put(b, "%s]", indent);
}

static void put_source(sbuf *b, const dm_profile_source *s, const char *preset)
{
    double total[3];
    dm_profile_source_total(s, total);
    const char *model = s->kind == DM_SOURCE_GAUSSIANS             ? "gaussians"
                        : s->kind == DM_SOURCE_BURLEY           ? "burley"
                        : s->medium.model == DM_MODEL_MULTIPOLE ? "multipole"
                                                                 : "dipole";
    put(b, "{\n    \"model\": \"%s\",\n    \"preset\": ", model);
    put_str(b, preset);
    if (s->kind == DM_SOURCE_GAUSSIANS) {
        put(b, ",\n    \"gaussians\": ");
        put_gaussians(b, &s->gaussians, "    ", 0);
    } else if (s->kind == DM_SOURCE_BURLEY) { /* Christensen & Burley 2015, S(A) for ℓ (searchlight) */
        put(b, ",\n    \"albedo\": ");
        put_rgb(b, s->burley.albedo);
        put(b, ",\n    \"mfp_mm\": ");
        put_rgb(b, s->burley.mfp_mm);
    } else {
        const dm_medium *m = &s->medium;
        put(b, ",\n    \"sigma_a_per_mm\": ");
        put_rgb(b, m->sigma_a_per_mm);
        put(b, ",\n    \"sigma_s_prime_per_mm\": ");
        put_rgb(b, m->sigma_s_prime_per_mm);
        put(b, ",\n    \"eta\": ");
        put_num(b, m->eta);
        if (m->model == DM_MODEL_MULTIPOLE) {
            put(b, ",\n    \"thickness_mm\": ");
            put_num(b, m->thickness_mm);
            put(b, ",\n    \"pairs\": %d", m->pair_count ? m->pair_count : DM_MULTIPOLE_PAIRS_DEFAULT);
        }
    }
    put(b, ",\n    \"total_reflectance_rgb\": ");
    put_rgb(b, total);
    put(b, "\n  }");
}

dm_result dm_profile_to_json(const dm_profile_doc *doc, char **json, dm_error *err)
{
    *json = NULL;
    dm_result r = dm_profile_validate(doc->profile, "profile to write", err);
    if (r != DM_OK) return r;
    const dm_profile *p = doc->profile;
    sbuf b = {0};
    put(&b, "{\n  \"format\": \"dermis-profile\",\n  \"version\": 1,\n  \"name\": ");
    put_str(&b, p->name);
    put(&b, ",\n  \"normalized\": %s,\n  \"gaussians\": ", doc->normalized ? "true" : "false");
    put_gaussians(&b, p, "  ", 1);
    put(&b, ",\n  \"blur_passes\": %d,\n  \"total_reflectance_rgb\": ", dm_profile_blur_passes(p->count));
    put_rgb(&b, doc->total_reflectance);
    if (doc->has_error) {
        put(&b, ",\n  \"error\": {\n    \"measure\": \"sqrt(integral r (R - sum G)^2 dr / integral r R^2 dr), per "
                "channel, before normalisation\",\n    \"relative_rgb\": ");
        put_rgb(&b, doc->error_relative);
        put(&b, ",\n    \"relative_max\": ");
        put_num(&b, doc->error_relative_max);
        put(&b, "\n  }");
    }
    if (doc->source) {
        put(&b, ",\n  \"source\": ");
        put_source(&b, doc->source, doc->source_preset);
    }
    if (doc->provenance) {
        char prov[64 * 1024];
        r = dm_prov_to_json(doc->provenance, prov, sizeof prov, err);
        if (r != DM_OK) {
            free(b.s);
            return r;
        }
        put(&b, ",\n  \"provenance\": %s", prov);
    }
    put(&b, "\n}\n");
    if (b.failed) {
        free(b.s);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "profile '%s': cannot build its JSON", p->name);
    }
    *json = b.s;
    return DM_OK;
}

dm_result dm_profile_write(const char *path, const dm_profile_doc *doc, dm_error *err)
{
    char *json = NULL;
    dm_result r = dm_profile_to_json(doc, &json, err);
    if (r != DM_OK) return r;
    dm_atomic_file af;
    r = dm_atomic_open(&af, path, err);
    if (r == DM_OK) {
        size_t n = strlen(json);
        if (fwrite(json, 1, n, af.fp) != n) {
            dm_atomic_abort(&af);
            r = dm_fail(err, DM_ERR_FILE_WRITE, "%s: short write of %zu bytes", path, n);
        } else {
            r = dm_atomic_commit(&af, err);
        }
    }
    free(json);
    return r;
}
