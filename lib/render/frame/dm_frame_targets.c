/* dm_frame_targets.c — the targets every screen pass shares: "screen" (float32, so read_linear
 * and read_view return it at full precision; alpha = coverage) with its depth buffer, "view"
 * (texture views at their own size), and the head's G-buffer when the plan shades deferred. */
#include "render/frame/dm_frame.h"
#include "render/gpu/dm_gpu_target.h"

dm_result dmr_frame_targets(dmr_frame *f, dm_error *err)
{
    dm_result rc = dmg_color_target(&f->gpu, "screen", f->width, f->height, GL_RGBA32F, GL_CLAMP_TO_EDGE,
                                    &f->screen_tex, &f->screen_fbo, err);
    if (rc != DM_OK) return rc;
    f->view_target = f->gpu.target_count;
    rc = dmg_color_target(&f->gpu, "view", 1, 1, GL_RGBA32F, GL_CLAMP_TO_EDGE, &f->view_tex, &f->view_fbo, err);
    if (rc != DM_OK) return rc;
    f->screen_depth = dmg_depth_buffer(&f->gpu, f->width, f->height);
    rc = dmg_attach_depth(f->screen_fbo, f->screen_depth, "screen", err);
    if (rc == DM_OK && f->plan.deferred)
        rc = dmg_gbuffer_targets(&f->gpu, "gbuffer", f->width, f->height, f->screen_depth, f->gbuf_tex, &f->gbuf_fbo,
                                 err);
    return rc;
}
