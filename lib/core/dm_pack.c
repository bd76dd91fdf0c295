#include "core/dm_pack.h"

#include <errno.h>
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
#include "core/dm_pack_needs.h"
#include "core/dm_profile.h"
#include "core/dm_prov.h"

/* --- names and formats ------------------------------------------------------------- */

static const char *const kind_names[DM_PACK_KIND_COUNT] = {
    "texture", "mesh.vertices", "mesh.indices", "env.sh", "profile", "scene",
};

const char *dm_pack_kind_name(dm_pack_kind k)
{
    return (unsigned)k < DM_PACK_KIND_COUNT ? kind_names[k] : NULL;
}

int dm_pack_kind_from_name(const char *name)
{
    for (int k = 0; k < DM_PACK_KIND_COUNT; ++k)
        if (name && strcmp(name, kind_names[k]) == 0) return k;
    return -1;
}

static const dm_tex_format_info formats[DM_TEX_FORMAT_COUNT] = {
    {"r8", 1, 1, false, false},      {"rg8", 2, 1, false, false},      {"rgba8", 4, 1, false, false},
    {"rgba8_srgb", 4, 1, false, true}, {"r16f", 1, 2, true, false},    {"rg16f", 2, 2, true, false},
    {"rgba16f", 4, 2, true, false},  {"r32f", 1, 4, true, false},      {"rg32f", 2, 4, true, false},
    {"rgba32f", 4, 4, true, false},
};

const dm_tex_format_info *dm_tex_format_get(dm_tex_format f)
{
    return (unsigned)f < DM_TEX_FORMAT_COUNT ? &formats[f] : NULL;
}

int dm_tex_format_from_name(const char *name)
{
    for (int f = 0; f < DM_TEX_FORMAT_COUNT; ++f)
        if (name && strcmp(name, formats[f].name) == 0) return f;
    return -1;
}

void dm_pack_hex64(uint64_t v, char out[17])
{
    snprintf(out, 17, "%016" PRIx64, v);
}

/* --- header ------------------------------------------------------------------------- */

static void put32(uint8_t *p, uint32_t v)
{
    for (int k = 0; k < 4; ++k) p[k] = (uint8_t)(v >> (8 * k));
}
static void put64(uint8_t *p, uint64_t v)
{
    for (int k = 0; k < 8; ++k) p[k] = (uint8_t)(v >> (8 * k));
}
static uint32_t get32(const uint8_t *p)
{
    uint32_t v = 0;
    for (int k = 3; k >= 0; --k) v = (v << 8) | p[k];
    return v;
}
static uint64_t get64(const uint8_t *p)
{
    uint64_t v = 0;
    for (int k = 7; k >= 0; --k) v = (v << 8) | p[k];
    return v;
}

void dm_pack_header_encode(const dm_pack_header *h, uint8_t out[DM_PACK_HEADER_SIZE])
{
    memcpy(out, DM_PACK_MAGIC, 8);
    put32(out + 8, h->version);
    put32(out + 12, h->flags);
    put64(out + 16, h->file_size);
    put64(out + 24, h->manifest_offset);
    put64(out + 32, h->manifest_size);
    put64(out + 40, h->blobs_offset);
    put64(out + 48, h->reserved);
    put64(out + 56, h->checksum);
}

uint64_t dm_pack_header_checksum(const uint8_t header[DM_PACK_HEADER_SIZE], const void *manifest,
                                 size_t manifest_size)
{
    return dm_hash64_pair(header, 56, manifest, manifest_size);
}

/* --- sizes -------------------------------------------------------------------------- */

static uint64_t level_dim(int size, int level)
{
    uint64_t d = (uint64_t)size >> level;
    return d ? d : 1;
}

uint64_t dm_pack_texture_level_size(const dm_pack_entry *e, int level)
{
    const dm_tex_format_info *f = dm_tex_format_get(e->format);
    if (!f) return 0;
    return level_dim(e->width, level) * level_dim(e->height, level) * (uint64_t)e->layers *
           (uint64_t)(f->components * f->component_size);
}

uint64_t dm_pack_texture_level_offset(const dm_pack_entry *e, int level)
{
    uint64_t off = 0;
    for (int l = 0; l < level; ++l) off += dm_pack_texture_level_size(e, l);
    return off;
}

static int max_levels(int w, int h)
{
    int m = w > h ? w : h, n = 1;
    while (m > 1) {
        m >>= 1;
        ++n;
    }
    return n;
}

dm_result dm_pack_entry_expected_size(const dm_pack_entry *e, const char *what, uint64_t *size, dm_error *err)
{
    *size = 0;
    switch (e->kind) {
    case DM_PACK_TEXTURE: {
        if (!dm_tex_format_get(e->format))
            return dm_fail(err, DM_ERR_FORMAT, "%s: format %d, expected a known texture format", what, (int)e->format);
        if (e->width < 1 || e->width > DM_PACK_TEXTURE_SIZE_MAX || e->height < 1 ||
            e->height > DM_PACK_TEXTURE_SIZE_MAX)
            return dm_fail(err, DM_ERR_RANGE, "%s: size %dx%d, expected 1..%d each way", what, e->width, e->height,
                           DM_PACK_TEXTURE_SIZE_MAX);
        if (e->layers < 1 || e->layers > DM_PACK_LAYERS_MAX)
            return dm_fail(err, DM_ERR_RANGE, "%s: %d layers, expected 1..%d", what, e->layers, DM_PACK_LAYERS_MAX);
        int lm = max_levels(e->width, e->height);
        if (e->levels < 1 || e->levels > lm)
            return dm_fail(err, DM_ERR_RANGE, "%s: %d levels, expected 1..%d for %dx%d", what, e->levels, lm, e->width,
                           e->height);
        if (e->channel_count != 0 && e->channel_count != dm_tex_format_get(e->format)->components)
            return dm_fail(err, DM_ERR_RANGE, "%s: %d channel names for format %s, expected %d", what,
                           e->channel_count, dm_tex_format_get(e->format)->name,
                           dm_tex_format_get(e->format)->components);
        *size = dm_pack_texture_level_offset(e, e->levels);
        return DM_OK;
    }
    case DM_PACK_MESH_VERTICES: {
        if (e->vertex_count < 1 || e->vertex_count > ((int64_t)1 << 32))
            return dm_fail(err, DM_ERR_RANGE, "%s: vertex_count %" PRId64 ", expected 1..2^32", what, e->vertex_count);
        if (e->stride < 4 || e->stride > 256 || e->stride % 4)
            return dm_fail(err, DM_ERR_RANGE, "%s: stride %d, expected a multiple of 4 in [4, 256]", what, e->stride);
        if (e->attribute_count < 1 || e->attribute_count > DM_PACK_MAX_ATTRIBUTES)
            return dm_fail(err, DM_ERR_RANGE, "%s: %d attributes, expected 1..%d", what, e->attribute_count,
                           DM_PACK_MAX_ATTRIBUTES);
        for (int a = 0; a < e->attribute_count; ++a) {
            const dm_vertex_attribute *at = &e->attributes[a];
            if (at->components < 1 || at->components > 4 || at->offset < 0 || at->offset % 4 ||
                at->offset + 4 * at->components > e->stride)
                return dm_fail(err, DM_ERR_RANGE,
                               "%s: attribute \"%s\" at offset %d with %d components, expected 1..4 float32 "
                               "values inside the %d-byte stride",
                               what, at->name, at->offset, at->components, e->stride);
        }
        *size = (uint64_t)e->vertex_count * (uint64_t)e->stride;
        return DM_OK;
    }
    case DM_PACK_MESH_INDICES:
        if (e->index_count < 3 || e->index_count % 3 || e->index_count > ((int64_t)3 << 32))
            return dm_fail(err, DM_ERR_RANGE, "%s: index_count %" PRId64 ", expected a positive multiple of 3", what,
                           e->index_count);
        if (!e->vertices[0])
            return dm_fail(err, DM_ERR_FORMAT, "%s: names no vertices entry, expected one", what);
        *size = (uint64_t)e->index_count * 4u;
        return DM_OK;
    case DM_PACK_ENV_SH:
        if (e->sh_order < 0 || e->sh_order > DM_PACK_SH_ORDER_MAX)
            return dm_fail(err, DM_ERR_RANGE, "%s: sh_order %d, expected 0..%d", what, e->sh_order,
                           DM_PACK_SH_ORDER_MAX);
        *size = (uint64_t)(e->sh_order + 1) * (uint64_t)(e->sh_order + 1) * 3u * 4u;
        return DM_OK;
    case DM_PACK_PROFILE:
    case DM_PACK_SCENE:
        *size = e->size; /* any JSON text; checked by parsing */
        if (e->size < 2) return dm_fail(err, DM_ERR_RANGE, "%s: %" PRIu64 " bytes, expected JSON text", what, e->size);
        return DM_OK;
    case DM_PACK_KIND_COUNT: break;
    }
    return dm_fail(err, DM_ERR_FORMAT, "%s: kind %d, expected a known kind", what, (int)e->kind);
}

/* --- manifest reading ---------------------------------------------------------------- */

typedef struct mctx {
    const char *what;
    dm_error *err;
    dm_result r;
} mctx;

static bool mfail(mctx *c, dm_result code, const char *jpath, const cJSON *v, const char *expected)
{
    char vt[80] = "(nothing)";
    char *t = v ? cJSON_PrintUnformatted(v) : NULL;
    if (t) {
        if (strlen(t) > 60)
            snprintf(vt, sizeof vt, "%.57s...", t);
        else
            snprintf(vt, sizeof vt, "%s", t);
        cJSON_free(t);
    }
    c->r = dm_fail(c->err, code, "%s: manifest %s: %s is not %s", c->what, jpath, vt, expected);
    return false;
}

static bool mkeys(mctx *c, const cJSON *obj, const char *jpath, const char *const *allowed)
{
    for (const cJSON *it = obj->child; it; it = it->next) {
        bool ok = false;
        for (const char *const *a = allowed; *a; ++a)
            if (strcmp(it->string, *a) == 0) ok = true;
        if (!ok) {
            c->r = dm_fail(c->err, DM_ERR_FORMAT, "%s: manifest %s.%s: unknown key", c->what, jpath, it->string);
            return false;
        }
        for (const cJSON *jt = it->next; jt; jt = jt->next)
            if (strcmp(it->string, jt->string) == 0) {
                c->r = dm_fail(c->err, DM_ERR_FORMAT, "%s: manifest %s.%s: key given twice", c->what, jpath,
                               it->string);
                return false;
            }
    }
    return true;
}

static const cJSON *mreq(mctx *c, const cJSON *obj, const char *jpath, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v) c->r = dm_fail(c->err, DM_ERR_FORMAT, "%s: manifest %s.%s: missing, expected it", c->what, jpath, key);
    return v;
}

static bool mint(mctx *c, const cJSON *obj, const char *jpath, const char *key, int64_t lo, int64_t hi, int64_t *out)
{
    const cJSON *v = mreq(c, obj, jpath, key);
    if (!v) return false;
    char p[160], want[96];
    snprintf(p, sizeof p, "%s.%s", jpath, key);
    snprintf(want, sizeof want, "an integer in [%" PRId64 ", %" PRId64 "]", lo, hi);
    if (!cJSON_IsNumber(v)) return mfail(c, DM_ERR_FORMAT, p, v, want);
    double d = v->valuedouble;
    if (!isfinite(d) || d != floor(d) || d < (double)lo || d > (double)hi) return mfail(c, DM_ERR_RANGE, p, v, want);
    *out = (int64_t)d;
    return true;
}

static bool mint32(mctx *c, const cJSON *obj, const char *jpath, const char *key, int lo, int hi, int *out)
{
    int64_t v;
    if (!mint(c, obj, jpath, key, lo, hi, &v)) return false;
    *out = (int)v;
    return true;
}

static const char *mstr(mctx *c, const cJSON *obj, const char *jpath, const char *key)
{
    const cJSON *v = mreq(c, obj, jpath, key);
    if (!v) return NULL;
    if (!cJSON_IsString(v)) {
        char p[160];
        snprintf(p, sizeof p, "%s.%s", jpath, key);
        mfail(c, DM_ERR_FORMAT, p, v, "a string");
        return NULL;
    }
    return v->valuestring;
}

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
    const char *s = mstr(c, obj, jpath, key);
    if (!s) return false;
    if (!valid_name(s)) {
        char p[160];
        snprintf(p, sizeof p, "%s.%s", jpath, key);
        return mfail(c, DM_ERR_FORMAT, p, cJSON_GetObjectItemCaseSensitive(obj, key),
                     "a name of 1..63 characters from [a-z0-9._-]");
    }
    snprintf(out, DM_PACK_NAME_SIZE, "%s", s);
    return true;
}

/* A provenance object, validated by dm_prov_from_json, kept as compact JSON. */
static bool mprov(mctx *c, const cJSON *obj, const char *jpath, char **out)
{
    const cJSON *v = mreq(c, obj, jpath, "provenance");
    if (!v) return false;
    char p[160];
    snprintf(p, sizeof p, "%s.provenance", jpath);
    if (!cJSON_IsObject(v)) return mfail(c, DM_ERR_FORMAT, p, v, "an object");
    char *text = cJSON_PrintUnformatted(v);
    if (!text) {
        c->r = dm_fail(c->err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", c->what);
        return false;
    }
    dm_provenance prov;
    char what[1200];
    snprintf(what, sizeof what, "%s: manifest %s", c->what, p);
    dm_result r = dm_prov_from_json(&prov, text, what, c->err);
    if (r != DM_OK) {
        cJSON_free(text);
        c->r = r;
        return false;
    }
    *out = text; /* cJSON's default allocator is malloc: freed with free() */
    return true;
}

static bool parse_entry(mctx *c, const cJSON *j, int index, dm_pack_entry *e)
{
    static const char *const common[] = {"name", "kind", "offset", "size", "xxh3", "provenance", NULL};
    static const char *const tex_keys[] = {"name", "kind",  "offset", "size",   "xxh3",     "provenance",
                                           "format", "width", "height", "layers", "levels", "channels", NULL};
    static const char *const vtx_keys[] = {"name", "kind", "offset", "size", "xxh3", "provenance",
                                           "vertex_count", "stride", "attributes", NULL};
    static const char *const idx_keys[] = {"name", "kind", "offset", "size", "xxh3", "provenance",
                                           "index_count", "type", "primitive", "vertices", NULL};
    static const char *const sh_keys[] = {"name", "kind", "offset", "size", "xxh3", "provenance", "sh_order", NULL};
    char jp[64];
    snprintf(jp, sizeof jp, "$.entries[%d]", index);
    memset(e, 0, sizeof *e);
    if (!cJSON_IsObject(j)) return mfail(c, DM_ERR_FORMAT, jp, j, "an object");
    if (!mname(c, j, jp, "name", e->name)) return false;
    const char *kind = mstr(c, j, jp, "kind");
    if (!kind) return false;
    int k = dm_pack_kind_from_name(kind);
    if (k < 0) {
        char p[96];
        snprintf(p, sizeof p, "%s.kind", jp);
        return mfail(c, DM_ERR_FORMAT, p, cJSON_GetObjectItemCaseSensitive(j, "kind"),
                     "one of texture, mesh.vertices, mesh.indices, env.sh, profile, scene");
    }
    e->kind = (dm_pack_kind)k;
    const char *const *keys = e->kind == DM_PACK_TEXTURE         ? tex_keys
                              : e->kind == DM_PACK_MESH_VERTICES ? vtx_keys
                              : e->kind == DM_PACK_MESH_INDICES  ? idx_keys
                              : e->kind == DM_PACK_ENV_SH        ? sh_keys
                                                                 : common;
    if (!mkeys(c, j, jp, keys)) return false;
    int64_t off, size;
    if (!mint(c, j, jp, "offset", 0, (int64_t)1 << 52, &off) || !mint(c, j, jp, "size", 0, (int64_t)1 << 52, &size))
        return false;
    e->offset = (uint64_t)off;
    e->size = (uint64_t)size;
    const char *hex = mstr(c, j, jp, "xxh3");
    if (!hex) return false;
    char *end = NULL;
    bool hex_ok = strlen(hex) == 16;
    for (const char *p = hex; hex_ok && *p; ++p) hex_ok = (*p >= '0' && *p <= '9') || (*p >= 'a' && *p <= 'f');
    if (!hex_ok) {
        char p[96];
        snprintf(p, sizeof p, "%s.xxh3", jp);
        return mfail(c, DM_ERR_FORMAT, p, cJSON_GetObjectItemCaseSensitive(j, "xxh3"), "16 lowercase hex digits");
    }
    e->xxh3 = strtoull(hex, &end, 16);
    if (!mprov(c, j, jp, &e->provenance_json)) return false;

    if (e->kind == DM_PACK_TEXTURE) {
        const char *f = mstr(c, j, jp, "format");
        if (!f) return false;
        int fi = dm_tex_format_from_name(f);
        if (fi < 0) {
            char p[96];
            snprintf(p, sizeof p, "%s.format", jp);
            return mfail(c, DM_ERR_FORMAT, p, cJSON_GetObjectItemCaseSensitive(j, "format"),
                         "one of r8, rg8, rgba8, rgba8_srgb, r16f, rg16f, rgba16f, r32f, rg32f, rgba32f");
        }
        e->format = (dm_tex_format)fi;
        if (!mint32(c, j, jp, "width", 1, DM_PACK_TEXTURE_SIZE_MAX, &e->width) ||
            !mint32(c, j, jp, "height", 1, DM_PACK_TEXTURE_SIZE_MAX, &e->height) ||
            !mint32(c, j, jp, "layers", 1, DM_PACK_LAYERS_MAX, &e->layers) ||
            !mint32(c, j, jp, "levels", 1, 15, &e->levels))
            return false;
        const cJSON *ch = cJSON_GetObjectItemCaseSensitive(j, "channels");
        if (ch) {
            char p[96];
            snprintf(p, sizeof p, "%s.channels", jp);
            int n = cJSON_IsArray(ch) ? cJSON_GetArraySize(ch) : -1;
            if (n < 1 || n > DM_PACK_MAX_CHANNELS) return mfail(c, DM_ERR_FORMAT, p, ch, "an array of 1..4 names");
            for (int q = 0; q < n; ++q) {
                const cJSON *s = cJSON_GetArrayItem(ch, q);
                if (!cJSON_IsString(s) || !*s->valuestring || strlen(s->valuestring) >= DM_PACK_CHANNEL_NAME_SIZE)
                    return mfail(c, DM_ERR_FORMAT, p, ch, "an array of short non-empty names");
                snprintf(e->channels[q], DM_PACK_CHANNEL_NAME_SIZE, "%s", s->valuestring);
            }
            e->channel_count = n;
        }
    } else if (e->kind == DM_PACK_MESH_VERTICES) {
        if (!mint(c, j, jp, "vertex_count", 1, (int64_t)1 << 32, &e->vertex_count) ||
            !mint32(c, j, jp, "stride", 4, 256, &e->stride))
            return false;
        const cJSON *at = mreq(c, j, jp, "attributes");
        if (!at) return false;
        char p[96];
        snprintf(p, sizeof p, "%s.attributes", jp);
        int n = cJSON_IsArray(at) ? cJSON_GetArraySize(at) : -1;
        if (n < 1 || n > DM_PACK_MAX_ATTRIBUTES) return mfail(c, DM_ERR_FORMAT, p, at, "an array of 1..8 attributes");
        for (int q = 0; q < n; ++q) {
            static const char *const akeys[] = {"name", "offset", "components", "type", NULL};
            const cJSON *a = cJSON_GetArrayItem(at, q);
            char ap[128];
            snprintf(ap, sizeof ap, "%s[%d]", p, q);
            if (!cJSON_IsObject(a)) return mfail(c, DM_ERR_FORMAT, ap, a, "an object");
            if (!mkeys(c, a, ap, akeys)) return false;
            const char *an = mstr(c, a, ap, "name"), *ty;
            if (!an) return false;
            if (!*an || strlen(an) >= DM_PACK_CHANNEL_NAME_SIZE)
                return mfail(c, DM_ERR_FORMAT, ap, a, "an attribute with a short non-empty name");
            snprintf(e->attributes[q].name, DM_PACK_CHANNEL_NAME_SIZE, "%s", an);
            if (!mint32(c, a, ap, "offset", 0, 252, &e->attributes[q].offset) ||
                !mint32(c, a, ap, "components", 1, 4, &e->attributes[q].components) || !(ty = mstr(c, a, ap, "type")))
                return false;
            if (strcmp(ty, "float32") != 0)
                return mfail(c, DM_ERR_UNSUPPORTED, ap, a, "an attribute of type \"float32\"");
        }
        e->attribute_count = n;
    } else if (e->kind == DM_PACK_MESH_INDICES) {
        const char *ty, *prim;
        if (!mint(c, j, jp, "index_count", 3, (int64_t)3 << 32, &e->index_count) || !(ty = mstr(c, j, jp, "type")) ||
            !(prim = mstr(c, j, jp, "primitive")) || !mname(c, j, jp, "vertices", e->vertices))
            return false;
        char p[96];
        snprintf(p, sizeof p, "%s.type", jp);
        if (strcmp(ty, "uint32") != 0)
            return mfail(c, DM_ERR_UNSUPPORTED, p, cJSON_GetObjectItemCaseSensitive(j, "type"), "\"uint32\"");
        snprintf(p, sizeof p, "%s.primitive", jp);
        if (strcmp(prim, "triangles") != 0)
            return mfail(c, DM_ERR_UNSUPPORTED, p, cJSON_GetObjectItemCaseSensitive(j, "primitive"), "\"triangles\"");
    } else if (e->kind == DM_PACK_ENV_SH) {
        if (!mint32(c, j, jp, "sh_order", 0, DM_PACK_SH_ORDER_MAX, &e->sh_order)) return false;
    }
    return true;
}

/* --- contents ----------------------------------------------------------------------- */

static bool all_finite32(const uint8_t *p, uint64_t count, uint64_t *bad)
{
    const uint32_t *u = (const uint32_t *)(const void *)p; /* blobs are 64-byte aligned */
    uint32_t acc = 0;
    for (uint64_t i = 0; i < count; ++i) acc |= ((u[i] & 0x7f800000u) == 0x7f800000u);
    if (!acc) return true;
    for (uint64_t i = 0; i < count; ++i)
        if ((u[i] & 0x7f800000u) == 0x7f800000u) {
            *bad = i;
            return false;
        }
    return false;
}

static bool all_finite16(const uint8_t *p, uint64_t count, uint64_t *bad)
{
    const uint16_t *u = (const uint16_t *)(const void *)p;
    for (uint64_t i = 0; i < count; ++i)
        if ((u[i] & 0x7c00u) == 0x7c00u) {
            *bad = i;
            return false;
        }
    return true;
}

static float value_at(const uint8_t *p, int component_size, uint64_t i)
{
    if (component_size == 4) {
        float f;
        memcpy(&f, p + 4 * i, 4);
        return f;
    }
    uint16_t h;
    memcpy(&h, p + 2 * i, 2);
    return (h & 0x03ffu) ? NAN : ((h & 0x8000u) ? -INFINITY : INFINITY);
}

static dm_result check_texture_values(const dm_pack *pack, const dm_pack_entry *e, dm_error *err)
{
    const dm_tex_format_info *f = dm_tex_format_get(e->format);
    if (!f->is_float) return DM_OK;
    for (int l = 0; l < e->levels; ++l) {
        const uint8_t *base = (const uint8_t *)e->data + dm_pack_texture_level_offset(e, l);
        uint64_t count = dm_pack_texture_level_size(e, l) / (uint64_t)f->component_size, bad = 0;
        bool ok = f->component_size == 4 ? all_finite32(base, count, &bad) : all_finite16(base, count, &bad);
        if (!ok) {
            uint64_t w = level_dim(e->width, l), h = level_dim(e->height, l);
            uint64_t texel = bad / (uint64_t)f->components, comp = bad % (uint64_t)f->components;
            uint64_t layer = texel / (w * h), in = texel % (w * h);
            return dm_fail(err, DM_ERR_NON_FINITE,
                           "%s: entry \"%s\": texel (%" PRIu64 ", %" PRIu64 ") of level %d layer %" PRIu64
                           ", component %" PRIu64 " is %g, expected a finite value",
                           pack->what, e->name, in % w, in / w, l, layer, comp,
                           (double)value_at(base, f->component_size, bad));
        }
    }
    return DM_OK;
}

static dm_result check_contents(const dm_pack *pack, const dm_pack_entry *e, dm_error *err)
{
    uint64_t bad = 0;
    switch (e->kind) {
    case DM_PACK_TEXTURE: return check_texture_values(pack, e, err);
    case DM_PACK_MESH_VERTICES:
        if (!all_finite32(e->data, e->size / 4, &bad))
            return dm_fail(err, DM_ERR_NON_FINITE,
                           "%s: entry \"%s\": vertex %" PRIu64 ", float %" PRIu64 " is %g, expected a finite value",
                           pack->what, e->name, bad * 4 / (uint64_t)e->stride, bad % ((uint64_t)e->stride / 4),
                           (double)value_at(e->data, 4, bad));
        return DM_OK;
    case DM_PACK_ENV_SH:
        if (!all_finite32(e->data, e->size / 4, &bad))
            return dm_fail(err, DM_ERR_NON_FINITE, "%s: entry \"%s\": coefficient %" PRIu64 " channel %" PRIu64
                           " is %g, expected a finite value",
                           pack->what, e->name, bad / 3, bad % 3, (double)value_at(e->data, 4, bad));
        return DM_OK;
    case DM_PACK_MESH_INDICES: {
        const dm_pack_entry *v = dm_pack_find(pack, e->vertices);
        if (!v || v->kind != DM_PACK_MESH_VERTICES)
            return dm_fail(err, DM_ERR_FORMAT, "%s: entry \"%s\": vertices \"%s\" is not a mesh.vertices entry of the pack",
                           pack->what, e->name, e->vertices);
        const uint32_t *idx = e->data;
        uint32_t mx = 0;
        for (int64_t i = 0; i < e->index_count; ++i) mx = idx[i] > mx ? idx[i] : mx;
        if ((int64_t)mx >= v->vertex_count) {
            for (int64_t i = 0; i < e->index_count; ++i)
                if ((int64_t)idx[i] >= v->vertex_count)
                    return dm_fail(err, DM_ERR_RANGE,
                                   "%s: entry \"%s\": index %" PRId64 " is %u, expected < %" PRId64
                                   " (vertex_count of \"%s\")",
                                   pack->what, e->name, i, idx[i], v->vertex_count, v->name);
        }
        return DM_OK;
    }
    case DM_PACK_PROFILE:
    case DM_PACK_SCENE: {
        if (memchr(e->data, 0, e->size))
            return dm_fail(err, DM_ERR_FORMAT, "%s: entry \"%s\": holds a NUL byte, expected JSON text", pack->what,
                           e->name);
        char *text = malloc(e->size + 1);
        if (!text) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", pack->what);
        memcpy(text, e->data, e->size);
        text[e->size] = '\0';
        char what[1200];
        snprintf(what, sizeof what, "%s#%s", pack->what, e->name);
        dm_result r;
        if (e->kind == DM_PACK_PROFILE) {
            dm_profile prof;
            r = dm_profile_from_json(text, what, &prof, err);
        } else {
            dm_scene *sc = malloc(sizeof *sc);
            r = sc ? dm_scene_parse(text, what, sc, err) : dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", what);
            free(sc);
        }
        free(text);
        return r;
    }
    case DM_PACK_KIND_COUNT: break;
    }
    return DM_OK;
}

/* --- open --------------------------------------------------------------------------- */

static int by_offset(const void *a, const void *b)
{
    const dm_pack_entry *x = *(const dm_pack_entry *const *)a, *y = *(const dm_pack_entry *const *)b;
    return x->offset < y->offset ? -1 : x->offset > y->offset;
}

static bool all_zero(const uint8_t *p, uint64_t n)
{
    for (uint64_t i = 0; i < n; ++i)
        if (p[i]) return false;
    return true;
}

static dm_result check_required(dm_pack *pack, dm_error *err)
{
    dm_scene *s = malloc(sizeof *s);
    if (!s) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", pack->what);
    dm_result r = dm_pack_scene(pack, s, err);
    int n;
    const dm_pack_need *needs = dm_pack_needs(&n);
    for (int k = 0; k < n && r == DM_OK; ++k) {
        for (int copy = 0; r == DM_OK && copy < dm_pack_need_copies(&needs[k], s); ++copy) { /* env<k>.* too */
            const dm_pack_need *nd = &needs[k];
            char name[DM_PACK_NAME_SIZE];
            const dm_pack_entry *e = dm_pack_find(pack, dm_pack_need_entry_name(nd, copy, name));
            if (!e) {
                if (!dm_pack_need_applies(nd, s)) continue;
                char by[256] = "";
                size_t m = 0;
                for (int fx = 0; fx < DM_EFFECT_COUNT; ++fx)
                    if ((nd->effects & DM_FX(fx)) && s->effects[fx])
                        m += (size_t)snprintf(by + m, m < sizeof by ? sizeof by - m : 0, "%s%s", m ? ", " : "",
                                              dm_effect_name((dm_effect)fx));
                r = dm_fail(err, DM_ERR_FORMAT, "%s: missing required entry \"%s\" (%s, needed by %s%s%s)", pack->what,
                            name, nd->why, m ? by : "every scene", nd->when ? " with a " : "",
                            dm_need_when_text(nd->when));
            } else if (e->kind != nd->kind || (nd->format >= 0 && e->format != (dm_tex_format)nd->format)) {
                r = dm_fail(err, DM_ERR_FORMAT, "%s: entry \"%s\" is %s%s%s, expected %s%s%s", pack->what, e->name,
                            dm_pack_kind_name(e->kind), e->kind == DM_PACK_TEXTURE ? " " : "",
                            e->kind == DM_PACK_TEXTURE ? dm_tex_format_get(e->format)->name : "",
                            dm_pack_kind_name(nd->kind), nd->format >= 0 ? " " : "",
                            nd->format >= 0 ? dm_tex_format_get((dm_tex_format)nd->format)->name : "");
            }
        }
    }
    free(s);
    return r;
}

static dm_result verify(dm_pack *pack, dm_error *err)
{
    const uint8_t *b = pack->base;
    const char *what = pack->what;
    uint64_t size = pack->size;
    if (size < DM_PACK_HEADER_SIZE)
        return dm_fail(err, DM_ERR_FORMAT, "%s: %" PRIu64 " bytes, expected at least the %d-byte header (truncated?)",
                       what, size, DM_PACK_HEADER_SIZE);
    if (memcmp(b, DM_PACK_MAGIC, 8) != 0)
        return dm_fail(err, DM_ERR_FORMAT,
                       "%s: magic %02x %02x %02x %02x %02x %02x %02x %02x, expected 89 44 50 4b 0d 0a 1a 0a (a .dpk pack)",
                       what, b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]);
    dm_pack_header h = {get32(b + 8), get32(b + 12), get64(b + 16), get64(b + 24),
                        get64(b + 32), get64(b + 40), get64(b + 48), get64(b + 56)};
    pack->version = h.version;
    pack->flags = h.flags;
    if (h.version != DM_PACK_VERSION)
        return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: version %u, expected %d", what, h.version, DM_PACK_VERSION);
    if (h.flags != 0)
        return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: flags 0x%08x, expected 0 (no flags are defined)", what, h.flags);
    if (h.file_size != size)
        return dm_fail(err, DM_ERR_FORMAT, "%s: header says %" PRIu64 " bytes, the file has %" PRIu64
                       " (truncated or extended)", what, h.file_size, size);
    if (h.manifest_offset != DM_PACK_HEADER_SIZE)
        return dm_fail(err, DM_ERR_FORMAT, "%s: manifest offset %" PRIu64 ", expected %d", what, h.manifest_offset,
                       DM_PACK_HEADER_SIZE);
    if (h.manifest_size < 2 || h.manifest_size > DM_PACK_MANIFEST_MAX || h.manifest_size > size - DM_PACK_HEADER_SIZE)
        return dm_fail(err, DM_ERR_FORMAT, "%s: manifest size %" PRIu64 ", expected 2..%" PRIu64 " bytes", what,
                       h.manifest_size,
                       (uint64_t)(size - DM_PACK_HEADER_SIZE < DM_PACK_MANIFEST_MAX ? size - DM_PACK_HEADER_SIZE
                                                                                  : DM_PACK_MANIFEST_MAX));
    uint64_t mend = DM_PACK_HEADER_SIZE + h.manifest_size;
    if (h.blobs_offset != dm_pack_align(mend) || h.blobs_offset > size)
        return dm_fail(err, DM_ERR_FORMAT, "%s: blobs offset %" PRIu64 ", expected %" PRIu64
                       " (the manifest's end aligned to 64, within the file)", what, h.blobs_offset, dm_pack_align(mend));
    if (h.reserved != 0)
        return dm_fail(err, DM_ERR_FORMAT, "%s: reserved header field 0x%" PRIx64 ", expected 0", what, h.reserved);
    uint64_t sum = dm_pack_header_checksum(b, b + DM_PACK_HEADER_SIZE, h.manifest_size);
    if (sum != h.checksum)
        return dm_fail(err, DM_ERR_CHECKSUM, "%s: header+manifest checksum %016" PRIx64 ", computed %016" PRIx64
                       " (the header or manifest is corrupt)", what, h.checksum, sum);
    if (!all_zero(b + mend, h.blobs_offset - mend))
        return dm_fail(err, DM_ERR_FORMAT, "%s: padding after the manifest is not zero (corrupt)", what);

    /* manifest */
    pack->manifest = malloc(h.manifest_size + 1);
    if (!pack->manifest) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", what);
    memcpy(pack->manifest, b + DM_PACK_HEADER_SIZE, h.manifest_size);
    pack->manifest[h.manifest_size] = '\0';
    if (strlen(pack->manifest) != h.manifest_size)
        return dm_fail(err, DM_ERR_FORMAT, "%s: manifest holds a NUL byte, expected JSON text", what);
    cJSON *root = cJSON_Parse(pack->manifest);
    if (!root) return dm_fail(err, DM_ERR_FORMAT, "%s: manifest is not valid JSON", what);
    mctx c = {what, err, DM_OK};
    static const char *const top[] = {"format", "version", "provenance", "entries", NULL};
    bool ok = cJSON_IsObject(root) ? mkeys(&c, root, "$", top) : mfail(&c, DM_ERR_FORMAT, "$", root, "an object");
    const char *fmt = ok ? mstr(&c, root, "$", "format") : NULL;
    int64_t ver = 0;
    ok = ok && fmt;
    if (ok && strcmp(fmt, "dermis-pack") != 0)
        ok = mfail(&c, DM_ERR_FORMAT, "$.format", cJSON_GetObjectItemCaseSensitive(root, "format"), "\"dermis-pack\"");
    ok = ok && mint(&c, root, "$", "version", 1, 1, &ver) && mprov(&c, root, "$", &pack->provenance_json);
    const cJSON *ents = ok ? mreq(&c, root, "$", "entries") : NULL;
    ok = ok && ents;
    if (ok && (!cJSON_IsArray(ents) || cJSON_GetArraySize(ents) > DM_PACK_ENTRIES_MAX))
        ok = mfail(&c, DM_ERR_FORMAT, "$.entries", ents, "an array of at most 1024 entries");
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

    /* descriptors, names, bounds */
    int n = pack->entry_count;
    for (int k = 0; k < n; ++k) {
        dm_pack_entry *e = &pack->entries[k];
        char ew[1200];
        snprintf(ew, sizeof ew, "%s: entry \"%s\"", what, e->name);
        for (int q = 0; q < k; ++q)
            if (strcmp(pack->entries[q].name, e->name) == 0)
                return dm_fail(err, DM_ERR_FORMAT, "%s: entries %d and %d are both named \"%s\", expected unique names",
                               what, q, k, e->name);
        if (e->kind == DM_PACK_SCENE && strcmp(e->name, "scene") != 0)
            return dm_fail(err, DM_ERR_FORMAT, "%s: is a scene entry, expected the name \"scene\"", ew);
        uint64_t want;
        dm_result r = dm_pack_entry_expected_size(e, ew, &want, err);
        if (r != DM_OK) return r;
        if (want != e->size)
            return dm_fail(err, DM_ERR_FORMAT, "%s: size %" PRIu64 " bytes, expected %" PRIu64 " for its format", ew,
                           e->size, want);
        if (e->offset % DM_PACK_ALIGN)
            return dm_fail(err, DM_ERR_FORMAT, "%s: offset %" PRIu64 ", expected a multiple of %d", ew, e->offset,
                           DM_PACK_ALIGN);
        if (e->offset < h.blobs_offset || e->offset > size || e->size > size - e->offset)
            return dm_fail(err, DM_ERR_FORMAT,
                           "%s: bytes [%" PRIu64 ", %" PRIu64 ") are outside the blob area [%" PRIu64 ", %" PRIu64 ")",
                           ew, e->offset, e->offset + e->size, h.blobs_offset, size);
        e->data = b + e->offset;
    }
    if (n > 0) {
        const dm_pack_entry **sorted = malloc((size_t)n * sizeof *sorted);
        if (!sorted) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", what);
        for (int k = 0; k < n; ++k) sorted[k] = &pack->entries[k];
        qsort(sorted, (size_t)n, sizeof *sorted, by_offset);
        uint64_t at = h.blobs_offset;
        dm_result r = DM_OK;
        for (int k = 0; k < n && r == DM_OK; ++k) {
            const dm_pack_entry *e = sorted[k];
            if (k > 0 && e->offset < sorted[k - 1]->offset + sorted[k - 1]->size)
                r = dm_fail(err, DM_ERR_FORMAT, "%s: entries \"%s\" [%" PRIu64 ", %" PRIu64 ") and \"%s\" [%" PRIu64
                            ", %" PRIu64 ") overlap, expected disjoint blobs",
                            what, sorted[k - 1]->name, sorted[k - 1]->offset, sorted[k - 1]->offset + sorted[k - 1]->size,
                            e->name, e->offset, e->offset + e->size);
            else if (e->offset != dm_pack_align(at))
                r = dm_fail(err, DM_ERR_FORMAT, "%s: entry \"%s\" at offset %" PRIu64 ", expected %" PRIu64
                            " (blobs packed in order, 64-byte aligned)", what, e->name, e->offset, dm_pack_align(at));
            else if (!all_zero(b + at, e->offset - at))
                r = dm_fail(err, DM_ERR_FORMAT, "%s: padding before entry \"%s\" is not zero (corrupt)", what, e->name);
            at = e->offset + e->size;
        }
        free(sorted);
        if (r != DM_OK) return r;
        if (at != size)
            return dm_fail(err, DM_ERR_FORMAT, "%s: %" PRIu64 " bytes after the last blob, expected the file to end there",
                           what, size - at);
    } else if (h.blobs_offset != size) {
        return dm_fail(err, DM_ERR_FORMAT, "%s: %" PRIu64 " bytes after the manifest but no entries", what,
                       size - h.blobs_offset);
    }
    for (int k = 0; k < n; ++k) {
        const dm_pack_entry *e = &pack->entries[k];
        uint64_t got = dm_hash64(e->data, e->size);
        if (got != e->xxh3)
            return dm_fail(err, DM_ERR_CHECKSUM, "%s: entry \"%s\": checksum %016" PRIx64 ", computed %016" PRIx64
                           " (the blob is corrupt)", what, e->name, e->xxh3, got);
    }
    for (int k = 0; k < n; ++k) {
        dm_result r = check_contents(pack, &pack->entries[k], err);
        if (r != DM_OK) return r;
    }
    if (!dm_pack_find(pack, "scene"))
        return dm_fail(err, DM_ERR_FORMAT, "%s: missing required entry \"scene\" (every pack holds its scene)", what);
    return check_required(pack, err);
}

dm_result dm_pack_open_memory(const void *data, size_t size, const char *what, dm_pack *pack, dm_error *err)
{
    memset(pack, 0, sizeof *pack);
    snprintf(pack->what, sizeof pack->what, "%s", what ? what : "(pack)");
    if ((uintptr_t)data % 16)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: pack bytes at an address that is not 16-byte aligned",
                       pack->what);
    pack->base = data;
    pack->size = size;
    dm_result r = verify(pack, err);
    if (r != DM_OK) dm_pack_close(pack);
    return r;
}

dm_result dm_pack_open(const char *path, dm_pack *pack, dm_error *err)
{
    memset(pack, 0, sizeof *pack);
    int fd = open(path, O_RDONLY);
    if (fd < 0) return dm_fail(err, DM_ERR_FILE_OPEN, "%s: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return dm_fail(err, DM_ERR_FILE_OPEN, "%s: not a regular file", path);
    }
    size_t size = (size_t)st.st_size;
    void *m = NULL;
    if (size > 0) {
        m = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
        if (m == MAP_FAILED) {
            int e = errno;
            close(fd);
            return dm_fail(err, DM_ERR_FILE_READ, "%s: cannot map (%s)", path, strerror(e));
        }
    }
    close(fd);
    static const uint8_t empty[1];
    dm_result r = dm_pack_open_memory(m ? m : empty, size, path, pack, err);
    if (r != DM_OK) {
        if (m) munmap(m, size);
        return r;
    }
    pack->mapped = m != NULL;
    return DM_OK;
}

void dm_pack_close(dm_pack *pack)
{
    if (!pack) return;
    for (int k = 0; k < pack->entry_count; ++k) free(pack->entries[k].provenance_json);
    free(pack->entries);
    free(pack->manifest);
    free(pack->provenance_json);
    if (pack->mapped) munmap((void *)(uintptr_t)pack->base, pack->size);
    pack->entries = NULL;
    pack->manifest = NULL;
    pack->provenance_json = NULL;
    pack->entry_count = 0;
    pack->mapped = false;
    pack->base = NULL;
    pack->size = 0;
}

const dm_pack_entry *dm_pack_find(const dm_pack *pack, const char *name)
{
    for (int k = 0; k < pack->entry_count; ++k)
        if (strcmp(pack->entries[k].name, name) == 0) return &pack->entries[k];
    return NULL;
}

dm_result dm_pack_scene(const dm_pack *pack, dm_scene *scene, dm_error *err)
{
    const dm_pack_entry *e = dm_pack_find(pack, "scene");
    if (!e || e->kind != DM_PACK_SCENE || !e->data)
        return dm_fail(err, DM_ERR_FORMAT, "%s: no scene entry, expected one", pack->what);
    char *text = malloc(e->size + 1);
    if (!text) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", pack->what);
    memcpy(text, e->data, e->size);
    text[e->size] = '\0';
    char what[1200];
    snprintf(what, sizeof what, "%s#scene", pack->what);
    dm_result r = dm_scene_parse(text, what, scene, err);
    free(text);
    return r;
}
