/* dm_level_blur.h — one separable pass of texture-space diffusion's stretch-corrected blur
 * (shaders/blur.glsl) on the CPU, for renderers whose OpenGL runs on the CPU too (llvmpipe):
 * there its bilinear RGBA32F fetches cost ~5 CPU ms per tap over a 1024² atlas, where plain C
 * reads the same two texels a tap in a fraction of that (docs/render-quality.md).
 *
 * The same arithmetic as the shader, in float: destination texel (x, y) at
 * uv = ((x + ½)/dst_w, (y + ½)/dst_h) is
 *     Σ_i weight[i] · src(uv + e · s(uv) · offset_mm[i])
 * with e the unit vector along u (or v), s the stretch's u (or v) component (UV units per mm,
 * read bilinearly with clamp-to-edge, as the shader's sampler reads it: dm_level_blur_step
 * samples it once per destination grid) and src read bilinearly with a zero border (outside
 * [0, 1]² it is 0). A pass along u keeps the rows (dst_h == src_h), a pass along v the
 * columns (dst_w == src_w), so each tap blends two texels of one row or column; widths
 * (heights) may differ, as the reduced blur levels' do. Tap positions are rounded as a GPU's
 * texture unit rounds them (float texel coordinates), not bit for bit as llvmpipe does: the
 * two agree to float rounding (tests/render: the renderer's two paths).
 *
 * Images are padded: DM_LEVEL_BLUR_PAD texels of zeros around each (rows of w + 2·PAD
 * texels, PAD rows above and below), the pointers at texel (0, 0) inside. The taps read the
 * border from there instead of testing each fetch (dm_level_blur_frame lays one out).
 *
 * Deterministic: every texel is computed alone, so the result is byte-identical for any
 * thread count. */
#ifndef DM_LEVEL_BLUR_H
#define DM_LEVEL_BLUR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_LEVEL_BLUR_PAD = 3, DM_LEVEL_BLUR_MAX_TAPS = 64 };

/* With points (the seam map's, render/passes/dm_pass_tsd.c): a tap's texel whose point lies
 * farther in 3-D from the texel being made than JUMP_FACTOR × the tap's offset + JUMP_MM is
 * another place of the surface that the atlas put beside this one (charts touching, a chart's
 * squashed rim): it is left out, and the coverage in alpha renormalises the rest. On a
 * continuous surface a tap's chord is at most its offset along the surface, so only a jump is
 * refused (docs/seam-map.md measures the margin). Only taps that reach across a cut
 * (dm_level_blur_cuts, once per scene) are checked: everywhere else the taps are the plain ones. */
#define DM_LEVEL_BLUR_JUMP_FACTOR 3.0f
#define DM_LEVEL_BLUR_JUMP_MM 3.0f

typedef struct dm_level_blur_pass {
    const float *src; /* RGBA, src_w × src_h, padded (its border zero) */
    int src_w, src_h;
    float *dst; /* RGBA, dst_w × dst_h, padded (its border left as it is); not overlapping src */
    int dst_w, dst_h;
    bool along_v; /* false: taps along u (dst_h == src_h); true: along v (dst_w == src_w) */
    const float *step; /* dst_w × dst_h, unpadded: s at each destination texel (dm_level_blur_step) */
    const float *offset_mm; /* taps: offsets in mm and their weights */
    const float *weight;
    int taps; /* 1..DM_LEVEL_BLUR_MAX_TAPS */
    int thread_count; /* 0 = every core */
    /* NULL, or RGBA, dst_w × dst_h, unpadded: each texel's 3-D point in mm (xyz) and whether
     * it has one (w > 0), with `cuts` (dm_level_blur_cuts) of the same grid; used only when the
     * pass keeps the grid (src_w == dst_w along u, src_h == dst_h along v). A texel checks its
     * taps only when they reach across a cut; a texel without a point neither refuses nor is
     * refused. */
    const float *points;
    const int16_t *cuts;
} dm_level_blur_pass;

/* Where the atlas jumps: between two 4-neighbours with points farther apart in 3-D than
 * DM_LEVEL_BLUR_CUT_STEPS × the median such distance (the atlas's typical texel, mm) and than
 * DM_LEVEL_BLUR_JUMP_MM (no tap is refused nearer). Per texel (x, y), RGBA: the nearest cut on
 * its left along its row (the largest c ≤ x with a jump between c − 1 and c; −1000 when none),
 * the nearest on its right (the smallest c > x; n + 1000 when none), and the same along its
 * column (below, above); a texel without a point has none. A tap that reads no texel across a
 * cut reads one surface, whose chord never passes the reach where the texels step evenly
 * (docs/seam-map.md). points and cuts are n × n. Returns the cuts found, or −1 when out of
 * memory (cuts untouched). */
#define DM_LEVEL_BLUR_CUT_STEPS 2.5f
long dm_level_blur_cuts(const float *points, int n, int16_t *cuts);

/* False (nothing written) when the sizes do not fit the rules above or a pointer is NULL. */
bool dm_level_blur(const dm_level_blur_pass *p);

/* The stretch's u (or, along_v, v) component at the texel centres of a dst_w × dst_h grid:
 * stretch is RG (UV units per mm), sw × sh, read bilinearly with clamp-to-edge; a non-finite
 * value becomes 0 (the taps then stay on their texel). False when a size is below 1. */
bool dm_level_blur_step(const float *stretch, int sw, int sh, int dst_w, int dst_h, bool along_v, float *out);

/* Padded images in a buffer of one's own: dm_level_blur_floats(w, h) floats hold a w × h
 * image; dm_level_blur_frame lays one out there (zeroing its border, so a buffer can hold
 * images of other sizes in turn) and returns its texel (0, 0). Rows are
 * dm_level_blur_stride(w) floats apart. */
static inline long dm_level_blur_stride(int w)
{
    return 4L * (w + 2 * DM_LEVEL_BLUR_PAD);
}
size_t dm_level_blur_floats(int w, int h);
float *dm_level_blur_frame(float *buffer, int w, int h);

#ifdef __cplusplus
}
#endif
#endif
