/* dm_render_kernel.h — the texture-space blur's numbers, no GL: each level's tap offsets (mm)
 * and weights from the profile and the tap count, the levels' weights per channel, the
 * stretch values the blurs and the automatic resolution read. Shared by the GL blur, the
 * CPU blur, translucency and the memory estimate. */
#ifndef DM_RENDER_KERNEL_H
#define DM_RENDER_KERNEL_H

#include <stddef.h>

#include "render/dm_render.h"

/* The blur of every level at one variance scale (1: the profile's). offset_mm[k] is level
 * k's (made from level k−1 by a blur of variance (v_k − v_{k−1}) · scale); k = 0 unused. */
typedef struct dmr_blur_kernel {
    float offset_mm[DM_PROFILE_MAX_GAUSSIANS][DM_BLUR_TAPS_MAX];
    float weight[DM_BLUR_TAPS_MAX];
    float scale;
    int taps;
} dmr_blur_kernel;
/* Fills k for taps (odd, 3..DM_BLUR_TAPS_MAX) and scale > 0: the discrete kernel's variance
 * is exactly each level's. */
void dmr_blur_kernel_make(const dm_profile *prof, int taps, float scale, dmr_blur_kernel *k);
/* The profile's weights divided by their sum per channel (TSD levels, translucency's T(d)),
 * times scale[c] (dm_renderer_set_profile_weights; 1 at create: the quotient exactly). */
void dmr_level_weights(const dm_profile *prof, const double scale[3], float weight[DM_PROFILE_MAX_GAUSSIANS][3]);
/* Value i of a stretch level (RG32F or RG16F texels), as float. */
float dmr_stretch_value(const dm_texture *t, size_t i);
/* The automatic blur resolution (dm_render_desc.blur_auto_resolution, without blur_reduce_from):
 * level k at irr_edge >> j, j the largest (<= 3, >= level k-1's, edge >= 8) keeping its total
 * sigma at least DM_BLUR_AUTO_SIGMA texels at the stretch's median along the coarser axis. No
 * change without the option or a stretch map. */
void dmr_auto_level_edges(const dm_render_assets *a, const dm_render_desc *d, const dm_profile *prof, int irr_edge,
                          int level_edge[DM_PROFILE_MAX_GAUSSIANS]);

#endif
