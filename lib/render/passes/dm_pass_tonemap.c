/* dm_pass_tonemap.c — tonemap: exposure, the filmic curve and sRGB into the 8-bit display
 * target (read by dm_renderer_read_display).
 *
 * Where the head is not, the screen holds the clear colour (0, 0, 0, 0) unless a background
 * or glow pass drew there; the filmic curve and sRGB take 0 to 0 exactly (alpha 1). Then the
 * display is cleared to that and only the head's pixels run the shader: a full-screen
 * triangle at the far plane, depth test GREATER, as the screen-space blurs do (variant 0 of
 * the row's state). The same bytes; the work scales with the head's pixels, not the frame's. */
#include <math.h>

#include "render/gpu/dm_gpu_target.h"
#include "render/passes/dm_pass_tonemap.h"

dm_result dmr_tonemap_targets(dmr_frame *f, void *st, dm_error *err)
{
    if (!f->plan.effects[DM_EFFECT_TONEMAP]) return DM_OK;
    dmr_tonemap *t = st;
    dm_result rc = dmg_color_target(&f->gpu, "display", f->width, f->height, GL_RGBA8, GL_CLAMP_TO_EDGE,
                                    &t->display_tex, &t->display_fbo, err);
    /* the screen's depth buffer too: the head-only variant tests the head's depth against it */
    return rc == DM_OK ? dmg_attach_depth(t->display_fbo, f->screen_depth, "display", err) : rc;
}

bool dmr_tonemap_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    (void)ps;
    *out = (dmr_output){((const dmr_tonemap *)st)->display_fbo, f->width, f->height, 0};
    return true;
}

int dmr_tonemap_variant(const dmr_frame *f, const void *st)
{
    (void)st;
    bool head_only = dm_render_plan_find(&f->plan, "background") < 0 && dm_render_plan_find(&f->plan, "glow_bright") < 0;
    return head_only ? 0 : 1;
}

void dmr_tonemap_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)st, (void)ps, (void)opt;
    GLuint p = f->prog[DM_PASS_TONEMAP];
    dmg_bind(UNIT_SRC, GL_TEXTURE_2D, f->screen_tex);
    dmg_u1f(p, "u_exposure_scale", exp2f(f->scene.exposure));
    if (f->plan.glow_in_tonemap) {
        dmg_bind(UNIT_GLOW, GL_TEXTURE_2D, f->glow_tex);
        dmg_u1f(p, "u_glow_intensity", f->scene.glow_intensity);
    }
    dmr_draw_fullscreen(f);
}
