/* png_inflate.h — a minimal, independent PNG decoder for tests (zlib inflate + the five
 * row filters, 8-bit and 16-bit, non-interlaced). It exists so that tests can check a
 * file's row order and values without going through the library that wrote it.
 * Returns pixels top-down as in the file (16-bit samples big-endian-decoded), or NULL. */
#ifndef TEST_PNG_INFLATE_H
#define TEST_PNG_INFLATE_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

static inline uint32_t tpng_be32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static inline int tpng_paeth(int a, int b, int c)
{
    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/* *samples gets width*height*channels values (uint16 for both depths). */
static inline uint16_t *tpng_read(const char *path, int *width, int *height, int *channels, int *bits)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *buf = malloc((size_t)n);
    if (!buf || fread(buf, 1, (size_t)n, f) != (size_t)n) {
        fclose(f);
        free(buf);
        return NULL;
    }
    fclose(f);
    static const unsigned char sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    if (n < 8 || memcmp(buf, sig, 8)) {
        free(buf);
        return NULL;
    }
    unsigned char *idat = NULL;
    size_t idat_n = 0;
    int ct = 0;
    for (long p = 8; p + 12 <= n;) {
        uint32_t len = tpng_be32(buf + p);
        const unsigned char *type = buf + p + 4, *data = buf + p + 8;
        if (!memcmp(type, "IHDR", 4)) {
            *width = (int)tpng_be32(data);
            *height = (int)tpng_be32(data + 4);
            *bits = data[8];
            ct = data[9];
        } else if (!memcmp(type, "IDAT", 4)) {
            idat = realloc(idat, idat_n + len);
            memcpy(idat + idat_n, data, len);
            idat_n += len;
        }
        p += 12 + (long)len;
    }
    free(buf);
    *channels = ct == 0 ? 1 : ct == 4 ? 2 : ct == 2 ? 3 : ct == 6 ? 4 : 0;
    if (!*channels || (*bits != 8 && *bits != 16)) {
        free(idat);
        return NULL;
    }
    size_t bpp = (size_t)*channels * (*bits / 8), row = (size_t)*width * bpp;
    uLongf raw_n = (uLongf)((row + 1) * (size_t)*height);
    unsigned char *raw = malloc(raw_n);
    if (uncompress(raw, &raw_n, idat, (uLong)idat_n) != Z_OK) {
        free(idat);
        free(raw);
        return NULL;
    }
    free(idat);
    unsigned char *img = calloc(row * (size_t)*height, 1);
    for (int y = 0; y < *height; ++y) {
        unsigned char *src = raw + (size_t)y * (row + 1), *dst = img + (size_t)y * row;
        const unsigned char *up = y ? img + (size_t)(y - 1) * row : NULL;
        for (size_t i = 0; i < row; ++i) {
            int a = i >= bpp ? dst[i - bpp] : 0, b = up ? up[i] : 0, c = (up && i >= bpp) ? up[i - bpp] : 0;
            int x = src[1 + i];
            switch (src[0]) {
            case 0: dst[i] = (unsigned char)x; break;
            case 1: dst[i] = (unsigned char)(x + a); break;
            case 2: dst[i] = (unsigned char)(x + b); break;
            case 3: dst[i] = (unsigned char)(x + (a + b) / 2); break;
            default: dst[i] = (unsigned char)(x + tpng_paeth(a, b, c)); break;
            }
        }
    }
    free(raw);
    size_t count = (size_t)*width * *height * *channels;
    uint16_t *out = malloc(count * sizeof *out);
    for (size_t i = 0; i < count; ++i)
        out[i] = *bits == 8 ? img[i] : (uint16_t)(img[2 * i] << 8 | img[2 * i + 1]);
    free(img);
    return out;
}

#endif
