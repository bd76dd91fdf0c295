/* dm_pack_format.c — the pack's kinds, texture formats, header encoding and the sizes
 * descriptors imply (dm_pack_format.h). Uses nothing else in lib/pack. */
#include "pack/dm_pack_format.h"

#include <inttypes.h>
#include <stdio.h>
#include <string.h>

#include "core/dm_hash.h"

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
static void put32(uint8_t *p, uint32_t v)
{
    for (int k = 0; k < 4; ++k) p[k] = (uint8_t)(v >> (8 * k));
}
static void put64(uint8_t *p, uint64_t v)
{
    for (int k = 0; k < 8; ++k) p[k] = (uint8_t)(v >> (8 * k));
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

void dm_pack_header_decode(const uint8_t in[DM_PACK_HEADER_SIZE], dm_pack_header *h)
{
    *h = (dm_pack_header){get32(in + 8),  get32(in + 12), get64(in + 16), get64(in + 24),
                          get64(in + 32), get64(in + 40), get64(in + 48), get64(in + 56)};
}

uint64_t dm_pack_header_checksum(const uint8_t header[DM_PACK_HEADER_SIZE], const void *manifest,
                                 size_t manifest_size)
{
    return dm_hash64_pair(header, 56, manifest, manifest_size);
}

/* --- sizes -------------------------------------------------------------------------- */

uint64_t dm_pack_texture_level_size(const dm_pack_entry *e, int level)
{
    const dm_tex_format_info *f = dm_tex_format_get(e->format);
    if (!f) return 0;
    return dm_pack_level_dim(e->width, level) * dm_pack_level_dim(e->height, level) * (uint64_t)e->layers *
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
        if (e->layer_value_count != 0 &&
            (e->layer_value_count != e->layers || e->layer_value_count > DM_PACK_LAYER_VALUES_MAX))
            return dm_fail(err, DM_ERR_RANGE, "%s: %d layer values for %d layers, expected one per layer (at most %d)",
                           what, e->layer_value_count, e->layers, DM_PACK_LAYER_VALUES_MAX);
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

