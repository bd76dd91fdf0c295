/* dm_render_glow.c — glow: a bright pass at half resolution, a separable Gaussian, added back
 * onto the screen. With a tonemap the tonemap pass adds it (the same float sum, one full-screen
 * pass fewer) and the screen gets it only when it is read (dmr_glow_settle). */
#include "render/dm_render_internal.h"

dm_result dmr_glow_targets(dm_renderer *r, dm_error *err)
{
    int gw = r->width / 2 > 0 ? r->width / 2 : 1, gh = r->height / 2 > 0 ? r->height / 2 : 1;
    dm_result rc =
        dmr_color_target(r, "glow_a", gw, gh, GL_RGBA32F, GL_CLAMP_TO_EDGE, &r->glow_tex[0], &r->glow_fbo[0], err);
    if (rc == DM_OK)
        rc = dmr_color_target(r, "glow_b", gw, gh, GL_RGBA32F, GL_CLAMP_TO_EDGE, &r->glow_tex[1], &r->glow_fbo[1],
                              err);
    return rc;
}

void dmr_pass_glow(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)opt;
    dm_pass_kind kind = ps->kind;
    int gw = r->width / 2 > 0 ? r->width / 2 : 1, gh = r->height / 2 > 0 ? r->height / 2 : 1;
    GLuint p = r->prog[kind];
    glUseProgram(p);
    glDisable(GL_DEPTH_TEST);
    if (kind == DM_PASS_GLOW_BRIGHT) {
        dmr_target_begin(r->glow_fbo[0], gw, gh);
        dmr_bind(UNIT_SRC, GL_TEXTURE_2D, r->screen_tex);
        u1f(p, "u_threshold", r->scene.glow_threshold);
    } else if (kind == DM_PASS_GLOW_BLUR_U) {
        dmr_target_begin(r->glow_fbo[1], gw, gh);
        dmr_bind(UNIT_SRC, GL_TEXTURE_2D, r->glow_tex[0]);
        u2f(p, "u_step", 1.0f / (float)gw, 0.0f);
    } else if (kind == DM_PASS_GLOW_BLUR_V) {
        dmr_target_begin(r->glow_fbo[0], gw, gh);
        dmr_bind(UNIT_SRC, GL_TEXTURE_2D, r->glow_tex[1]);
        u2f(p, "u_step", 0.0f, 1.0f / (float)gh);
    } else {
        dmr_target_begin(r->screen_fbo, r->width, r->height);
        dmr_bind(UNIT_SRC, GL_TEXTURE_2D, r->glow_tex[0]);
        u1f(p, "u_intensity", r->scene.glow_intensity);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
    }
    dmr_draw_fullscreen(r);
    glDisable(GL_BLEND);
}

void dmr_glow_settle(dm_renderer *r)
{
    if (!r->glow_pending) return;
    r->glow_pending = false;
    dmr_pass_glow(r, &(dm_pass){.kind = DM_PASS_GLOW_ADD}, NULL);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}
