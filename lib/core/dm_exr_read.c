#include "core/dm_exr_read.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <zlib.h>

#include "core/dm_input.h"
#include "core/dm_half.h"

/* ---- bounded little-endian cursor -------------------------------------------------------- */

typedef struct cursor {
    const uint8_t *p;
    size_t size, at;
    bool bad; /* a read ran past the end */
} cursor;

static bool take(cursor *c, void *out, size_t n)
{
    if (c->bad || n > c->size - c->at) {
        c->bad = true;
        memset(out, 0, n);
        return false;
    }
    memcpy(out, c->p + c->at, n);
    c->at += n;
    return true;
}
static uint32_t rd_u32(const uint8_t *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}
static int32_t get_i32(cursor *c)
{
    uint8_t b[4];
    take(c, b, 4);
    return (int32_t)rd_u32(b);
}
static uint64_t get_u64(cursor *c)
{
    uint8_t b[8];
    take(c, b, 8);
    return (uint64_t)rd_u32(b) | (uint64_t)rd_u32(b + 4) << 32;
}
/* A NUL-terminated string of at most max−1 bytes; false when absent, too long or cut. */
static bool get_cstr(cursor *c, char *out, size_t max)
{
    size_t i = 0;
    while (!c->bad) {
        if (c->at >= c->size) {
            c->bad = true;
            break;
        }
        char ch = (char)c->p[c->at++];
        if (ch == 0) {
            out[i] = 0;
            return true;
        }
        if (i + 1 >= max) return false;
        out[i++] = ch;
    }
    out[0] = 0;
    return false;
}

/* ---- header ------------------------------------------------------------------------------ */

typedef struct header {
    bool has_channels, has_compression, has_window;
    int32_t xmin, ymin, xmax, ymax;
    size_t prov_at, prov_size; /* the provenance string's bytes in the buffer */
    bool has_prov;
} header;

static dm_result parse_chlist(cursor *a, const char *what, dm_exr_file *f, dm_error *err)
{
    for (;;) {
        char name[DM_EXR_READ_NAME_SIZE];
        if (!get_cstr(a, name, sizeof name))
            return dm_fail(err, DM_ERR_FORMAT, "%s: channel list: a name is cut or longer than %d bytes", what,
                           DM_EXR_READ_NAME_SIZE - 1);
        if (!name[0]) return DM_OK;
        int32_t type = get_i32(a);
        uint8_t plinear_reserved[4];
        take(a, plinear_reserved, 4);
        int32_t xs = get_i32(a), ys = get_i32(a);
        if (a->bad) return dm_fail(err, DM_ERR_FORMAT, "%s: channel list: channel '%s' is cut short", what, name);
        if (type != 1 && type != 2)
            return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: channel '%s': pixel type %d, expected 1 (HALF) or 2 (FLOAT)",
                           what, name, (int)type);
        if (xs != 1 || ys != 1)
            return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: channel '%s': sampling %dx%d, expected 1x1", what, name,
                           (int)xs, (int)ys);
        if (f->channel_count == DM_EXR_READ_MAX_CHANNELS)
            return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: more than %d channels", what, DM_EXR_READ_MAX_CHANNELS);
        if (f->channel_count > 0 && strcmp(f->names[f->channel_count - 1], name) >= 0)
            return dm_fail(err, DM_ERR_FORMAT, "%s: channel '%s' after '%s': names must be unique and sorted", what,
                           name, f->names[f->channel_count - 1]);
        memcpy(f->names[f->channel_count], name, sizeof name);
        f->types[f->channel_count++] = type;
    }
}

static dm_result parse_header(cursor *c, const char *what, dm_exr_file *f, header *h, dm_error *err)
{
    uint8_t magic[4];
    take(c, magic, 4);
    int32_t version = get_i32(c);
    if (c->bad || rd_u32(magic) != 20000630u)
        return dm_fail(err, DM_ERR_FORMAT, "%s: not an OpenEXR file (magic number 20000630 missing)", what);
    if ((version & 0xff) != 2)
        return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: EXR version %d, expected 2", what, (int)(version & 0xff));
    if (version & 0x200) return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: tiled EXR, expected scanlines", what);
    if (version & 0x800) return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: deep EXR, expected flat scanlines", what);
    if (version & 0x1000) return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: multi-part EXR, expected one part", what);
    if (version & ~0x4ff)
        return dm_fail(err, DM_ERR_FORMAT, "%s: unknown version flags 0x%x", what, (unsigned)(version & ~0xff));
    for (int count = 0;; ++count) {
        char name[DM_EXR_READ_NAME_SIZE], type[DM_EXR_READ_NAME_SIZE];
        if (!get_cstr(c, name, sizeof name))
            return dm_fail(err, DM_ERR_FORMAT, "%s: header: an attribute name is cut or too long", what);
        if (!name[0]) break;
        if (count > 10000) return dm_fail(err, DM_ERR_FORMAT, "%s: header: more than 10000 attributes", what);
        if (!get_cstr(c, type, sizeof type))
            return dm_fail(err, DM_ERR_FORMAT, "%s: attribute '%s': its type name is cut or too long", what, name);
        int32_t size = get_i32(c);
        if (c->bad || size < 0 || (size_t)size > c->size - c->at)
            return dm_fail(err, DM_ERR_FORMAT, "%s: attribute '%s': size %d runs past the end of the file", what,
                           name, (int)size);
        cursor a = {.p = c->p + c->at, .size = (size_t)size};
        const size_t value_at = c->at;
        c->at += (size_t)size;
        if (!strcmp(name, "channels")) {
            if (strcmp(type, "chlist") || h->has_channels)
                return dm_fail(err, DM_ERR_FORMAT, "%s: attribute channels: type '%s'%s, expected one chlist", what,
                               type, h->has_channels ? " (twice)" : "");
            dm_result rc = parse_chlist(&a, what, f, err);
            if (rc != DM_OK) return rc;
            if (a.at != a.size)
                return dm_fail(err, DM_ERR_FORMAT, "%s: channel list: %zu bytes after its end", what, a.size - a.at);
            h->has_channels = true;
        } else if (!strcmp(name, "compression")) {
            if (strcmp(type, "compression") || size != 1)
                return dm_fail(err, DM_ERR_FORMAT, "%s: attribute compression: type '%s' size %d, expected 1 byte",
                               what, type, (int)size);
            int comp = c->p[value_at];
            if (comp != 0 && comp != 2 && comp != 3)
                return dm_fail(err, DM_ERR_UNSUPPORTED,
                               "%s: compression %d, expected 0 (none), 2 (ZIPS) or 3 (ZIP)", what, comp);
            f->compression = comp;
            h->has_compression = true;
        } else if (!strcmp(name, "dataWindow")) {
            if (strcmp(type, "box2i") || size != 16)
                return dm_fail(err, DM_ERR_FORMAT, "%s: attribute dataWindow: type '%s' size %d, expected box2i", what,
                               type, (int)size);
            h->xmin = get_i32(&a), h->ymin = get_i32(&a), h->xmax = get_i32(&a), h->ymax = get_i32(&a);
            int64_t w = (int64_t)h->xmax - h->xmin + 1, hh = (int64_t)h->ymax - h->ymin + 1;
            if (w < 1 || hh < 1 || w > DM_EXR_READ_MAX_SIDE || hh > DM_EXR_READ_MAX_SIDE)
                return dm_fail(err, DM_ERR_FORMAT, "%s: data window %lldx%lld, expected 1..%d per side", what,
                               (long long)w, (long long)hh, DM_EXR_READ_MAX_SIDE);
            f->width = (int)w, f->height = (int)hh;
            h->has_window = true;
        } else if (!strcmp(name, "dermis.provenance")) {
            if (strcmp(type, "string"))
                return dm_fail(err, DM_ERR_FORMAT, "%s: attribute dermis.provenance: type '%s', expected string", what,
                               type);
            h->prov_at = value_at, h->prov_size = (size_t)size, h->has_prov = true;
        }
    }
    if (!h->has_channels || !h->has_compression || !h->has_window)
        return dm_fail(err, DM_ERR_FORMAT, "%s: header lacks %s", what,
                       !h->has_channels ? "channels" : !h->has_compression ? "compression" : "dataWindow");
    if (f->channel_count == 0) return dm_fail(err, DM_ERR_FORMAT, "%s: no channels", what);
    return DM_OK;
}

/* ---- chunks ------------------------------------------------------------------------------ */

/* ZIP/ZIPS: zlib, then the predictor (byte deltas + 128) and the two-halves interleave. */
static bool unzip_chunk(const uint8_t *src, size_t src_size, uint8_t *dst, size_t dst_size, uint8_t *tmp)
{
    uLongf n = (uLongf)dst_size;
    if (uncompress(tmp, &n, src, (uLong)src_size) != Z_OK || n != dst_size) return false;
    for (size_t i = 1; i < dst_size; ++i) tmp[i] = (uint8_t)(tmp[i - 1] + tmp[i] - 128);
    const uint8_t *t1 = tmp, *t2 = tmp + (dst_size + 1) / 2;
    for (size_t i = 0; i < dst_size; ++i) dst[i] = (i & 1) ? *t2++ : *t1++;
    return true;
}

dm_result dm_exr_decode(const uint8_t *data, size_t size, const char *what, dm_exr_file *f, dm_error *err)
{
    memset(f, 0, sizeof *f);
    cursor c = {.p = data, .size = size};
    header h = {0};
    dm_result rc = parse_header(&c, what, f, &h, err);
    if (rc != DM_OK) return rc;

    const int w = f->width, hgt = f->height, nc = f->channel_count;
    const int lpc = f->compression == 3 ? 16 : 1;
    const int chunks = (hgt + lpc - 1) / lpc;
    size_t line_size = 0; /* bytes of one line, every channel */
    for (int k = 0; k < nc; ++k) line_size += (size_t)w * (f->types[k] == 1 ? 2 : 4);
    /* the allocation bound: nothing decodes to more than ~1032x its zlib stream */
    const size_t total = line_size * (size_t)hgt;
    if (total / 1100 > size)
        return dm_fail(err, DM_ERR_FORMAT, "%s: %dx%d with %d channels (%zu bytes) cannot come from %zu bytes", what,
                       w, hgt, nc, total, size);
    if ((size_t)chunks > (size - c.at) / 8)
        return dm_fail(err, DM_ERR_FORMAT, "%s: the offset table of %d chunks runs past the end of the file", what,
                       chunks);
    uint64_t *offsets = malloc((size_t)chunks * sizeof *offsets);
    uint8_t *seen = calloc((size_t)chunks, 1);
    const size_t chunk_size = line_size * (size_t)(hgt < lpc ? hgt : lpc);
    uint8_t *raw = malloc(chunk_size), *tmp = malloc(chunk_size);
    f->planes = malloc((size_t)nc * w * hgt * sizeof(float));
    if (!offsets || !seen || !raw || !tmp || !f->planes) {
        rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: cannot allocate %dx%d x %d channels", what, w, hgt, nc);
        goto done;
    }
    for (int i = 0; i < chunks; ++i) offsets[i] = get_u64(&c);
    const size_t data_start = c.at;
    for (int i = 0; i < chunks && rc == DM_OK; ++i) {
        if (offsets[i] < data_start || offsets[i] > size - 8) {
            rc = dm_fail(err, DM_ERR_FORMAT, "%s: chunk %d: offset %llu outside the data [%zu, %zu)", what, i,
                         (unsigned long long)offsets[i], data_start, size);
            break;
        }
        cursor k = {.p = data, .size = size, .at = (size_t)offsets[i]};
        int32_t y = get_i32(&k), packed = get_i32(&k);
        int64_t rel = (int64_t)y - h.ymin;
        if (rel < 0 || rel >= hgt || rel % lpc) {
            rc = dm_fail(err, DM_ERR_FORMAT, "%s: chunk %d: first line %d, expected a multiple of %d from %d to %d",
                         what, i, (int)y, lpc, (int)h.ymin, (int)h.ymax);
            break;
        }
        int ci = (int)(rel / lpc);
        if (seen[ci]) {
            rc = dm_fail(err, DM_ERR_FORMAT, "%s: chunk %d: line %d appears twice", what, i, (int)y);
            break;
        }
        seen[ci] = 1;
        int lines = hgt - (int)rel < lpc ? hgt - (int)rel : lpc;
        size_t want = line_size * (size_t)lines;
        if (packed <= 0 || (size_t)packed > size - k.at || (size_t)packed > want) {
            rc = dm_fail(err, DM_ERR_FORMAT, "%s: chunk at line %d: %d bytes, expected 1..%zu within the file", what,
                         (int)y, (int)packed, want);
            break;
        }
        const uint8_t *src = data + k.at;
        if ((size_t)packed == want) { /* stored: uncompressed, or compression did not pay */
            memcpy(raw, src, want);
        } else if (f->compression == 0 || !unzip_chunk(src, (size_t)packed, raw, want, tmp)) {
            rc = dm_fail(err, DM_ERR_FORMAT, "%s: chunk at line %d: %d bytes do not %s to %zu", what, (int)y,
                         (int)packed, f->compression ? "inflate" : "hold the uncompressed lines", want);
            break;
        }
        /* lines of every channel in turn; file line rel+j is memory row hgt−1−(rel+j) */
        const uint8_t *q = raw;
        for (int j = 0; j < lines && rc == DM_OK; ++j) {
            size_t row = (size_t)(hgt - 1 - ((int)rel + j));
            for (int ch = 0; ch < nc; ++ch) {
                float *dst = f->planes + ((size_t)ch * hgt + row) * w;
                for (int x = 0; x < w; ++x) {
                    float v;
                    if (f->types[ch] == 1) {
                        v = dm_half_to_float((uint16_t)(q[0] | q[1] << 8));
                        q += 2;
                    } else {
                        uint32_t u = rd_u32(q);
                        memcpy(&v, &u, 4);
                        q += 4;
                    }
                    if (!isfinite(v)) {
                        rc = dm_fail(err, DM_ERR_NON_FINITE, "%s: channel %s, pixel (%d, %d): %s", what, f->names[ch],
                                     x + (int)h.xmin, (int)y + j, isnan(v) ? "NaN" : "Inf");
                        break;
                    }
                    dst[x] = v;
                }
                if (rc != DM_OK) break;
            }
        }
    }
    if (rc == DM_OK && h.has_prov) {
        char *json = malloc(h.prov_size + 1);
        if (!json) {
            rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: provenance", what);
        } else {
            memcpy(json, data + h.prov_at, h.prov_size);
            json[h.prov_size] = 0;
            rc = dm_prov_from_json(&f->prov, json, what, err);
            f->has_provenance = rc == DM_OK;
            free(json);
        }
    }
done:
    free(offsets);
    free(seen);
    free(raw);
    free(tmp);
    if (rc != DM_OK) {
        free(f->planes);
        memset(f, 0, sizeof *f);
    }
    return rc;
}

dm_result dm_exr_load(const char *path, dm_exr_file *out, dm_error *err)
{
    memset(out, 0, sizeof *out);
    char *data = NULL;
    size_t size = 0;
    dm_result rc = dm_input_read(path, DM_INPUT_IMAGE, &data, &size, err);
    if (rc != DM_OK) return rc;
    rc = dm_exr_decode((const uint8_t *)data, size, path, out, err);
    free(data);
    return rc;
}

void dm_exr_file_free(dm_exr_file *f)
{
    if (!f) return;
    free(f->planes);
    memset(f, 0, sizeof *f);
}

const float *dm_exr_file_channel(const dm_exr_file *f, const char *name)
{
    for (int k = 0; k < f->channel_count; ++k)
        if (!strcmp(f->names[k], name)) return f->planes + (size_t)k * f->width * f->height;
    return NULL;
}
