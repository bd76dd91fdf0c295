/* dm_pass_diffusion.c — the levels' weighted sum at each texel of the irradiance grid
 * (diffusion.glsl), times coverage, into the target texture space published (diff_fbo); the
 * final pass reads it through dm_diffusion (shaders/common.glsl). The levels come through the
 * binder; a level whose upload a CPU chain deferred is brought up first. With a thin-part map
 * (DM_THIN) it adds the light from across thin parts and folds. */
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
    GLuint p = f->prog[DM_PASS_DIFFUSION];
    dmg_u2f(p, "u_size", (float)f->irr_edge, (float)f->irr_edge);
    if (f->tex_thin) { /* DM_THIN: the candidates across thin parts and folds, the levels' variances */
        float v[DM_PROFILE_MAX_GAUSSIANS];
        for (int k = 0; k < f->profile.count; ++k) v[k] = (float)f->profile.variance_mm2[k];
        glUniform1fv(dmg_loc(p, "u_level_var"), f->profile.count, v);
        dmg_bind(UNIT_THIN, GL_TEXTURE_2D, f->tex_thin);
    }
    dmr_draw_fullscreen(f);
}
