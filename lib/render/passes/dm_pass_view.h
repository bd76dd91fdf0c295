/* dm_pass_view.h — texture debug views (irradiance, blurK, stretchK, shadowK, diffusion,
 * curvature) into the frame's "view" target at their own size, then over the screen. Keeps the
 * colour scale of the stretch and curvature views (read by dm_renderer_view_scale). */
#ifndef DM_PASS_VIEW_H
#define DM_PASS_VIEW_H

#include "render/frame/dm_frame_pass.h"

typedef struct dmr_view {
    GLuint range_of; /* the map lo, hi were measured on (stretch/curvature views) */
    float lo, hi;    /* their colour scale: 1st and 99th percentile */
    GLuint src;      /* this frame's: the texture shown, its size, its coverage shift */
    int width, height, cov_shift;
} dmr_view;

bool dmr_view_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_view_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);

#endif
