/* Scene files: the bundled scenes, path resolution, the JSON round trip, and one named
 * test per kind of error, each checking that the message names the JSON path, the value
 * and what was expected. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "pack/dm_pack_needs.h"
#include "core/dm_scene.h"

#define SCENES "assets/scenes/"

static dm_scene scene;

static void read_bundled(const char *name)
{
    char path[512];
    snprintf(path, sizeof path, SCENES "%s", name);
    dm_error err = {0};
    cr_assert_eq(dm_scene_read(path, &scene, &err), DM_OK, "%s", err.detail);
}

/* Parses json as if from /scenes/test.json and expects failure `code` with every needle. */
static void expect_error(const char *json, dm_result code, const char *n1, const char *n2)
{
    dm_error err = {0};
    dm_result r = dm_scene_parse(json, "/scenes/test.json", &scene, &err);
    cr_assert_eq(r, code, "expected %s, got %s: %s", dm_result_name(code), dm_result_name(r), err.detail);
    cr_assert(strstr(err.detail, "/scenes/test.json"), "no file name in: %s", err.detail);
    if (n1) cr_assert(strstr(err.detail, n1), "'%s' not in: %s", n1, err.detail);
    if (n2) cr_assert(strstr(err.detail, n2), "'%s' not in: %s", n2, err.detail);
}

#define MESH "\"mesh\": {\"path\": \"head.obj\"}"
#define BASE MESH ", \"effects\": {}"

Test(scene, bundled_full_scene_has_every_effect_and_existing_files)
{
    read_bundled("lps.json");
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) /* translucency is off unless asked (issue 13) */
        cr_assert(scene.effects[e] == (e != DM_EFFECT_TRANSLUCENCY), "%s", dm_effect_name((dm_effect)e));
    cr_assert_eq(scene.light_count, 3);
    cr_assert_eq(scene.lights[1].type, DM_LIGHT_POINT);
    cr_assert_eq(access(scene.mesh, R_OK), 0, "%s", scene.mesh);
    cr_assert_eq(access(scene.albedo, R_OK), 0, "%s", scene.albedo);
    cr_assert_eq(access(scene.normal_map, R_OK), 0, "%s", scene.normal_map);
    cr_assert_eq(access(scene.specular_map, R_OK), 0, "%s", scene.specular_map);
    cr_assert_eq(access(scene.environment, R_OK), 0, "%s", scene.environment);
    cr_assert_eq(scene.env_alternative_count, 1);
    cr_assert_eq(access(scene.env_alternatives[0], R_OK), 0, "%s", scene.env_alternatives[0]);
    /* directional lights are normalised */
    const float *d = scene.lights[0].direction;
    cr_assert_float_eq(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0f, 1e-6f);
    cr_assert_eq(scene.profile.count, 6);
}

/* The demo's lights all cast shadows: unshadowed, its two lights from behind lit the walls
 * inside the eye slits and nostrils and the texture-space blur drew a red line along the lids
 * (docs/crevices.md). lps-demo-eyes.json is the demo's close-up: the same lights, material and
 * subsurface, so what it measures there is what the demo shows. */
Test(scene, the_demo_s_lights_cast_shadows_and_its_close_up_shares_them)
{
    read_bundled("lps.json");
    dm_scene demo = scene;
    for (int i = 0; i < demo.light_count; ++i) cr_expect(demo.lights[i].casts_shadow, "light %d", i);
    read_bundled("lps-demo-eyes.json");
    cr_assert_eq(scene.light_count, demo.light_count);
    cr_expect_eq(memcmp(scene.lights, demo.lights, sizeof demo.lights), 0);
    cr_expect_eq(memcmp(&scene.profile, &demo.profile, sizeof demo.profile), 0);
    cr_expect_eq(scene.irradiance_size, demo.irradiance_size);
    cr_expect_eq(scene.roughness, demo.roughness);
    cr_expect_eq(scene.rho_s, demo.rho_s);
    cr_expect_str_eq(scene.albedo, demo.albedo);
    cr_expect_str_eq(scene.normal_map, demo.normal_map);
    cr_expect(scene.effects[DM_EFFECT_SUBSURFACE] && scene.effects[DM_EFFECT_SHADOWS] && !scene.effects[DM_EFFECT_GLOW]);
}

/* An inline profile survives the scene's JSON bit for bit: 0.39354874902655007 printed with
 * cJSON's 15 digits reads back one ulp off (cJSON keeps 15 when they come within an ulp), so
 * the scene writes the profile with the profile writer's 17 and reads it from the node. */
Test(scene, inline_profile_round_trips_bit_for_bit)
{
    const char *json = "{\"mesh\": {\"path\": \"head.obj\"}, \"effects\": {\"subsurface\": {\"profile\": "
                       "{\"name\": \"fit\", \"gaussians\": [{\"variance_mm2\": 0.39354874902655007, "
                       "\"weights\": [0.04516739832256841, 0.75, 0.5]}, {\"variance_mm2\": 10.882114324236698, "
                       "\"weights\": [0.9, 0.25, 0.125]}]}}}}";
    dm_error err = {0};
    dm_scene a, b;
    cr_assert_eq(dm_scene_parse(json, "/scenes/test.json", &a, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(a.profile.variance_mm2[0], 0.39354874902655007);
    char *text = NULL;
    cr_assert_eq(dm_scene_to_json(&a, &text, &err), DM_OK);
    cr_assert_eq(dm_scene_parse(text, "/scenes/test.json", &b, &err), DM_OK, "%s\n%s", err.detail, text);
    cr_assert_eq(memcmp(b.profile.variance_mm2, a.profile.variance_mm2, sizeof a.profile.variance_mm2), 0, "%s", text);
    cr_assert_eq(memcmp(b.profile.weight, a.profile.weight, sizeof a.profile.weight), 0, "%s", text);
    free(text);
}

/* The scene file is read once: its content hash comes with the parse (the packer's
 * provenance used to read the file a second time to hash it). */
Test(scene, read_keeps_the_file_hash)
{
    read_bundled("lps-sss.json");
    char hex[DM_HASH_HEX_SIZE];
    dm_error err = {0};
    cr_assert_eq(dm_hash_file_hex(SCENES "lps-sss.json", hex, &err), DM_OK, "%s", err.detail);
    cr_assert_str_eq(scene.file_hash, hex);
    char *json = NULL;
    cr_assert_eq(dm_scene_to_json(&scene, &json, &err), DM_OK);
    cr_assert_eq(dm_scene_parse(json, SCENES "lps-sss.json", &scene, &err), DM_OK, "%s", err.detail);
    cr_assert_str_eq(scene.file_hash, ""); /* parsed from a string: no file */
    free(json);
}

Test(scene, bundled_single_effect_scenes)
{
    read_bundled("lps-specular.json");
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) cr_assert_eq(scene.effects[e], e == DM_EFFECT_SPECULAR);
    read_bundled("lps-sss.json");
    cr_assert(scene.effects[DM_EFFECT_SUBSURFACE] && !scene.effects[DM_EFFECT_SPECULAR]);
    read_bundled("lps-env.json");
    cr_assert(scene.effects[DM_EFFECT_ENVIRONMENT_LIGHTING] && !scene.effects[DM_EFFECT_SPECULAR] &&
              !scene.effects[DM_EFFECT_SUBSURFACE]);
    cr_assert_eq(scene.light_count, 0);
}

Test(scene, effect_off_removes_its_entries)
{
    read_bundled("lps-specular.json");
    cr_assert(dm_pack_need_applies(dm_pack_need_find("lut.beckmann"), &scene));
    cr_assert(!dm_pack_need_applies(dm_pack_need_find("profile"), &scene));
    cr_assert(!dm_pack_need_applies(dm_pack_need_find("lut.rho_dt"), &scene));
    cr_assert(!dm_pack_need_applies(dm_pack_need_find("env.sh"), &scene));
    read_bundled("lps-sss.json");
    cr_assert(!dm_pack_need_applies(dm_pack_need_find("lut.beckmann"), &scene));
    cr_assert(!dm_pack_need_applies(dm_pack_need_find("specular"), &scene));
    cr_assert(dm_pack_need_applies(dm_pack_need_find("profile"), &scene));
}

Test(scene, needs_table_is_consistent)
{
    int n;
    const dm_pack_need *t = dm_pack_needs(&n);
    for (int k = 0; k < n; ++k) {
        cr_assert(dm_pack_kind_name(t[k].kind));
        cr_assert_eq(t[k].kind == DM_PACK_TEXTURE, t[k].format >= 0, "%s", t[k].entry);
        for (int q = 0; q < k; ++q) cr_assert(strcmp(t[k].entry, t[q].entry) != 0, "%s twice", t[k].entry);
    }
}

Test(scene, effect_names_round_trip)
{
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) cr_assert_eq(dm_effect_from_name(dm_effect_name((dm_effect)e)), e);
    cr_assert_null(dm_effect_name(DM_EFFECT_COUNT));
    cr_assert_eq(dm_effect_from_name("bloom"), -1);
}

Test(scene, relative_paths_resolve_against_the_scene_folder)
{
    dm_error err = {0};
    const char *json = "{\"mesh\": {\"path\": \"lps/head.obj\"}, \"effects\": {}, \"material\": {\"albedo\": \"/abs/col.jpg\"}}";
    cr_assert_eq(dm_scene_parse(json, "/data/scenes/x.json", &scene, &err), DM_OK, "%s", err.detail);
    cr_assert_str_eq(scene.mesh, "/data/scenes/lps/head.obj");
    cr_assert_str_eq(scene.albedo, "/abs/col.jpg");
    cr_assert_eq(dm_scene_parse(json, "x.json", &scene, &err), DM_OK, "%s", err.detail);
    cr_assert_str_eq(scene.mesh, "lps/head.obj");
}

Test(scene, defaults_when_optional_sections_are_absent)
{
    dm_error err = {0};
    cr_assert_eq(dm_scene_parse("{" MESH ", \"effects\": {\"specular\": {}}}", "/s/t.json", &scene, &err), DM_OK,
                 "%s", err.detail);
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) cr_assert_eq(scene.effects[e], e == DM_EFFECT_SPECULAR);
    cr_assert_eq(scene.mm_per_unit, 50.0);
    cr_assert_eq(scene.width, 1280);
    cr_assert_eq(scene.blur_taps, 7);
    cr_assert_eq(scene.light_count, 0);
}

Test(scene, environment_alternatives_resolve_in_order)
{
    dm_error err = {0};
    const char *json = "{" BASE ", \"environment\": {\"path\": \"a.hdr\", "
                       "\"alternatives\": [\"env/b.hdr\", \"/abs/c.exr\"]}}";
    cr_assert_eq(dm_scene_parse(json, "/data/scenes/x.json", &scene, &err), DM_OK, "%s", err.detail);
    cr_assert_str_eq(scene.environment, "/data/scenes/a.hdr");
    cr_assert_eq(scene.env_alternative_count, 2);
    cr_assert_str_eq(scene.env_alternatives[0], "/data/scenes/env/b.hdr");
    cr_assert_str_eq(scene.env_alternatives[1], "/abs/c.exr");
    cr_assert_eq(dm_scene_parse("{" BASE "}", "/s/t.json", &scene, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(scene.env_alternative_count, 0);
}

Test(scene_error, missing_effects)
{
    expect_error("{" MESH "}", DM_ERR_FORMAT, "$.effects: missing", NULL);
}

Test(scene, to_json_round_trips)
{
    read_bundled("lps.json");
    dm_scene a = scene;
    char *text = NULL;
    dm_error err = {0};
    cr_assert_eq(dm_scene_to_json(&a, &text, &err), DM_OK);
    dm_scene *b = malloc(sizeof *b);
    cr_assert_eq(dm_scene_parse(text, "/elsewhere/pack#scene", b, &err), DM_OK, "%s\n%s", err.detail, text);
    cr_assert_str_eq(b->mesh, a.mesh[0] == '/' ? a.mesh : b->mesh); /* relative stays relative to its new home */
    cr_assert_eq(b->light_count, a.light_count);
    cr_assert_eq(memcmp(b->lights, a.lights, sizeof a.lights), 0);
    cr_assert_eq(memcmp(b->effects, a.effects, sizeof a.effects), 0);
    cr_assert_eq(b->profile.count, a.profile.count);
    cr_assert_eq(memcmp(b->profile.variance_mm2, a.profile.variance_mm2, sizeof a.profile.variance_mm2), 0);
    cr_assert_eq(memcmp(b->profile.weight, a.profile.weight, sizeof a.profile.weight), 0);
    cr_assert_eq(b->mm_per_unit, a.mm_per_unit);
    cr_assert_eq(b->roughness, a.roughness);
    cr_assert_eq(b->env_rotation_deg, a.env_rotation_deg);
    cr_assert_eq(b->env_alternative_count, a.env_alternative_count);
    cr_assert_gt(a.env_alternative_count, 0);
    for (int k = 0; k < a.env_alternative_count; ++k) { /* a relative path lands in the new home's folder */
        char want[DM_SCENE_PATH_SIZE + 16];
        snprintf(want, sizeof want, "%s%s", a.env_alternatives[k][0] == '/' ? "" : "/elsewhere/",
                 a.env_alternatives[k]);
        cr_assert_str_eq(b->env_alternatives[k], want);
    }
    cr_assert_eq(memcmp(b->camera_eye, a.camera_eye, sizeof a.camera_eye), 0);
    cr_assert_eq(b->width, a.width);
    free(b);
    free(text);
}

/* --- one test per kind of error ----------------------------------------------------- */

Test(scene_error, invalid_json_names_line_and_column)
{
    expect_error("{\n  \"mesh\": {\"path\": \"a.obj\",}\n}", DM_ERR_FORMAT, "test.json:2:", "invalid JSON");
}

Test(scene_error, root_not_an_object)
{
    expect_error("[1, 2]", DM_ERR_FORMAT, "$: [1,2] is not a JSON object", NULL);
}

Test(scene_error, unknown_top_level_key)
{
    expect_error("{" BASE ", \"meshes\": 1}", DM_ERR_FORMAT, "$.meshes: unknown key", "expected one of");
}

Test(scene_error, unknown_nested_key)
{
    expect_error("{" MESH ", \"effects\": {\"subsurface\": {\"tapz\": 7}}}", DM_ERR_FORMAT,
                 "$.effects.subsurface.tapz: unknown key", "taps");
}

Test(scene_error, unknown_effect)
{
    expect_error("{" MESH ", \"effects\": {\"bloom\": true}}", DM_ERR_FORMAT, "$.effects.bloom: unknown key",
                 "environment_lighting");
}

Test(scene_error, key_given_twice)
{
    expect_error("{" BASE ", \"output\": {\"width\": 10, \"width\": 20}}", DM_ERR_FORMAT, "$.output.width",
                 "given twice");
}

Test(scene_error, wrong_type_number)
{
    expect_error("{\"mesh\": {\"path\": \"a.obj\", \"mm_per_unit\": \"50\"}}", DM_ERR_FORMAT,
                 "$.mesh.mm_per_unit: \"50\" is not a number in [1e-06, 1e+06]", NULL);
}

Test(scene_error, wrong_type_bool)
{
    expect_error("{" BASE ", \"environment\": {\"background\": 1}}", DM_ERR_FORMAT,
                 "$.environment.background: 1 is not true or false", NULL);
}

Test(scene_error, wrong_type_effect)
{
    expect_error("{" MESH ", \"effects\": {\"glow\": \"yes\"}}", DM_ERR_FORMAT,
                 "$.effects.glow: \"yes\" is not true, false or an object", NULL);
}

Test(scene_error, wrong_type_vector)
{
    expect_error("{" BASE ", \"camera\": {\"eye\": [0, 1]}}", DM_ERR_FORMAT,
                 "$.camera.eye: [0,1] is not an array of 3 numbers", NULL);
}

Test(scene_error, even_taps_out_of_range)
{
    expect_error("{" MESH ", \"effects\": {\"subsurface\": {\"taps\": 4}}}", DM_ERR_RANGE,
                 "$.effects.subsurface.taps: 4 is not an odd integer in [3, 63]", NULL);
}

Test(scene_error, non_integer_size)
{
    expect_error("{" BASE ", \"output\": {\"width\": 12.5}}", DM_ERR_RANGE,
                 "$.output.width: 12.5 is not an integer in [1, 16384]", NULL);
}

Test(scene_error, roughness_out_of_range)
{
    expect_error("{" BASE ", \"material\": {\"roughness\": 1.5}}", DM_ERR_RANGE,
                 "$.material.roughness: 1.5 is not a number in [0, 1]", NULL);
}

Test(scene_error, negative_colour)
{
    expect_error("{" BASE ", \"lights\": [{\"type\": \"point\", \"position\": [0,0,0], \"color\": [1, -1, 0]}]}",
                 DM_ERR_RANGE, "$.lights[0].color: [1,-1,0]", "in [0, 1e+06]");
}

Test(scene_error, missing_mesh)
{
    expect_error("{\"output\": {}}", DM_ERR_FORMAT, "$.mesh: missing", NULL);
}

Test(scene_error, missing_mesh_path)
{
    expect_error("{\"mesh\": {\"mm_per_unit\": 50}}", DM_ERR_FORMAT, "$.mesh.path: missing", NULL);
}

Test(scene_error, empty_mesh_path)
{
    expect_error("{\"mesh\": {\"path\": \"\"}}", DM_ERR_RANGE, "$.mesh.path: \"\" is not a non-empty file path",
                 NULL);
}

Test(scene_error, unknown_light_type)
{
    expect_error("{" BASE ", \"lights\": [{\"type\": \"spot\"}]}", DM_ERR_FORMAT,
                 "$.lights[0].type: \"spot\" is not \"directional\" or \"point\"", NULL);
}

Test(scene_error, light_without_direction)
{
    expect_error("{" BASE ", \"lights\": [{\"type\": \"directional\"}]}", DM_ERR_FORMAT, "$.lights[0].direction: missing",
                 NULL);
}

Test(scene_error, light_key_of_the_other_type)
{
    expect_error("{" BASE ", \"lights\": [{\"type\": \"directional\", \"position\": [0,0,1]}]}", DM_ERR_FORMAT,
                 "$.lights[0].position: unknown key", NULL);
}

Test(scene_error, zero_light_direction)
{
    expect_error("{" BASE ", \"lights\": [{\"type\": \"directional\", \"direction\": [0,0,0]}]}", DM_ERR_RANGE,
                 "$.lights[0].direction: [0,0,0]", "not all zero");
}

Test(scene_error, too_many_lights)
{
    char json[2048];
    size_t n = (size_t)snprintf(json, sizeof json, "{" BASE ", \"lights\": [");
    for (int k = 0; k < DM_SCENE_MAX_LIGHTS + 1; ++k)
        n += (size_t)snprintf(json + n, sizeof json - n, "%s{\"type\": \"point\", \"position\": [0,0,0]}", k ? "," : "");
    snprintf(json + n, sizeof json - n, "]}");
    expect_error(json, DM_ERR_RANGE, "$.lights: 9 lights, expected at most 8", NULL);
}

Test(scene_error, too_many_environment_alternatives)
{
    expect_error("{" BASE ", \"environment\": {\"path\": \"a.hdr\", \"alternatives\": "
                 "[\"1\", \"2\", \"3\", \"4\", \"5\", \"6\", \"7\", \"8\"]}}",
                 DM_ERR_RANGE, "$.environment.alternatives: 8 maps", "at most 7");
}

Test(scene_error, environment_alternatives_wrong_type)
{
    expect_error("{" BASE ", \"environment\": {\"path\": \"a.hdr\", \"alternatives\": \"b.hdr\"}}",
                 DM_ERR_FORMAT, "$.environment.alternatives: \"b.hdr\" is not an array", NULL);
    expect_error("{" BASE ", \"environment\": {\"path\": \"a.hdr\", \"alternatives\": [\"b.hdr\", 3]}}",
                 DM_ERR_FORMAT, "$.environment.alternatives[1]: 3 is not a file path string", NULL);
    expect_error("{" BASE ", \"environment\": {\"path\": \"a.hdr\", \"alternatives\": [\"\"]}}",
                 DM_ERR_RANGE, "$.environment.alternatives[0]", "non-empty");
}

Test(scene_error, environment_alternatives_without_main_map)
{
    expect_error("{" BASE ", \"environment\": {\"alternatives\": [\"b.hdr\"]}}", DM_ERR_MISMATCH,
                 "$.environment.alternatives", "$.environment.path is missing");
}

Test(scene_error, environment_lighting_without_map)
{
    expect_error("{" MESH ", \"effects\": {\"environment_lighting\": true}}", DM_ERR_MISMATCH,
                 "$.effects.environment_lighting", "$.environment.path is missing");
}

Test(scene_error, camera_eye_equals_target)
{
    expect_error("{" BASE ", \"camera\": {\"eye\": [1,2,3], \"target\": [1,2,3]}}", DM_ERR_RANGE,
                 "$.camera.eye: equals $.camera.target", NULL);
}

Test(scene_error, camera_up_parallel_to_view)
{
    expect_error("{" BASE ", \"camera\": {\"eye\": [0,5,0], \"target\": [0,0,0], \"up\": [0,1,0]}}", DM_ERR_RANGE,
                 "$.camera.up", "parallel");
}

Test(scene_error, fov_out_of_range)
{
    expect_error("{" BASE ", \"camera\": {\"fov_y_deg\": 180}}", DM_ERR_RANGE,
                 "$.camera.fov_y_deg: 180 is not a number in [1, 179]", NULL);
}

Test(scene_error, unsupported_version)
{
    expect_error("{\"version\": 2, " BASE "}", DM_ERR_UNSUPPORTED, "$.version: 2", NULL);
}

Test(scene_error, wrong_format_tag)
{
    expect_error("{\"format\": \"dermis-pack\", " BASE "}", DM_ERR_FORMAT, "$.format: \"dermis-pack\"",
                 "\"dermis-scene\"");
}

Test(scene_error, missing_profile_file)
{
    expect_error("{" MESH ", \"effects\": {\"subsurface\": {\"profile\": \"nowhere.json\"}}}", DM_ERR_FILE_OPEN,
                 "$.effects.subsurface.profile", "/scenes/nowhere.json");
}

Test(scene_error, invalid_inline_profile)
{
    expect_error("{" MESH ", \"effects\": {\"subsurface\": {\"profile\": {\"gaussians\": [{\"variance_mm2\": -1, "
                 "\"weights\": [1, 0, 0]}]}}}}",
                 DM_ERR_RANGE, "$.effects.subsurface.profile", "variance_mm2");
}

Test(scene_error, path_too_long)
{
    char *json = malloc(4096);
    char *p = json + sprintf(json, "{\"mesh\": {\"path\": \"");
    memset(p, 'a', 2000);
    strcpy(p + 2000, "\"}}");
    expect_error(json, DM_ERR_RANGE, "$.mesh.path", "too long");
    free(json);
}

Test(scene_error, file_with_nul_byte_or_missing)
{
    dm_error err = {0};
    cr_assert_eq(dm_scene_read("/nonexistent/scene.json", &scene, &err), DM_ERR_FILE_OPEN);
    cr_assert(strstr(err.detail, "/nonexistent/scene.json"));
}

/* material.albedo_from: "map" (the default) or "skin", which needs a physical skin profile. */
Test(scene, albedo_from_skin_round_trips_and_map_is_not_written)
{
    read_bundled("lps-skin.json");
    cr_assert_eq(scene.albedo_from, DM_ALBEDO_FROM_SKIN);
    cr_assert(scene.skin.given);
    char *text = NULL;
    dm_error err = {0};
    cr_assert_eq(dm_scene_to_json(&scene, &text, &err), DM_OK);
    cr_assert(strstr(text, "\"albedo_from\":\t\"skin\""), "%s", text);
    dm_scene *b = malloc(sizeof *b);
    cr_assert_eq(dm_scene_parse(text, "/elsewhere/s.json", b, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(b->albedo_from, DM_ALBEDO_FROM_SKIN);
    free(text);
    /* the default is left out, so a scene without the key writes what it always did */
    cr_assert_eq(dm_scene_parse("{" BASE ", \"material\": {\"albedo_from\": \"map\"}}", "/s.json", b, &err), DM_OK);
    cr_assert_eq(b->albedo_from, DM_ALBEDO_FROM_MAP);
    cr_assert_eq(dm_scene_to_json(b, &text, &err), DM_OK);
    cr_assert(!strstr(text, "albedo_from"), "%s", text);
    free(text);
    free(b);
}

Test(scene_error, albedo_from_skin_without_a_skin_profile)
{
    expect_error("{" MESH ", \"material\": {\"albedo_from\": \"skin\"}, \"effects\": {\"subsurface\": true}}",
                 DM_ERR_MISMATCH, "$.material.albedo_from: \"skin\"", "profile is gems3-skin, expected {\"skin\"");
    expect_error("{" MESH ", \"material\": {\"albedo_from\": \"skin\"}, \"effects\": {\"subsurface\": {\"profile\": "
                 "{\"gaussians\": [{\"variance_mm2\": 1, \"weights\": [1, 1, 1]}]}}}}",
                 DM_ERR_MISMATCH, "$.material.albedo_from", "profile is a Gaussian profile");
}

Test(scene_error, albedo_from_unknown_value)
{
    expect_error("{" BASE ", \"material\": {\"albedo_from\": \"melanin\"}}", DM_ERR_RANGE, "$.material.albedo_from",
                 "is not \"map\" or \"skin\"");
    expect_error("{" BASE ", \"material\": {\"albedo_from\": 1}}", DM_ERR_FORMAT, "$.material.albedo_from", NULL);
}
