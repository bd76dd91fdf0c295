/* small_pack.h — a small valid pack built in memory (a few KiB: scene, LUTs, a mipmapped
 * layered texture, a three-vertex mesh, env.sh, optionally a profile), the fixture's knobs
 * that spoil one thing each, and the helpers that edit its manifest and expect the reader
 * to refuse it (test_pack, test_pack_bad, test_pack_env). */
#ifndef TEST_SMALL_PACK_H
#define TEST_SMALL_PACK_H

#include <criterion/criterion.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_lut.h"
#include "core/dm_brdf.h"
#include "core/dm_profile.h"
#include "core/dm_prov.h"
#include "pack/dm_pack.h"
#include "pack/dm_pack_write.h"

/* specular + energy conservation: needs scene, lut.beckmann (r8), lut.rho_dt (r32f) */
static const char *const scene_json = "{\"mesh\": {\"path\": \"head.obj\"}, "
                                "\"effects\": {\"specular\": true, \"energy_conservation\": true}}";

typedef struct fixture {
    bool skip_beckmann, nan_in_rho, bad_index, beckmann_as_float, no_tangent;
    int profile; /* 0: no "profile" entry; 1: the scene's (gems3-skin); 2: another */
} fixture;

/* A three-vertex mesh in the dermis layout (unit normals and tangents, as the reader wants
 * them); bad_index puts an index out of range. */
static inline void add_mesh(dm_pack_writer *wp, const dm_provenance *pp, bool bad_index, bool no_tangent)
{
    dm_error err = {0};
    dm_pack_entry d;
    float v[3 * 12] = {0};
    for (int k = 0; k < 3; ++k) {
        v[k * 12 + k] = 1.0f;                         /* position: a unit axis */
        v[k * 12 + DM_PACK_VERTEX_NORMAL / 4 + 2] = 1.0f; /* normal +z */
        v[k * 12 + DM_PACK_VERTEX_TANGENT / 4] = 1.0f;    /* tangent +x, w = +1 */
        v[k * 12 + DM_PACK_VERTEX_TANGENT / 4 + 3] = 1.0f;
    }
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "mesh.vertices");
    d.kind = DM_PACK_MESH_VERTICES;
    d.vertex_count = 3;
    d.stride = DM_PACK_VERTEX_STRIDE;
    d.attribute_count = no_tangent ? 3 : 4;
    const char *an[4] = {"position", "normal", "uv", "tangent"};
    const int ao[4] = {DM_PACK_VERTEX_POSITION, DM_PACK_VERTEX_NORMAL, DM_PACK_VERTEX_UV, DM_PACK_VERTEX_TANGENT};
    const int ac[4] = {3, 3, 2, 4};
    for (int k = 0; k < 4; ++k) {
        snprintf(d.attributes[k].name, sizeof d.attributes[k].name, "%s", an[k]);
        d.attributes[k].offset = ao[k];
        d.attributes[k].components = ac[k];
    }
    cr_assert_eq(dm_pack_writer_add(wp, &d, v, sizeof v, pp, &err), DM_OK, "%s", err.detail);

    uint32_t idx[3] = {0, 1, bad_index ? 7u : 2u};
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "mesh.indices");
    d.kind = DM_PACK_MESH_INDICES;
    d.index_count = 3;
    snprintf(d.vertices, sizeof d.vertices, "mesh.vertices");
    cr_assert_eq(dm_pack_writer_add(wp, &d, idx, sizeof idx, pp, &err), DM_OK, "%s", err.detail);
}

/* Adds the scene entry (`json`) to w. */
static inline void add_scene(dm_pack_writer *w, const dm_provenance *p, const char *json)
{
    dm_error err = {0};
    dm_pack_entry d;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "scene");
    d.kind = DM_PACK_SCENE;
    cr_assert_eq(dm_pack_writer_add(w, &d, json, strlen(json), p, &err), DM_OK, "%s", err.detail);
}

/* Builds a small pack in memory (64-byte aligned, free with free()). */
static inline uint8_t *build(const fixture *fx, size_t *size)
{
    dm_pack_writer w;
    dm_pack_writer_init(&w);
    dm_provenance p;
    dm_prov_init(&p, "test_pack");
    dm_prov_add_int(&p, "n", 1);
    dm_error err = {0};
    add_scene(&w, &p, scene_json);
    dm_pack_entry d;

    if (!fx->skip_beckmann) {
        dm_beckmann_lut lut;
        cr_assert_eq(dm_lut_bake_beckmann(16, 16, 0, 1, &lut, &err), DM_OK);
        if (fx->beckmann_as_float) {
            float f[256] = {0};
            d = dm_pack_texture_entry("lut.beckmann", DM_TEX_R32F, 16, 16);
            cr_assert_eq(dm_pack_writer_add(&w, &d, f, sizeof f, &p, &err), DM_OK, "%s", err.detail);
        } else {
            d = dm_pack_texture_entry("lut.beckmann", DM_TEX_R8, 16, 16);
            cr_assert_eq(dm_pack_writer_add(&w, &d, lut.texels, 256, &p, &err), DM_OK, "%s", err.detail);
        }
        dm_beckmann_lut_free(&lut);
    }
    dm_directional_lut dl;
    cr_assert_eq(dm_lut_bake_directional(8, 8, DM_SKIN_F0, 16, 1, &dl, &err), DM_OK);
    if (fx->nan_in_rho) dl.rho_dt[3 * 8 + 5] = NAN;
    d = dm_pack_texture_entry("lut.rho_dt", DM_TEX_R32F, 8, 8);
    cr_assert_eq(dm_pack_writer_add(&w, &d, dl.rho_dt, 64 * sizeof(float), &p, &err), DM_OK, "%s", err.detail);
    dm_directional_lut_free(&dl);

    /* a mipmapped rgba16f texture with 2 layers: level sizes and layout */
    uint16_t half[(4 * 4 + 2 * 2 + 1) * 2 * 4];
    for (size_t k = 0; k < sizeof half / sizeof half[0]; ++k) half[k] = 0x3c00; /* 1.0 */
    d = dm_pack_texture_entry("test.mipmapped", DM_TEX_RGBA16F, 4, 4);
    d.layers = 2;
    d.levels = 3;
    cr_assert_eq(dm_pack_writer_add(&w, &d, half, sizeof half, &p, &err), DM_OK, "%s", err.detail);

    add_mesh(&w, &p, fx->bad_index, fx->no_tangent);

    float sh[27];
    for (int k = 0; k < 27; ++k) sh[k] = 0.1f * k;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "env.sh");
    d.kind = DM_PACK_ENV_SH;
    d.sh_order = 2;
    cr_assert_eq(dm_pack_writer_add(&w, &d, sh, sizeof sh, &p, &err), DM_OK, "%s", err.detail);

    if (fx->profile) {
        dm_profile pr;
        dm_profile_gems3_skin(&pr);
        if (fx->profile == 2) pr.weight[5][0] *= 0.5;
        char *text = NULL;
        cr_assert_eq(dm_profile_to_json(&pr, &text, &err), DM_OK, "%s", err.detail);
        memset(&d, 0, sizeof d);
        snprintf(d.name, sizeof d.name, "profile");
        d.kind = DM_PACK_PROFILE;
        cr_assert_eq(dm_pack_writer_add(&w, &d, text, strlen(text), &p, &err), DM_OK, "%s", err.detail);
        free(text);
    }

    uint8_t *buf = NULL;
    cr_assert_eq(dm_pack_writer_build(&w, &p, &buf, size, &err), DM_OK, "%s", err.detail);
    dm_pack_writer_free(&w);
    return buf;
}

static inline uint8_t *build_valid(size_t *size)
{
    fixture fx = {0};
    return build(&fx, size);
}

/* Opens bytes (copied to an aligned buffer) and expects failure `code` (or any failure
 * when code is DM_OK) with a message containing needle. */
static inline void expect_refused(const uint8_t *bytes, size_t size, dm_result code, const char *needle)
{
    uint8_t *copy = aligned_alloc(64, (size / 64 + 1) * 64); /* C11: a multiple of the alignment */
    if (size) memcpy(copy, bytes, size);
    dm_pack pack;
    dm_error err = {0};
    dm_result r = dm_pack_open_memory(copy, size, "t.dpk", &pack, &err);
    cr_assert_neq(r, DM_OK, "accepted (size %zu)", size);
    if (code != DM_OK) cr_assert_eq(r, code, "%s instead of %s: %s", dm_result_name(r), dm_result_name(code), err.detail);
    cr_assert(strncmp(err.detail, "t.dpk", 5) == 0, "message does not name the file: %s", err.detail);
    if (needle) cr_assert(strstr(err.detail, needle), "'%s' not in: %s", needle, err.detail);
    dm_pack_close(&pack);
    free(copy);
}

/* Replaces the manifest by `json` (no longer than the original; padded with spaces)
 * and recomputes the header checksum, so that the manifest check itself is tested. */
static inline void set_manifest(uint8_t *buf, const char *json)
{
    uint64_t msize = 0;
    for (int k = 7; k >= 0; --k) msize = (msize << 8) | buf[32 + k];
    size_t n = strlen(json);
    cr_assert_leq(n, msize);
    memset(buf + 64, ' ', msize);
    memcpy(buf + 64, json, n);
    uint64_t sum = dm_pack_header_checksum(buf, buf + 64, msize);
    for (int k = 0; k < 8; ++k) buf[56 + k] = (uint8_t)(sum >> (8 * k));
}

static inline char *manifest_of(const uint8_t *buf)
{
    uint64_t msize = 0;
    for (int k = 7; k >= 0; --k) msize = (msize << 8) | buf[32 + k];
    char *m = malloc(msize + 1);
    memcpy(m, buf + 64, msize);
    m[msize] = '\0';
    return m;
}

/* Replaces the first occurrence of `from` after `after` in the manifest by `to`. */
static inline void edit_manifest(uint8_t *buf, const char *after, const char *from, const char *to)
{
    char *m = manifest_of(buf);
    char *a = strstr(m, after);
    cr_assert(a, "'%s' not in manifest", after);
    char *f = strstr(a, from);
    cr_assert(f, "'%s' not after '%s'", from, after);
    size_t out_size = strlen(m) + strlen(to) + 1;
    char *out = malloc(out_size);
    snprintf(out, out_size, "%.*s%s%s", (int)(f - m), m, to, f + strlen(from));
    set_manifest(buf, out);
    free(out);
    free(m);
}

#endif
