/* dm_envmap.h — an equirectangular HDR environment as the bakes read it: validated float
 * RGB radiance with a box-filtered mip pyramid, sampled by direction (core/dm_equirect.h).
 *
 * Input rules (every texel of R, G, B is checked; alpha and further channels are ignored;
 * a 1- or 2-channel image is grey and copied to R, G, B):
 *   - width = 2 × height exactly, height ≥ 2;
 *   - every value finite and at most DM_ENVMAP_RADIANCE_MAX (so every sum, SH coefficient
 *     and prefiltered value stays finite in float);
 *   - every value ≥ −negative_tolerance. Values in [−tolerance, 0) are set to 0 and
 *     counted: lossy EXR compression (DWA) rings slightly below zero next to bright
 *     texels (the bundled courtyard.exr reaches −0.0032, night.exr −0.0033). Anything
 *     more negative is refused. Tolerance 0 refuses every negative value.
 * A refusal names the texel as (x, y) in file pixels: x from the left, y from the TOP row
 * of the file (what an image viewer shows), plus the channel and the value.
 *
 * Memory: level 0 is the input, rows bottom-up, RGB interleaved floats. Level l + 1 is the
 * 2 × 2 box average of level l in texture space (sizes halve, never below 1; an odd size
 * drops its last row/column into the previous texel's average by clamping). A texel of
 * level l spans 2^l × 2^l texels of level 0.
 */
#ifndef DM_ENVMAP_H
#define DM_ENVMAP_H

#include <stdint.h>

#include "pack/dm_pack_semantic.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define DM_ENVMAP_RADIANCE_MAX DM_PACK_RADIANCE_MAX /* one bound: the pack reader takes what this takes */
#define DM_ENVMAP_NEGATIVE_TOLERANCE_DEFAULT 0.01
enum { DM_ENVMAP_LEVEL_MAX = 16, DM_ENVMAP_SIZE_MAX = 16384 };

typedef struct dm_envmap {
    int width, height; /* level 0; width = 2 × height */
    int level_count;   /* mip levels including level 0, down to 2 × 1 */
    int level_width[DM_ENVMAP_LEVEL_MAX], level_height[DM_ENVMAP_LEVEL_MAX];
    float *level[DM_ENVMAP_LEVEL_MAX]; /* RGB interleaved, bottom-up; owned */
    /* What validation found (the caller decides whether to warn). */
    int64_t clamped_texels;      /* values in [−tolerance, 0) set to 0 (per channel) */
    double most_negative;        /* the lowest such value, 0 when none */
    int most_negative_x, most_negative_y; /* its file position (y from the top) */
} dm_envmap;

/* Reads an .hdr, .exr or any float image OpenImageIO knows, validates it and builds the
 * pyramid. negative_tolerance ≥ 0. Free with dm_envmap_free, also after a failure. */
dm_result dm_envmap_load(const char *path, double negative_tolerance, dm_envmap *out, dm_error *err);
/* The same from memory: rgb holds width*height*channels floats, rows bottom-up; it is
 * copied. `what` names the source in messages. */
dm_result dm_envmap_from_pixels(const float *pixels, int width, int height, int channels, double negative_tolerance,
                                const char *what, dm_envmap *out, dm_error *err);
void dm_envmap_free(dm_envmap *map);

/* Bilinear lookup of mip level `level` at (u, v): u wraps, v clamps to the edge texels,
 * as GL_REPEAT / GL_CLAMP_TO_EDGE would. */
void dm_envmap_fetch(const dm_envmap *map, int level, double u, double v, double rgb[3]);
/* Trilinear lookup: lod ≥ 0 in level units (clamped to the pyramid). */
void dm_envmap_sample(const dm_envmap *map, double u, double v, double lod, double rgb[3]);

#ifdef __cplusplus
}
#endif
#endif
