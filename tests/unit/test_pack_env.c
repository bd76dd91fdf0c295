/* The .dpk pack with several environments (environment.alternatives): every one the scene
 * names must be packed, and the specular entries' layer_values and t_range round-trip. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../common/small_pack.h"
#include "core/dm_hash.h"
#include "pack/dm_pack.h"
#include "pack/dm_pack_needs.h"
#include "pack/dm_pack_write.h"

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
    add_scene(&w, &p, json);
    dm_pack_entry d;
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
