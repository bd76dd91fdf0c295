/* The .dpk pack: a valid pack round-trips without copies; every kind of bad input is
 * refused with a message naming the file, the field and what was expected, never a crash.
 * The packs here are small (a few KiB) so that every truncation and every bit flip can be
 * tried in well under a second. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bake/dm_lut.h"
#include "pack/dm_pack_write.h"
#include "core/dm_brdf.h"
#include "core/dm_hash.h"
#include "core/dm_lut_check.h"
#include "pack/dm_pack.h"
#include "pack/dm_pack_needs.h"
#include "core/dm_profile.h"

/* specular + energy conservation: needs scene, lut.beckmann (r8), lut.rho_dt (r32f) */
static const char *scene_json = "{\"mesh\": {\"path\": \"head.obj\"}, "
                                "\"effects\": {\"specular\": true, \"energy_conservation\": true}}";

typedef struct fixture {
    bool skip_beckmann, nan_in_rho, bad_index, beckmann_as_float, no_tangent;
    int profile; /* 0: no "profile" entry; 1: the scene's (gems3-skin); 2: another */
} fixture;

/* A three-vertex mesh in the dermis layout (unit normals and tangents, as the reader wants
 * them); bad_index puts an index out of range. */
static void add_mesh(dm_pack_writer *wp, const dm_provenance *pp, bool bad_index, bool no_tangent)
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

/* Builds a small pack in memory (64-byte aligned, free with free()). */
static uint8_t *build(const fixture *fx, size_t *size)
{
    dm_pack_writer w;
    dm_pack_writer_init(&w);
    dm_provenance p;
    dm_prov_init(&p, "test_pack");
    dm_prov_add_int(&p, "n", 1);
    dm_error err = {0};
    dm_pack_entry d;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "scene");
    d.kind = DM_PACK_SCENE;
    cr_assert_eq(dm_pack_writer_add(&w, &d, scene_json, strlen(scene_json), &p, &err), DM_OK, "%s", err.detail);

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

static uint8_t *build_valid(size_t *size)
{
    fixture fx = {0};
    return build(&fx, size);
}

/* Opens bytes (copied to an aligned buffer) and expects failure `code` (or any failure
 * when code is DM_OK) with a message containing needle. */
static void expect_refused(const uint8_t *bytes, size_t size, dm_result code, const char *needle)
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
static void set_manifest(uint8_t *buf, const char *json)
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

static char *manifest_of(const uint8_t *buf)
{
    uint64_t msize = 0;
    for (int k = 7; k >= 0; --k) msize = (msize << 8) | buf[32 + k];
    char *m = malloc(msize + 1);
    memcpy(m, buf + 64, msize);
    m[msize] = '\0';
    return m;
}

/* Replaces the first occurrence of `from` after `after` in the manifest by `to`. */
static void edit_manifest(uint8_t *buf, const char *after, const char *from, const char *to)
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

/* --- the valid pack ----------------------------------------------------------------- */

Test(pack, valid_pack_opens_without_copies)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    dm_pack pack;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open_memory(buf, size, "t.dpk", &pack, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(pack.entry_count, 7);
    for (int k = 0; k < pack.entry_count; ++k) {
        const dm_pack_entry *e = &pack.entries[k];
        cr_assert((const uint8_t *)e->data >= buf && (const uint8_t *)e->data + e->size <= buf + size, "copied");
        cr_assert_eq((uintptr_t)e->data % 64, 0);
        cr_assert_not_null(e->provenance_json);
    }
    const dm_pack_entry *t = dm_pack_find(&pack, "test.mipmapped");
    cr_assert_not_null(t);
    cr_assert_eq(dm_pack_texture_level_size(t, 0), 4 * 4 * 2 * 8);
    cr_assert_eq(dm_pack_texture_level_size(t, 2), 1 * 1 * 2 * 8);
    cr_assert_eq(dm_pack_texture_level_offset(t, 2), (4 * 4 + 2 * 2) * 2 * 8);
    const dm_pack_entry *vx = dm_pack_find(&pack, "mesh.vertices");
    cr_assert_eq(vx->stride, 48);
    cr_assert_str_eq(vx->attributes[3].name, "tangent");
    dm_scene sc;
    cr_assert_eq(dm_pack_scene(&pack, &sc, &err), DM_OK, "%s", err.detail);
    cr_assert(sc.effects[DM_EFFECT_SPECULAR]);
    dm_pack_close(&pack);
    dm_pack_close(&pack); /* safe twice */
    free(buf);
}

Test(pack, build_is_deterministic_and_file_round_trips)
{
    size_t a_size, b_size;
    uint8_t *a = build_valid(&a_size), *b = build_valid(&b_size);
    cr_assert_eq(a_size, b_size);
    cr_assert_eq(memcmp(a, b, a_size), 0);
    char path[] = "/tmp/dermis-test-pack-XXXXXX";
    int fd = mkstemp(path);
    cr_assert_geq(fd, 0);
    cr_assert_eq(write(fd, a, a_size), (ssize_t)a_size);
    close(fd);
    dm_pack pack;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open(path, &pack, &err), DM_OK, "%s", err.detail);
    cr_assert(pack.mapped);
    cr_assert_eq(memcmp(dm_pack_find(&pack, "env.sh")->data, dm_pack_find(&pack, "env.sh")->data, 108), 0);
    dm_pack_close(&pack);
    unlink(path);
    free(a);
    free(b);
}

Test(pack, writer_write_refuses_an_invalid_pack)
{
    fixture fx = {.nan_in_rho = true};
    dm_pack_writer w;
    dm_pack_writer_init(&w);
    (void)fx;
    dm_provenance p;
    dm_prov_init(&p, "test_pack");
    dm_error err = {0};
    /* a scene that needs lut.beckmann, packed without it */
    dm_pack_entry d;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "scene");
    d.kind = DM_PACK_SCENE;
    cr_assert_eq(dm_pack_writer_add(&w, &d, scene_json, strlen(scene_json), &p, &err), DM_OK);
    add_mesh(&w, &p, false, false);
    char path[] = "/tmp/dermis-test-pack-w-XXXXXX";
    int fd = mkstemp(path);
    close(fd);
    unlink(path);
    cr_assert_neq(dm_pack_writer_write(&w, path, &p, NULL, &err), DM_OK);
    cr_assert(strstr(err.detail, "missing required entry \"lut.beckmann\""), "%s", err.detail);
    cr_assert_neq(access(path, F_OK), 0, "a refused pack was written");
    dm_pack_writer_free(&w);
}

Test(pack, writer_refuses_size_not_matching_format)
{
    dm_pack_writer w;
    dm_pack_writer_init(&w);
    dm_provenance p;
    dm_prov_init(&p, "test_pack");
    dm_error err = {0};
    dm_pack_entry d = dm_pack_texture_entry("lut.beckmann", DM_TEX_R8, 16, 16);
    uint8_t t[255] = {0};
    cr_assert_eq(dm_pack_writer_add(&w, &d, t, sizeof t, &p, &err), DM_ERR_INVALID_ARGUMENT);
    cr_assert(strstr(err.detail, "255 bytes given, expected 256"), "%s", err.detail);
    dm_pack_writer_free(&w);
}

/* --- bad input: one test per kind ---------------------------------------------------- */

Test(pack_bad, truncated_at_every_length)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    for (size_t n = 0; n < size; ++n) expect_refused(buf, n, DM_OK, NULL);
    free(buf);
}

Test(pack_bad, truncated_with_a_consistent_header)
{
    /* file_size patched to the truncated length, checksum recomputed: the blob bounds fail */
    size_t size;
    uint8_t *buf = build_valid(&size);
    size_t n = size - 100;
    for (int k = 0; k < 8; ++k) buf[16 + k] = (uint8_t)((uint64_t)n >> (8 * k));
    char *m = manifest_of(buf);
    set_manifest(buf, m);
    free(m);
    expect_refused(buf, n, DM_ERR_FORMAT, "outside the blob area");
    free(buf);
}

Test(pack_bad, flipped_bit_anywhere)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    int tried = 0;
    for (size_t byte = 0; byte < size; ++byte)
        for (int bit = 0; bit < 8; ++bit, ++tried) {
            buf[byte] ^= (uint8_t)(1u << bit);
            expect_refused(buf, size, DM_OK, NULL);
            buf[byte] ^= (uint8_t)(1u << bit);
        }
    cr_assert_eq(tried, (int)size * 8);
    free(buf);
}

Test(pack_bad, wrong_magic)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    memcpy(buf, "PK\x03\x04zipx", 8);
    expect_refused(buf, size, DM_ERR_FORMAT, "magic 50 4b 03 04");
    free(buf);
}

Test(pack_bad, wrong_version)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    buf[8] = 2;
    expect_refused(buf, size, DM_ERR_UNSUPPORTED, "version 2, expected 1");
    free(buf);
}

Test(pack_bad, unknown_flags)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    buf[12] = 1;
    expect_refused(buf, size, DM_ERR_UNSUPPORTED, "flags 0x00000001");
    free(buf);
}

Test(pack_bad, header_checksum)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    buf[60] ^= 0x10;
    expect_refused(buf, size, DM_ERR_CHECKSUM, "header+manifest checksum");
    free(buf);
}

Test(pack_bad, blob_checksum)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    buf[size - 1] ^= 0x01; /* inside the last blob (env.sh) */
    expect_refused(buf, size, DM_ERR_CHECKSUM, "entry \"env.sh\": checksum");
    free(buf);
}

Test(pack_bad, offset_past_the_end)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    char *m = manifest_of(buf), *e = strstr(m, "\"name\":\t\"env.sh\"");
    cr_assert(e);
    long off;
    cr_assert_eq(sscanf(strstr(e, "\"offset\":") + 9, "%ld", &off), 1);
    char from[32], to[32];
    snprintf(from, sizeof from, "%ld", off);
    long far = 1;
    for (size_t k = 0; k < strlen(from); ++k) far *= 10;
    far = (far - 1) / 64 * 64; /* aligned, as many digits, past the end of this small pack */
    cr_assert_gt(far, (long)size);
    snprintf(to, sizeof to, "%ld", far);
    edit_manifest(buf, "\"name\":\t\"env.sh\"", from, to);
    expect_refused(buf, size, DM_ERR_FORMAT, "outside the blob area");
    free(m);
    free(buf);
}

Test(pack_bad, overlapping_blobs)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    char *m = manifest_of(buf);
    long a, b;
    cr_assert_eq(sscanf(strstr(strstr(m, "\"name\":\t\"mesh.indices\""), "\"offset\":") + 9, "%ld", &a), 1);
    cr_assert_eq(sscanf(strstr(strstr(m, "\"name\":\t\"env.sh\""), "\"offset\":") + 9, "%ld", &b), 1);
    char from[32], to[32];
    snprintf(from, sizeof from, "%ld", b);
    snprintf(to, sizeof to, "%ld", a);
    edit_manifest(buf, "\"name\":\t\"env.sh\"", from, to);
    expect_refused(buf, size, DM_ERR_FORMAT, "overlap");
    free(m);
    free(buf);
}

Test(pack_bad, misaligned_offset)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    char *m = manifest_of(buf);
    long b;
    cr_assert_eq(sscanf(strstr(strstr(m, "\"name\":\t\"env.sh\""), "\"offset\":") + 9, "%ld", &b), 1);
    char from[32], to[32];
    snprintf(from, sizeof from, "%ld", b);
    snprintf(to, sizeof to, "%ld", b + 4);
    edit_manifest(buf, "\"name\":\t\"env.sh\"", from, to);
    expect_refused(buf, size, DM_ERR_FORMAT, "expected a multiple of 64");
    free(m);
    free(buf);
}

Test(pack_bad, malformed_manifest_json)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    set_manifest(buf, "{\"format\": \"dermis-pack\", \"entries\": [");
    expect_refused(buf, size, DM_ERR_FORMAT, "manifest is not valid JSON");
    free(buf);
}

Test(pack_bad, manifest_unknown_key)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    edit_manifest(buf, "\"name\":\t\"lut.rho_dt\"", "\"layers\"", "\"layerz\"");
    expect_refused(buf, size, DM_ERR_FORMAT, "$.entries[2].layerz: unknown key");
    free(buf);
}

Test(pack_bad, manifest_unknown_kind)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    edit_manifest(buf, "\"name\":\t\"env.sh\"", "\"kind\":\t\"env.sh\"", "\"kind\":\t\"env.xx\"");
    expect_refused(buf, size, DM_ERR_FORMAT, "\"env.xx\" is not one of texture");
    free(buf);
}

Test(pack_bad, manifest_unknown_format)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    edit_manifest(buf, "\"name\":\t\"lut.rho_dt\"", "\"r32f\"", "\"r64f\"");
    expect_refused(buf, size, DM_ERR_FORMAT, "$.entries[2].format: \"r64f\"");
    free(buf);
}

Test(pack_bad, manifest_missing_field)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    edit_manifest(buf, "\"name\":\t\"lut.rho_dt\"", "\"width\"", "\"widtx\"");
    expect_refused(buf, size, DM_ERR_FORMAT, "widtx: unknown key");
    free(buf);
}

Test(pack_bad, size_against_format)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    edit_manifest(buf, "\"name\":\t\"lut.rho_dt\"", "\"width\":\t8", "\"width\":\t9");
    expect_refused(buf, size, DM_ERR_FORMAT, "size 256 bytes, expected 288 for its format");
    free(buf);
}

Test(pack_bad, duplicate_entry_name)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    edit_manifest(buf, "\"offset\"", "\"name\":\t\"env.sh\"", "\"name\":\t\"scene\"");
    expect_refused(buf, size, DM_ERR_FORMAT, "named \"scene\"");
    free(buf);
}

Test(pack_bad, missing_required_entry)
{
    fixture fx = {.skip_beckmann = true};
    size_t size;
    uint8_t *buf = build(&fx, &size);
    expect_refused(buf, size, DM_ERR_FORMAT, "missing required entry \"lut.beckmann\"");
    free(buf);
}

Test(pack_bad, required_entry_of_the_wrong_format)
{
    fixture fx = {.beckmann_as_float = true};
    size_t size;
    uint8_t *buf = build(&fx, &size);
    expect_refused(buf, size, DM_ERR_FORMAT, "\"lut.beckmann\" is texture r32f, expected texture r8");
    free(buf);
}

/* The one reader of the mesh entries' layout (renderer and reference alike): a pack whose
 * mesh.vertices lacks it is refused on open. */
Test(pack, mesh_layout)
{
    size_t size;
    fixture good = {0}, bad = {.no_tangent = true};
    dm_pack pack;
    dm_error err = {0};
    const dm_pack_entry *v, *ix;
    uint8_t *buf = build(&good, &size);
    cr_assert_eq(dm_pack_open_memory(buf, size, "good.dpk", &pack, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_pack_mesh(&pack, &v, &ix, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(v->vertex_count, 3);
    cr_assert_eq(ix->index_count, 3);
    dm_pack_close(&pack);
    free(buf);
    buf = build(&bad, &size);
    expect_refused(buf, size, DM_ERR_FORMAT, "t.dpk: mesh.vertices lacks \"tangent\" at byte 32 with 4 floats");
    free(buf);
}

/* One route for the profile: the "profile" entry must hold the scene's Gaussians. */
Test(pack_bad, profile_entry_differs_from_the_scene)
{
    size_t size;
    fixture same = {.profile = 1}, other = {.profile = 2};
    uint8_t *buf = build(&same, &size);
    dm_pack pack;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open_memory(buf, size, "same.dpk", &pack, &err), DM_OK, "%s", err.detail);
    cr_assert_not_null(pack.profile);
    cr_assert_eq(pack.profile->count, 6);
    dm_pack_close(&pack);
    free(buf);
    buf = build(&other, &size);
    expect_refused(buf, size, DM_ERR_MISMATCH, "entry \"profile\" ('gems3-skin', 6 Gaussians) differs from the scene's profile");
    free(buf);
}

Test(pack_bad, nan_in_a_texture)
{
    fixture fx = {.nan_in_rho = true};
    size_t size;
    uint8_t *buf = build(&fx, &size);
    expect_refused(buf, size, DM_ERR_NON_FINITE, "entry \"lut.rho_dt\": texel (5, 3) of level 0 layer 0");
    free(buf);
}

Test(pack_bad, index_out_of_range)
{
    fixture fx = {.bad_index = true};
    size_t size;
    uint8_t *buf = build(&fx, &size);
    expect_refused(buf, size, DM_ERR_RANGE, "index 2 is 7, expected < 3");
    free(buf);
}

Test(pack_bad, empty_and_tiny_files)
{
    static const uint8_t z[64] = {0};
    expect_refused(z, 0, DM_ERR_FORMAT, "0 bytes, expected at least the 64-byte header");
    expect_refused(z, 64, DM_ERR_FORMAT, "magic");
}

Test(pack_bad, not_a_file)
{
    dm_pack pack;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open("/nonexistent/x.dpk", &pack, &err), DM_ERR_FILE_OPEN);
    cr_assert(strstr(err.detail, "/nonexistent/x.dpk"));
    cr_assert_eq(dm_pack_open("/tmp", &pack, &err), DM_ERR_FILE_OPEN);
}

/* --- LUT texel re-evaluation --------------------------------------------------------- */

Test(lut_check, baked_tables_pass)
{
    dm_error err = {0};
    dm_beckmann_lut b;
    cr_assert_eq(dm_lut_bake_beckmann(64, 64, 0, 1, &b, &err), DM_OK);
    dm_lut_check c;
    dm_lut_check_beckmann(b.texels, 64, 64, &c);
    cr_assert_eq(c.failures, 0);
    cr_assert_eq(c.samples, 100);
    dm_directional_lut d;
    cr_assert_eq(dm_lut_bake_directional(16, 16, DM_SKIN_F0, 16, 1, &d, &err), DM_OK);
    dm_lut_check_directional(d.rho_dt, 1, 1, 16, 16, DM_SKIN_F0, 16, &c);
    cr_assert_eq(c.failures, 0, "max error %g", c.max_error);
    dm_beckmann_lut_free(&b);
    dm_directional_lut_free(&d);
}

Test(lut_check, corrupted_texel_and_wrong_f0_fail)
{
    dm_error err = {0};
    dm_beckmann_lut b;
    cr_assert_eq(dm_lut_bake_beckmann(64, 64, 0, 1, &b, &err), DM_OK);
    b.texels[63] ^= 0x40; /* corner (63, 0): always sampled */
    dm_lut_check c;
    dm_lut_check_beckmann(b.texels, 64, 64, &c);
    cr_assert_geq(c.failures, 1);
    cr_assert_eq(c.worst_i, 63);
    cr_assert_eq(c.worst_j, 0);
    dm_directional_lut d;
    cr_assert_eq(dm_lut_bake_directional(16, 16, 0.5, 16, 1, &d, &err), DM_OK);
    dm_lut_check_directional(d.rho_dt, 1, 1, 16, 16, DM_SKIN_F0, 16, &c);
    cr_assert_gt(c.failures, 50);
    dm_beckmann_lut_free(&b);
    dm_directional_lut_free(&d);
}

/* --- already-baked LUT files: provenance matching ----------------------------------- */

#include "image/dm_exr.h"
#include "image/dm_image.h"
#include "bake/dm_lut_prov.h"

Test(lut_prov, matching_and_mismatching_files)
{
    dm_provenance want, have;
    dm_error err = {0};
    dm_lut_prov_directional(&want, "dermis-pack", "rho_dt", 64, 64, DM_SKIN_F0, 32);
    dm_lut_prov_directional(&have, "dermis-bake-lut", "rho_dt", 64, 64, DM_SKIN_F0, 32);
    cr_assert_eq(dm_lut_prov_match(&have, &want, "a.exr", &err), DM_OK, "%s", err.detail); /* tool may differ */
    dm_lut_prov_directional(&have, "dermis-bake-lut", "rho_dt", 64, 64, DM_SKIN_F0, 48);
    cr_assert_eq(dm_lut_prov_match(&have, &want, "a.exr", &err), DM_ERR_MISMATCH);
    cr_assert(strstr(err.detail, "a.exr: nodes is 48, expected 32"), "%s", err.detail);
    dm_lut_prov_directional(&have, "dermis-bake-lut", "env_brdf", 64, 64, DM_SKIN_F0, 32);
    cr_assert_eq(dm_lut_prov_match(&have, &want, "a.exr", &err), DM_ERR_MISMATCH);
    cr_assert(strstr(err.detail, "table is \"env_brdf\", expected \"rho_dt\""), "%s", err.detail);
    dm_lut_prov_directional(&have, "dermis-bake-lut", "rho_dt", 64, 64, DM_SKIN_F0, 32);
    snprintf(have.version, sizeof have.version, "0.0.1");
    cr_assert_eq(dm_lut_prov_match(&have, &want, "a.exr", &err), DM_ERR_MISMATCH);
    cr_assert(strstr(err.detail, "baked by dermis 0.0.1"), "%s", err.detail);
}

Test(lut_prov, provenance_survives_png_and_exr_files)
{
    dm_error err = {0};
    dm_beckmann_lut b;
    cr_assert_eq(dm_lut_bake_beckmann(32, 32, 0, 1, &b, &err), DM_OK);
    dm_provenance p;
    dm_lut_prov_beckmann(&p, "dermis-bake-lut", 32, 32);
    dm_image img = {.width = 32, .height = 32, .channels = 1, .type = DM_PIXEL_U8, .pixels = b.texels};
    char png[64];
    snprintf(png, sizeof png, "/tmp/dermis-test-lut-%ld.png", (long)getpid());
    cr_assert_eq(dm_png_write(png, &img, &p, &err), DM_OK, "%s", err.detail);
    dm_image back;
    cr_assert_eq(dm_image_read(png, DM_PIXEL_U8, &back, &err), DM_OK, "%s", err.detail);
    cr_assert(back.has_provenance);
    cr_assert_eq(dm_lut_prov_match(&back.prov, &p, png, &err), DM_OK, "%s", err.detail);
    dm_lut_check c;
    dm_lut_check_beckmann(back.pixels, 32, 32, &c);
    cr_assert_eq(c.failures, 0);
    dm_image_free(&back);
    dm_beckmann_lut_free(&b);
    unlink(png);
}

/* --- several environments (environment.alternatives) -------------------------------- */

/* Environment lighting with one alternative map and no background: needs scene, the mesh,
 * lut.env_brdf, env.sh, env.specular, env1.sh, env1.specular. skip names one to leave out. */
/* with_m: the specular entries carry their layers' Beckmann m ("layer_values") */
static uint8_t *build_env(const char *skip, bool with_m, size_t *size)
{
    static const char *json = "{\"mesh\": {\"path\": \"head.obj\"}, \"environment\": {\"path\": \"a.hdr\", "
                              "\"background\": false, \"alternatives\": [\"b.hdr\"]}, "
                              "\"effects\": {\"environment_lighting\": true}}";
    dm_pack_writer w;
    dm_pack_writer_init(&w);
    dm_provenance p;
    dm_prov_init(&p, "test_pack");
    dm_error err = {0};
    dm_pack_entry d;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "scene");
    d.kind = DM_PACK_SCENE;
    cr_assert_eq(dm_pack_writer_add(&w, &d, json, strlen(json), &p, &err), DM_OK, "%s", err.detail);
    add_mesh(&w, &p, false, false);
    float rg[4 * 4 * 2] = {0}, rgba[4 * 2 * 4] = {0}, sh[27] = {0};
    d = dm_pack_texture_entry("lut.env_brdf", DM_TEX_RG32F, 4, 4);
    cr_assert_eq(dm_pack_writer_add(&w, &d, rg, sizeof rg, &p, &err), DM_OK, "%s", err.detail);
    const char *names[] = {"env.sh", "env.specular", "env1.sh", "env1.specular"};
    for (int k = 0; k < 4; ++k) {
        if (skip && !strcmp(skip, names[k])) continue;
        if (k % 2 == 0) {
            memset(&d, 0, sizeof d);
            snprintf(d.name, sizeof d.name, "%s", names[k]);
            d.kind = DM_PACK_ENV_SH;
            d.sh_order = 2;
            cr_assert_eq(dm_pack_writer_add(&w, &d, sh, sizeof sh, &p, &err), DM_OK, "%s", err.detail);
        } else {
            d = dm_pack_texture_entry(names[k], DM_TEX_RGBA32F, 4, 2);
            if (with_m) {
                d.layer_value_count = 1;
                d.layer_values[0] = 0.3f + 0.1f * (float)k;
            }
            cr_assert_eq(dm_pack_writer_add(&w, &d, rgba, sizeof rgba, &p, &err), DM_OK, "%s", err.detail);
        }
    }
    uint8_t *buf = NULL;
    cr_assert_eq(dm_pack_writer_build(&w, &p, &buf, size, &err), DM_OK, "%s", err.detail);
    dm_pack_writer_free(&w);
    return buf;
}

Test(pack_env, alternatives_present_open_and_are_known)
{
    size_t size;
    uint8_t *buf = build_env(NULL, true, &size);
    dm_pack pack;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open_memory(buf, size, "t.dpk", &pack, &err), DM_OK, "%s", err.detail);
    dm_scene sc;
    cr_assert_eq(dm_pack_scene(&pack, &sc, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(sc.env_alternative_count, 1);
    int copy = -1;
    cr_assert_eq(dm_pack_need_find_copy("env1.specular", &copy), dm_pack_need_find("env.specular"));
    cr_assert_eq(copy, 1);
    cr_assert(dm_pack_entry_applies("env1.sh", &sc));
    cr_assert(!dm_pack_entry_applies("env2.sh", &sc), "only one alternative");
    cr_assert(!dm_pack_entry_applies("env1.background", &sc), "background is off");
    cr_assert_null(dm_pack_need_find("env8.sh"), "at most 7 alternatives");
    cr_assert_null(dm_pack_need_find("env0.sh"));
    cr_assert_null(dm_pack_need_find("env01.sh"));
    cr_assert_null(dm_pack_need_find("env1.mesh"));
    cr_assert_null(dm_pack_need_find("lut1.beckmann"));
    dm_pack_close(&pack);
    free(buf);
}

Test(pack_env, missing_alternative_is_refused_by_name)
{
    size_t size;
    uint8_t *buf = build_env("env1.specular", true, &size);
    expect_refused(buf, size, DM_ERR_FORMAT, "missing required entry \"env1.specular\"");
    free(buf);
    buf = build_env("env1.sh", true, &size);
    expect_refused(buf, size, DM_ERR_FORMAT, "missing required entry \"env1.sh\"");
    free(buf);
}

/* Data the renderer needs is in the manifest, never read back from provenance: the layers'
 * Beckmann m ("layer_values") and a table's row range ("t_range") round-trip exactly; a
 * specular entry without them is refused by name; malformed values are refused. */
Test(pack_env, layer_values_and_t_range_round_trip)
{
    size_t size;
    uint8_t *buf = build_env(NULL, true, &size);
    dm_pack pack;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open_memory(buf, size, "m.dpk", &pack, &err), DM_OK, "%s", err.detail);
    float m[1];
    cr_assert_eq(dm_pack_env_level_m(&pack, dm_pack_find(&pack, "env1.specular"), m, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(m[0], 0.3f + 0.1f * 3.0f);
    dm_pack_close(&pack);
    free(buf);

    /* a pack from before layer_values: refused on open, by every reader alike */
    buf = build_env(NULL, false, &size);
    expect_refused(buf, size, DM_ERR_FORMAT,
                   "entry \"env.specular\": no \"layer_values\" (the Beckmann m of each of its 1 layers); pack the "
                   "scene again");
    free(buf);

    /* layer_values of the wrong length: the writer refuses, and so does the reader */
    dm_pack_writer w;
    dm_pack_writer_init(&w);
    dm_provenance p;
    dm_prov_init(&p, "test_pack");
    dm_pack_entry d = dm_pack_texture_entry("t", DM_TEX_R32F, 2, 2);
    d.layers = 2;
    d.layer_value_count = 1;
    float texels[8] = {0};
    cr_assert_eq(dm_pack_writer_add(&w, &d, texels, sizeof texels, &p, &err), DM_ERR_RANGE);
    dm_pack_writer_free(&w);
    buf = build_env(NULL, true, &size);
    char *man = manifest_of(buf);
    char *lv = strstr(strstr(man, "\"env1.specular\""), "\"layer_values\"");
    char *open = strchr(lv, '['), *close = strchr(lv, ']');
    memset(open, ' ', (size_t)(close - open + 1));
    memcpy(open, "[1,2]", 5);
    set_manifest(buf, man);
    free(man);
    expect_refused(buf, size, DM_ERR_FORMAT, "layer_values");
    free(buf);
}
