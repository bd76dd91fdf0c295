/* The runtime's strict EXR reader (core/dm_exr_read.h) against files written by the
 * offline side's OpenEXR writer (image/dm_exr.h, ZIP): every sample back bit for bit
 * (FLOAT) or exactly as its half (HALF), rows bottom-up, provenance back; then every
 * truncation and single-byte corruption of a small file is either decoded or refused
 * with a message, never a crash (ASan in config=sanitize). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image/dm_exr.h"
#include "core/dm_exr_read.h"
#include "core/dm_file.h"
#include "../common/tmpdir.h"

static char dir[512];

static float value(int c, int x, int y)
{
    /* varied, signed, with exponents well outside half's range for the FLOAT channels */
    return (float)((c + 1) * 0.37 * sin(0.13 * x + 0.29 * y + c) * pow(10.0, (x + 2 * y) % 9 - 4));
}

/* Writes a w x h file with R, G (FLOAT), B (HALF), A (FLOAT coverage 0/1). */
static void write_test_file(const char *path, int w, int h, float **planes)
{
    for (int c = 0; c < 4; ++c) {
        planes[c] = malloc((size_t)w * h * sizeof(float));
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                planes[c][(size_t)y * w + x] = c == 3 ? (float)((x + y) % 3 != 0) : value(c, x, y);
    }
    dm_exr_channel ch[4] = {{"R", planes[0], DM_EXR_FLOAT},
                            {"G", planes[1], DM_EXR_FLOAT},
                            {"B", planes[2], DM_EXR_HALF},
                            {"A", planes[3], DM_EXR_FLOAT}};
    dm_provenance p;
    dm_prov_init(&p, "test_exr_read");
    dm_prov_add_string(&p, "mode", "texture-space");
    dm_prov_add_int(&p, "size", w);
    dm_error err = {0};
    cr_assert_eq(dm_exr_write(path, w, h, ch, 4, &p, &err), DM_OK, "%s", err.detail);
}

static void check_roundtrip(int w, int h)
{
    cr_assert_not_null(test_tmpdir(dir, sizeof dir));
    char path[600];
    snprintf(path, sizeof path, "%s/t.exr", dir);
    float *planes[4];
    write_test_file(path, w, h, planes);
    dm_exr_file f;
    dm_error err = {0};
    cr_assert_eq(dm_exr_load(path, &f, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(f.width, w);
    cr_assert_eq(f.height, h);
    cr_assert_eq(f.channel_count, 4);
    cr_assert_eq(f.compression, 3, "dm_exr_write uses ZIP");
    cr_assert_str_eq(f.names[0], "A"); /* sorted, as the file stores them */
    cr_assert(f.has_provenance);
    cr_assert_str_eq(f.prov.tool, "test_exr_read");
    cr_assert_str_eq(dm_prov_find(&f.prov, "mode")->s, "texture-space");
    static const char *names[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c) {
        const float *got = dm_exr_file_channel(&f, names[c]);
        cr_assert_not_null(got);
        for (size_t i = 0; i < (size_t)w * h; ++i) {
            float want = planes[c][i];
            if (c == 2) { /* HALF: the writer rounds to nearest half; compare with that */
                float a = fabsf(want);
                float ulp = a < 6.103515625e-05f ? 5.9604644775390625e-08f : ldexpf(1.0f, ilogbf(a) - 10);
                cr_assert(fabsf(got[i] - want) <= 0.5f * ulp + 1e-30f, "B[%zu]: %g vs %g", i, got[i], want);
            } else {
                cr_assert(memcmp(&got[i], &want, 4) == 0, "%s[%zu]: %a vs %a", names[c], i, got[i], want);
            }
        }
    }
    cr_assert_null(dm_exr_file_channel(&f, "Z"));
    dm_exr_file_free(&f);
    for (int c = 0; c < 4; ++c) free(planes[c]);
    remove(path);
    rmdir(dir);
}

Test(exr_read, zip_written_by_openexr_bit_for_bit)
{
    check_roundtrip(37, 53); /* 4 ZIP chunks, the last one short; odd width */
    check_roundtrip(1, 1);
    check_roundtrip(256, 16);
}

static uint8_t *small_file(size_t *size)
{
    cr_assert_not_null(test_tmpdir(dir, sizeof dir));
    char path[600];
    snprintf(path, sizeof path, "%s/s.exr", dir);
    float *planes[4];
    write_test_file(path, 9, 20, planes);
    for (int c = 0; c < 4; ++c) free(planes[c]);
    char *data = NULL;
    dm_error err = {0};
    cr_assert_eq(dm_read_file(path, &data, size, &err), DM_OK);
    remove(path);
    rmdir(dir);
    return (uint8_t *)data;
}

Test(exr_read, every_truncation_is_an_error_with_a_message)
{
    size_t size;
    uint8_t *data = small_file(&size);
    for (size_t n = 0; n < size; ++n) {
        uint8_t *cut = malloc(n ? n : 1); /* exactly n bytes: ASan sees any overread */
        memcpy(cut, data, n);
        dm_exr_file f;
        dm_error err = {0};
        dm_result rc = dm_exr_decode(cut, n, "cut.exr", &f, &err);
        cr_assert_neq(rc, DM_OK, "a file cut to %zu of %zu bytes decoded", n, size);
        cr_assert(err.detail[0] && strstr(err.detail, "cut.exr"), "no message at %zu bytes", n);
        cr_assert_null(f.planes);
        free(cut);
    }
    free(data);
}

Test(exr_read, every_byte_corruption_is_decoded_or_refused)
{
    size_t size;
    uint8_t *data = small_file(&size);
    uint8_t *copy = malloc(size);
    int refused = 0;
    static const uint8_t flips[] = {0x01, 0x80, 0xff};
    for (size_t i = 0; i < size; ++i)
        for (size_t k = 0; k < sizeof flips; ++k) {
            memcpy(copy, data, size);
            copy[i] ^= flips[k];
            dm_exr_file f;
            dm_error err = {0};
            if (dm_exr_decode(copy, size, "flip.exr", &f, &err) == DM_OK) {
                for (size_t j = 0; j < (size_t)f.channel_count * f.width * f.height; ++j)
                    cr_assert(isfinite(f.planes[j]));
            } else {
                cr_assert(err.detail[0], "byte %zu ^ 0x%02x: no message", i, flips[k]);
                ++refused;
            }
            dm_exr_file_free(&f);
        }
    cr_assert_gt(refused, 0);
    free(copy);
    free(data);
}

Test(exr_read, refuses_what_it_does_not_support)
{
    size_t size;
    uint8_t *data = small_file(&size);
    dm_exr_file f;
    dm_error err = {0};
    uint8_t *c = malloc(size);
    memcpy(c, data, size);
    c[5] |= 0x02; /* version flags: tiled */
    cr_assert_eq(dm_exr_decode(c, size, "tiled.exr", &f, &err), DM_ERR_UNSUPPORTED);
    cr_assert(strstr(err.detail, "tiled"), "%s", err.detail);
    memcpy(c, data, size);
    c[0] = 'P';
    cr_assert_eq(dm_exr_decode(c, size, "png.exr", &f, &err), DM_ERR_FORMAT);
    cr_assert(strstr(err.detail, "not an OpenEXR file"), "%s", err.detail);
    /* the compression byte: find the attribute and set PIZ (4) */
    memcpy(c, data, size);
    uint8_t *at = NULL;
    for (size_t i = 0; i + 24 < size && !at; ++i)
        if (!memcmp(c + i, "compression\0compression", 24)) at = c + i;
    cr_assert_not_null(at);
    at[24 + 4] = 4;
    cr_assert_eq(dm_exr_decode(c, size, "piz.exr", &f, &err), DM_ERR_UNSUPPORTED);
    cr_assert(strstr(err.detail, "compression 4"), "%s", err.detail);
    free(c);
    free(data);
}

/* The offline reader (image/dm_exr.h) and what fuzz_bake_exr found: OpenEXR allocates what a
 * header or chunk claims before reading it, so a 1 KiB file claiming a data window 218
 * million texels wide made it ask for 3 GB. Refused now: sides beyond DM_EXR_SIDE_MAX; a chunk
 * claiming more bytes than the file holds is refused too (OpenEXR's leader check). */
static uint8_t *patched(const char *path, size_t *size)
{
    uint8_t *d = NULL;
    cr_assert_eq(dm_read_file(path, (char **)&d, size, NULL), DM_OK);
    return d;
}

static void write_bytes(const char *path, const uint8_t *d, size_t size)
{
    FILE *fp = fopen(path, "wb");
    cr_assert_not_null(fp);
    cr_assert_eq(fwrite(d, 1, size, fp), size);
    fclose(fp);
}

Test(exr_read, offline_reader_refuses_claims_the_file_cannot_hold)
{
    cr_assert_not_null(test_tmpdir(dir, sizeof dir));
    char path[600], bad[600];
    snprintf(path, sizeof path, "%s/t.exr", dir);
    snprintf(bad, sizeof bad, "%s/bad.exr", dir);
    float *planes[4];
    write_test_file(path, 8, 4, planes);
    dm_exr_image img;
    dm_error err = {0};
    cr_assert_eq(dm_exr_read(path, &img, &err), DM_OK, "%s", err.detail);
    dm_exr_free(&img);

    size_t size;
    uint8_t *d = patched(path, &size);
    uint8_t *dw = NULL; /* "dataWindow\0box2i\0", int32 size, then xmin ymin xmax ymax */
    for (size_t i = 0; i + 17 < size && !dw; ++i)
        if (!memcmp(d + i, "dataWindow\0box2i\0", 17)) dw = d + i + 17 + 4;
    cr_assert_not_null(dw);
    int32_t xmax = 218103815;
    memcpy(dw + 8, &xmax, 4);
    write_bytes(bad, d, size);
    cr_assert_eq(dm_exr_read(bad, &img, &err), DM_ERR_FORMAT);
    cr_assert(strstr(err.detail, "218103816x4") && strstr(err.detail, "out of range"), "%s", err.detail);
    dm_exr_free(&img);
    free(d);

    /* the one chunk's packed size (after its int32 line number) made larger than the file */
    d = patched(path, &size);
    size_t end = 8; /* magic, version, then attributes up to an empty name */
    while (end < size && d[end]) {
        end += strlen((const char *)d + end) + 1; /* name */
        end += strlen((const char *)d + end) + 1; /* type */
        int32_t n;
        memcpy(&n, d + end, 4);
        end += 4 + (size_t)n;
    }
    uint64_t off;
    memcpy(&off, d + end + 1, 8); /* the offset table after the header's terminating 0 */
    cr_assert(off + 8 < size);
    int32_t huge = 0x7fffffff;
    memcpy(d + off + 4, &huge, 4);
    write_bytes(bad, d, size);
    cr_assert_eq(dm_exr_read(bad, &img, &err), DM_ERR_FORMAT);
    cr_assert(strstr(err.detail, "bad.exr") && strstr(err.detail, "chunk"), "%s", err.detail); /* OpenEXR's own leader check */
    dm_exr_free(&img);
    free(d);
    for (int c = 0; c < 4; ++c) free(planes[c]);
    remove(path);
    remove(bad);
    rmdir(dir);
}
