/* glTF 2.0 meshes in the bakers and the packer: the head as OBJ and as GLB bakes the same
 * stretch (library and tool), dermis-pack takes a glTF's material maps, and a scene's
 * mesh.name selects a glTF mesh. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image/dm_image.h"
#include "mesh/dm_mesh.h"
#include "bake/dm_stretch.h"
#include "core/dm_file.h"
#include "pack/dm_pack.h"
#include "core/dm_png.h"
#include "core/dm_scene.h"
#include "../common/gltf_quad.h"
#include "../common/gltf_write.h"

TestSuite(gltf, .init = setup, .timeout = 60);

/* ---- the head: OBJ and GLB bake the same stretch --------------------------------- */

Test(gltf, head_obj_and_glb_bake_identical_stretch, .timeout = 120)
{
    const char *obj = DERMIS_ASSETS "/lps/LeePerrySmith.obj";
    if (access(obj, R_OK) != 0) cr_skip_test("no head at %s", obj);
    dm_mesh a, b;
    load_ok(obj, NULL, &a);
    const char *glb = in_dir("head.glb");
    cr_assert_eq(test_glb_from_mesh(&a, glb), 0);
    load_ok(glb, NULL, &b);
    cr_assert_eq(b.triangle_count, a.triangle_count);
    /* Same shape: every corner's position and UV equal. glTF stores v' = 1 − v; the
     * round trip 1 − (1 − v) in float is exact for v ≥ 0.5 and within 2^-25 otherwise. */
    int64_t uv_exact = 0;
    for (int64_t k = 0; k < (int64_t)a.triangle_count * 3; ++k) {
        for (int d = 0; d < 3; ++d)
            cr_assert_eq(a.positions[a.indices[k] * 3 + d], b.positions[b.indices[k] * 3 + d], "corner %lld",
                         (long long)k);
        cr_assert_eq(a.uvs[k * 2], b.uvs[k * 2]);
        cr_assert_float_eq(a.uvs[k * 2 + 1], b.uvs[k * 2 + 1], 3e-8);
        uv_exact += a.uvs[k * 2 + 1] == b.uvs[k * 2 + 1];
    }
    dm_stretch_options so = {.width = 512, .height = 512, .mm_per_unit = 50, .thread_count = 2};
    dm_stretch_map sa, sb;
    dm_error err = {0};
    cr_assert_eq(dm_stretch_bake(&a, &so, &sa, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_stretch_bake(&b, &so, &sb, &err), DM_OK, "%s", err.detail);
    size_t n = (size_t)512 * 512;
    int64_t mask_diff = 0, value_diff = 0;
    double rel_max = 0;
    for (size_t i = 0; i < n; ++i) mask_diff += sa.mask[i] != sb.mask[i];
    for (int l = 0; l < sa.level_count; ++l)
        for (size_t i = 0; i < n; ++i) {
            value_diff += sa.s_u[l][i] != sb.s_u[l][i] || sa.s_v[l][i] != sb.s_v[l][i];
            double ru = fabs((double)sa.s_u[l][i] - sb.s_u[l][i]) / sa.s_u[l][i];
            double rv = fabs((double)sa.s_v[l][i] - sb.s_v[l][i]) / sa.s_v[l][i];
            if (ru > rel_max) rel_max = ru;
            if (rv > rel_max) rel_max = rv;
        }
    fprintf(stderr, "head: %lld/%lld v exact after the flip; %lld mask texels differ, %lld stretch values differ, max rel %.3g\n",
            (long long)uv_exact, (long long)a.triangle_count * 3, (long long)mask_diff, (long long)value_diff, rel_max);
    cr_assert_eq(mask_diff, 0);
    cr_assert_eq(value_diff, 0);
    dm_stretch_map_free(&sa);
    dm_stretch_map_free(&sb);
    dm_mesh_free(&a);
    dm_mesh_free(&b);
}

/* dermis-bake-stretch takes the GLB like the OBJ, and --mesh NAME selects (exit 2 when
 * no mesh has that name). */
Test(gltf, bake_stretch_tool_reads_glb, .timeout = 120)
{
    const char *obj = DERMIS_ASSETS "/lps/LeePerrySmith.obj";
    if (access(obj, R_OK) != 0) cr_skip_test("no head at %s", obj);
    dm_mesh a;
    load_ok(obj, NULL, &a);
    const char *glb = in_dir("head.glb");
    cr_assert_eq(test_glb_from_mesh(&a, glb), 0);
    dm_mesh_free(&a);
    char cmd[4096];
    const char *out_obj = in_dir("obj.exr"), *out_glb = in_dir("glb.exr"), *log = in_dir("log.txt");
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-bake-stretch %s -o %s --size 256 --quiet", obj, out_obj);
    cr_assert_eq(test_run(cmd, log), 0, "%s", cmd);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-bake-stretch %s --mesh head -o %s --size 256 --quiet", glb, out_glb);
    cr_assert_eq(test_run(cmd, log), 0, "%s", cmd);
    dm_stretch_map sa, sb;
    dm_provenance pa, pb;
    dm_error err = {0};
    cr_assert_eq(dm_stretch_read(out_obj, &sa, &pa, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_stretch_read(out_glb, &sb, &pb, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(sa.level_count, sb.level_count);
    size_t n = (size_t)sa.width * sa.height;
    cr_assert_eq(memcmp(sa.mask, sb.mask, n * sizeof(float)), 0);
    for (int l = 0; l < sa.level_count; ++l) {
        cr_assert_eq(memcmp(sa.s_u[l], sb.s_u[l], n * sizeof(float)), 0, "level %d u", l);
        cr_assert_eq(memcmp(sa.s_v[l], sb.s_v[l], n * sizeof(float)), 0, "level %d v", l);
    }
    dm_stretch_map_free(&sa);
    dm_stretch_map_free(&sb);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-bake-stretch %s --mesh nose -o %s --size 256", glb, out_glb);
    cr_assert_eq(test_run(cmd, log), 2, "%s", cmd);
    char *text = test_slurp(log);
    cr_assert_not_null(strstr(text, "no mesh named \"nose\""), "%s", text);
    free(text);
}

/* A scene whose mesh is a GLB and that names no maps: dermis-pack packs the material's
 * embedded baseColor PNG as albedo and its external normal.png as the normal map, texel
 * for texel what dm_image_read gives for the same PNG files. */
Test(gltf, pack_takes_the_gltf_material_maps, .timeout = 120)
{
    /* 3×2 RGB test images (different, so albedo and normal cannot be swapped) */
    uint8_t colour[18], normal[18];
    for (int i = 0; i < 18; ++i) colour[i] = (uint8_t)(i * 13 + 7), normal[i] = (uint8_t)(250 - i * 11);
    const char *colour_png = in_dir("colour.png"), *normal_png = in_dir("normal.png");
    dm_error err = {0};
    cr_assert_eq(dm_png_write_pixels(colour_png, 3, 2, 3, 8, colour, NULL, NULL, 0, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_png_write_pixels(normal_png, 3, 2, 3, 8, normal, NULL, NULL, 0, &err), DM_OK, "%s", err.detail);
    char *png = NULL;
    size_t png_size = 0;
    cr_assert_eq(dm_read_file(colour_png, &png, &png_size, &err), DM_OK);
    write_quad("material.glb", &(quad_opts){.png = png, .png_size = png_size});
    free(png);
    const char *scene = in_dir("scene.json");
    const char *json = "{\"format\":\"dermis-scene\",\"version\":1,\"mesh\":{\"path\":\"material.glb\",\"name\":\"quad\"},"
                       "\"effects\":{\"specular\":false}}";
    cr_assert_eq(test_write_bytes(scene, json, strlen(json)), 0);
    char cmd[2048];
    const char *pack = in_dir("material.dpk"), *log = in_dir("pack.log");
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack %s -o %s", scene, pack);
    int rc = test_run(cmd, log);
    char *text = test_slurp(log);
    cr_assert_eq(rc, 0, "%s\n%s", cmd, text);
    cr_assert_not_null(strstr(text, "baseColorTexture"), "%s", text);
    free(text);
    dm_pack pk;
    cr_assert_eq(dm_pack_open(pack, &pk, &err), DM_OK, "%s", err.detail);
    const char *entries[2] = {"albedo", "normal"}, *files[2] = {colour_png, normal_png};
    for (int k = 0; k < 2; ++k) {
        const dm_pack_entry *e = dm_pack_find(&pk, entries[k]);
        cr_assert_not_null(e, "no %s entry", entries[k]);
        cr_assert_eq(e->width, 3);
        cr_assert_eq(e->height, 2);
        dm_image ref;
        cr_assert_eq(dm_image_read(files[k], DM_PIXEL_U8, &ref, &err), DM_OK, "%s", err.detail);
        const uint8_t *got = e->data, *want = ref.pixels;
        for (int i = 0; i < 6; ++i)
            for (int c = 0; c < 3; ++c)
                cr_assert_eq(got[i * 4 + c], want[i * ref.channels + c], "%s texel %d channel %d", entries[k], i, c);
        dm_image_free(&ref);
    }
    dm_pack_close(&pk);
    /* a scene that names its own albedo keeps it */
    json = "{\"format\":\"dermis-scene\",\"version\":1,\"mesh\":{\"path\":\"material.glb\"},"
           "\"material\":{\"albedo\":\"normal.png\"},\"effects\":{\"specular\":false}}";
    cr_assert_eq(test_write_bytes(scene, json, strlen(json)), 0);
    cr_assert_eq(test_run(cmd, log), 0);
    cr_assert_eq(dm_pack_open(pack, &pk, &err), DM_OK, "%s", err.detail);
    const uint8_t *got = dm_pack_find(&pk, "albedo")->data;
    dm_image ref;
    cr_assert_eq(dm_image_read(normal_png, DM_PIXEL_U8, &ref, &err), DM_OK);
    cr_assert_eq(got[0], ((uint8_t *)ref.pixels)[0]);
    dm_image_free(&ref);
    dm_pack_close(&pk);
}

/* mesh.name in a scene: a string, kept through dm_scene_to_json; anything else refused. */
Test(gltf, scene_mesh_name)
{
    dm_scene *s = malloc(sizeof *s);
    dm_error err = {0};
    const char *ok = "{\"format\":\"dermis-scene\",\"version\":1,\"mesh\":{\"path\":\"h.glb\",\"name\":\"head\"},"
                     "\"effects\":{}}";
    cr_assert_eq(dm_scene_parse(ok, "/x/scene.json", s, &err), DM_OK, "%s", err.detail);
    cr_assert_str_eq(s->mesh_name, "head");
    char *json = NULL;
    cr_assert_eq(dm_scene_to_json(s, &json, &err), DM_OK);
    cr_assert_not_null(strstr(json, "\"name\":"), "%s", json);
    free(json);
    const char *bad = "{\"format\":\"dermis-scene\",\"version\":1,\"mesh\":{\"path\":\"h.glb\",\"name\":3},\"effects\":{}}";
    cr_assert_eq(dm_scene_parse(bad, "/x/scene.json", s, &err), DM_ERR_FORMAT);
    cr_assert_not_null(strstr(err.detail, "$.mesh.name"), "%s", err.detail);
    free(s);
}
