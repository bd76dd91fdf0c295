/* dm_render_kernel.c — the texture-space blur's numbers (dm_render_kernel.h), and the public
 * dm_render_blur_kernel and dm_render_stretch_median (dm_render.h). */
#include "render/input/dm_render_kernel.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "core/dm_half.h"
#include "core/dm_sort.h"

/* The tested tap weights of lib/core (dm_blur_taps: bin masses of the unit Gaussian, each
 * end bin running to infinity), taps spread over ±3σ. */
double dm_render_blur_kernel(int taps, float *offsets_sigma, float *weights)
{
    assert(taps >= 3 && taps <= DM_BLUR_TAPS_MAX && taps % 2 == 1);
    int h = (taps - 1) / 2;
    double step = 3.0 / h, var = 0.0, w[DM_BLUR_TAPS_MAX];
    dm_result rc = dm_blur_taps(taps, step, 1, w, NULL, NULL);
    assert(rc == DM_OK);
    (void)rc;
    for (int i = 0; i < taps; ++i) {
        double x = (i - h) * step;
        offsets_sigma[i] = (float)x;
        weights[i] = (float)w[i];
        var += w[i] * x * x;
    }
    return var;
}

void dmr_blur_kernel_make(const dm_profile *prof, int taps, float scale, dmr_blur_kernel *k)
{
    float off_sigma[DM_BLUR_TAPS_MAX];
    double var = dm_render_blur_kernel(taps, off_sigma, k->weight);
    k->scale = scale;
    k->taps = taps;
    for (int l = 1; l < prof->count; ++l) {
        double dv = (prof->variance_mm2[l] - prof->variance_mm2[l - 1]) * (double)scale;
        /* scale so that the discrete kernel's variance is exactly dv */
        double s = sqrt(dv / var);
        for (int i = 0; i < taps; ++i) k->offset_mm[l][i] = (float)(off_sigma[i] * s);
    }
}

void dmr_level_weights(const dm_profile *prof, const double scale[3], float weight[DM_PROFILE_MAX_GAUSSIANS][3])
{
    for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (int k = 0; k < prof->count; ++k) sum += prof->weight[k][c];
        for (int k = 0; k < prof->count; ++k)
            weight[k][c] = sum > 0 ? (float)(prof->weight[k][c] / sum * scale[c]) : 0.0f;
    }
}

float dmr_stretch_value(const dm_texture *t, size_t i)
{
    return t->format == DM_TEX_RG32F ? ((const float *)t->texels)[i] : dm_half_to_float(((const uint16_t *)t->texels)[i]);
}

bool dm_render_stretch_median(const dm_render_assets *a, float med[2])
{
    const dm_texture *t = &a->stretch[0];
    med[0] = med[1] = 0.0f;
    if (a->stretch_level_count < 1 || !t->texels || (t->format != DM_TEX_RG32F && t->format != DM_TEX_RG16F))
        return false;
    size_t n = (size_t)t->width * (size_t)t->height, k = 0;
    const uint8_t *mask = a->stretch_mask.texels && a->stretch_mask.width == t->width &&
                                  a->stretch_mask.height == t->height ? a->stretch_mask.texels : NULL;
    float *u = malloc(sizeof *u * n), *v = malloc(sizeof *v * n);
    for (size_t i = 0; u && v && i < n; ++i) {
        float su = dmr_stretch_value(t, 2 * i), sv = dmr_stretch_value(t, 2 * i + 1);
        if ((mask ? mask[i] > 0 : su > 0) && isfinite(su) && isfinite(sv)) u[k] = su, v[k++] = sv;
    }
    if (k) {
        dm_sort_floats(u, k), dm_sort_floats(v, k);
        med[0] = u[k / 2], med[1] = v[k / 2];
    }
    free(u), free(v);
    return k > 0;
}

void dmr_auto_level_edges(const dm_render_assets *a, const dm_render_desc *d, const dm_profile *prof, int irr_edge,
                          int level_edge[DM_PROFILE_MAX_GAUSSIANS])
{
    float med[2];
    if (!d->blur_auto_resolution || d->blur_reduce_from != 0 || !dm_render_stretch_median(a, med)) return;
    double uv_per_mm = fmin(med[0], med[1]);
    int j = 0;
    for (int k = 1; k < prof->count && uv_per_mm > 0; ++k) {
        double sigma_texels = sqrt(prof->variance_mm2[k]) * uv_per_mm * irr_edge;
        while (j < 3 && (irr_edge >> (j + 1)) >= 8 && sigma_texels / (1 << (j + 1)) >= DM_BLUR_AUTO_SIGMA) ++j;
        level_edge[k] = irr_edge >> j;
    }
}
