/* dm_ref_lookup.h — the irradiance the ground truth reads at a surface point: the atlas
 * premultiplied by its coverage, sampled bilinearly (dm_reference_elements.c and
 * dm_reference_eval.c read it; dm_reference.c makes it). Depends on nothing else in
 * lib/reference but the atlas type. */
#ifndef DM_REF_LOOKUP_H
#define DM_REF_LOOKUP_H

#include <stddef.h>

#include "reference/dm_reference.h"

/* The atlas premultiplied by its coverage (r·α, g·α, b·α, α, α clamped to [0, 1],
 * non-finite values 0), so a lookup is one weighted sum and one division. */
typedef struct dm_ref_lookup {
    int width, height;
    float *texel; /* width*height*4 */
} dm_ref_lookup;

dm_result dm_ref_premultiply(const dm_reference_atlas *a, dm_ref_lookup *out, dm_error *err);

/* The nearest covered texel within 2 texels of texel position (x, y) (rgb 0 and 0 returned
 * when there is none). */
int dm_ref_sample_nearest(const dm_ref_lookup *a, double x, double y, double rgb[3]);

/* I at (u, v): bilinear over covered texels, renormalised; nearest covered texel within
 * 2 texels when none of the 2×2 is covered. Returns 0 (and zero rgb) when none is near,
 * 1 otherwise. Inline: it is most of the evaluation's time. */
static inline __attribute__((always_inline)) int dm_ref_sample(const dm_ref_lookup *a, double u, double v, double rgb[3])
{
    double x = u * a->width - 0.5, y = v * a->height - 0.5;
    if (!(x > -1.0)) x = -1.0; /* also NaN */
    if (!(y > -1.0)) y = -1.0;
    if (x > a->width) x = a->width;
    if (y > a->height) y = a->height;
    int i0 = (int)(x + 1.0) - 1, j0 = (int)(y + 1.0) - 1; /* floor for x ≥ −1 */
    double fx = x - i0, fy = y - j0;
    int i1 = i0 + 1, j1 = j0 + 1;
    /* clamp to edge, as the renderer's textures */
    if (i0 < 0) i0 = 0;
    if (j0 < 0) j0 = 0;
    if (i1 >= a->width) i1 = a->width - 1;
    if (j1 >= a->height) j1 = a->height - 1;
    const float *t00 = a->texel + 4 * ((size_t)j0 * a->width + i0), *t10 = a->texel + 4 * ((size_t)j0 * a->width + i1);
    const float *t01 = a->texel + 4 * ((size_t)j1 * a->width + i0), *t11 = a->texel + 4 * ((size_t)j1 * a->width + i1);
    double w00 = (1.0 - fx) * (1.0 - fy), w10 = fx * (1.0 - fy), w01 = (1.0 - fx) * fy, w11 = fx * fy;
    double al = w00 * t00[3] + w10 * t10[3] + w01 * t01[3] + w11 * t11[3];
    if (al > 1e-12) {
        double inv = al == 1.0 ? 1.0 : 1.0 / al; /* inside a chart: no division */
        for (int c = 0; c < 3; ++c) rgb[c] = (w00 * t00[c] + w10 * t10[c] + w01 * t01[c] + w11 * t11[c]) * inv;
        return 1;
    }
    return dm_ref_sample_nearest(a, x, y, rgb);
}

#endif
