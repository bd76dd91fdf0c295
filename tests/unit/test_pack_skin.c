/* A scene whose profile is a physical skin ("profile": {"skin": {…}}): the scene reader
 * (core) stores the parameters, the packer fits the profile (packer/dm_pack_build_skin.c);
 * the packed profile is the one dermis-fit-profile --skin writes for the same parameters,
 * and the pack's scene carries it inline for the renderer. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/tmpdir.h"
#include "core/dm_scene.h"
#include "pack/dm_pack.h"
#include "packer/dm_pack_build.h"

#define HEAD DERMIS_ASSETS "/lps/LeePerrySmith.obj"

static char dir[256];
static void setup(void) { cr_assert(test_tmpdir(dir, sizeof dir)); }

/* A scene with screen-space subsurface (the profile and its kernel, no texture bake). */
static void write_scene(char *path, size_t size, const char *name, const char *profile)
{
    snprintf(path, size, "%s/%s.json", dir, name);
    FILE *f = fopen(path, "w");
    cr_assert(f);
    fprintf(f, "{\"mesh\": {\"path\": \"%s\", \"mm_per_unit\": 50}, "
               "\"effects\": {\"subsurface\": {\"technique\": \"screen-space\", \"profile\": %s}}, "
               "\"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1]}]}\n",
            HEAD, profile);
    fclose(f);
}

/* Gaussians identical: same count, variances and weights to the bit (the same calls on the
 * same parameters, deterministic). */
static void same_profile(const dm_profile *a, const dm_profile *b, const char *what)
{
    cr_assert_eq(a->count, b->count, "%s: %d vs %d Gaussians", what, a->count, b->count);
    for (int k = 0; k < a->count; ++k) {
        cr_assert_eq(a->variance_mm2[k], b->variance_mm2[k], "%s: variance %d", what, k);
        for (int c = 0; c < 3; ++c)
            cr_assert_eq(a->weight[k][c], b->weight[k][c], "%s: weight[%d][%d] %.17g vs %.17g", what, k, c,
                         a->weight[k][c], b->weight[k][c]);
    }
}

static void tool_profile(const char *args, dm_profile *out)
{
    char cmd[1024], path[320];
    snprintf(path, sizeof path, "%s/tool.json", dir);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-fit-profile %s -o %s --quiet", args, path);
    cr_assert_eq(test_run(cmd, NULL), 0, "%s", cmd);
    dm_error err = {0};
    cr_assert_eq(dm_profile_read(path, out, &err), DM_OK, "%s", err.detail);
}

Test(pack_skin, inline_skin_packs_as_dermis_fit_profile_fits_it, .init = setup, .timeout = 120)
{
    char scene[320], pack_path[320], cmd[1200];
    write_scene(scene, sizeof scene, "skin",
                "{\"skin\": {\"melanin\": 0.05, \"eumelanin\": 0.6, \"blood\": 0.02, \"epidermis-mm\": 0.1}}");
    /* the scene reader keeps the numbers; the profile is a stand-in until packing */
    dm_scene *s = malloc(sizeof *s);
    dm_error err = {0};
    cr_assert_eq(dm_scene_read(scene, s, &err), DM_OK, "%s", err.detail);
    cr_assert(s->skin.given && s->skin.key_count == 4 && !strcmp(s->profile_source, "skin"));
    free(s);

    snprintf(pack_path, sizeof pack_path, "%s/skin.dpk", dir);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack '%s' -o '%s' --beckmann-size 16 --lut-size 8 --lut-nodes 8 --quiet",
             scene, pack_path);
    cr_assert_eq(test_run(cmd, NULL), 0, "%s", cmd);
    dm_pack pack;
    cr_assert_eq(dm_pack_open(pack_path, &pack, &err), DM_OK, "%s", err.detail);
    cr_assert(pack.profile && pack.scene, "the pack has a profile entry and a scene");
    dm_profile ref;
    tool_profile("--skin melanin=0.05,eumelanin=0.6,blood=0.02,epidermis-mm=0.1", &ref);
    same_profile(pack.profile, &ref, "the packed profile");
    same_profile(&pack.scene->profile, &ref, "the pack's scene");
    cr_assert(!pack.scene->skin.given && !strcmp(pack.scene->profile_source, "inline"),
              "the pack's scene holds the fitted profile inline");
    cr_assert(dm_pack_find(&pack, "profile"));
    /* the entry's provenance names the skin it was fitted to, exactly */
    cr_expect(strstr(pack.manifest, "melanin=0.050000000000000003,eumelanin=0.59999999999999998"), "%s", pack.manifest);
    dm_pack_close(&pack);
}

/* {"skin": {"preset": …}} is --skin-preset; a key beside the preset overrides it. */
Test(pack_skin, preset_and_override, .init = setup, .timeout = 60)
{
    char scene[320];
    write_scene(scene, sizeof scene, "preset", "{\"skin\": {\"preset\": \"fitzpatrick-3\"}}");
    static const dm_pack_build_options small = {.beckmann_size = 16, .lut_size = 8, .lut_nodes = 8, .quiet = true};
    dm_pack_build *b = malloc(sizeof *b);
    dm_error err = {0};
    cr_assert_eq(dm_pack_build_begin(b, scene, NULL, 0, &small, &err), DM_OK, "%s", err.detail);
    dm_profile ref;
    tool_profile("--skin-preset fitzpatrick-3", &ref);
    same_profile(&b->scene.profile, &ref, "preset");
    cr_assert_str_eq(b->scene.profile.name, "fitzpatrick-3");
    dm_pack_build_free(b);

    write_scene(scene, sizeof scene, "override", "{\"skin\": {\"preset\": \"fitzpatrick-3\", \"blood\": 0.03}}");
    cr_assert_eq(dm_pack_build_begin(b, scene, NULL, 0, &small, &err), DM_OK, "%s", err.detail);
    tool_profile("--skin melanin=0.013,eumelanin=0.7,blood=0.03,epidermis-mm=0.075", &ref);
    same_profile(&b->scene.profile, &ref, "override");
    dm_pack_build_free(b);
    free(b);
}

/* Names and types are the scene reader's to refuse (core); ranges and presets the packer's
 * (the model's ranges live offline): each message names the JSON path and what was expected. */
Test(pack_skin, bad_skins_are_refused_with_the_path, .init = setup, .timeout = 60)
{
    struct {
        const char *profile, *says;
        bool at_read;
    } bad[] = {
        {"{\"skin\": {\"melanin\": 0.1, \"eumelanin\": 0.5, \"blood\": 0.01, \"hair\": 1}}", "$.effects.subsurface.profile.skin.hair", true},
        {"{\"skin\": {\"melanin\": \"dark\", \"eumelanin\": 0.5, \"blood\": 0.01}}", "a number", true},
        {"{\"skin\": {\"melanin\": 0.1, \"blood\": 0.01}}", "\"eumelanin\"", true},
        {"{\"skin\": 3}", "an object of skin parameters", true},
        {"{\"skin\": {\"melanin\": 0.7, \"eumelanin\": 0.5, \"blood\": 0.01}}", "melanin_fraction (melanin, Cm) = 0.7, expected a value in [0, 0.5]", false},
        {"{\"skin\": {\"preset\": \"martian\"}}", "fitzpatrick-1", false},
    };
    static const dm_pack_build_options small = {.beckmann_size = 16, .lut_size = 8, .lut_nodes = 8, .quiet = true};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        char scene[320];
        write_scene(scene, sizeof scene, "bad", bad[k].profile);
        dm_scene *s = malloc(sizeof *s);
        dm_error err = {0};
        dm_result r = dm_scene_read(scene, s, &err);
        free(s);
        if (!bad[k].at_read) {
            cr_assert_eq(r, DM_OK, "%s: %s", bad[k].profile, err.detail);
            dm_pack_build *b = malloc(sizeof *b);
            r = dm_pack_build_begin(b, scene, NULL, 0, &small, &err);
            dm_pack_build_free(b);
            free(b);
            cr_expect(strstr(err.detail, "$.effects.subsurface.profile.skin"), "%s", err.detail);
        }
        cr_expect_neq(r, DM_OK, "%s should be refused", bad[k].profile);
        cr_expect(strstr(err.detail, bad[k].says), "%s: '%s' lacks '%s'", bad[k].profile, err.detail, bad[k].says);
    }
}

/* An unpacked scene writes its skin back as it read it (dm_scene_to_json), to the bit. */
Test(pack_skin, unpacked_skin_round_trips, .init = setup)
{
    char scene[320], again[320];
    write_scene(scene, sizeof scene, "rt", "{\"skin\": {\"preset\": \"asian\", \"blood\": 0.012345678901234567}}");
    dm_scene *s = malloc(sizeof *s), *t = malloc(sizeof *t);
    dm_error err = {0};
    cr_assert_eq(dm_scene_read(scene, s, &err), DM_OK, "%s", err.detail);
    char *json = NULL;
    cr_assert_eq(dm_scene_to_json(s, &json, &err), DM_OK, "%s", err.detail);
    snprintf(again, sizeof again, "%s/again.json", dir);
    FILE *f = fopen(again, "w");
    cr_assert(f);
    fputs(json, f);
    fclose(f);
    free(json);
    cr_assert_eq(dm_scene_read(again, t, &err), DM_OK, "%s", err.detail);
    cr_assert(t->skin.given && !strcmp(t->skin.preset, "asian") && t->skin.key_count == 1);
    cr_assert_eq(t->skin.value[0], s->skin.value[0]);
    cr_assert_str_eq(t->profile_source, "skin");
    free(s);
    free(t);
}
