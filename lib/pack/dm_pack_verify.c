/* dm_pack_verify.c — VERIFIED ON OPEN (pack/dm_pack.h): header, bounds, overlaps, padding,
 * checksums, contents, the entries the scene needs, and last the physical ranges of every
 * entry's values (dm_pack_semantic.c). */
#include "pack/dm_pack_impl.h"

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

#include "pack/dm_format_version.h"
#include "core/dm_hash.h"
#include "pack/dm_pack_needs.h"
#include "pack/dm_pack_semantic.h"
#include "core/dm_profile.h"
#include "core/dm_prov.h"

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
            uint64_t w = dm_pack_level_dim(e->width, l), h = dm_pack_level_dim(e->height, l);
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

static dm_result check_contents(dm_pack *pack, const dm_pack_entry *e, dm_error *err)
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
        if (e->kind == DM_PACK_PROFILE) { /* kept for check_required's comparison with the scene's */
            dm_profile *prof = malloc(sizeof *prof);
            r = prof ? dm_profile_from_json(text, what, prof, err)
                     : dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", what);
            if (r == DM_OK && !pack->profile && strcmp(e->name, "profile") == 0) pack->profile = prof, prof = NULL;
            free(prof);
        } else { /* the scene is parsed here once and kept: dm_pack_scene hands out copies */
            dm_scene *sc = malloc(sizeof *sc);
            r = sc ? dm_scene_parse(text, what, sc, err) : dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", what);
            if (r == DM_OK && !pack->scene && strcmp(e->name, "scene") == 0) pack->scene = sc, sc = NULL;
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
            if (!e) { /* the kind and format of those present: dm_pack_check_values */
                if (!dm_pack_need_applies(nd, s) || nd->optional) continue;
                char by[256] = "";
                size_t m = 0;
                for (int fx = 0; fx < DM_EFFECT_COUNT; ++fx)
                    if ((nd->effects & DM_FX(fx)) && s->effects[fx])
                        m += (size_t)snprintf(by + m, m < sizeof by ? sizeof by - m : 0, "%s%s", m ? ", " : "",
                                              dm_effect_name((dm_effect)fx));
                r = dm_fail(err, DM_ERR_FORMAT, "%s: missing required entry \"%s\" (%s, needed by %s%s%s)", pack->what,
                            name, nd->why, m ? by : "every scene", nd->when ? " with a " : "",
                            dm_need_when_text(nd->when));
            }
        }
    }
    /* One route for the profile: the renderer takes the scene's; the "profile" entry (the
     * file as it was, with its fit report) must hold the same Gaussians. */
    const dm_profile *pe = pack->profile, *ps = &s->profile;
    bool same = pe && pe->count == ps->count; /* by value: a -0 weight in a file is 0 in the scene JSON */
    for (int k = 0; same && k < ps->count; ++k)
        same = pe->variance_mm2[k] == ps->variance_mm2[k] && pe->weight[k][0] == ps->weight[k][0] &&
               pe->weight[k][1] == ps->weight[k][1] && pe->weight[k][2] == ps->weight[k][2];
    if (r == DM_OK && pe && !same)
        r = dm_fail(err, DM_ERR_MISMATCH,
                    "%s: entry \"profile\" ('%s', %d Gaussians) differs from the scene's profile ('%s', %d Gaussians)",
                    pack->what, pe->name, pe->count, ps->name, ps->count);
    free(s);
    return r;
}

dm_result dm_pack_verify(dm_pack *pack, dm_error *err)
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
    dm_pack_header h;
    dm_pack_header_decode(b, &h);
    pack->version = h.version;
    pack->flags = h.flags;
    if (h.version != DM_PACK_VERSION) /* the version policy's refusal: docs/dermis-dpk.5.md */
        return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: version %u, expected %d (%s)", what, h.version, DM_PACK_VERSION,
                       dm_format_advice(DM_FORMAT_PACK, dm_format_judge(h.version, DM_PACK_VERSION)));
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
    dm_result mr = dm_pack_manifest_parse(pack, b + DM_PACK_HEADER_SIZE, h.manifest_size, err);
    if (mr != DM_OK) return mr;

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
    dm_result r = check_required(pack, err);
    return r != DM_OK ? r : dm_pack_check_values(pack, err);
}

