#include "core/dm_prov.h"

#include <assert.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include <cJSON.h>

#include "core/dm_jread.h"

#include "core/dm_version.h"

static void copy_str(char *dst, size_t dst_size, const char *src)
{
    snprintf(dst, dst_size, "%s", src ? src : "");
}

void dm_prov_init(dm_provenance *p, const char *tool)
{
    assert(p && tool);
    memset(p, 0, sizeof *p);
    copy_str(p->tool, sizeof p->tool, tool);
    copy_str(p->version, sizeof p->version, DM_VERSION);
}

static dm_param *add(dm_provenance *p, const char *name, dm_param_type type)
{
    assert(p && name && p->param_count < DM_PROV_PARAM_MAX);
    dm_param *q = &p->params[p->param_count++];
    memset(q, 0, sizeof *q);
    copy_str(q->name, sizeof q->name, name);
    q->type = type;
    return q;
}

void dm_prov_add_int(dm_provenance *p, const char *name, int64_t value)
{
    dm_param *q = add(p, name, DM_PARAM_INT);
    q->i = value;
    q->d = (double)value;
}

void dm_prov_add_double(dm_provenance *p, const char *name, double value)
{
    add(p, name, DM_PARAM_DOUBLE)->d = value;
}

void dm_prov_add_string(dm_provenance *p, const char *name, const char *value)
{
    dm_param *q = add(p, name, DM_PARAM_STRING);
    copy_str(q->s, sizeof q->s, value);
}

const dm_param *dm_prov_find(const dm_provenance *p, const char *name)
{
    for (int k = 0; k < p->param_count; ++k)
        if (strcmp(p->params[k].name, name) == 0) return &p->params[k];
    return NULL;
}

dm_result dm_prov_to_json(const dm_provenance *p, char *out, size_t out_size, dm_error *err)
{
    /* Written by hand rather than through cJSON_Print so doubles keep 17 digits. */
    size_t n = 0;
    int w;
#define APPEND(...)                                                               \
    do {                                                                          \
        w = snprintf(out + n, n < out_size ? out_size - n : 0, __VA_ARGS__);      \
        if (w < 0) return dm_fail(err, DM_ERR_INTERNAL, "provenance: format error"); \
        n += (size_t)w;                                                           \
    } while (0)
    cJSON *s;
    char *txt;
    APPEND("{\"tool\":");
    s = cJSON_CreateString(p->tool); txt = cJSON_PrintUnformatted(s); APPEND("%s", txt); cJSON_free(txt); cJSON_Delete(s);
    APPEND(",\"version\":");
    s = cJSON_CreateString(p->version); txt = cJSON_PrintUnformatted(s); APPEND("%s", txt); cJSON_free(txt); cJSON_Delete(s);
    APPEND(",\"input_hash\":");
    s = cJSON_CreateString(p->input_hash); txt = cJSON_PrintUnformatted(s); APPEND("%s", txt); cJSON_free(txt); cJSON_Delete(s);
    APPEND(",\"params\":{");
    for (int k = 0; k < p->param_count; ++k) {
        const dm_param *q = &p->params[k];
        APPEND("%s\"%s\":", k ? "," : "", q->name);
        if (q->type == DM_PARAM_INT) {
            APPEND("%lld", (long long)q->i);
        } else if (q->type == DM_PARAM_DOUBLE) {
            if (!isfinite(q->d)) {
                APPEND("null");
            } else {
                char num[40];
                snprintf(num, sizeof num, "%.17g", q->d);
                APPEND("%s%s", num, strpbrk(num, ".eE") ? "" : ".0");
            }
        } else {
            s = cJSON_CreateString(q->s); txt = cJSON_PrintUnformatted(s); APPEND("%s", txt); cJSON_free(txt); cJSON_Delete(s);
        }
    }
    APPEND("}}");
#undef APPEND
    if (n >= out_size) return dm_fail(err, DM_ERR_RANGE, "provenance: %zu bytes do not fit in %zu", n + 1, out_size);
    return DM_OK;
}

/* One $.params member into p: a string, a number (integral values read back as ints, with .d
 * set as well: JSON does not keep int from double, so parameters compare through .d) or null
 * (NaN). Names are [a-z0-9_], shorter than DM_PROV_NAME_SIZE: what the writers make, and what
 * prints back as JSON without escaping. */
static bool read_param(dm_jread *c, const cJSON *it, dm_provenance *p)
{
    char jp[DM_JPATH_SIZE];
    dm_jread_path(jp, "$.params", it->string ? it->string : "");
    size_t len = it->string ? strlen(it->string) : 0;
    bool ok = len > 0 && len < DM_PROV_NAME_SIZE;
    for (size_t i = 0; ok && i < len; ++i) {
        char ch = it->string[i];
        ok = (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_';
    }
    if (!ok) {
        char want[96];
        snprintf(want, sizeof want, "a parameter named by [a-z0-9_], 1..%d characters", DM_PROV_NAME_SIZE - 1);
        return dm_jread_fail(c, DM_ERR_FORMAT, jp, it, want);
    }
    if (p->param_count >= DM_PROV_PARAM_MAX) {
        char want[64];
        snprintf(want, sizeof want, "within the first %d parameters", DM_PROV_PARAM_MAX);
        return dm_jread_fail(c, DM_ERR_RANGE, jp, it, want);
    }
    if (cJSON_IsString(it)) {
        dm_prov_add_string(p, it->string, it->valuestring);
    } else if (cJSON_IsNumber(it)) {
        double d = it->valuedouble;
        if (d == floor(d) && fabs(d) < 9007199254740992.0)
            dm_prov_add_int(p, it->string, (int64_t)d);
        else
            dm_prov_add_double(p, it->string, d);
    } else if (cJSON_IsNull(it)) {
        dm_prov_add_double(p, it->string, NAN);
    } else {
        return dm_jread_fail(c, DM_ERR_FORMAT, jp, it, "a string, a number or null");
    }
    return true;
}

dm_result dm_prov_from_json(dm_provenance *p, const char *json, const char *what, dm_error *err)
{
    cJSON *root = cJSON_Parse(json);
    dm_result r = dm_prov_from_cjson(p, root, what, err);
    cJSON_Delete(root);
    return r;
}

dm_result dm_prov_from_cjson(dm_provenance *p, const cJSON *root, const char *what, dm_error *err)
{
    static const char *const keys[] = {"tool", "version", "input_hash", "params", NULL};
    memset(p, 0, sizeof *p);
    char where[320];
    snprintf(where, sizeof where, "%s: provenance", what);
    dm_jread c = {where, err, DM_OK};
    bool ok = cJSON_IsObject(root) ? dm_jread_keys(&c, root, "$", keys)
                                   : dm_jread_fail(&c, DM_ERR_FORMAT, "$", NULL, "a JSON object");
    const char *tool = ok ? dm_jread_string(&c, root, "$", "tool") : NULL;
    const char *ver = tool ? dm_jread_string(&c, root, "$", "version") : NULL;
    const cJSON *hash = ver ? dm_jread_get(root, "input_hash") : NULL;
    ok = ok && tool && ver;
    if (ok && hash && !cJSON_IsString(hash)) ok = dm_jread_fail(&c, DM_ERR_FORMAT, "$.input_hash", hash, "a string");
    bool have = false;
    const cJSON *params = ok ? dm_jread_object(&c, root, "$", "params", true, &have) : NULL;
    ok = ok && have && params;
    if (ok) {
        copy_str(p->tool, sizeof p->tool, tool);
        copy_str(p->version, sizeof p->version, ver);
        if (hash) copy_str(p->input_hash, sizeof p->input_hash, hash->valuestring);
    }
    for (const cJSON *it = ok ? params->child : NULL; it && ok; it = it->next) ok = read_param(&c, it, p);
    if (!ok) {
        memset(p, 0, sizeof *p);
        return c.r;
    }
    return DM_OK;
}
