/* tests/fixtures/pack-v1: a pack written by dermis-pack when version 1 was the format (its
 * README says how). This dermis must open it, verify it and read the same entries and values
 * as were recorded when it was made. A change that cannot is a format change: bump
 * DM_PACK_VERSION and follow docs/dermis-dpk.5.md's VERSION POLICY; never regenerate the
 * fixture to make this test pass. Run from the repository root (scripts/run-tests.sh). */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/tmpdir.h"
#include "pack/dm_pack.h"
#include "core/dm_scene.h"

#define FIXTURE_DIR "tests/fixtures/pack-v1"
#define FIXTURE FIXTURE_DIR "/pack-v1.dpk"

/* Recorded from the file when it was made (the README's command). */
static const struct {
    const char *name;
    dm_pack_kind kind;
    int format; /* textures; -1 otherwise */
    int width, height, layers, levels;
    uint64_t offset, size;
    const char *xxh3;
} recorded[] = {
    {"scene", DM_PACK_SCENE, -1, 0, 0, 0, 0, 4544, 1926, "6a5d76ad7c7ea65f"},
    {"mesh.vertices", DM_PACK_MESH_VERTICES, -1, 0, 0, 0, 0, 6528, 8880, "39eff01961f827a4"},
    {"mesh.indices", DM_PACK_MESH_INDICES, -1, 0, 0, 0, 0, 15424, 3456, "c17d6bc6e15e8d8f"},
    {"albedo", DM_PACK_TEXTURE, DM_TEX_RGBA8_SRGB, 32, 32, 1, 1, 18880, 4096, "dcee12b8ee907dc0"},
    {"lut.beckmann", DM_PACK_TEXTURE, DM_TEX_R8, 32, 32, 1, 1, 22976, 1024, "7031bff82f2befff"},
    {"lut.rho_dt", DM_PACK_TEXTURE, DM_TEX_R32F, 16, 16, 1, 1, 24000, 1024, "06511fbcef34af49"},
    {"profile", DM_PACK_PROFILE, -1, 0, 0, 0, 0, 25024, 663, "84da179c2090ed5a"},
    {"stretch", DM_PACK_TEXTURE, DM_TEX_RG32F, 64, 64, 6, 1, 25728, 196608, "eec1fcc28246c2dc"},
    {"stretch.mask", DM_PACK_TEXTURE, DM_TEX_R8, 64, 64, 1, 1, 222336, 4096, "bd144584c918672b"},
};
enum { RECORDED_COUNT = sizeof recorded / sizeof recorded[0], RECORDED_FILE_SIZE = 226432 };

Test(pack_fixture, opens_with_the_recorded_entries)
{
    dm_pack pack;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open(FIXTURE, &pack, &err), DM_OK, "%s (a format change? see %s/README.md)", err.detail,
                 FIXTURE_DIR);
    cr_expect_eq(pack.version, 1);
    cr_expect_eq(pack.size, RECORDED_FILE_SIZE);
    cr_assert_eq(pack.entry_count, RECORDED_COUNT);
    for (int k = 0; k < RECORDED_COUNT; ++k) {
        const dm_pack_entry *e = &pack.entries[k];
        char hex[17];
        dm_pack_hex64(e->xxh3, hex);
        cr_expect_str_eq(e->name, recorded[k].name);
        cr_expect_eq(e->kind, recorded[k].kind, "%s", e->name);
        cr_expect_eq(e->offset, recorded[k].offset, "%s", e->name);
        cr_expect_eq(e->size, recorded[k].size, "%s", e->name);
        cr_expect_str_eq(hex, recorded[k].xxh3, "%s", e->name);
        if (e->kind != DM_PACK_TEXTURE) continue;
        cr_expect_eq((int)e->format, recorded[k].format, "%s", e->name);
        cr_expect(e->width == recorded[k].width && e->height == recorded[k].height, "%s: %dx%d", e->name, e->width,
                  e->height);
        cr_expect(e->layers == recorded[k].layers && e->levels == recorded[k].levels, "%s", e->name);
    }
    dm_pack_close(&pack);
}

Test(pack_fixture, recorded_values)
{
    dm_pack pack;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open(FIXTURE, &pack, &err), DM_OK, "%s", err.detail);
    dm_scene *s = malloc(sizeof *s);
    cr_assert_eq(dm_pack_scene(&pack, s, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(s->mm_per_unit, 50.0);
    cr_expect_eq(s->irradiance_size, 64);
    cr_expect(s->effects[DM_EFFECT_SPECULAR] && s->effects[DM_EFFECT_SUBSURFACE] &&
              s->effects[DM_EFFECT_ENERGY_CONSERVATION] && !s->effects[DM_EFFECT_GLOW]);
    cr_expect_str_eq(s->mesh, FIXTURE_DIR "/sphere.obj"); /* stored "sphere.obj", beside the pack */
    free(s);

    const dm_pack_entry *v, *ix;
    cr_assert_eq(dm_pack_mesh(&pack, &v, &ix, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(v->vertex_count, 185);
    cr_expect_eq(ix->index_count, 864);
    /* vertex 1 (position, normal, uv, tangent xyzw) and vertex 100, as written: exact floats */
    static const float v1[12] = {0.618034005f, 1.90211296f,  -0.0f, 0.309016854f, 0.95105654f, -0.0f,
                                 0.0f,         0.899999976f, -0.176782489f, 0.0574400835f, -0.982572436f, 1.0f};
    static const float v100[12] = {2, 0, 0, 1, 0, 0, 1, 0.5f, 0, 0, -1, 1};
    const float *vf = v->data;
    for (int c = 0; c < 12; ++c) {
        cr_expect_eq(vf[12 * 1 + c], v1[c], "vertex 1 [%d]: %.9g, recorded %.9g", c, vf[12 + c], v1[c]);
        cr_expect_eq(vf[12 * 100 + c], v100[c], "vertex 100 [%d]: %.9g, recorded %.9g", c, vf[1200 + c], v100[c]);
    }
    static const uint32_t first[9] = {0, 1, 2, 3, 2, 4, 5, 4, 6};
    cr_expect_arr_eq(ix->data, first, sizeof first);

    cr_assert_not_null(pack.profile);
    cr_expect_eq(pack.profile->count, 6);
    cr_expect_eq(pack.profile->variance_mm2[0], 0.0064);
    cr_expect_eq(pack.profile->variance_mm2[5], 7.41);
    const dm_pack_entry *st = dm_pack_find(&pack, "stretch");
    cr_assert_not_null(st);
    const float *sf = st->data; /* texel (32, 32) of layer 0: u and v in UV units per mm */
    cr_expect_eq(sf[2 * (32 * 64 + 32)], 0.0016018218593671918f);
    cr_expect_eq(sf[2 * (32 * 64 + 32) + 1], 0.0031962271314114332f);
    dm_pack_close(&pack);
}

Test(pack_fixture, dermis_check_passes, .timeout = 60)
{
    char dir[256], log[320];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(log, sizeof log, "%s/check.log", dir);
    int rc = test_run(DERMIS_BIN "/dermis-check " FIXTURE, log);
    char *text = test_slurp(log);
    cr_expect_eq(rc, 0, "%s", text ? text : "");
    cr_expect(text && strstr(text, FIXTURE ": ok (pack, made by dermis-pack "), "%s", text ? text : "");
    free(text);
    rc = test_run(DERMIS_BIN "/dermis-check --format-version " FIXTURE, log);
    text = test_slurp(log);
    cr_expect_eq(rc, 0, "%s", text ? text : "");
    cr_expect_str_eq(text ? text : "", FIXTURE ": dermis-pack version 1 (this dermis reads version 1: ok)\n");
    free(text);
}
