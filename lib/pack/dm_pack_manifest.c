/* dm_pack_manifest.c — the strict manifest reader (dm_pack_impl.h): unknown keys refused,
 * every error naming the JSON path, the value and what was expected. */
#include "pack/dm_pack_impl.h"

#include <errno.h>
#include <float.h>
#include <fcntl.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cJSON.h>

#include "core/dm_hash.h"
#include "core/dm_jread.h"
#include "pack/dm_pack_needs.h"
#include "core/dm_profile.h"
#include "core/dm_prov.h"

/* --- manifest reading ---------------------------------------------------------------- */

/* The strict reader (core/dm_jread.h) with where = "PACK: manifest". */
typedef dm_jread mctx;

static bool valid_name(const char *s)
{
    size_t n = strlen(s);
    if (n < 1 || n >= DM_PACK_NAME_SIZE) return false;
    for (const char *p = s; *p; ++p)
        if (!((*p >= 'a' && *p <= 'z') || (*p >= '0' && *p <= '9') || *p == '.' || *p == '_' || *p == '-'))
            return false;
    return true;
}

static bool mname(mctx *c, const cJSON *obj, const char *jpath, const char *key, char out[DM_PACK_NAME_SIZE])
{
    const char *s = dm_jread_string(c, obj, jpath, key);
    if (!s) return false;
    if (!valid_name(s)) {
        char p[160];
        snprintf(p, sizeof p, "%s.%s", jpath, key);
        return dm_jread_fail(c, DM_ERR_FORMAT, p, cJSON_GetObjectItemCaseSensitive(obj, key),
                     "a name of 1..63 characters from [a-z0-9._-]");
    }
    snprintf(out, DM_PACK_NAME_SIZE, "%s", s);
    return true;
}

/* A provenance object, validated by dm_prov_from_json, kept as compact JSON. */
static bool mprov(mctx *c, const cJSON *obj, const char *jpath, char **out)
{
    const cJSON *v = dm_jread_required(c, obj, jpath, "provenance", "an object");
    if (!v) return false;
    char p[160];
    snprintf(p, sizeof p, "%s.provenance", jpath);
    if (!cJSON_IsObject(v)) return dm_jread_fail(c, DM_ERR_FORMAT, p, v, "an object");
    char *text = cJSON_PrintUnformatted(v);
    if (!text) {
        c->r = dm_fail(c->err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", c->where);
        return false;
    }
    dm_provenance prov;
    char what[1200];
    snprintf(what, sizeof what, "%s %s", c->where, p);
    dm_result r = dm_prov_from_json(&prov, text, what, c->err);
    if (r != DM_OK) {
        cJSON_free(text);
        c->r = r;
        return false;
    }
    *out = text; /* cJSON's default allocator is malloc: freed with free() */
    return true;
}

/* v (at jp.key) as exactly n finite numbers (n < 0: none will do) into out, or an error. */
static bool mfloats(dm_jread *c, const cJSON *v, const char *jp, const char *key, int n, const char *want, float *out)
{
    char p[96];
    snprintf(p, sizeof p, "%s.%s", jp, key);
    if (n < 0 || !cJSON_IsArray(v) || cJSON_GetArraySize(v) != n) return dm_jread_fail(c, DM_ERR_FORMAT, p, v, want);
    for (int k = 0; k < n; ++k) {
        const cJSON *x = cJSON_GetArrayItem(v, k);
        if (!cJSON_IsNumber(x) || !isfinite(x->valuedouble) || !(fabs(x->valuedouble) <= FLT_MAX))
            return dm_jread_fail(c, DM_ERR_FORMAT, p, v, want);
        out[k] = (float)x->valuedouble;
    }
    return true;
}

/* The string at jp.key named by from_name (an enum value, < 0 when unknown): *out, or an
 * error naming the key, the value and `want`. */
static bool menum(dm_jread *c, const cJSON *j, const char *jp, const char *key, int (*from_name)(const char *),
                  const char *want, int *out)
{
    const char *v = dm_jread_string(c, j, jp, key);
    if (!v) return false;
    *out = from_name(v);
    if (*out >= 0) return true;
    char p[96];
    snprintf(p, sizeof p, "%s.%s", jp, key);
    return dm_jread_fail(c, DM_ERR_FORMAT, p, cJSON_GetObjectItemCaseSensitive(j, key), want);
}

static bool parse_entry(mctx *c, const cJSON *j, int index, dm_pack_entry *e)
{
    static const char *const common[] = {"name", "kind", "offset", "size", "xxh3", "provenance", NULL};
    static const char *const tex_keys[] = {"name", "kind",  "offset", "size",   "xxh3",     "provenance",
                                           "format", "width", "height", "layers", "levels", "channels",
                                           "layer_values", "t_range", NULL};
    static const char *const vtx_keys[] = {"name", "kind", "offset", "size", "xxh3", "provenance",
                                           "vertex_count", "stride", "attributes", NULL};
    static const char *const idx_keys[] = {"name", "kind", "offset", "size", "xxh3", "provenance",
                                           "index_count", "type", "primitive", "vertices", NULL};
    static const char *const sh_keys[] = {"name", "kind", "offset", "size", "xxh3", "provenance", "sh_order", NULL};
    char jp[64];
    snprintf(jp, sizeof jp, "$.entries[%d]", index);
    memset(e, 0, sizeof *e);
    if (!cJSON_IsObject(j)) return dm_jread_fail(c, DM_ERR_FORMAT, jp, j, "an object");
    if (!mname(c, j, jp, "name", e->name)) return false;
    int k;
    if (!menum(c, j, jp, "kind", dm_pack_kind_from_name,
               "one of texture, mesh.vertices, mesh.indices, env.sh, profile, scene", &k))
        return false;
    e->kind = (dm_pack_kind)k;
    const char *const *keys = e->kind == DM_PACK_TEXTURE         ? tex_keys
                              : e->kind == DM_PACK_MESH_VERTICES ? vtx_keys
                              : e->kind == DM_PACK_MESH_INDICES  ? idx_keys
                              : e->kind == DM_PACK_ENV_SH        ? sh_keys
                                                                 : common;
    if (!dm_jread_keys(c, j, jp, keys)) return false;
    int64_t off, size;
    if (!dm_jread_int64(c, j, jp, "offset", 0, (int64_t)1 << 52, &off) || !dm_jread_int64(c, j, jp, "size", 0, (int64_t)1 << 52, &size))
        return false;
    e->offset = (uint64_t)off;
    e->size = (uint64_t)size;
    const char *hex = dm_jread_string(c, j, jp, "xxh3");
    if (!hex) return false;
    char *end = NULL;
    bool hex_ok = strlen(hex) == 16;
    for (const char *p = hex; hex_ok && *p; ++p) hex_ok = (*p >= '0' && *p <= '9') || (*p >= 'a' && *p <= 'f');
    if (!hex_ok) {
        char p[96];
        snprintf(p, sizeof p, "%s.xxh3", jp);
        return dm_jread_fail(c, DM_ERR_FORMAT, p, cJSON_GetObjectItemCaseSensitive(j, "xxh3"), "16 lowercase hex digits");
    }
    e->xxh3 = strtoull(hex, &end, 16);
    if (!mprov(c, j, jp, &e->provenance_json)) return false;

    if (e->kind == DM_PACK_TEXTURE) {
        int fi;
        if (!menum(c, j, jp, "format", dm_tex_format_from_name,
                   "one of r8, rg8, rgba8, rgba8_srgb, r16f, rg16f, rgba16f, r32f, rg32f, rgba32f", &fi))
            return false;
        e->format = (dm_tex_format)fi;
        if (!dm_jread_int32(c, j, jp, "width", 1, DM_PACK_TEXTURE_SIZE_MAX, &e->width) ||
            !dm_jread_int32(c, j, jp, "height", 1, DM_PACK_TEXTURE_SIZE_MAX, &e->height) ||
            !dm_jread_int32(c, j, jp, "layers", 1, DM_PACK_LAYERS_MAX, &e->layers) ||
            !dm_jread_int32(c, j, jp, "levels", 1, 15, &e->levels))
            return false;
        const cJSON *ch = cJSON_GetObjectItemCaseSensitive(j, "channels");
        if (ch) {
            char p[96];
            snprintf(p, sizeof p, "%s.channels", jp);
            int n = cJSON_IsArray(ch) ? cJSON_GetArraySize(ch) : -1;
            if (n < 1 || n > DM_PACK_MAX_CHANNELS) return dm_jread_fail(c, DM_ERR_FORMAT, p, ch, "an array of 1..4 names");
            for (int q = 0; q < n; ++q) {
                const cJSON *s = cJSON_GetArrayItem(ch, q);
                if (!cJSON_IsString(s) || !*s->valuestring || strlen(s->valuestring) >= DM_PACK_CHANNEL_NAME_SIZE)
                    return dm_jread_fail(c, DM_ERR_FORMAT, p, ch, "an array of short non-empty names");
                snprintf(e->channels[q], DM_PACK_CHANNEL_NAME_SIZE, "%s", s->valuestring);
            }
            e->channel_count = n;
        }
        const cJSON *lv = cJSON_GetObjectItemCaseSensitive(j, "layer_values");
        if (lv && !mfloats(c, lv, jp, "layer_values", e->layers > DM_PACK_LAYER_VALUES_MAX ? -1 : e->layers,
                           "finite numbers, one per layer (at most 16 layers)", e->layer_values))
            return false;
        e->layer_value_count = lv ? e->layers : 0;
        const cJSON *tr = cJSON_GetObjectItemCaseSensitive(j, "t_range");
        if (tr && !mfloats(c, tr, jp, "t_range", 2, "[first, last]: two finite numbers", e->t_range)) return false;
        e->has_t_range = tr != NULL;
    } else if (e->kind == DM_PACK_MESH_VERTICES) {
        if (!dm_jread_int64(c, j, jp, "vertex_count", 1, (int64_t)1 << 32, &e->vertex_count) ||
            !dm_jread_int32(c, j, jp, "stride", 4, 256, &e->stride))
            return false;
        const cJSON *at = dm_jread_required(c, j, jp, "attributes", "an array of attributes");
        if (!at) return false;
        char p[96];
        snprintf(p, sizeof p, "%s.attributes", jp);
        int n = cJSON_IsArray(at) ? cJSON_GetArraySize(at) : -1;
        if (n < 1 || n > DM_PACK_MAX_ATTRIBUTES) return dm_jread_fail(c, DM_ERR_FORMAT, p, at, "an array of 1..8 attributes");
        for (int q = 0; q < n; ++q) {
            static const char *const akeys[] = {"name", "offset", "components", "type", NULL};
            const cJSON *a = cJSON_GetArrayItem(at, q);
            char ap[128];
            snprintf(ap, sizeof ap, "%s[%d]", p, q);
            if (!cJSON_IsObject(a)) return dm_jread_fail(c, DM_ERR_FORMAT, ap, a, "an object");
            if (!dm_jread_keys(c, a, ap, akeys)) return false;
            const char *an = dm_jread_string(c, a, ap, "name"), *ty;
            if (!an) return false;
            if (!*an || strlen(an) >= DM_PACK_CHANNEL_NAME_SIZE)
                return dm_jread_fail(c, DM_ERR_FORMAT, ap, a, "an attribute with a short non-empty name");
            snprintf(e->attributes[q].name, DM_PACK_CHANNEL_NAME_SIZE, "%s", an);
            if (!dm_jread_int32(c, a, ap, "offset", 0, 252, &e->attributes[q].offset) ||
                !dm_jread_int32(c, a, ap, "components", 1, 4, &e->attributes[q].components) || !(ty = dm_jread_string(c, a, ap, "type")))
                return false;
            if (strcmp(ty, "float32") != 0)
                return dm_jread_fail(c, DM_ERR_UNSUPPORTED, ap, a, "an attribute of type \"float32\"");
        }
        e->attribute_count = n;
    } else if (e->kind == DM_PACK_MESH_INDICES) {
        const char *ty, *prim;
        if (!dm_jread_int64(c, j, jp, "index_count", 3, (int64_t)3 << 32, &e->index_count) || !(ty = dm_jread_string(c, j, jp, "type")) ||
            !(prim = dm_jread_string(c, j, jp, "primitive")) || !mname(c, j, jp, "vertices", e->vertices))
            return false;
        char p[96];
        snprintf(p, sizeof p, "%s.type", jp);
        if (strcmp(ty, "uint32") != 0)
            return dm_jread_fail(c, DM_ERR_UNSUPPORTED, p, cJSON_GetObjectItemCaseSensitive(j, "type"), "\"uint32\"");
        snprintf(p, sizeof p, "%s.primitive", jp);
        if (strcmp(prim, "triangles") != 0)
            return dm_jread_fail(c, DM_ERR_UNSUPPORTED, p, cJSON_GetObjectItemCaseSensitive(j, "primitive"), "\"triangles\"");
    } else if (e->kind == DM_PACK_ENV_SH) {
        if (!dm_jread_int32(c, j, jp, "sh_order", 0, DM_PACK_SH_ORDER_MAX, &e->sh_order)) return false;
    }
    return true;
}

/* --- contents ----------------------------------------------------------------------- */

dm_result dm_pack_manifest_parse(dm_pack *pack, const uint8_t *bytes, uint64_t size, dm_error *err)
{
    const char *what = pack->what;
    struct { uint64_t manifest_size; } h = {size};
    pack->manifest = malloc(h.manifest_size + 1);
    if (!pack->manifest) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", what);
    memcpy(pack->manifest, bytes, h.manifest_size);
    pack->manifest[h.manifest_size] = '\0';
    if (strlen(pack->manifest) != h.manifest_size)
        return dm_fail(err, DM_ERR_FORMAT, "%s: manifest holds a NUL byte, expected JSON text", what);
    cJSON *root = cJSON_Parse(pack->manifest);
    if (!root) return dm_fail(err, DM_ERR_FORMAT, "%s: manifest is not valid JSON", what);
    char where[1100];
    snprintf(where, sizeof where, "%s: manifest", what);
    mctx c = {where, err, DM_OK};
    static const char *const top[] = {"format", "version", "provenance", "entries", NULL};
    bool ok = cJSON_IsObject(root) ? dm_jread_keys(&c, root, "$", top) : dm_jread_fail(&c, DM_ERR_FORMAT, "$", root, "an object");
    const char *fmt = ok ? dm_jread_string(&c, root, "$", "format") : NULL;
    int64_t ver = 0;
    ok = ok && fmt;
    if (ok && strcmp(fmt, "dermis-pack") != 0)
        ok = dm_jread_fail(&c, DM_ERR_FORMAT, "$.format", cJSON_GetObjectItemCaseSensitive(root, "format"), "\"dermis-pack\"");
    ok = ok && dm_jread_int64(&c, root, "$", "version", DM_PACK_VERSION, DM_PACK_VERSION, &ver) &&
         mprov(&c, root, "$", &pack->provenance_json);
    const cJSON *ents = ok ? dm_jread_required(&c, root, "$", "entries", "an array of entries") : NULL;
    ok = ok && ents;
    if (ok && (!cJSON_IsArray(ents) || cJSON_GetArraySize(ents) > DM_PACK_ENTRIES_MAX))
        ok = dm_jread_fail(&c, DM_ERR_FORMAT, "$.entries", ents, "an array of at most 1024 entries");
    if (ok) {
        int n = cJSON_GetArraySize(ents);
        pack->entries = calloc((size_t)(n ? n : 1), sizeof *pack->entries);
        if (!pack->entries) {
            cJSON_Delete(root);
            return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", what);
        }
        int k = 0;
        for (const cJSON *j = ents->child; j && ok; j = j->next, ++k) {
            ok = parse_entry(&c, j, k, &pack->entries[k]);
            pack->entry_count = k + 1;
        }
    }
    cJSON_Delete(root);
    if (!ok) return c.r;
    return DM_OK;
}
