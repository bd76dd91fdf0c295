/* dm_render_views.c — what the debug views report: the colour scale of the stretch and
 * curvature views (measured by the view pass), the specular view's gain (the final pass's),
 * a scalar view's PNG with its legend; and whether the blurs run on the CPU. */
#include <stdlib.h>
#include <string.h>

#include "render/dm_render_internal.h"
#include "render/dm_render_legend.h"

void dm_renderer_view_scale(const dm_renderer *r, float *lo, float *hi, const char **quantity)
{
    dm_view view = r->f.plan.view;
    bool scaled = view == DM_VIEW_STRETCH || view == DM_VIEW_CURVATURE || view == DM_VIEW_SEAM || view == DM_VIEW_THIN ||
                  view == DM_VIEW_GATHER;
    *lo = scaled ? r->view.lo : 0.0f, *hi = scaled ? r->view.hi : 0.0f;
    if (quantity)
        *quantity = view == DM_VIEW_STRETCH     ? "mm per texel"
                    : view == DM_VIEW_CURVATURE ? "mean curvature, 1/mm"
                    : view == DM_VIEW_SEAM      ? "seam map: mm beyond the edge of the chart"
                    : view == DM_VIEW_THIN      ? "thin-part map: mm across, the nearer point"
                    : view == DM_VIEW_GATHER    ? "thin gather: taps a texel, both levels"
                                                : NULL;
}

float dm_renderer_view_gain(const dm_renderer *r)
{
    return r->f.plan.view == DM_VIEW_SPECULAR && r->f.view_gain > 0 ? r->f.view_gain : 1.0f;
}

/* A stretch or curvature view's PNG: its colour scale's legend in a strip below the picture
 * (*px, RGBA8, grows by the strip; *h with it). Other views unchanged. */
dm_result dm_render_view_with_legend(const dm_renderer *r, void **px, int w, int *h, dm_error *err)
{
    float lo, hi;
    const char *quantity;
    dm_renderer_view_scale(r, &lo, &hi, &quantity);
    if (!quantity) return DM_OK;
    int lh = dm_render_scalar_legend_height(w), nh = *h + lh;
    uint8_t *out = malloc((size_t)w * nh * 4);
    if (!out) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "cannot allocate the legend");
    memset(out, 0, (size_t)w * lh * 4);
    memcpy(out + (size_t)w * lh * 4, *px, (size_t)w * *h * 4); /* bottom-up: the strip is the first rows */
    dm_view view = r->f.plan.view;
    dm_render_scalar_legend(out, w, nh, lo, hi, quantity,
                            view == DM_VIEW_SEAM || view == DM_VIEW_THIN ? "0 TO 3 SIGMA OF THE WIDEST GAUSSIAN"
                            : view == DM_VIEW_GATHER                     ? "0 TO THE MOST TAPS OF A TEXEL"
                                                                         : NULL);
    free(*px);
    *px = out, *h = nh;
    return DM_OK;
}

bool dm_renderer_blur_on_cpu(const dm_renderer *r)
{
    return r && r->f.blur_cpu;
}

bool dm_renderer_seam_map(const dm_renderer *r)
{
    return r && r->f.tex_seam && r->f.plan.texture_space;
}

bool dm_renderer_thin_map(const dm_renderer *r)
{
    return r && r->f.tex_thin && r->f.plan.texture_space;
}

bool dm_renderer_thin_gather(const dm_renderer *r)
{
    return r && r->f.plan.texture_space &&
           (r->f.blur_cpu ? r->blur_cpu.gather.value != NULL : r->f.tex_gather_index != 0);
}
