/* dm_albedo_skin.h — the diffuse colour from the physical skin model (material.albedo_from
 * "skin", docs/skin-model.md): the model's total diffuse reflectance per linear-sRGB channel,
 * modulated by an albedo map's luminance detail, so one head renders at any skin tone.
 *
 *   out_c(x) = T_c · Y(x) / Ȳ,   Y = 0.2126 R + 0.7152 G + 0.0722 B of the decoded map,
 *   Ȳ = Σ w(x) Y(x) / Σ w(x),    w(x) = the mm² of skin texel x stands for (0 off the charts)
 *
 * T_c is the colorimetric total (bake/dm_skin_rgb.h: CIE D65, linear sRGB), clamped at 0 (a
 * dark skin's channel can be a hair below zero from the colour weights' negative lobes). Y is
 * the linear-sRGB luminance (ITU-R BT.709's row of the sRGB matrix). So the result keeps the
 * map's luminance detail — pores, stubble, eyebrows, lips darker or lighter than the cheek —
 * and drops its chroma and its overall tone, and its area-weighted mean over the skin is T
 * exactly (before the 8-bit rounding and the clip at 1: `dm_albedo_skin_stats` says what they
 * left). The mean is over the skin's area rather than the texels because the charts are not
 * equally stretched: the mean of what a viewer sees, all around the head, is T.
 */
#ifndef DM_ALBEDO_SKIN_H
#define DM_ALBEDO_SKIN_H

#include <stdint.h>

#include "core/dm_result.h"
#include "mesh/dm_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The luminance weights of linear sRGB (BT.709). */
#define DM_ALBEDO_SKIN_LUMA_R 0.2126
#define DM_ALBEDO_SKIN_LUMA_G 0.7152
#define DM_ALBEDO_SKIN_LUMA_B 0.0722

/* The skin area each texel of a width × height map stands for, mm²: for the triangle whose UV
 * image covers the texel's centre (mesh/dm_uv_raster.h), its 3-D area over its UV area, over
 * width·height; 0 where no triangle does. weight: width*height floats, caller-owned, rows
 * bottom-up. thread_count 0 = all cores. *skin_area_mm2 (may be NULL) gets Σ weight. */
dm_result dm_albedo_skin_weights(const dm_mesh *m, double mm_per_unit, int width, int height, int thread_count,
                                 float *weight, double *skin_area_mm2, dm_error *err);

typedef struct dm_albedo_skin_stats {
    double mean_luminance;  /* Ȳ, linear */
    double mean_rgb[3];     /* Σ w out / Σ w of the 8-bit result decoded: T up to rounding and clipping */
    int64_t covered_texels; /* texels with w > 0 */
    int64_t clipped_texels; /* covered texels with a channel above 1 before the clip */
} dm_albedo_skin_stats;

/* The colour map: rgba is width*height texels of 4 bytes, sRGB-encoded colour (alpha kept
 * as it is); out (the same size, caller-owned, may be rgba itself) gets out_c above in sRGB,
 * rounded to nearest. weight as dm_albedo_skin_weights fills it. total_rgb: T per channel,
 * finite. `what` names the map in messages. DM_ERR_EMPTY when no texel has weight or the map
 * is black over all of them (Ȳ = 0: no detail to keep). stats may be NULL. */
dm_result dm_albedo_skin_apply(const uint8_t *rgba, int width, int height, const float *weight,
                               const double total_rgb[3], const char *what, uint8_t *out, dm_albedo_skin_stats *stats,
                               dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
