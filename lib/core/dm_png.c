#include "core/dm_png.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include <zlib.h>

#include "core/dm_file.h"

static void put32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

static int write_chunk(FILE *f, const char type[4], const unsigned char *data, size_t size)
{
    unsigned char hdr[8];
    put32(hdr, (uint32_t)size);
    memcpy(hdr + 4, type, 4);
    uLong crc = crc32(0L, (const Bytef *)type, 4);
    if (size) crc = crc32(crc, data, (uInt)size);
    unsigned char tail[4];
    put32(tail, (uint32_t)crc);
    return fwrite(hdr, 1, 8, f) == 8 && (size == 0 || fwrite(data, 1, size, f) == size) && fwrite(tail, 1, 4, f) == 4;
}

static int write_text(FILE *f, const char *key, const char *value)
{
    size_t k = strlen(key), v = strlen(value);
    if (k < 1 || k > 79) return 0;
    unsigned char *buf = malloc(k + 1 + v);
    if (!buf) return 0;
    memcpy(buf, key, k);
    buf[k] = 0;
    memcpy(buf + k + 1, value, v);
    int ok = write_chunk(f, "tEXt", buf, k + 1 + v);
    free(buf);
    return ok;
}

dm_result dm_png_write_pixels(const char *path, int width, int height, int channels, int bits, const void *pixels,
                              const dm_provenance *prov, const dm_png_text *text, int text_count, dm_error *err)
{
    assert(path && (pixels || width * height == 0) && (text || text_count == 0));
    if (width <= 0 || height <= 0 || width > (1 << 24) || height > (1 << 24))
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: image size %dx%d out of range", path, width, height);
    if (channels < 1 || channels > 4 || (bits != 8 && bits != 16))
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: %d channels of %d bits: PNG needs 1..4 of 8 or 16", path,
                       channels, bits);
    static const unsigned char color_type[5] = {0, 0, 4, 2, 6};
    size_t bpp = (size_t)channels * (bits / 8);
    size_t row = (size_t)width * bpp;
    size_t raw_size = (row + 1) * (size_t)height;
    unsigned char *raw = malloc(raw_size);
    uLongf zsize = compressBound((uLong)raw_size);
    unsigned char *z = malloc(zsize);
    if (!raw || !z) {
        free(raw);
        free(z);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory for %dx%d", path, width, height);
    }
    /* Filter type 0 (none) on every row: simple, and zlib still compresses tables well. */
    for (int y = 0; y < height; ++y) {
        unsigned char *dst = raw + (size_t)y * (row + 1);
        const unsigned char *src = (const unsigned char *)pixels + (size_t)(height - 1 - y) * row;
        dst[0] = 0;
        if (bits == 8) {
            memcpy(dst + 1, src, row);
        } else {
            const uint16_t *s16 = (const uint16_t *)(const void *)src;
            for (size_t i = 0; i < row / 2; ++i) {
                dst[1 + 2 * i] = (unsigned char)(s16[i] >> 8);
                dst[2 + 2 * i] = (unsigned char)(s16[i] & 0xff);
            }
        }
    }
    int zr = compress2(z, &zsize, raw, (uLong)raw_size, 6);
    free(raw);
    if (zr != Z_OK) {
        free(z);
        return dm_fail(err, DM_ERR_INTERNAL, "%s: zlib compression failed (%d)", path, zr);
    }
    char json[16384];
    if (prov) {
        dm_result r = dm_prov_to_json(prov, json, sizeof json, err);
        if (r != DM_OK) {
            free(z);
            return r;
        }
    }
    dm_atomic_file af;
    dm_result r = dm_atomic_open(&af, path, err);
    if (r != DM_OK) {
        free(z);
        return r;
    }
    static const unsigned char sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    unsigned char ihdr[13];
    put32(ihdr, (uint32_t)width);
    put32(ihdr + 4, (uint32_t)height);
    ihdr[8] = (unsigned char)bits;
    ihdr[9] = color_type[channels];
    ihdr[10] = ihdr[11] = ihdr[12] = 0;
    int ok = fwrite(sig, 1, 8, af.fp) == 8 && write_chunk(af.fp, "IHDR", ihdr, 13);
    if (ok && prov) {
        char software[2 * DM_PROV_NAME_SIZE + 2];
        snprintf(software, sizeof software, "%s %s", prov->tool, prov->version);
        ok = write_text(af.fp, "Software", software) && write_text(af.fp, "dermis:provenance", json);
    }
    for (int k = 0; ok && k < text_count; ++k) ok = write_text(af.fp, text[k].key, text[k].value);
    ok = ok && write_chunk(af.fp, "IDAT", z, zsize) && write_chunk(af.fp, "IEND", NULL, 0);
    free(z);
    if (!ok) {
        dm_atomic_abort(&af);
        return dm_fail(err, DM_ERR_FILE_WRITE, "%s: write failed", path);
    }
    return dm_atomic_commit(&af, err);
}
