/* dm_render_tonemap.c — tonemap: exposure, the filmic curve and sRGB into the 8-bit display
 * target (read by dm_renderer_read_display). */
#include <math.h>

#include "render/dm_render_internal.h"

dm_result dmr_tonemap_targets(dm_renderer *r, dm_error *err)
{
    return dmr_color_target(r, "display", r->width, r->height, GL_RGBA8, GL_CLAMP_TO_EDGE, &r->display_tex,
                            &r->display_fbo, err);
}

void dmr_pass_tonemap(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    GLuint p = r->prog[DM_PASS_TONEMAP];
    dmr_target_begin(r->display_fbo, r->width, r->height);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(p);
    dmr_bind(UNIT_SRC, GL_TEXTURE_2D, r->screen_tex);
    u1f(p, "u_exposure_scale", exp2f(r->scene.exposure));
    dmr_draw_fullscreen(r);
}
