/* dm_render_tonemap.c — tonemap: exposure, the filmic curve and sRGB into the 8-bit display
 * target (read by dm_renderer_read_display). */
#include <math.h>

#include "render/dm_render_internal.h"

dm_result dmr_tonemap_targets(dm_renderer *r, dm_error *err)
{
    dm_result rc = dmr_color_target(r, "display", r->width, r->height, GL_RGBA8, GL_CLAMP_TO_EDGE, &r->display_tex,
                                    &r->display_fbo, err);
    if (rc != DM_OK) return rc;
    /* the screen's depth buffer too: dmr_pass_tonemap tests the head's depth against it */
    glBindFramebuffer(GL_FRAMEBUFFER, r->display_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->screen_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return dm_fail(err, DM_ERR_GL, "target display with depth: framebuffer incomplete");
    return DM_OK;
}

/* Where the head is not, the screen holds the clear colour (0, 0, 0, 0) unless a background
 * or glow pass drew there; the filmic curve and sRGB take 0 to 0 exactly (alpha 1). Then the
 * display is cleared to that and only the head's pixels run the shader: a full-screen
 * triangle at the far plane, depth test GREATER, as the screen-space blurs do. The same
 * bytes; the work scales with the head's pixels, not the frame's. */
void dmr_pass_tonemap(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    GLuint p = r->prog[DM_PASS_TONEMAP];
    bool head_only = dm_render_plan_find(&r->plan, "background") < 0 && dm_render_plan_find(&r->plan, "glow_bright") < 0;
    dmr_target_begin(r->display_fbo, r->width, r->height);
    if (head_only) {
        glClearColor(0, 0, 0, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_GREATER);
        glDepthMask(GL_FALSE);
    } else {
        glDisable(GL_DEPTH_TEST);
    }
    glUseProgram(p);
    dmr_bind(UNIT_SRC, GL_TEXTURE_2D, r->screen_tex);
    u1f(p, "u_exposure_scale", exp2f(r->scene.exposure));
    if (r->plan.glow_in_tonemap) {
        dmr_bind(UNIT_GLOW, GL_TEXTURE_2D, r->glow_tex[0]);
        u1f(p, "u_glow_intensity", r->scene.glow_intensity);
    }
    dmr_draw_fullscreen(r);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
}
