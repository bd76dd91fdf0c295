/* dm_jread.c — the strict JSON reader (dm_jread.h). */
#include "core/dm_jread.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* The JSON text of a value, shortened for messages. */
static void value_text(const cJSON *v, char *out, size_t out_size)
{
    char *t = v ? cJSON_PrintUnformatted(v) : NULL;
    if (!t) {
        snprintf(out, out_size, "(nothing)");
        return;
    }
    if (strlen(t) > 60)
        snprintf(out, out_size, "%.57s...", t);
    else
        snprintf(out, out_size, "%s", t);
    cJSON_free(t);
}

void dm_jread_path(char out[DM_JPATH_SIZE], const char *parent, const char *key)
{
    if (snprintf(out, DM_JPATH_SIZE, "%s.%s", parent, key) >= DM_JPATH_SIZE) out[DM_JPATH_SIZE - 1] = '\0';
}

bool dm_jread_fail(dm_jread *c, dm_result code, const char *jpath, const cJSON *v, const char *expected)
{
    char vt[80];
    value_text(v, vt, sizeof vt);
    c->r = dm_fail(c->err, code, "%s: %s: %s is not %s", c->where, jpath, vt, expected);
    return false;
}

bool dm_jread_keys(dm_jread *c, const cJSON *obj, const char *jpath, const char *const *allowed)
{
    for (const cJSON *it = obj->child; it; it = it->next) {
        bool ok = false;
        for (const char *const *a = allowed; *a; ++a)
            if (strcmp(it->string, *a) == 0) ok = true;
        if (!ok) {
            char list[512] = "";
            size_t n = 0;
            for (const char *const *a = allowed; *a && n < sizeof list; ++a)
                n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", a == allowed ? "" : ", ", *a);
            c->r = dm_fail(c->err, DM_ERR_FORMAT, "%s: %s.%s: unknown key, expected one of: %s", c->where, jpath,
                           it->string, list);
            return false;
        }
        for (const cJSON *jt = it->next; jt; jt = jt->next)
            if (strcmp(it->string, jt->string) == 0) {
                c->r = dm_fail(c->err, DM_ERR_FORMAT, "%s: %s.%s: key given twice, expected once", c->where, jpath,
                               it->string);
                return false;
            }
    }
    return true;
}

const cJSON *dm_jread_get(const cJSON *obj, const char *key)
{
    return cJSON_GetObjectItemCaseSensitive(obj, key);
}

const cJSON *dm_jread_required(dm_jread *c, const cJSON *obj, const char *jpath, const char *key,
                               const char *expected)
{
    const cJSON *v = dm_jread_get(obj, key);
    if (!v) c->r = dm_fail(c->err, DM_ERR_FORMAT, "%s: %s.%s: missing, expected %s", c->where, jpath, key, expected);
    return v;
}

const cJSON *dm_jread_object(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, bool required,
                             bool *ok)
{
    const cJSON *v = dm_jread_get(obj, key);
    *ok = true;
    if (!v) {
        if (required) *ok = dm_jread_required(c, obj, jpath, key, "an object") != NULL;
        return NULL;
    }
    if (!cJSON_IsObject(v)) {
        char p[DM_JPATH_SIZE];
        dm_jread_path(p, jpath, key);
        *ok = dm_jread_fail(c, DM_ERR_FORMAT, p, v, "an object");
        return NULL;
    }
    return v;
}

const char *dm_jread_string(dm_jread *c, const cJSON *obj, const char *jpath, const char *key)
{
    const cJSON *v = dm_jread_required(c, obj, jpath, key, "a string");
    if (!v) return NULL;
    if (!cJSON_IsString(v)) {
        char p[DM_JPATH_SIZE];
        dm_jread_path(p, jpath, key);
        dm_jread_fail(c, DM_ERR_FORMAT, p, v, "a string");
        return NULL;
    }
    return v->valuestring;
}

/* v an integer in [lo, hi] (jpath.key names it in the message). */
static bool integer(dm_jread *c, const cJSON *v, const char *jpath, const char *key, double lo, double hi,
                    const char *want, double *out)
{
    char p[DM_JPATH_SIZE];
    dm_jread_path(p, jpath, key);
    if (!cJSON_IsNumber(v)) return dm_jread_fail(c, DM_ERR_FORMAT, p, v, want);
    double d = v->valuedouble;
    if (!isfinite(d) || d != floor(d) || d < lo || d > hi) return dm_jread_fail(c, DM_ERR_RANGE, p, v, want);
    *out = d;
    return true;
}

bool dm_jread_int64(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, int64_t lo, int64_t hi,
                    int64_t *out)
{
    char want[96];
    snprintf(want, sizeof want, "an integer in [%" PRId64 ", %" PRId64 "]", lo, hi);
    const cJSON *v = dm_jread_required(c, obj, jpath, key, want);
    double d;
    if (!v || !integer(c, v, jpath, key, (double)lo, (double)hi, want, &d)) return false;
    *out = (int64_t)d;
    return true;
}

bool dm_jread_int32(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, int lo, int hi, int *out)
{
    int64_t v;
    if (!dm_jread_int64(c, obj, jpath, key, lo, hi, &v)) return false;
    *out = (int)v;
    return true;
}

bool dm_jread_double_opt(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, double lo, double hi,
                         double *out)
{
    const cJSON *v = dm_jread_get(obj, key);
    if (!v) return true;
    char p[DM_JPATH_SIZE], want[96];
    dm_jread_path(p, jpath, key);
    snprintf(want, sizeof want, "a number in [%g, %g]", lo, hi);
    if (!cJSON_IsNumber(v)) return dm_jread_fail(c, DM_ERR_FORMAT, p, v, want);
    if (!isfinite(v->valuedouble) || v->valuedouble < lo || v->valuedouble > hi)
        return dm_jread_fail(c, DM_ERR_RANGE, p, v, want);
    *out = v->valuedouble;
    return true;
}

bool dm_jread_float_opt(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, double lo, double hi,
                        float *out)
{
    double d = *out;
    if (!dm_jread_double_opt(c, obj, jpath, key, lo, hi, &d)) return false;
    *out = (float)d;
    return true;
}

bool dm_jread_int_opt(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, int lo, int hi,
                      bool odd_only, int *out)
{
    const cJSON *v = dm_jread_get(obj, key);
    if (!v) return true;
    char want[96];
    snprintf(want, sizeof want, "%s integer in [%d, %d]", odd_only ? "an odd" : "an", lo, hi);
    double d;
    if (!integer(c, v, jpath, key, lo, hi, want, &d)) return false;
    if (odd_only && fmod(d, 2.0) == 0.0) {
        char p[DM_JPATH_SIZE];
        dm_jread_path(p, jpath, key);
        return dm_jread_fail(c, DM_ERR_RANGE, p, v, want);
    }
    *out = (int)d;
    return true;
}

bool dm_jread_bool_opt(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, bool *out)
{
    const cJSON *v = dm_jread_get(obj, key);
    if (!v) return true;
    char p[DM_JPATH_SIZE];
    dm_jread_path(p, jpath, key);
    if (!cJSON_IsBool(v)) return dm_jread_fail(c, DM_ERR_FORMAT, p, v, "true or false");
    *out = cJSON_IsTrue(v);
    return true;
}

bool dm_jread_vec3_opt(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, double lo, double hi,
                       bool nonzero, float out[3])
{
    const cJSON *v = dm_jread_get(obj, key);
    if (!v) return true;
    char p[DM_JPATH_SIZE], want[128];
    dm_jread_path(p, jpath, key);
    snprintf(want, sizeof want, "an array of 3 numbers in [%g, %g]%s", lo, hi, nonzero ? ", not all zero" : "");
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3) return dm_jread_fail(c, DM_ERR_FORMAT, p, v, want);
    float t[3];
    double len2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        const cJSON *x = cJSON_GetArrayItem(v, k);
        if (!cJSON_IsNumber(x)) return dm_jread_fail(c, DM_ERR_FORMAT, p, v, want);
        double d = x->valuedouble;
        if (!isfinite(d) || d < lo || d > hi) return dm_jread_fail(c, DM_ERR_RANGE, p, v, want);
        t[k] = (float)d;
        len2 += d * d;
    }
    if (nonzero && !(len2 > 1e-12)) return dm_jread_fail(c, DM_ERR_RANGE, p, v, want);
    memcpy(out, t, sizeof t);
    return true;
}
