/* dm_render_glow.c — glow: a bright pass at half resolution, a separable Gaussian, added back
 * onto the screen. With a tonemap the tonemap pass adds it (the same float sum, one full-screen
 * pass fewer) and the screen gets it only when it is read (dmr_glow_settle). The Gaussian's
 * two passes run on the CPU (core/dm_glow_blur.h) where the texture-space blur would
 * (dm_render_desc.blur_path): the bright pass's result read back, blurred along x, then y,
 * and uploaded where the tonemap reads it; the same sums to float rounding. */
#include <stdlib.h>

#include "core/dm_glow_blur.h"
#include "render/dm_render_internal.h"

dm_result dmr_glow_targets(dm_renderer *r, dm_error *err)
{
    int gw = r->width / 2 > 0 ? r->width / 2 : 1, gh = r->height / 2 > 0 ? r->height / 2 : 1;
    dm_result rc =
        dmr_color_target(r, "glow_a", gw, gh, GL_RGBA32F, GL_CLAMP_TO_EDGE, &r->glow_tex[0], &r->glow_fbo[0], err);
    if (rc == DM_OK)
        rc = dmr_color_target(r, "glow_b", gw, gh, GL_RGBA32F, GL_CLAMP_TO_EDGE, &r->glow_tex[1], &r->glow_fbo[1],
                              err);
    if (rc == DM_OK && dmr_blur_cpu_wanted(&r->desc, r->timing_cpu)) {
        for (int i = 0; i < 2; ++i) r->glow_buf[i] = malloc(sizeof(float) * 4 * (size_t)gw * (size_t)gh);
        r->glow_cpu = r->glow_buf[0] && r->glow_buf[1]; /* out of memory: in GL */
    }
    return rc;
}

void dmr_glow_free(dm_renderer *r)
{
    for (int i = 0; i < 2; ++i) free(r->glow_buf[i]), r->glow_buf[i] = NULL;
}

static void upload(GLuint tex, int gw, int gh, const float *px)
{
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, gw, gh, GL_RGBA, GL_FLOAT, px);
}

/* The Gaussian's passes on the CPU: along x from the bright pass's target, along y back into
 * it. False when the CPU pass cannot run (no memory for its tap table): the glow goes on in
 * GL from here, its input where the shader reads it. */
static bool blur_on_cpu(dm_renderer *r, bool along_y, int gw, int gh)
{
    if (!along_y) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, r->glow_fbo[0]);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glReadPixels(0, 0, gw, gh, GL_RGBA, GL_FLOAT, r->glow_buf[0]);
        return dm_glow_blur(r->glow_buf[0], r->glow_buf[1], gw, gh, false, 0);
    }
    if (!dm_glow_blur(r->glow_buf[1], r->glow_buf[0], gw, gh, true, 0)) {
        upload(r->glow_tex[1], gw, gh, r->glow_buf[1]); /* the x pass's result, for the shader */
        return false;
    }
    upload(r->glow_tex[0], gw, gh, r->glow_buf[0]);
    return true;
}

void dmr_pass_glow(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)opt;
    dm_pass_kind kind = ps->kind;
    int gw = r->width / 2 > 0 ? r->width / 2 : 1, gh = r->height / 2 > 0 ? r->height / 2 : 1;
    if (r->glow_cpu && (kind == DM_PASS_GLOW_BLUR_U || kind == DM_PASS_GLOW_BLUR_V)) {
        if (blur_on_cpu(r, kind == DM_PASS_GLOW_BLUR_V, gw, gh)) return;
        r->glow_cpu = false;
    }
    GLuint p = r->prog[kind];
    glUseProgram(p);
    glDisable(GL_DEPTH_TEST);
    if (kind == DM_PASS_GLOW_BRIGHT) {
        dmr_target_begin(r->glow_fbo[0], gw, gh);
        dmr_bind(UNIT_SRC, GL_TEXTURE_2D, r->screen_tex);
        u1f(p, "u_threshold", r->scene.glow_threshold);
    } else if (kind == DM_PASS_GLOW_BLUR_U || kind == DM_PASS_GLOW_BLUR_V) {
        bool along_y = kind == DM_PASS_GLOW_BLUR_V; /* x: glow_a to glow_b; y: back */
        float w[3], o[2];
        dm_glow_kernel(w, o);
        dmr_target_begin(r->glow_fbo[along_y ? 0 : 1], gw, gh);
        dmr_bind(UNIT_SRC, GL_TEXTURE_2D, r->glow_tex[along_y ? 1 : 0]);
        u2f(p, "u_step", along_y ? 0.0f : 1.0f / (float)gw, along_y ? 1.0f / (float)gh : 0.0f);
        glUniform3fv(loc(p, "u_weight"), 1, w);
        glUniform2fv(loc(p, "u_offset"), 1, o);
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
