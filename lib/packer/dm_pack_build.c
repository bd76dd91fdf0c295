/* dm_pack_build.c — the pack-building pipeline (dm_pack_build.h): the scene, the step table
 * and its runner, --explain's listing. What the steps share: dm_pack_build_job.c. The steps:
 * dm_pack_build_steps.c (scene, maps, LUTs, profile, kernels, mesh) and dm_pack_build_bake.c
 * (stretch, pre-integrated table, curvature, environments), dm_pack_build_seam.c and
 * dm_pack_build_thin.c (the seam and thin-part maps). */
#include "packer/dm_pack_build.h"

#include <stdio.h>
#include <string.h>

#include "mesh/dm_gltf_map.h"
#include "core/dm_brdf.h"
#include "core/dm_cli.h"
#include "pack/dm_pack_needs.h"

#include "packer/dm_pack_build_impl.h"

/* The bake steps, in pack order. A step runs when one of its entries applies to the scene
 * (dm_pack_needs.h); it adds only the entries that apply.
 */
typedef struct step {
    const char *name;
    const char *entries[4];
    dm_result (*run)(dm_pack_build *j, dm_error *err);
} step;

static const step steps[] = {
    {"scene", {"scene"}, dmpb_step_scene},
    {"mesh", {"mesh.vertices", "mesh.indices"}, dmpb_step_mesh},
    {"albedo map", {"albedo"}, dmpb_step_albedo},
    {"normal map", {"normal"}, dmpb_step_normal},
    {"specular map", {"specular"}, dmpb_step_specular},
    {"roughness map", {"roughness"}, dmpb_step_roughness},
    {"Beckmann LUT", {"lut.beckmann"}, dmpb_step_beckmann},
    {"directional LUTs", {"lut.rho_dt", "lut.env_brdf"}, dmpb_step_directional},
    {"profile", {"profile"}, dmpb_step_profile},
    {"stretch", {"stretch", "stretch.mask"}, dmpb_step_stretch},
    {"seam map", {"seam"}, dmpb_step_seam},
    {"thin-part map", {"thin", "thin.half"}, dmpb_step_thin},
    {"thin gather", {"gather.index", "gather.taps", "gather.half.index", "gather.half.taps"}, dmpb_step_gather},
    {"screen-space kernel", {"sss.kernel"}, dmpb_step_ss_kernel},
    {"pre-integrated table", {"sss.preintegrated"}, dmpb_step_preintegrated},
    {"curvature", {"sss.curvature"}, dmpb_step_curvature},
    {"environment", {"env.sh", "env.specular", "env.background"}, dmpb_step_environment},
};


/* A glTF mesh brings its material: where the scene names no albedo or normal map, the
 * material's baseColor / normal texture stands in (the map's path becomes the glTF file,
 * which pack_map reads through dm_gltf_map_read). */
static dm_result gltf_material_maps(dm_pack_build *j, dm_error *err)
{
    if (!dm_gltf_is_file(j->scene.mesh)) return DM_OK;
    struct { char *field; dm_gltf_map which; const char *what; } maps[2] = {
        {j->scene.albedo, DM_GLTF_MAP_BASE_COLOR, "albedo"}, {j->scene.normal_map, DM_GLTF_MAP_NORMAL, "normal_map"}};
    for (int k = 0; k < 2; ++k) {
        if (maps[k].field[0]) continue;
        int found = 0;
        char src[300];
        dm_result r = dm_gltf_map_find(j->scene.mesh, j->scene.mesh_name, maps[k].which, &found, src, sizeof src, err);
        if (r != DM_OK) return r;
        if (!found) continue;
        snprintf(maps[k].field, DM_SCENE_PATH_SIZE, "%s", j->scene.mesh);
        if (!j->opt->quiet)
            fprintf(stderr, "note: material.%s: the glTF material's %s, %s\n", maps[k].what,
                    maps[k].which == DM_GLTF_MAP_BASE_COLOR ? "baseColorTexture" : "normalTexture", src);
    }
    return DM_OK;
}


dm_result dm_pack_build_begin(dm_pack_build *b, const char *scene_path, const char *const *asset_dirs, int asset_count,
                              const dm_pack_build_options *opt, dm_error *err)
{
    memset(b, 0, sizeof *b);
    b->opt = opt;
    b->scene_path = scene_path;
    dm_pack_writer_init(&b->w);
    dm_result r = dm_scene_read_assets(scene_path, asset_dirs, asset_count, &b->scene, err);
    if (r == DM_OK) snprintf(b->scene_hash, sizeof b->scene_hash, "%s", b->scene.file_hash);
    if (r == DM_OK) r = dmpb_fit_skin(b, err);
    if (r == DM_OK) r = gltf_material_maps(b, err);
    if (r == DM_OK && b->scene.albedo_from == DM_ALBEDO_FROM_SKIN && !b->scene.albedo[0]) /* after a glTF's map could stand in */
        r = dm_fail(err, DM_ERR_MISMATCH,
                    "%s: $.material.albedo_from: \"skin\" modulates the albedo map's luminance detail, but "
                    "$.material.albedo is empty, expected a map",
                    scene_path);
    return r;
}

dm_result dm_pack_build_run(dm_pack_build *b, const char **failed_step, dm_error *err)
{
    /* a bar by step (a step's own work is not split) when stderr is a terminal */
    enum { STEP_COUNT = sizeof steps / sizeof steps[0] };
    bool will_run[STEP_COUNT];
    int run_count = 0, done = 0;
    for (size_t s = 0; s < STEP_COUNT; ++s) {
        will_run[s] = false;
        for (int e = 0; e < 4 && steps[s].entries[e]; ++e)
            will_run[s] = will_run[s] || dm_pack_build_wants(b, steps[s].entries[e]);
        run_count += will_run[s];
    }
    dm_progress bar;
    dm_progress_begin(&bar, "pack", b->opt->quiet);
    dm_result r = DM_OK;
    for (size_t s = 0; s < STEP_COUNT && r == DM_OK; ++s) {
        if (!will_run[s]) continue;
        b->step_t0 = dm_now_ms();
        r = steps[s].run(b, err);
        dm_progress_update(&bar, (double)++done / (run_count + 1));
        if (r != DM_OK && failed_step) *failed_step = steps[s].name;
    }
    dm_progress_end(&bar);
    return r;
}

dm_result dm_pack_build_write(const dm_pack_build *b, const char *path, size_t *written_size, dm_error *err)
{
    const dm_pack_build_options *o = b->opt;
    dm_provenance p;
    dm_prov_init(&p, DM_PACK_BUILD_TOOL);
    snprintf(p.input_hash, sizeof p.input_hash, "%s", b->scene_hash);
    dm_prov_add_string(&p, "scene", b->scene_path);
    dm_prov_add_int(&p, "beckmann_size", o->beckmann_size);
    dm_prov_add_int(&p, "lut_size", o->lut_size);
    dm_prov_add_int(&p, "lut_nodes", o->lut_nodes);
    dm_prov_add_double(&p, "f0", DM_SKIN_F0);
    dm_prov_add_string(&p, "beckmann_file", o->beckmann ? o->beckmann : "");
    dm_prov_add_string(&p, "rho_dt_file", o->rho_dt ? o->rho_dt : "");
    dm_prov_add_string(&p, "env_brdf_file", o->env_brdf ? o->env_brdf : "");
    size_t size = 0;
    dm_result r = dm_pack_writer_write(&b->w, path, &p, &size, err);
    if (written_size) *written_size = size;
    return r;
}

void dm_pack_build_free(dm_pack_build *b)
{
    dm_pack_writer_free(&b->w);
    if (b->mesh_loaded) dm_mesh_free(&b->mesh);
    b->mesh_loaded = false;
}

/* --- explain ------------------------------------------------------------------------ */

void dm_pack_build_explain(const dm_scene *s)
{
    printf("scene %s\neffects:", s->path);
    for (int e = 0; e < DM_EFFECT_COUNT; ++e)
        printf(" %s=%s", dm_effect_name((dm_effect)e), s->effects[e] ? "on" : "off");
    printf("\n\n%-8s %-15s %-19s %-52s %s\n", "status", "entry", "kind", "needed by", "what");
    int n;
    const dm_pack_need *needs = dm_pack_needs(&n);
    for (int k = 0; k < n; ++k) {
        const dm_pack_need *nd = &needs[k];
        bool applies = dm_pack_need_applies(nd, s);
        char kind[64], by[160] = "";
        snprintf(kind, sizeof kind, "%s%s%s", dm_pack_kind_name(nd->kind), nd->format >= 0 ? " " : "",
                 nd->format >= 0 ? dm_tex_format_get((dm_tex_format)nd->format)->name : "");
        size_t m = 0;
        if (!nd->effects) m += (size_t)snprintf(by, sizeof by, "always");
        for (int e = 0; e < DM_EFFECT_COUNT; ++e)
            if (nd->effects & DM_FX(e))
                m += (size_t)snprintf(by + m, m < sizeof by ? sizeof by - m : 0, "%s%s%s", m ? "|" : "",
                                      dm_effect_name((dm_effect)e), s->effects[e] ? "" : "(off)");
        if (nd->when && m < sizeof by)
            snprintf(by + m, sizeof by - m, " if %s", dm_need_when_text(nd->when));
        const char *status = applies ? "pack" : "skip";
        for (int c = 0; c < dm_pack_need_copies(nd, s); ++c) { /* env<k>.*: one per alternative map */
            char name[DM_PACK_NAME_SIZE], why[1200];
            if (c == 0 && s->albedo_from == DM_ALBEDO_FROM_SKIN && !strcmp(nd->entry, "albedo"))
                snprintf(why, sizeof why, "%s: albedo_from skin, the skin's total reflectance x the map's luminance "
                         "detail", nd->why);
            else if (c == 0)
                snprintf(why, sizeof why, "%s", nd->why);
            else
                snprintf(why, sizeof why, "%s (alternative %d: %s)", nd->why, c, dmpb_base_name(s->env_alternatives[c - 1]));
            printf("%-8s %-15s %-19s %-52s %s\n", status, dm_pack_need_entry_name(nd, c, name), kind, by, why);
        }
    }
    printf("\npack = baked and packed; skip = no enabled effect or input needs it\n");
}

