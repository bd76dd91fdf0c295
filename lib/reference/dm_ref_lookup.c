/* dm_ref_lookup.c — the ground truth's irradiance lookup (dm_ref_lookup.h): the atlas
 * premultiplied by its coverage, and the nearest covered texel where bilinear finds none. */
#include "reference/dm_ref_lookup.h"

#include <math.h>
#include <stdlib.h>

dm_result dm_ref_premultiply(const dm_reference_atlas *a, dm_ref_lookup *out, dm_error *err)
{
    size_t n = (size_t)a->width * a->height;
    out->width = a->width;
    out->height = a->height;
    out->texel = malloc(sizeof *out->texel * 4 * n);
    if (!out->texel) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference: %dx%d lookup", a->width, a->height);
    for (size_t i = 0; i < n; ++i) {
        float al = a->rgba[4 * i + 3];
        al = al > 0.0f && isfinite(al) ? (al < 1.0f ? al : 1.0f) : 0.0f;
        for (int c = 0; c < 3; ++c) {
            float v = a->rgba[4 * i + (size_t)c];
            out->texel[4 * i + (size_t)c] = isfinite(v) ? v * al : 0.0f;
        }
        out->texel[4 * i + 3] = al;
    }
    return DM_OK;
}

/* The nearest covered texel within 2 texels of texel position (x, y). */
static int nearest_covered(const dm_ref_lookup *a, double x, double y, double rgb[3])
{
    int ic = (int)floor(x + 0.5), jc = (int)floor(y + 0.5);
    double best = INFINITY;
    for (int j = jc - 2; j <= jc + 2; ++j)
        for (int i = ic - 2; i <= ic + 2; ++i) {
            if (i < 0 || j < 0 || i >= a->width || j >= a->height) continue;
            const float *t = a->texel + 4 * ((size_t)j * a->width + i);
            if (!(t[3] > 0.0f)) continue;
            double d = (i - x) * (i - x) + (j - y) * (j - y);
            if (d < best) {
                best = d;
                for (int c = 0; c < 3; ++c) rgb[c] = t[c] / t[3];
            }
        }
    return best < INFINITY;
}

int dm_ref_sample_nearest(const dm_ref_lookup *a, double x, double y, double rgb[3])
{
    rgb[0] = rgb[1] = rgb[2] = 0.0;
    return nearest_covered(a, x, y, rgb);
}
