/* material.albedo_from "skin" through dermis-pack on the head (packer/dm_pack_build_skin.c):
 * the packed albedo's mean over the skin is the model's total reflectance as
 * dermis-fit-profile reports it; without the option the pack is what it always was; misuse
 * is refused naming the key. The colour rule itself, on known answers: test_albedo_skin.c. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "../common/tmpdir.h"
#include "bake/dm_albedo_skin.h"
#include "core/dm_scene.h"
#include "core/dm_srgb.h"
#include "image/dm_image.h"
#include "mesh/dm_mesh.h"
#include "pack/dm_pack.h"

#define LPS DERMIS_ASSETS "/lps/"
#define PACK_SMALL "--beckmann-size 16 --lut-size 8 --lut-nodes 8 --quiet"

static char dir[256];
static void setup(void) { cr_assert(test_tmpdir(dir, sizeof dir)); }

/* A scene with the head's map and no bakes beyond it (no effects: the base shading's entries). */
static void write_scene(char *path, size_t size, const char *name, const char *material_extra, const char *profile)
{
    snprintf(path, size, "%s/%s.json", dir, name);
    FILE *f = fopen(path, "w");
    cr_assert(f);
    fprintf(f, "{\"mesh\": {\"path\": \"%s\", \"mm_per_unit\": 50}, "
               "\"material\": {\"albedo\": \"%s\"%s}, "
               "\"effects\": {\"subsurface\": {\"enabled\": false, \"profile\": %s}}, "
               "\"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1]}]}\n",
            LPS "LeePerrySmith.obj", LPS "Map-COL.jpg", material_extra, profile);
    fclose(f);
}

static void pack(const char *scene, const char *out)
{
    char cmd[1200];
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack '%s' -o '%s' " PACK_SMALL, scene, out);
    cr_assert_eq(test_run(cmd, NULL), 0, "%s", cmd);
}

/* The physical total reflectance dermis-fit-profile reports for a preset (its JSON's source). */
static void tool_total(const char *preset, double rgb[3])
{
    char cmd[600], path[320];
    snprintf(path, sizeof path, "%s/p.json", dir);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-fit-profile --skin-preset %s -o %s --quiet", preset, path);
    cr_assert_eq(test_run(cmd, NULL), 0, "%s", cmd);
    char *text = test_slurp(path);
    cJSON *j = cJSON_Parse(text);
    const cJSON *t = cJSON_GetObjectItem(cJSON_GetObjectItem(j, "source"), "total_reflectance_rgb");
    cr_assert(cJSON_GetArraySize(t) == 3, "%s", text);
    for (int c = 0; c < 3; ++c) rgb[c] = cJSON_GetArrayItem(t, c)->valuedouble;
    cJSON_Delete(j);
    free(text);
}

static double half_step(uint8_t v)
{
    double lo = dm_srgb_to_linear((v > 0 ? v - 0.5 : 0.0) / 255.0), hi = dm_srgb_to_linear((v + 0.5) / 255.0);
    return 0.5 * (hi - lo);
}

/* The head at a light, a middle and a dark preset: the packed map's mean over the skin (each
 * texel weighted by the mm² it stands for) is the model's total per channel, within the mean
 * half 8-bit step of the texels (the rounding's bound, nothing clipping at these presets). The
 * bound is 0.6–1.0 % of the total (measured: Fitzpatrick 1 0.59–0.73 %, 6 0.67–1.04 %); the
 * rounding's errors mostly cancel, and the means measured are within 0.1 % of the totals.
 * The bound stays under 1.5 %: a colour 2 % off the model's fails here. */
Test(pack_albedo_skin, head_mean_over_the_skin_is_the_model_total, .init = setup, .timeout = 180)
{
    dm_mesh mesh;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(LPS "LeePerrySmith.obj", NULL, &mesh, &err), DM_OK, "%s", err.detail);
    const char *presets[] = {"fitzpatrick-1", "fitzpatrick-3", "fitzpatrick-6"};
    float *weight = NULL;
    for (int k = 0; k < 3; ++k) {
        char scene[320], out[320], profile[128];
        snprintf(profile, sizeof profile, "{\"skin\": {\"preset\": \"%s\"}}", presets[k]);
        write_scene(scene, sizeof scene, presets[k], ", \"albedo_from\": \"skin\"", profile);
        snprintf(out, sizeof out, "%s/%s.dpk", dir, presets[k]);
        pack(scene, out);
        dm_pack p;
        cr_assert_eq(dm_pack_open(out, &p, &err), DM_OK, "%s", err.detail);
        const dm_pack_entry *e = dm_pack_find(&p, "albedo");
        cr_assert(e && e->format == DM_TEX_RGBA8_SRGB);
        if (!weight) {
            weight = malloc((size_t)e->width * e->height * sizeof *weight);
            cr_assert_eq(dm_albedo_skin_weights(&mesh, 50.0, e->width, e->height, 0, weight, NULL, &err), DM_OK);
        }
        double total[3];
        tool_total(presets[k], total);
        const uint8_t *px = e->data;
        for (int c = 0; c < 3; ++c) {
            double sum = 0, w_sum = 0, tol = 0;
            for (size_t i = 0; i < (size_t)e->width * e->height; ++i) {
                sum += weight[i] * dm_srgb_to_linear(px[4 * i + c] / 255.0);
                tol += weight[i] * half_step(px[4 * i + c]);
                w_sum += weight[i];
            }
            double mean = sum / w_sum;
            cr_expect(fabs(mean - total[c]) <= tol / w_sum, "%s channel %d: mean %.5f over the skin, model %.5f (+- %.5f)",
                      presets[k], c, mean, total[c], tol / w_sum);
            cr_expect(tol / w_sum < 0.015 * total[c], "%s: the bound %.5f is under 1.5 %% of %.5f", presets[k],
                      tol / w_sum, total[c]);
            cr_log_info("%s channel %d: mean %.5f, model %.5f (%+.2f %%), bound %.2f %%", presets[k], c, mean, total[c],
                        100 * (mean / total[c] - 1), 100 * tol / w_sum / total[c]);
        }
        cr_expect(strstr(e->provenance_json, "\"clipped_texels\":0"), "%s", e->provenance_json);
        dm_pack_close(&p);
    }
    free(weight);
    dm_mesh_free(&mesh);
}

/* The entry says what made it; the pack's scene takes the baked colour as its map (its profile
 * is inline now, no longer a skin, so "skin" could not stand there). */
Test(pack_albedo_skin, provenance_and_the_packs_scene, .init = setup, .timeout = 60)
{
    char scene[320], out[320];
    write_scene(scene, sizeof scene, "s", ", \"albedo_from\": \"skin\"",
                "{\"skin\": {\"preset\": \"fitzpatrick-4\", \"blood\": 0.01}}");
    snprintf(out, sizeof out, "%s/s.dpk", dir);
    pack(scene, out);
    dm_pack p;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open(out, &p, &err), DM_OK, "%s", err.detail);
    const char *prov = dm_pack_find(&p, "albedo")->provenance_json;
    const char *want[] = {"\"albedo_from\":\"skin\"", "\"skin_preset\":\"fitzpatrick-4\"", "blood=0.01",
                          "\"skin_total_reflectance_r\":", "\"map_mean_luminance\":", "\"albedo_mean_b\":"};
    for (size_t k = 0; k < sizeof want / sizeof want[0]; ++k) cr_expect(strstr(prov, want[k]), "%s lacks %s", prov, want[k]);
    cr_assert_eq(p.scene->albedo_from, DM_ALBEDO_FROM_MAP);
    cr_assert(!p.scene->skin.given && !strcmp(p.scene->profile_source, "inline"));
    const dm_pack_entry *s = dm_pack_find(&p, "scene");
    char *json = strndup(s->data, s->size);
    cr_assert(!strstr(json, "albedo_from"), "the pack's scene names no albedo_from: %s", json);
    free(json);
    dm_pack_close(&p);
}

/* Off (absent, or "map") the albedo entry is the map as read, byte for byte, and the two packs
 * are the same entry for entry: the option costs nothing when it is not asked for. */
Test(pack_albedo_skin, off_packs_the_map_as_it_is, .init = setup, .timeout = 60)
{
    char absent[320], map[320], pa[320], pm[320];
    const char *skin = "{\"skin\": {\"preset\": \"fitzpatrick-2\"}}";
    write_scene(absent, sizeof absent, "absent", "", skin);
    write_scene(map, sizeof map, "map", ", \"albedo_from\": \"map\"", skin);
    snprintf(pa, sizeof pa, "%s/absent.dpk", dir);
    snprintf(pm, sizeof pm, "%s/map.dpk", dir);
    pack(absent, pa);
    pack(map, pm);
    dm_pack a, m;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open(pa, &a, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_pack_open(pm, &m, &err), DM_OK, "%s", err.detail);
    dm_image img;
    cr_assert_eq(dm_image_read(LPS "Map-COL.jpg", DM_PIXEL_U8, &img, &err), DM_OK, "%s", err.detail);
    const dm_pack_entry *e = dm_pack_find(&a, "albedo");
    cr_assert(e && e->width == img.width && e->height == img.height && img.channels == 3);
    const uint8_t *px = e->data, *in = img.pixels;
    for (size_t i = 0; i < (size_t)img.width * img.height; ++i)
        for (int c = 0; c < 4; ++c)
            cr_assert_eq(px[4 * i + c], c < 3 ? in[3 * i + c] : 255, "texel %zu channel %d", i, c);
    cr_assert(!strstr(e->provenance_json, "albedo_from"), "%s", e->provenance_json);
    cr_assert_eq(a.entry_count, m.entry_count);
    for (int k = 0; k < a.entry_count; ++k) {
        cr_assert_str_eq(a.entries[k].name, m.entries[k].name);
        cr_assert_eq(a.entries[k].xxh3, m.entries[k].xxh3, "entry %s differs", a.entries[k].name);
    }
    dm_image_free(&img);
    dm_pack_close(&a);
    dm_pack_close(&m);
}

/* Misuse: a non-zero exit and a message naming the key and what was expected. */
Test(pack_albedo_skin, misuse_is_refused_naming_the_key, .init = setup, .timeout = 60)
{
    struct {
        const char *extra, *profile, *says;
    } bad[] = {
        {", \"albedo_from\": \"skin\"", "\"gems3-skin\"", "$.effects.subsurface.profile is gems3-skin, expected {\"skin\""},
        {", \"albedo_from\": \"paint\"", "{\"skin\": {\"preset\": \"asian\"}}", "\"map\" or \"skin\""},
        {", \"albedo_from\": true", "{\"skin\": {\"preset\": \"asian\"}}", "\"map\" or \"skin\""},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        char scene[320], cmd[1200], log[320];
        write_scene(scene, sizeof scene, "bad", bad[k].extra, bad[k].profile);
        snprintf(log, sizeof log, "%s/log.txt", dir);
        snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack '%s' -o '%s/bad.dpk' " PACK_SMALL, scene, dir);
        cr_expect_eq(test_run(cmd, log), 2, "%s: exit 2 (cannot load the scene)", bad[k].extra);
        char *text = test_slurp(log);
        cr_expect(strstr(text, "error: ") && strstr(text, "$.material.albedo_from") && strstr(text, bad[k].says),
                  "%s: '%s' lacks '%s'", bad[k].extra, text, bad[k].says);
        free(text);
    }
    /* no map to take the detail from */
    char scene[320], cmd[1200], log[320];
    snprintf(scene, sizeof scene, "%s/nomap.json", dir);
    FILE *f = fopen(scene, "w");
    fprintf(f, "{\"mesh\": {\"path\": \"%s\"}, \"material\": {\"albedo_from\": \"skin\"}, "
               "\"effects\": {\"subsurface\": {\"profile\": {\"skin\": {\"preset\": \"asian\"}}}}}\n",
            LPS "LeePerrySmith.obj");
    fclose(f);
    snprintf(log, sizeof log, "%s/log.txt", dir);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack '%s' -o '%s/bad.dpk' " PACK_SMALL, scene, dir);
    cr_expect_eq(test_run(cmd, log), 2);
    char *text = test_slurp(log);
    cr_expect(strstr(text, "$.material.albedo_from") && strstr(text, "$.material.albedo is empty"), "%s", text);
    free(text);
}

/* --explain says where the colour comes from. */
Test(pack_albedo_skin, explain_names_the_rule, .init = setup, .timeout = 60)
{
    char scene[320], cmd[1200], log[320];
    write_scene(scene, sizeof scene, "x", ", \"albedo_from\": \"skin\"", "{\"skin\": {\"preset\": \"asian\"}}");
    snprintf(log, sizeof log, "%s/explain.txt", dir);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack --explain '%s'", scene);
    cr_assert_eq(test_run(cmd, log), 0, "%s", cmd);
    char *text = test_slurp(log);
    cr_expect(strstr(text, "albedo_from skin, the skin's total reflectance x the map's luminance detail"), "%s", text);
    free(text);
}
