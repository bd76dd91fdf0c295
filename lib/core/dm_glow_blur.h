/* dm_glow_blur.h — the glow's separable Gaussian (shaders/glow_blur.glsl) on the CPU, for
 * renderers whose OpenGL runs on the CPU too (llvmpipe): 9 taps exp(−i²/8), normalised (σ = 2
 * texels of the half-resolution glow target), taken as the shader takes them, 5 bilinear
 * fetches: the centre, and each pair (1, 2), (3, 4) at its weighted mean offset with the
 * pair's summed weight. The kernel is defined here once; the shader receives it as uniforms.
 *
 * A pass along x (or y) of an RGBA image, w × h, rows packed: destination texel i is
 *     weight[0]·src(i) + weight[1]·(src(i + o₁) + src(i − o₁)) + weight[2]·(src(i + o₂) + src(i − o₂))
 * with src read linearly between texels and clamped to the edge (GL_CLAMP_TO_EDGE,
 * GL_LINEAR), alpha 1 as the shader writes it. The tap positions are rounded as a GPU's
 * texture unit rounds them: the two agree to float rounding. Each texel alone: byte-identical
 * results on any thread count. */
#ifndef DM_GLOW_BLUR_H
#define DM_GLOW_BLUR_H

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The centre's and the two pairs' weights, and the pairs' offsets in texels. */
void dm_glow_kernel(float weight[3], float offset[2]);

/* One pass, src to dst (not overlapping). False when a pointer is NULL, a size below 1 or
 * memory for the taps' table (4 entries a texel along the axis) is short. */
bool dm_glow_blur(const float *src, float *dst, int w, int h, bool along_y, int thread_count);

#ifdef __cplusplus
}
#endif
#endif
