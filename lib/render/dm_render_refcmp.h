/* dm_render_refcmp.h — comparison of a render with a ground-truth reference EXR
 * (dermis-reference), shared by `dermis-render --reference` and `dermis-view --reference`
 * so both report and draw the same numbers. No GL: plain arrays in, RGBA8 out.
 *
 * References (float RGBA EXR, read with core/dm_exr_read.h, no OpenEXR):
 *   texture-space: N×N, the exact diffused radiance per texel, A = 1 on chart texels; it
 *                  is compared with the renderer's `diffusion` view at irradiance size N.
 *   frame:         W×H linear radiance from the scene's camera, A = 1 on skin pixels; it
 *                  is compared with the final linear image (read_linear) at W×H.
 * The mode comes from the provenance parameter "mode" ("texture-space" or "frame"); a
 * dermis-render EXR is accepted too (view "diffusion" → texture-space, "final" → frame).
 *
 * Error: per channel c, rel = |render − ref| / max(ref, floor_c) over the texels/pixels
 * where both alphas are 1 (≥ 0.5), each counted once (texel- or pixel-weighted, not
 * area-weighted), floor_c = DM_REFCMP_FLOOR_FRACTION × the mean of ref_c over those
 * texels (so near-black texels do not dominate). Reported: count, per channel mean, p95
 * (the value below which 95 % of the texels' errors lie, nearest rank) and max.
 *
 * Images in memory are interleaved RGBA, rows bottom-up, as the renderer reads them.
 */
#ifndef DM_RENDER_REFCMP_H
#define DM_RENDER_REFCMP_H

#include <stdbool.h>
#include <stdint.h>

#include "core/dm_prov.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define DM_REFCMP_FLOOR_FRACTION 0.01
#define DM_REFCMP_DEFAULT_ERROR_SCALE 0.1 /* relative error at the top of the colour scale */

typedef enum dm_refcmp_mode { DM_REFCMP_TEXTURE_SPACE = 0, DM_REFCMP_FRAME } dm_refcmp_mode;

typedef struct dm_refcmp_ref {
    dm_refcmp_mode mode;
    int width, height;
    float *rgba; /* width*height*4, bottom-up; free with dm_refcmp_ref_free */
    bool has_provenance;
    dm_provenance prov;
} dm_refcmp_ref;

/* Loads a reference EXR: channels R, G, B and A required (DM_ERR_FORMAT naming the missing
 * one), mode from the provenance (DM_ERR_FORMAT when it cannot be told), texture-space
 * references square. Free with dm_refcmp_ref_free, also after a failure. */
dm_result dm_refcmp_load(const char *path, dm_refcmp_ref *ref, dm_error *err);
void dm_refcmp_ref_free(dm_refcmp_ref *ref);
const char *dm_refcmp_mode_name(dm_refcmp_mode m); /* "texture-space", "frame" */

typedef struct dm_refcmp_stats {
    long count;          /* texels/pixels compared (both alphas 1) */
    long ref_only;       /* covered in the reference only */
    long render_only;    /* covered in the render only */
    double floor[3];     /* floor_c used in the denominator */
    double mean[3], p95[3], max[3];
} dm_refcmp_stats;

/* Statistics of render against ref (both width*height*4). rel, when not NULL, receives
 * width*height values: the largest channel's relative error per texel, −1 where not
 * compared (−2 where the coverages differ). DM_ERR_OUT_OF_MEMORY, or DM_ERR_EMPTY when no
 * texel is covered in both. */
dm_result dm_refcmp_stats_compute(const float *ref, const float *render, int width, int height,
                                  dm_refcmp_stats *st, float *rel, dm_error *err);

typedef enum dm_refcmp_layout {
    DM_REFCMP_SIDE_BY_SIDE = 0, /* [reference | render | error map] */
    DM_REFCMP_SPLIT,            /* reference left of the divider, render right of it */
    DM_REFCMP_ERROR,            /* the error map alone */
    DM_REFCMP_LAYOUT_COUNT
} dm_refcmp_layout;

typedef struct dm_refcmp_view {
    dm_refcmp_layout layout;
    float split;        /* divider position in [0, 1] of the panel width (SPLIT) */
    double error_scale; /* relative error shown at the top of the colour scale; 0 = default */
    int margin_right_px;  /* the legend keeps out of this strip (a viewer's panel); 0 = none */
    int margin_bottom_px; /* nothing is drawn in this strip (a viewer's attribution line) */
} dm_refcmp_view;

const char *dm_refcmp_layout_name(dm_refcmp_layout l); /* "side", "split", "error" */
bool dm_refcmp_layout_parse(const char *text, dm_refcmp_layout *l);

/* The legend's height in pixels for an image out_width wide. */
int dm_refcmp_legend_height(int out_width);

/* Draws the comparison into rgba (out_width*out_height*4 bytes, bottom-up, alpha 255):
 * the panels (each image fitted with its aspect kept, labelled; linear values shown as
 * sRGB of value / white, white = the 99th percentile of the reference's largest channel
 * over its covered texels) above a legend: the colour scale with its numbers, the error
 * definition and floor, and per channel mean and p95. rel is dm_refcmp_stats_compute's. */
void dm_refcmp_compose(const float *ref, const float *render, const float *rel, int width, int height,
                       const dm_refcmp_stats *st, const dm_refcmp_view *view, uint8_t *rgba, int out_width,
                       int out_height);

/* The stats as text lines ("R: mean 0.123 %, p95 0.456 %, max 2.1 %" per channel and the
 * count and floor), into out (always NUL-terminated). */
void dm_refcmp_stats_text(const dm_refcmp_stats *st, dm_refcmp_mode mode, char *out, int out_size);

#ifdef __cplusplus
}
#endif
#endif
