/* dm_pack_build_skin.c — a scene's physical skin becomes its profile, and with
 * material.albedo_from "skin" its colour, when it is packed (dm_pack_build_impl.h): the scene
 * reader (core) stored the parameters; the model is offline (bake/dm_skin_profile.h), so it is
 * evaluated and fitted here. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_albedo_skin.h"
#include "bake/dm_profile_fit.h"
#include "bake/dm_skin_spec.h"
#include "packer/dm_pack_build_impl.h"

dm_result dmpb_fit_skin(dm_pack_build *j, dm_error *err)
{
    dm_scene_skin *k = &j->scene.skin;
    if (!k->given) return DM_OK;
    char what[DM_SCENE_PATH_SIZE + 64];
    snprintf(what, sizeof what, "%s: $.effects.subsurface.profile.skin", j->scene_path);
    const char *keys[DM_SKIN_KEY_COUNT];
    for (int i = 0; i < k->key_count; ++i) keys[i] = dm_skin_keys[k->key[i]];
    dm_skin_params p;
    dm_result r = dm_skin_spec_pairs(k->preset[0] ? k->preset : NULL, keys, k->value, k->key_count, what, &p, err);
    if (r != DM_OK) return r;
    /* as dermis-fit-profile --skin does by default: the same calls, the same bytes */
    dm_profile_source src; /* ~2 KB: the dense Gaussians */
    if ((r = dm_profile_source_skin(&p, &src, err)) != DM_OK) return r;
    dm_fit_options fo = {0};
    dm_fit_result fr;
    if ((r = dm_profile_fit(&src, &fo, k->preset[0] ? k->preset : "skin", &fr, err)) != DM_OK) return r;
    if ((r = dm_profile_normalize_white(&fr.profile, NULL, err)) != DM_OK) return r;
    j->scene.profile = fr.profile;
    j->skin = *k;
    dm_skin_spec_format(&p, 17, j->skin_spec, sizeof j->skin_spec);
    dm_profile_source_total(&src, j->skin_total_rgb); /* what dermis-fit-profile prints as the skin's */
    /* the scene now holds the fitted profile inline: what the pack's scene entry carries and
     * the renderer reads (it never evaluates the model) */
    k->given = false;
    snprintf(j->scene.profile_source, sizeof j->scene.profile_source, "inline");
    return DM_OK;
}

dm_result dmpb_albedo_from_skin(dm_pack_build *j, uint8_t *rgba, int w, int h, dm_provenance *p, char *src,
                                size_t src_size, dm_error *err)
{
    dm_result r = dmpb_ensure_mesh(j, err);
    if (r != DM_OK) return r;
    float *weight = malloc((size_t)w * (size_t)h * sizeof *weight);
    if (!weight) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", j->scene.albedo);
    double area_mm2 = 0.0;
    dm_albedo_skin_stats st;
    r = dm_albedo_skin_weights(&j->mesh, j->scene.mm_per_unit, w, h, j->opt->threads, weight, &area_mm2, err);
    if (r == DM_OK) r = dm_albedo_skin_apply(rgba, w, h, weight, j->skin_total_rgb, j->scene.albedo, rgba, &st, err);
    free(weight);
    if (r != DM_OK) return r;
    dm_prov_add_string(p, "albedo_from", "skin");
    dm_prov_add_string(p, "skin", j->skin_spec);
    if (j->skin.preset[0]) dm_prov_add_string(p, "skin_preset", j->skin.preset);
    dm_prov_add_string(p, "albedo_rule", "linear rgb = skin total reflectance x map luminance (BT.709) / its "
                                         "area-weighted mean over the mesh's UV charts");
    static const char *const t[3] = {"skin_total_reflectance_r", "skin_total_reflectance_g", "skin_total_reflectance_b"};
    static const char *const m[3] = {"albedo_mean_r", "albedo_mean_g", "albedo_mean_b"};
    for (int c = 0; c < 3; ++c) dm_prov_add_double(p, t[c], j->skin_total_rgb[c]);
    dm_prov_add_double(p, "map_mean_luminance", st.mean_luminance);
    for (int c = 0; c < 3; ++c) dm_prov_add_double(p, m[c], st.mean_rgb[c]);
    dm_prov_add_int(p, "clipped_texels", st.clipped_texels);
    dm_prov_add_double(p, "skin_area_mm2", area_mm2);
    size_t n = strlen(src);
    snprintf(src + n, src_size - n, ", skin colour %.3f %.3f %.3f", st.mean_rgb[0], st.mean_rgb[1], st.mean_rgb[2]);
    if (j->opt->verbose)
        fprintf(stderr, "albedo from the skin %s: total reflectance %.4f %.4f %.4f, map mean luminance %.4f, "
                        "result's mean over the skin %.4f %.4f %.4f, %lld of %lld texels clipped\n",
                j->skin.preset[0] ? j->skin.preset : j->skin_spec, j->skin_total_rgb[0], j->skin_total_rgb[1],
                j->skin_total_rgb[2], st.mean_luminance, st.mean_rgb[0], st.mean_rgb[1], st.mean_rgb[2],
                (long long)st.clipped_texels, (long long)st.covered_texels);
    return DM_OK;
}
