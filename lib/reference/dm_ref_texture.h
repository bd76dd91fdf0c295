/* dm_ref_texture.h — sampling a pack texture on the CPU exactly as OpenGL's GL_LINEAR
 * filter does, for the ground truth.
 *
 * Texels are the pack's (dm_pack.h): rows bottom-up, tightly packed, any dm_tex_format.
 * A texel is first decoded to linear float RGBA as a GL sampler returns it: 8-bit UNORM
 * v/255; RGBA8_SRGB through the exact sRGB curve (per texel, before filtering, as
 * GL_SRGB8_ALPHA8 does); 16-bit floats from IEEE half; missing components filled as GL
 * does (R → (r, 0, 0, 1), RG → (r, g, 0, 1)). Then bilinear: x = u·width − 0.5,
 * y = v·height − 0.5, the 2×2 texels around (x, y) weighted by the fractions, in double
 * (GL hardware rounds the fractions to 8 bits; this does not).
 * Wrap: clamp-to-edge or repeat, per axis. No mipmaps: the reference samples the map at
 * the point (level 0), where the renderer's minified lookups may read coarser levels.
 */
#ifndef DM_REF_TEXTURE_H
#define DM_REF_TEXTURE_H

#include <stdbool.h>

#include "pack/dm_pack.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_ref_texture {
    dm_tex_format format;
    int width, height;  /* texels, ≥ 1 */
    const void *texels; /* NULL = absent */
    bool repeat_u;      /* wrap u (GL_REPEAT) instead of clamping; v is always clamped */
} dm_ref_texture;

/* Linear RGBA of texel (i, j) (indices clamped into the image). t->texels non-NULL. */
void dm_ref_texel(const dm_ref_texture *t, int i, int j, double rgba[4]);

/* Bilinear lookup at (u, v) (any finite values). t->texels non-NULL. */
void dm_ref_texture_sample(const dm_ref_texture *t, double u, double v, double rgba[4]);

#ifdef __cplusplus
}
#endif
#endif
