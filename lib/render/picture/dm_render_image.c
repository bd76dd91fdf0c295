#include "render/dm_render_image.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <zlib.h>

#include "core/dm_file.h"
#include "core/dm_math.h"
#include "core/dm_png.h"

dm_result dm_render_write_png(const char *path, int width, int height, const uint8_t *rgba,
                              const dm_provenance *prov, dm_error *err)
{
    return dm_png_write_pixels(path, width, height, 4, 8, rgba, prov, NULL, 0, err);
}

/* ---- EXR ------------------------------------------------------------------------------ */

typedef struct wbuf {
    uint8_t *p;
    size_t len, cap;
    int failed;
} wbuf;

static void wb(wbuf *b, const void *data, size_t n)
{
    if (b->failed) return;
    if (b->len + n > b->cap) {
        size_t cap = (b->cap ? b->cap * 2 : 4096) + n;
        uint8_t *q = realloc(b->p, cap);
        if (!q) {
            b->failed = 1;
            return;
        }
        b->p = q, b->cap = cap;
    }
    memcpy(b->p + b->len, data, n);
    b->len += n;
}
static void wb_i32(wbuf *b, int32_t v)
{
    uint8_t x[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    wb(b, x, 4);
}
static void wb_u64(wbuf *b, uint64_t v)
{
    for (int i = 0; i < 8; ++i) {
        uint8_t x = (uint8_t)(v >> (8 * i));
        wb(b, &x, 1);
    }
}
static void wb_f32(wbuf *b, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    wb_i32(b, (int32_t)u);
}
static void wb_attr(wbuf *b, const char *name, const char *type, int32_t size)
{
    wb(b, name, strlen(name) + 1);
    wb(b, type, strlen(type) + 1);
    wb_i32(b, size);
}

dm_result dm_render_write_exr(const char *path, int width, int height, const float *rgba,
                              const dm_provenance *prov, dm_error *err)
{
    size_t n = (size_t)width * (size_t)height * 4, at;
    size_t bad = dm_count_nonfinite(rgba, n, &at);
    if (bad) /* rows bottom-up in memory, top-down in the file: the file's row is named */
        return dm_fail(err, DM_ERR_NON_FINITE,
                       "%s: %zu of %zu values are NaN or infinite, the first at pixel (%zu, %zu) channel %zu; nothing "
                       "written",
                       path, bad, n, at / 4 % (size_t)width, (size_t)height - 1 - at / 4 / (size_t)width, at % 4);
    char *json = malloc(16384);
    if (!json) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: cannot allocate", path);
    dm_result rc = dm_prov_to_json(prov, json, 16384, err);
    if (rc != DM_OK) {
        free(json);
        return rc;
    }
    wbuf b = {0};
    static const uint8_t magic[4] = {0x76, 0x2f, 0x31, 0x01};
    wb(&b, magic, 4);
    wb_i32(&b, 2); /* version 2, scanline, no flags */
    static const char *chans[4] = {"A", "B", "G", "R"}; /* sorted, as EXR requires */
    static const int src_channel[4] = {3, 2, 1, 0};
    wb_attr(&b, "channels", "chlist", 4 * (2 + 16) + 1);
    for (int c = 0; c < 4; ++c) {
        wb(&b, chans[c], 2);
        wb_i32(&b, 2); /* FLOAT */
        static const uint8_t plinear_reserved[4] = {0, 0, 0, 0};
        wb(&b, plinear_reserved, 4);
        wb_i32(&b, 1);
        wb_i32(&b, 1);
    }
    wb(&b, "", 1);
    static const uint8_t zero = 0;
    wb_attr(&b, "compression", "compression", 1);
    wb(&b, &zero, 1);
    for (int w = 0; w < 2; ++w) {
        wb_attr(&b, w ? "displayWindow" : "dataWindow", "box2i", 16);
        wb_i32(&b, 0), wb_i32(&b, 0), wb_i32(&b, width - 1), wb_i32(&b, height - 1);
    }
    wb_attr(&b, "lineOrder", "lineOrder", 1);
    wb(&b, &zero, 1);
    wb_attr(&b, "pixelAspectRatio", "float", 4);
    wb_f32(&b, 1.0f);
    wb_attr(&b, "screenWindowCenter", "v2f", 8);
    wb_f32(&b, 0.0f), wb_f32(&b, 0.0f);
    wb_attr(&b, "screenWindowWidth", "float", 4);
    wb_f32(&b, 1.0f);
    wb_attr(&b, "dermis.provenance", "string", (int32_t)strlen(json));
    wb(&b, json, strlen(json));
    wb(&b, "", 1); /* end of header */
    free(json);
    const uint64_t block = 8 + (uint64_t)width * 4 * 4;
    const uint64_t first = b.len + (uint64_t)height * 8;
    for (int y = 0; y < height; ++y) wb_u64(&b, first + (uint64_t)y * block);
    for (int y = 0; y < height && !b.failed; ++y) {
        wb_i32(&b, y);
        wb_i32(&b, width * 16);
        const float *row = rgba + (size_t)(height - 1 - y) * width * 4;
        for (int c = 0; c < 4; ++c)
            for (int x = 0; x < width; ++x) wb_f32(&b, row[(size_t)x * 4 + src_channel[c]]);
    }
    if (b.failed) {
        free(b.p);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: cannot allocate the EXR buffer", path);
    }
    dm_atomic_file af;
    rc = dm_atomic_open(&af, path, err);
    if (rc == DM_OK) {
        if (fwrite(b.p, 1, b.len, af.fp) != b.len) {
            dm_atomic_abort(&af);
            rc = dm_fail(err, DM_ERR_FILE_WRITE, "%s: write failed", path);
        } else {
            rc = dm_atomic_commit(&af, err);
        }
    }
    free(b.p);
    return rc;
}
