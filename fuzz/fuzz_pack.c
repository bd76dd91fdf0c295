/* libFuzzer target: the pack reader (dm_pack_open_memory), in three modes chosen by the
 * first byte of the input:
 *  - odd: the input is a pack; after the mutation every blob's checksum in the manifest is
 *    rewritten to match its mutated bytes and the header+manifest checksum is recomputed,
 *    so the fuzzer reaches the manifest schema, the layout and the content checks of every
 *    blob kind (a valid pack's first byte, 0x89, is odd: blob checksum failures themselves
 *    are covered by test_pack_bad's every-bit-flip test);
 *  - low nibble 0xe (VALUES): the input edits the values of a valid small pack built here
 *    (one per subsurface technique), blob values and the manifest's t_range and
 *    layer_values, with plausible and absurd numbers (0, -0, 1e-38, 1e38, -1e38, FLT_MAX,
 *    huge indices, raw bits...); every checksum is right, so only the semantic checks
 *    (pack/dm_pack_semantic.h) stand. Whatever opens is then checked here, independently,
 *    to be finite and in the documented ranges;
 *  - any other even byte: the bytes as they are.
 * Every refusal must carry a message. */
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_hash.h"
#include "pack/dm_pack.h"
#include "pack/dm_pack_impl.h"
#include "pack/dm_pack_semantic.h"
#include "core/dm_profile.h"
#include "core/dm_ssss_kernel.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* --- checksum-fixing mode ----------------------------------------------------------- */

/* Rewrites each entry's "xxh3" in the manifest to the hash of the bytes it names. */
static void fix_blob_checksums(uint8_t *buf, size_t size, uint64_t msize)
{
    dm_pack scratch;
    memset(&scratch, 0, sizeof scratch);
    dm_error err = {0};
    if (dm_pack_manifest_parse(&scratch, buf + DM_PACK_HEADER_SIZE, msize, &err) == DM_OK) {
        char *m = (char *)buf + DM_PACK_HEADER_SIZE;
        for (int k = 0; k < scratch.entry_count; ++k) {
            const dm_pack_entry *e = &scratch.entries[k];
            if (e->offset > size || e->size > size - e->offset) continue;
            char old[17], now[17];
            dm_pack_hex64(e->xxh3, old);
            dm_pack_hex64(dm_hash64(buf + e->offset, (size_t)e->size), now);
            /* the first "xxh3" value equal to the old one, inside the manifest */
            for (uint64_t i = 0; i + 16 <= msize; ++i)
                if (!memcmp(m + i, old, 16)) {
                    memcpy(m + i, now, 16);
                    break;
                }
        }
    }
    dm_pack_close(&scratch);
}

/* --- VALUES mode: a valid small pack, built here ------------------------------------ */

enum { BLOBS_MAX = 16, TECHNIQUES = 3 };

typedef struct blob {
    const char *name, *kind; /* kind: "texture", "mesh.vertices", ... */
    const char *format;      /* textures */
    int width, height, layers;
    uint8_t *data;
    size_t size;
    const char *extra; /* more manifest keys, "" for none */
} blob;

typedef struct base {
    blob b[BLOBS_MAX];
    int count;
    float t_range_max, layer_m[2]; /* editable manifest values */
} base;

static const char *const technique_names[TECHNIQUES] = {"texture-space", "screen-space", "pre-integrated"};

static blob *add(base *s, const char *name, const char *kind, const char *format, int w, int h, int layers,
                 size_t bytes)
{
    blob *b = &s->b[s->count++];
    *b = (blob){name, kind, format, w, h, layers, calloc(1, bytes ? bytes : 1), bytes, ""};
    return b;
}

static void fill(blob *b, const float *pattern, int period)
{
    float *f = (float *)(void *)b->data;
    for (size_t i = 0; i < b->size / 4; ++i) f[i] = pattern[i % (size_t)period];
}

static void add_text(base *s, const char *name, const char *kind, const char *text)
{
    blob *b = add(s, name, kind, NULL, 0, 0, 0, strlen(text));
    memcpy(b->data, text, b->size);
}

/* The pack of a scene with specular, energy conservation, environment lighting and
 * subsurface by `technique`: every entry it needs, each holding plausible values. */
static void base_build(base *s, int technique)
{
    memset(s, 0, sizeof *s);
    char scene[512];
    snprintf(scene, sizeof scene,
             "{\"mesh\": {\"path\": \"m.obj\", \"mm_per_unit\": 50}, \"environment\": {\"path\": \"a.hdr\", "
             "\"background\": false}, \"effects\": {\"specular\": true, \"energy_conservation\": true, "
             "\"environment_lighting\": true, \"subsurface\": {\"technique\": \"%s\"}}}",
             technique_names[technique]);
    add_text(s, "scene", "scene", scene);
    dm_profile p;
    dm_profile_gems3_skin(&p);
    char *json = NULL;
    if (dm_profile_to_json(&p, &json, NULL) == DM_OK) add_text(s, "profile", "profile", json);
    free(json);
    blob *v = add(s, "mesh.vertices", "mesh.vertices", NULL, 0, 0, 0, 3 * DM_PACK_VERTEX_STRIDE);
    float *f = (float *)(void *)v->data;
    for (int k = 0; k < 3; ++k) { /* a unit axis, normal +z, uv, tangent +x w = +1 */
        float vert[12] = {0, 0, 0, 0, 0, 1, 0.5f * (float)k, 0.25f, 1, 0, 0, 1};
        vert[k] = 1.0f;
        memcpy(f + 12 * k, vert, sizeof vert);
    }
    v->extra = "\"vertex_count\": 3, \"stride\": 48, \"attributes\": [{\"name\": \"position\", \"offset\": 0, "
               "\"components\": 3, \"type\": \"float32\"}, {\"name\": \"normal\", \"offset\": 12, \"components\": 3, "
               "\"type\": \"float32\"}, {\"name\": \"uv\", \"offset\": 24, \"components\": 2, \"type\": \"float32\"}, "
               "{\"name\": \"tangent\", \"offset\": 32, \"components\": 4, \"type\": \"float32\"}]";
    blob *ix = add(s, "mesh.indices", "mesh.indices", NULL, 0, 0, 0, 12);
    uint32_t tri[3] = {0, 1, 2};
    memcpy(ix->data, tri, sizeof tri);
    ix->extra = "\"index_count\": 3, \"type\": \"uint32\", \"primitive\": \"triangles\", "
                "\"vertices\": \"mesh.vertices\"";
    memset(add(s, "lut.beckmann", "texture", "r8", 4, 4, 1, 16)->data, 128, 16);
    fill(add(s, "lut.rho_dt", "texture", "r32f", 4, 4, 1, 64), (const float[]){0.1f}, 1);
    fill(add(s, "lut.env_brdf", "texture", "rg32f", 4, 4, 1, 128), (const float[]){0.5f, 0.1f}, 2);
    blob *sh = add(s, "env.sh", "env.sh", NULL, 0, 0, 0, 27 * 4);
    fill(sh, (const float[]){1.0f, 1.0f, 1.0f, 0.1f, -0.1f, 0.2f}, 6);
    sh->extra = "\"sh_order\": 2";
    fill(add(s, "env.specular", "texture", "rgba32f", 4, 2, 2, 2 * 4 * 2 * 16), (const float[]){2.0f, 1.0f, 0.5f, 1},
         4);
    s->layer_m[0] = 0.1f, s->layer_m[1] = 0.5f;
    s->t_range_max = 1.0f;
    if (technique == 0) {
        fill(add(s, "stretch", "texture", "rg32f", 4, 4, p.count, 4 * 4 * (size_t)p.count * 8),
             (const float[]){0.004f, 0.005f}, 2);
        memset(add(s, "stretch.mask", "texture", "r8", 4, 4, 1, 16)->data, 255, 16);
    } else if (technique == 1) {
        dm_ssss_kernel k;
        blob *kb = add(s, "sss.kernel", "texture", "rgba32f", 7, DM_SSSS_ROWS, 1, 7 * DM_SSSS_ROWS * 16);
        if (dm_ssss_kernel_fit(&p, 7, &k, NULL) == DM_OK) dm_ssss_kernel_texels(&k, (float *)(void *)kb->data);
        kb->extra = "\"t_range\": [0.02, 2.56]"; /* DM_SSSS_ROW0_MM_PER_PX and 2^7 times it */
    } else {
        fill(add(s, "sss.preintegrated", "texture", "rgba32f", 4, 2, 1, 4 * 2 * 16),
             (const float[]){0.5f, 0.4f, 0.3f, 1}, 4);
        fill(add(s, "sss.curvature", "texture", "r32f", 4, 4, 1, 64), (const float[]){0.02f}, 1);
    }
}

static void base_free(base *s)
{
    for (int k = 0; k < s->count; ++k) free(s->b[k].data);
}

#define PROV "{\"tool\": \"fuzz_pack\", \"version\": \"0\", \"input_hash\": \"\", \"params\": {}}"

/* The pack bytes (64-byte aligned, free them) of the base as it is now; NULL when out of memory. */
static uint8_t *base_assemble(base *s, size_t *size)
{
    size_t cap = 16384, msize = 0, blobs_offset = 0;
    char *m = malloc(cap);
    for (int pass = 0; m && pass < 8; ++pass) { /* offsets depend on the manifest's size: settle them */
        size_t at = blobs_offset, n = 0;
        n += (size_t)snprintf(m + n, cap - n,
                              "{\"format\": \"dermis-pack\", \"version\": 1, \"provenance\": " PROV ", \"entries\": [");
        for (int k = 0; k < s->count; ++k) {
            blob *b = &s->b[k];
            char hex[17];
            dm_pack_hex64(dm_hash64(b->data, b->size), hex);
            at = dm_pack_align(at);
            n += (size_t)snprintf(m + n, cap - n,
                                  "%s{\"name\": \"%s\", \"kind\": \"%s\", \"offset\": %zu, \"size\": %zu, \"xxh3\": "
                                  "\"%s\", \"provenance\": " PROV,
                                  k ? ", " : "", b->name, b->kind, at, b->size, hex);
            if (b->format)
                n += (size_t)snprintf(m + n, cap - n,
                                      ", \"format\": \"%s\", \"width\": %d, \"height\": %d, \"layers\": %d, "
                                      "\"levels\": 1",
                                      b->format, b->width, b->height, b->layers);
            if (!strcmp(b->name, "env.specular"))
                n += (size_t)snprintf(m + n, cap - n, ", \"layer_values\": [%.9g, %.9g]", (double)s->layer_m[0],
                                      (double)s->layer_m[1]);
            if (!strcmp(b->name, "sss.preintegrated"))
                n += (size_t)snprintf(m + n, cap - n, ", \"t_range\": [0, %.9g]", (double)s->t_range_max);
            n += (size_t)snprintf(m + n, cap - n, "%s%s}", b->extra[0] ? ", " : "", b->extra);
            at += b->size;
        }
        n += (size_t)snprintf(m + n, cap - n, "]}");
        msize = n;
        size_t settled = blobs_offset;
        blobs_offset = dm_pack_align(DM_PACK_HEADER_SIZE + msize);
        if (blobs_offset == settled) break;
    }
    size_t end = blobs_offset;
    for (int k = 0; k < s->count; ++k) end = dm_pack_align(end) + s->b[k].size;
    uint8_t *buf = m ? aligned_alloc(64, dm_pack_align(end)) : NULL;
    if (buf) {
        memset(buf, 0, dm_pack_align(end));
        memcpy(buf + DM_PACK_HEADER_SIZE, m, msize);
        size_t at = blobs_offset;
        for (int k = 0; k < s->count; ++k) {
            at = dm_pack_align(at);
            memcpy(buf + at, s->b[k].data, s->b[k].size);
            at += s->b[k].size;
        }
        dm_pack_header h = {DM_PACK_VERSION, 0, end, DM_PACK_HEADER_SIZE, msize, blobs_offset, 0, 0};
        dm_pack_header_encode(&h, buf);
        memcpy(buf, DM_PACK_MAGIC, 8);
        h.checksum = dm_pack_header_checksum(buf, m, msize);
        dm_pack_header_encode(&h, buf);
        memcpy(buf, DM_PACK_MAGIC, 8);
    }
    free(m);
    *size = end;
    return buf;
}

/* Plausible and absurd numbers; the last entry stands for the record's raw bits. */
static const float values[] = {0.0f,   -0.0f,  1e-38f, -1e-38f, 1e-45f, 1.0f,     -1.0f,    0.5f,  0.01f,
                               2.0f,   3.2f,   1e3f,   1001.0f, 1e6f,   1.1e6f,   1e18f,    2e18f, 1e38f,
                               -1e38f, -1e6f,  200.0f, 201.0f,  FLT_MAX, -FLT_MAX, 1.0005f, 1.01f, 0.0f};
enum { VALUE_COUNT = (int)(sizeof values / sizeof values[0]) };
static const uint32_t indices[] = {0, 1, 2, 3, 0x7fffffffu, 0xffffffffu};

static float value_of(uint8_t sel, uint32_t raw)
{
    if (sel % VALUE_COUNT == VALUE_COUNT - 1) {
        float f;
        memcpy(&f, &raw, 4);
        return f;
    }
    return values[sel % VALUE_COUNT];
}

/* Applies the records of 10 bytes: [target][value][position u32][raw u32]. Targets past
 * the blobs edit the manifest: t_range's end, layer_values[0], layer_values[1]. */
static void base_edit(base *s, const uint8_t *d, size_t n)
{
    for (; n >= 10; d += 10, n -= 10) {
        uint32_t pos = (uint32_t)d[2] | (uint32_t)d[3] << 8 | (uint32_t)d[4] << 16 | (uint32_t)d[5] << 24;
        uint32_t raw = (uint32_t)d[6] | (uint32_t)d[7] << 8 | (uint32_t)d[8] << 16 | (uint32_t)d[9] << 24;
        int target = d[0] % (s->count + 3);
        float v = value_of(d[1], raw);
        if (target == s->count) s->t_range_max = v;
        else if (target > s->count) s->layer_m[target - s->count - 1] = v;
        else {
            blob *b = &s->b[target];
            if (!strcmp(b->kind, "scene") || !strcmp(b->kind, "profile") || b->size < 4) continue;
            size_t at = pos % (b->size / 4);
            if (!strcmp(b->kind, "mesh.indices"))
                memcpy(b->data + 4 * at, d[1] % 7 == 6 ? &raw : &indices[d[1] % 7], 4);
            else if (!strcmp(b->name, "lut.beckmann") || !strcmp(b->name, "stretch.mask"))
                b->data[pos % b->size] = (uint8_t)raw;
            else
                memcpy(b->data + 4 * at, &v, 4);
        }
    }
}

/* --- the oracle: what opened holds what dm_pack_semantic.h promises ------------------- */

static void expect(int ok)
{
    if (!ok) abort();
}

static void all_in(const dm_pack_entry *e, double lo, double hi, int lo_open)
{
    const float *f = e->data;
    for (uint64_t i = 0; i < e->size / 4; ++i)
        expect((lo_open ? f[i] > lo : f[i] >= lo) && f[i] <= hi);
}

static void oracle(const dm_pack *pack)
{
    for (int k = 0; k < pack->entry_count; ++k) {
        const dm_pack_entry *e = &pack->entries[k];
        const float *f = e->data;
        if (!strcmp(e->name, "mesh.vertices")) {
            for (int64_t i = 0; i < e->vertex_count; ++i) {
                const float *q = f + 12 * i;
                for (int d = 0; d < 12; ++d) expect(isfinite(q[d]));
                for (int d = 0; d < 3; ++d) expect(fabs(q[d]) * pack->scene->mm_per_unit <= DM_PACK_POSITION_MAX_MM);
                expect(fabs(sqrt((double)q[3] * q[3] + (double)q[4] * q[4] + (double)q[5] * q[5]) - 1) <= 1e-3);
                expect(fabs(sqrt((double)q[8] * q[8] + (double)q[9] * q[9] + (double)q[10] * q[10]) - 1) <= 1e-3);
                expect(q[11] == 1.0f || q[11] == -1.0f);
            }
        } else if (!strcmp(e->name, "mesh.indices")) {
            for (int64_t i = 0; i < e->index_count; ++i) expect(((const uint32_t *)e->data)[i] < 3);
        } else if (!strcmp(e->name, "lut.rho_dt") || !strcmp(e->name, "lut.env_brdf")) {
            all_in(e, 0, DM_PACK_DIRECTIONAL_MAX, 0);
        } else if (!strcmp(e->name, "stretch")) {
            all_in(e, 0, DM_PACK_STRETCH_MAX_PER_MM, 1);
        } else if (!strcmp(e->name, "env.sh")) {
            for (int i = 0; i < 27; ++i) expect(fabsf(f[i]) <= DM_PACK_SH_MAX && (i >= 3 || f[i] >= 0));
        } else if (!strcmp(e->name, "env.specular")) {
            all_in(e, 0, DM_PACK_RADIANCE_MAX, 0);
            for (int i = 0; i < e->layers; ++i) {
                const float *m = e->layer_values;
                expect(m[i] >= 0.0099f && m[i] <= 2 && (!i || m[i] > m[i - 1]));
            }
        } else if (!strcmp(e->name, "sss.preintegrated")) {
            all_in(e, 0, DM_PACK_PREINT_MAX, 0);
            expect(e->t_range[0] == 0 && e->t_range[1] > 0 && e->t_range[1] <= DM_PACK_CURVATURE_MAX_PER_MM);
        } else if (!strcmp(e->name, "sss.curvature")) {
            all_in(e, -FLT_MAX, FLT_MAX, 0);
        } else if (!strcmp(e->name, "sss.kernel")) {
            for (int r = 0; r < e->height; ++r) {
                const float *g = f + 4 * (size_t)r * e->width;
                double sum[3] = {0, 0, 0};
                for (int a = 0; a < e->width; ++a) {
                    for (int c = 0; c < 3; ++c) expect(g[4 * a + c] >= 0), sum[c] += g[4 * a + c];
                    expect(!a || g[4 * a + 3] > g[4 * a - 1]);
                }
                for (int c = 0; c < 3; ++c) expect(fabs(sum[c] - 1) <= 1e-4);
            }
        }
    }
}

static void values_mode(const uint8_t *data, size_t size)
{
    static base bases[TECHNIQUES];
    static int built;
    if (!built) {
        for (int t = 0; t < TECHNIQUES; ++t) base_build(&bases[t], t);
        built = 1;
        for (int t = 0; t < TECHNIQUES; ++t) { /* the bases themselves are valid */
            size_t n;
            uint8_t *buf = base_assemble(&bases[t], &n);
            dm_pack pack;
            dm_error err = {0};
            if (!buf || dm_pack_open_memory(buf, n, "base.dpk", &pack, &err) != DM_OK) {
                fprintf(stderr, "fuzz_pack: base %s: %s\n", technique_names[t], err.detail);
                abort();
            }
            dm_pack_close(&pack);
            free(buf);
        }
    }
    base s = bases[size > 1 ? data[1] % TECHNIQUES : 0]; /* a copy: its blobs are copied below */
    for (int k = 0; k < s.count; ++k) {
        uint8_t *copy = malloc(s.b[k].size ? s.b[k].size : 1);
        memcpy(copy, s.b[k].data, s.b[k].size);
        s.b[k].data = copy;
    }
    if (size > 2) base_edit(&s, data + 2, size - 2);
    size_t n;
    uint8_t *buf = base_assemble(&s, &n);
    dm_pack pack;
    dm_error err = {0};
    if (buf && dm_pack_open_memory(buf, n, "values.dpk", &pack, &err) == DM_OK) oracle(&pack);
    else if (buf && !err.detail[0]) abort();
    dm_pack_close(&pack);
    free(buf);
    base_free(&s);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    if ((data[0] & 0x0f) == 0x0e) {
        values_mode(data, size);
        return 0;
    }
    bool fix = data[0] & 1;
    uint8_t *buf = aligned_alloc(64, ((size + 63) / 64) * 64);
    if (!buf) return 0;
    memcpy(buf, data, size);
    if (fix && size >= DM_PACK_HEADER_SIZE) {
        uint64_t msize = 0;
        for (int k = 7; k >= 0; --k) msize = (msize << 8) | buf[32 + k];
        if (msize <= size - DM_PACK_HEADER_SIZE) fix_blob_checksums(buf, size, msize);
        if (msize <= size - DM_PACK_HEADER_SIZE) {
            uint64_t sum = dm_pack_header_checksum(buf, buf + DM_PACK_HEADER_SIZE, (size_t)msize);
            for (int k = 0; k < 8; ++k) buf[56 + k] = (uint8_t)(sum >> (8 * k));
        }
    }
    dm_pack pack;
    dm_error err = {0};
    if (dm_pack_open_memory(buf, size, "fuzz.dpk", &pack, &err) == DM_OK) {
        /* touch every blob the reader hands out */
        volatile uint8_t x = 0;
        for (int k = 0; k < pack.entry_count; ++k) {
            const dm_pack_entry *e = &pack.entries[k];
            if (e->size) x ^= ((const uint8_t *)e->data)[0] ^ ((const uint8_t *)e->data)[e->size - 1];
        }
        (void)x;
    } else if (!err.detail[0]) {
        abort();
    }
    dm_pack_close(&pack);
    free(buf);
    return 0;
}
