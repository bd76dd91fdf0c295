/* dm_pack_build_bake.c — the pack's baking steps: the stretch chain, the pre-integrated table,
 * the curvature map and the environments (dm_pack_build.h). */
#include "packer/dm_pack_build.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_curvature.h"
#include "packer/dm_pack_env.h"
#include "bake/dm_preintegrated.h"
#include "bake/dm_stretch.h"
#include "core/dm_file.h"
#include "pack/dm_pack_needs.h"

#include "packer/dm_pack_build_impl.h"

static dm_result read_stretch(dm_pack_build *j, const char *file, dm_stretch_map *map, dm_error *err)
{
    dm_provenance p;
    dm_result r = dm_stretch_read(file, map, &p, err);
    if (r != DM_OK) return r;
    const dm_param *mm = dm_prov_find(&p, "mm_per_unit"), *name = dm_prov_find(&p, "mesh_name");
    const char *baked_name = name && name->type == DM_PARAM_STRING ? name->s : "";
    const int n = j->scene.irradiance_size;
    const dm_profile *pr = &j->scene.profile;
    if (strcmp(p.input_hash, j->mesh_hash) != 0)
        r = dm_fail(err, DM_ERR_MISMATCH, "%s: baked from a mesh with hash %s, %s has %s", file,
                    p.input_hash[0] ? p.input_hash : "(none)", j->scene.mesh, j->mesh_hash);
    else if (strcmp(baked_name, j->scene.mesh_name) != 0)
        r = dm_fail(err, DM_ERR_MISMATCH, "%s: baked from mesh name \"%s\", the scene's mesh.name is \"%s\"", file,
                    baked_name, j->scene.mesh_name);
    else if (!mm || mm->type == DM_PARAM_STRING || mm->d != j->scene.mm_per_unit)
        r = dm_fail(err, DM_ERR_MISMATCH, "%s: mm_per_unit is %g, the scene says %g", file, mm ? mm->d : 0.0,
                    j->scene.mm_per_unit);
    else if (map->width != n || map->height != n)
        r = dm_fail(err, DM_ERR_MISMATCH, "%s: %dx%d, the scene's irradiance size is %d (bake it with --size %d)",
                    file, map->width, map->height, n, n);
    else if (map->level_count != pr->count)
        r = dm_fail(err, DM_ERR_MISMATCH, "%s: %d levels, the scene's profile %s has %d Gaussians", file,
                    map->level_count, pr->name, pr->count);
    for (int k = 0; r == DM_OK && k < pr->count; ++k)
        if (map->variance_mm2[k] != pr->variance_mm2[k])
            r = dm_fail(err, DM_ERR_MISMATCH, "%s: level %d stands for %.17g mm^2, the scene's profile has %.17g",
                        file, k, map->variance_mm2[k], pr->variance_mm2[k]);
    if (r != DM_OK) dm_stretch_map_free(map);
    return r;
}

/* The stretch chain at the scene's irradiance size: one RG32F layer per Gaussian (u, v in
 * UV units per mm), and the chart mask as R8. */
dm_result dmpb_step_stretch(dm_pack_build *j, dm_error *err)
{
    dm_result r = dmpb_ensure_mesh(j, err);
    if (r != DM_OK) return r;
    const int n = j->scene.irradiance_size;
    dm_stretch_options so = {.width = n,
                             .height = n,
                             .mm_per_unit = j->scene.mm_per_unit,
                             .profile = &j->scene.profile,
                             .thread_count = j->opt->threads};
    dm_stretch_map map;
    char src[200];
    snprintf(src, sizeof src, "baked from %.150s", dmpb_base_name(j->scene.mesh));
    if (j->opt->stretch_file) {
        if ((r = read_stretch(j, j->opt->stretch_file, &map, err)) != DM_OK) return r;
        snprintf(src, sizeof src, "from %.150s", dmpb_base_name(j->opt->stretch_file));
    } else if ((r = dm_stretch_bake(&j->mesh, &so, &map, err)) != DM_OK) {
        return r;
    }
    const size_t texels = (size_t)n * n;
    float *rg = malloc(texels * 2 * (size_t)map.level_count * sizeof *rg);
    uint8_t *mask = malloc(texels);
    if (!rg || !mask) r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "stretch %dx%d: out of memory", n, n);
    for (int k = 0; r == DM_OK && k < map.level_count; ++k)
        for (size_t i = 0; i < texels; ++i) {
            rg[((size_t)k * texels + i) * 2] = map.s_u[k][i];
            rg[((size_t)k * texels + i) * 2 + 1] = map.s_v[k][i];
        }
    for (size_t i = 0; r == DM_OK && i < texels; ++i) mask[i] = map.mask[i] > 0.5f ? 255 : 0;
    dm_provenance p;
    dmpb_mesh_prov(j, &p, "stretch chain, UV units per mm, one layer per Gaussian");
    dm_prov_add_int(&p, "size", n);
    dm_prov_add_string(&p, "profile", j->scene.profile.name);
    for (int k = 0; k < map.level_count; ++k) {
        char name[32];
        snprintf(name, sizeof name, "variance%d_mm2", k);
        dm_prov_add_double(&p, name, map.variance_mm2[k]);
    }
    dm_prov_add_double(&p, "coverage", map.stats.coverage);
    if (j->opt->stretch_file) dm_prov_add_string(&p, "baked_file", j->opt->stretch_file);
    if (r == DM_OK) {
        dm_pack_entry d = dm_pack_texture_entry("stretch", DM_TEX_RG32F, n, n);
        d.layers = map.level_count;
        d.channel_count = 2;
        snprintf(d.channels[0], sizeof d.channels[0], "u");
        snprintf(d.channels[1], sizeof d.channels[1], "v");
        r = dmpb_add(j, &d, rg, texels * 2 * (size_t)map.level_count * sizeof *rg, &p, src, err);
    }
    if (r == DM_OK) {
        dm_pack_entry d = dm_pack_texture_entry("stretch.mask", DM_TEX_R8, n, n);
        dmpb_mesh_prov(j, &p, "chart coverage mask, 255 covered");
        dm_prov_add_int(&p, "size", n);
        r = dmpb_add(j, &d, mask, texels, &p, src, err);
    }
    free(rg);
    free(mask);
    dm_stretch_map_free(&map);
    return r;
}

/* The pre-integrated technique's table (bake/dm_preintegrated.h) for the scene's profile:
 * 128 N.L x 64 curvature texels over 0..1 /mm, RGBA32F with a = 1; layout in the provenance. */
enum { PREINT_WIDTH = 128, PREINT_HEIGHT = 64 };
dm_result dmpb_step_preintegrated(dm_pack_build *j, dm_error *err)
{
    dm_preint_lut lut;
    dm_result r = dm_preint_bake(&j->scene.profile, PREINT_WIDTH, PREINT_HEIGHT, DM_PREINT_CURVATURE_MAX_DEFAULT,
                                 j->opt->threads, &lut, err);
    if (r != DM_OK) return r;
    size_t texels = (size_t)lut.width * lut.height;
    float *rgba = malloc(texels * 4 * sizeof *rgba);
    if (!rgba) {
        dm_preint_lut_free(&lut);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "pre-integrated table: out of memory");
    }
    for (size_t i = 0; i < texels; ++i) {
        for (int c = 0; c < 3; ++c) rgba[4 * i + c] = lut.rgb[c * texels + i];
        rgba[4 * i + 3] = 1.0f;
    }
    dm_provenance p;
    dm_prov_init(&p, DM_PACK_BUILD_TOOL);
    dm_prov_add_string(&p, "source", j->scene.profile_source);
    dm_prov_add_string(&p, "product", "pre-integrated skin diffuse D(N.L, curvature) (Penner 2011), rgb");
    dm_prov_add_string(&p, "s", "N.L = 2s-1 at texel centres");
    dm_prov_add_string(&p, "t", "curvature = curvature_max*j/(height-1) on row j");
    dm_prov_add_double(&p, "curvature_max_per_mm", lut.curvature_max_per_mm);
    char src[160];
    snprintf(src, sizeof src, "%dx%d, curvature 0..%g /mm, %.0f ms", lut.width, lut.height, lut.curvature_max_per_mm,
             lut.bake_ms);
    dm_pack_entry d = dm_pack_texture_entry("sss.preintegrated", DM_TEX_RGBA32F, lut.width, lut.height);
    d.has_t_range = true; /* the rows' curvature, 1/mm: what the renderer needs of the layout */
    d.t_range[0] = 0.0f;
    d.t_range[1] = (float)lut.curvature_max_per_mm;
    r = dmpb_add(j, &d, rgba, texels * 4 * sizeof *rgba, &p, src, err);
    free(rgba);
    dm_preint_lut_free(&lut);
    return r;
}

/* Mean curvature per texel at the irradiance size (bake/dm_curvature.h), smoothed over the
 * profile's RMS radius. */
dm_result dmpb_step_curvature(dm_pack_build *j, dm_error *err)
{
    dm_result r = dmpb_ensure_mesh(j, err);
    if (r != DM_OK) return r;
    const int n = j->scene.irradiance_size;
    double smooth_mm = dm_curvature_profile_scale_mm(&j->scene.profile);
    dm_curvature_options o = {.width = n, .height = n, .mm_per_unit = j->scene.mm_per_unit, .smooth_mm = smooth_mm,
                              .thread_count = j->opt->threads};
    dm_curvature_map map;
    if ((r = dm_curvature_bake(&j->mesh, &o, &map, err)) != DM_OK) {
        dm_curvature_map_free(&map);
        return r;
    }
    dm_provenance p;
    dmpb_mesh_prov(j, &p, "mean curvature, 1/mm, > 0 convex (cotangent Laplacian)");
    dm_prov_add_int(&p, "size", n);
    dm_prov_add_double(&p, "smooth_mm", smooth_mm);
    dm_prov_add_string(&p, "profile", j->scene.profile.name);
    char src[200];
    snprintf(src, sizeof src, "baked from %.120s, median %.3g /mm, smoothing %.2f mm", dmpb_base_name(j->scene.mesh),
             map.stats.percentile[2], smooth_mm);
    dm_pack_entry d = dm_pack_texture_entry("sss.curvature", DM_TEX_R32F, n, n);
    r = dmpb_add(j, &d, map.curvature, (size_t)n * n * sizeof(float), &p, src, err);
    dm_curvature_map_free(&map);
    return r;
}

/* One packed environment: k = 0 the main map (env.*), k > 0 alternative k (env<k>.*). */
static dm_result bake_environment(dm_pack_build *j, int k, dm_error *err)
{
    const dm_pack_need *sh_row = dm_pack_need_find("env.sh"), *spec_row = dm_pack_need_find("env.specular"),
                       *bg_row = dm_pack_need_find("env.background");
    char sh_name[DM_PACK_NAME_SIZE], spec_name[DM_PACK_NAME_SIZE], bg_name[DM_PACK_NAME_SIZE];
    dm_pack_need_entry_name(sh_row, k, sh_name);
    dm_pack_need_entry_name(spec_row, k, spec_name);
    dm_pack_need_entry_name(bg_row, k, bg_name);
    const char *path = k == 0 ? j->scene.environment : j->scene.env_alternatives[k - 1];
    bool lighting = dm_pack_build_wants(j, sh_name) || dm_pack_build_wants(j, spec_name);
    bool background = dm_pack_build_wants(j, bg_name);
    if (!lighting && !background) return DM_OK;
    dm_pack_env env;
    dm_result r = DM_OK;
    char src[200];
    snprintf(src, sizeof src, "from %.150s", dmpb_base_name(path));
    /* An already-baked file for this map (matched by content hash), else bake. A file for
     * another map is skipped; an unreadable file, or one for this map that cannot serve,
     * is an error that says why. */
    int used = -1;
    for (int f = 0; f < j->opt->env_file_count && used < 0; ++f) {
        bool same_map = false;
        r = dm_pack_env_from_file(j->opt->env_files[f], path, lighting, background, DM_PACK_BUILD_TOOL, &env, &same_map, err);
        if (r == DM_OK) {
            used = f;
            break;
        }
        dm_pack_env_free(&env);
        if (r != DM_ERR_MISMATCH || same_map) return r;
        r = DM_OK;
    }
    if (used >= 0) {
        j->env_file_used[used] = true;
        snprintf(src, sizeof src, "from %.150s", dmpb_base_name(j->opt->env_files[used]));
    } else {
        r = dm_pack_env_bake(path, lighting, background, DM_PACK_BUILD_TOOL, j->opt->threads, &env, err);
    }
    if (r == DM_OK && lighting) {
        dm_pack_entry d;
        memset(&d, 0, sizeof d);
        snprintf(d.name, sizeof d.name, "%s", sh_name);
        d.kind = DM_PACK_ENV_SH;
        d.sh_order = 2;
        r = dmpb_add(j, &d, env.sh, sizeof env.sh, &env.sh_prov, src, err);
        if (r == DM_OK) {
            d = dm_pack_texture_entry(spec_name, DM_TEX_RGBA32F, env.spec_width, env.spec_height);
            d.layers = env.spec_layers;
            d.layer_value_count = env.spec_layers;
            memcpy(d.layer_values, env.spec_m, sizeof(float) * (size_t)env.spec_layers);
            r = dmpb_add(j, &d, env.spec_rgba, (size_t)env.spec_width * env.spec_height * env.spec_layers * 4 * sizeof(float),
                    &env.spec_prov, src, err);
        }
    }
    if (r == DM_OK && background) {
        dm_pack_entry d = dm_pack_texture_entry(bg_name, DM_TEX_RGBA32F, env.background_width, env.background_height);
        r = dmpb_add(j, &d, env.background_rgba, (size_t)env.background_width * env.background_height * 4 * sizeof(float),
                &env.background_prov, src, err);
    }
    dm_pack_env_free(&env);
    return r;
}

/* The main environment, then each alternative of environment.alternatives. */
dm_result dmpb_step_environment(dm_pack_build *j, dm_error *err)
{
    dm_result r = DM_OK;
    for (int k = 0; r == DM_OK && k <= j->scene.env_alternative_count; ++k) r = bake_environment(j, k, err);
    return r;
}

