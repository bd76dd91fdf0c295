/* dm_pass_diffusion.c — the levels' weighted sum at each texel of the irradiance grid
 * (diffusion.glsl), times coverage, into the target texture space published (diff_fbo); the
 * final pass reads it through dm_diffusion (shaders/common.glsl). The levels come through the
 * binder; a level whose upload a CPU chain deferred is brought up first. With a thin-part map
 * (DM_THIN) it adds the light from across thin parts and folds; with a thin gather (DM_GATHER)
 * the widest levels of the texels near a surface facing away or a seam are the 3-D sum over the
 * surface's sites. */
#include "render/passes/dm_pass_diffusion.h"

#include <math.h>

#include "core/dm_level_sum.h"

dm_result dmr_diffusion_setup(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err)
{
    (void)st;
    const dm_texture *gt, *gi = dm_render_assets_gather(a, f->irr_edge, &gt);
    if (f->plan.texture_space && gi) {
        const float *ix = gi->texels; /* the "gather" debug view's copy (views are per frame) and its scale's top */
        for (size_t i = 0; i < (size_t)gi->width * gi->height; ++i)
            f->gather_view_max = fmaxf(f->gather_view_max, ix[4 * i + 1] + ix[4 * i + 2]);
        dm_result rc = dmr_upload(f, gi, "gather_view", false, GL_NEAREST, &f->tex_gather_view, err);
        if (rc != DM_OK) return rc;
    }
    if (f->blur_cpu || !f->tex_thin || !f->gather_ok) return DM_OK; /* checked at upload (dm_pass_tsd.c) */
    f->tex_gather_index = f->tex_gather_view; /* the view's upload above: one texture, owned by f->gpu */
    return dmr_upload(f, gt, "gather_taps", false, GL_NEAREST, &f->tex_gather_taps, err);
}

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
    if (f->tex_gather_index) { /* DM_GATHER: the widest levels as the 3-D sum over the surface's sites */
        glUniform1i(dmg_loc(p, "u_gather_first"), f->gather_first);
        glUniform1i(dmg_loc(p, "u_gather_count"), f->gather_count);
        dmg_bind(UNIT_GATHER_INDEX, GL_TEXTURE_2D, f->tex_gather_index);
        dmg_bind(UNIT_GATHER_TAPS, GL_TEXTURE_2D, f->tex_gather_taps);
    }
    dmr_draw_fullscreen(f);
}
