/* dm_pass_diffusion.c — the levels' weighted sum at each texel of the irradiance grid
 * (diffusion.glsl), times coverage, into the target texture space published (diff_fbo); the
 * final pass reads it through dm_diffusion (shaders/common.glsl). The levels come through the
 * binder; a level whose upload a CPU chain deferred is brought up first. */
#include "render/passes/dm_pass_diffusion.h"

bool dmr_diffusion_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    (void)st, (void)ps;
    dmr_levels_need(f, ~0u); /* before the target: the sync binds its own framebuffers */
    *out = (dmr_output){f->diff_fbo, f->irr_edge, f->irr_edge, 0};
    return true;
}

void dmr_diffusion_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)st, (void)ps, (void)opt;
    dmg_u2f(f->prog[DM_PASS_DIFFUSION], "u_size", (float)f->irr_edge, (float)f->irr_edge);
    dmr_draw_fullscreen(f);
}
