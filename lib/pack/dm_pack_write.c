#include "pack/dm_pack_write.h"

#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "core/dm_file.h"
#include "core/dm_hash.h"

dm_pack_entry dm_pack_texture_entry(const char *name, dm_tex_format f, int w, int h)
{
    dm_pack_entry d;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "%s", name);
    d.kind = DM_PACK_TEXTURE;
    d.format = f;
    d.width = w;
    d.height = h;
    d.layers = 1;
    d.levels = 1;
    return d;
}

void dm_pack_writer_init(dm_pack_writer *w)
{
    memset(w, 0, sizeof *w);
}

void dm_pack_writer_free(dm_pack_writer *w)
{
    for (int k = 0; k < w->count; ++k) {
        free(w->blobs[k].data);
        free(w->blobs[k].provenance_json);
    }
    free(w->blobs);
    memset(w, 0, sizeof *w);
}

static char *prov_json(const dm_provenance *prov, dm_error *err)
{
    size_t cap = 1 << 16;
    char *s = malloc(cap);
    if (!s) return NULL;
    if (dm_prov_to_json(prov, s, cap, err) != DM_OK) {
        free(s);
        return NULL;
    }
    return s;
}

dm_result dm_pack_writer_add(dm_pack_writer *w, const dm_pack_entry *desc, const void *data, size_t size,
                             const dm_provenance *prov, dm_error *err)
{
    assert(w && desc && prov && (data || size == 0));
    char what[128];
    snprintf(what, sizeof what, "pack entry \"%s\"", desc->name);
    size_t n = strlen(desc->name);
    if (n < 1 || n >= DM_PACK_NAME_SIZE || strspn(desc->name, "abcdefghijklmnopqrstuvwxyz0123456789._-") != n)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: expected a name of 1..63 characters from [a-z0-9._-]", what);
    for (int k = 0; k < w->count; ++k)
        if (strcmp(w->blobs[k].desc.name, desc->name) == 0)
            return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: added twice, expected unique names", what);
    dm_pack_entry d = *desc;
    d.size = size;
    d.offset = 0;
    d.data = NULL;
    d.provenance_json = NULL;
    uint64_t want = 0;
    dm_result r = dm_pack_entry_expected_size(&d, what, &want, err);
    if (r != DM_OK) return r;
    if (want != size)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: %zu bytes given, expected %llu for its descriptor", what, size,
                       (unsigned long long)want);
    if (w->count == w->capacity) {
        int cap = w->capacity ? 2 * w->capacity : 16;
        dm_pack_blob *nb = realloc(w->blobs, (size_t)cap * sizeof *nb);
        if (!nb) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", what);
        w->blobs = nb;
        w->capacity = cap;
    }
    dm_pack_blob *b = &w->blobs[w->count];
    memset(b, 0, sizeof *b);
    b->desc = d;
    b->data = malloc(size ? size : 1);
    b->provenance_json = prov_json(prov, err);
    if (!b->data || !b->provenance_json) {
        free(b->data);
        free(b->provenance_json);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory or provenance too large", what);
    }
    if (size) memcpy(b->data, data, size);
    b->desc.xxh3 = dm_hash64(b->data, size);
    w->count++;
    return DM_OK;
}

static cJSON *entry_json(const dm_pack_blob *b)
{
    const dm_pack_entry *e = &b->desc;
    char hex[17];
    dm_pack_hex64(e->xxh3, hex);
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", e->name);
    cJSON_AddStringToObject(o, "kind", dm_pack_kind_name(e->kind));
    cJSON_AddNumberToObject(o, "offset", (double)e->offset);
    cJSON_AddNumberToObject(o, "size", (double)e->size);
    cJSON_AddStringToObject(o, "xxh3", hex);
    switch (e->kind) {
    case DM_PACK_TEXTURE:
        cJSON_AddStringToObject(o, "format", dm_tex_format_get(e->format)->name);
        cJSON_AddNumberToObject(o, "width", e->width);
        cJSON_AddNumberToObject(o, "height", e->height);
        cJSON_AddNumberToObject(o, "layers", e->layers);
        cJSON_AddNumberToObject(o, "levels", e->levels);
        if (e->channel_count > 0) {
            cJSON *ch = cJSON_AddArrayToObject(o, "channels");
            for (int k = 0; k < e->channel_count; ++k) cJSON_AddItemToArray(ch, cJSON_CreateString(e->channels[k]));
        }
        if (e->layer_value_count > 0) {
            cJSON *lv = cJSON_AddArrayToObject(o, "layer_values");
            for (int k = 0; k < e->layer_value_count; ++k) cJSON_AddItemToArray(lv, cJSON_CreateNumber(e->layer_values[k]));
        }
        if (e->has_t_range) {
            cJSON *tr = cJSON_AddArrayToObject(o, "t_range");
            for (int k = 0; k < 2; ++k) cJSON_AddItemToArray(tr, cJSON_CreateNumber(e->t_range[k]));
        }
        break;
    case DM_PACK_MESH_VERTICES: {
        cJSON_AddNumberToObject(o, "vertex_count", (double)e->vertex_count);
        cJSON_AddNumberToObject(o, "stride", e->stride);
        cJSON *at = cJSON_AddArrayToObject(o, "attributes");
        for (int k = 0; k < e->attribute_count; ++k) {
            cJSON *a = cJSON_CreateObject();
            cJSON_AddStringToObject(a, "name", e->attributes[k].name);
            cJSON_AddNumberToObject(a, "offset", e->attributes[k].offset);
            cJSON_AddNumberToObject(a, "components", e->attributes[k].components);
            cJSON_AddStringToObject(a, "type", "float32");
            cJSON_AddItemToArray(at, a);
        }
        break;
    }
    case DM_PACK_MESH_INDICES:
        cJSON_AddNumberToObject(o, "index_count", (double)e->index_count);
        cJSON_AddStringToObject(o, "type", "uint32");
        cJSON_AddStringToObject(o, "primitive", "triangles");
        cJSON_AddStringToObject(o, "vertices", e->vertices);
        break;
    case DM_PACK_ENV_SH: cJSON_AddNumberToObject(o, "sh_order", e->sh_order); break;
    default: break;
    }
    cJSON_AddItemToObject(o, "provenance", cJSON_CreateRaw(b->provenance_json));
    return o;
}

/* The manifest for blobs placed from blobs_offset on; NULL when out of memory. */
static char *manifest_for(const dm_pack_writer *w, const char *pack_prov, uint64_t blobs_offset, uint64_t *end)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "format", "dermis-pack");
    cJSON_AddNumberToObject(root, "version", DM_PACK_VERSION);
    cJSON_AddItemToObject(root, "provenance", cJSON_CreateRaw(pack_prov));
    cJSON *ents = cJSON_AddArrayToObject(root, "entries");
    uint64_t at = blobs_offset;
    for (int k = 0; k < w->count; ++k) {
        dm_pack_blob b = w->blobs[k];
        b.desc.offset = dm_pack_align(at);
        at = b.desc.offset + b.desc.size;
        cJSON_AddItemToArray(ents, entry_json(&b));
    }
    *end = at;
    char *s = cJSON_Print(root); /* indented: the manifest is meant to be read by people too */
    cJSON_Delete(root);
    return s;
}

dm_result dm_pack_writer_build(const dm_pack_writer *w, const dm_provenance *pack_prov, uint8_t **out,
                               size_t *out_size, dm_error *err)
{
    *out = NULL;
    *out_size = 0;
    char *pj = prov_json(pack_prov, err);
    if (!pj) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "pack: out of memory or provenance too large");
    /* Offsets live in the manifest, whose length depends on them: iterate to a fixed point. */
    uint64_t blobs_offset = DM_PACK_HEADER_SIZE, end = 0;
    char *m = NULL;
    for (int it = 0; it < 16; ++it) {
        free(m);
        m = manifest_for(w, pj, blobs_offset, &end);
        if (!m) break;
        uint64_t need = dm_pack_align(DM_PACK_HEADER_SIZE + strlen(m));
        if (need == blobs_offset) break;
        blobs_offset = need;
    }
    free(pj);
    if (!m || dm_pack_align(DM_PACK_HEADER_SIZE + strlen(m)) != blobs_offset) {
        free(m);
        return dm_fail(err, DM_ERR_INTERNAL, "pack: cannot lay out the manifest");
    }
    size_t msize = strlen(m);
    if (msize > DM_PACK_MANIFEST_MAX) {
        free(m);
        return dm_fail(err, DM_ERR_RANGE, "pack: manifest of %zu bytes, expected at most %d", msize,
                       DM_PACK_MANIFEST_MAX);
    }
    uint8_t *buf = aligned_alloc(DM_PACK_ALIGN, (size_t)dm_pack_align(end ? end : 1));
    if (!buf) {
        free(m);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "pack: out of memory for %llu bytes", (unsigned long long)end);
    }
    memset(buf, 0, (size_t)dm_pack_align(end ? end : 1));
    memcpy(buf + DM_PACK_HEADER_SIZE, m, msize);
    uint64_t at = blobs_offset;
    for (int k = 0; k < w->count; ++k) {
        uint64_t off = dm_pack_align(at);
        memcpy(buf + off, w->blobs[k].data, w->blobs[k].desc.size);
        at = off + w->blobs[k].desc.size;
    }
    dm_pack_header h = {DM_PACK_VERSION, 0, end, DM_PACK_HEADER_SIZE, msize, blobs_offset, 0, 0};
    dm_pack_header_encode(&h, buf);
    h.checksum = dm_pack_header_checksum(buf, m, msize);
    dm_pack_header_encode(&h, buf);
    free(m);
    *out = buf;
    *out_size = (size_t)end;
    return DM_OK;
}

dm_result dm_pack_writer_write(const dm_pack_writer *w, const char *path, const dm_provenance *pack_prov,
                               size_t *written_size, dm_error *err)
{
    uint8_t *buf = NULL;
    size_t size = 0;
    dm_result r = dm_pack_writer_build(w, pack_prov, &buf, &size, err);
    if (r != DM_OK) return r;
    /* Never write a pack the reader would refuse. */
    dm_pack check;
    r = dm_pack_open_memory(buf, size, path, &check, err);
    dm_pack_close(&check);
    dm_atomic_file af;
    if (r == DM_OK) r = dm_atomic_open(&af, path, err);
    if (r == DM_OK) {
        if (fwrite(buf, 1, size, af.fp) != size) {
            dm_atomic_abort(&af);
            r = dm_fail(err, DM_ERR_FILE_WRITE, "%s: short write", path);
        } else {
            r = dm_atomic_commit(&af, err);
        }
    }
    free(buf);
    if (r == DM_OK && written_size) *written_size = size;
    return r;
}
