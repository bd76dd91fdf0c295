/* dm_pass_glow.c — glow: a bright pass at half resolution, a separable Gaussian, added back
 * onto the screen (the add row blends). With a tonemap the tonemap pass adds it (the same
 * float sum, one full-screen pass fewer) and the screen gets it only when it is read (the
 * renderer runs the add row then). The Gaussian's two passes run on the CPU
 * (core/dm_glow_blur.h) where the texture-space blur would (dm_render_desc.blur_path): the
 * bright pass's result read back, blurred along x, then y, and uploaded where the tonemap
 * reads it; the same sums to float rounding. */
#include <stdlib.h>

#include "core/dm_glow_blur.h"
#include "render/gpu/dm_gpu_target.h"
#include "render/input/dm_render_estimate.h"
#include "render/passes/dm_pass_glow.h"

static void half_size(const dmr_frame *f, int *gw, int *gh)
{
    *gw = f->width / 2 > 0 ? f->width / 2 : 1, *gh = f->height / 2 > 0 ? f->height / 2 : 1;
}

dm_result dmr_glow_targets(dmr_frame *f, void *st, dm_error *err)
{
    if (!f->plan.effects[DM_EFFECT_GLOW]) return DM_OK;
    dmr_glow *g = st;
    int gw, gh;
    half_size(f, &gw, &gh);
    dm_result rc = dmg_color_target(&f->gpu, "glow_a", gw, gh, GL_RGBA32F, GL_CLAMP_TO_EDGE, &g->tex[0], &g->fbo[0], err);
    if (rc == DM_OK)
        rc = dmg_color_target(&f->gpu, "glow_b", gw, gh, GL_RGBA32F, GL_CLAMP_TO_EDGE, &g->tex[1], &g->fbo[1], err);
    f->glow_tex = g->tex[0];
    if (rc == DM_OK && dmr_blur_cpu_wanted(&f->desc, f->software_gl)) {
        for (int i = 0; i < 2; ++i) g->buf[i] = malloc(sizeof(float) * 4 * (size_t)gw * (size_t)gh);
        g->cpu = g->buf[0] && g->buf[1]; /* out of memory: in GL */
    }
    return rc;
}

void dmr_glow_free(dmr_frame *f, void *st)
{
    (void)f;
    dmr_glow *g = st;
    for (int i = 0; i < 2; ++i) free(g->buf[i]), g->buf[i] = NULL;
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
static bool blur_on_cpu(dmr_glow *g, bool along_y, int gw, int gh)
{
    if (!along_y) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, g->fbo[0]);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glReadPixels(0, 0, gw, gh, GL_RGBA, GL_FLOAT, g->buf[0]);
        return dm_glow_blur(g->buf[0], g->buf[1], gw, gh, false, 0);
    }
    if (!dm_glow_blur(g->buf[1], g->buf[0], gw, gh, true, 0)) {
        upload(g->tex[1], gw, gh, g->buf[1]); /* the x pass's result, for the shader */
        return false;
    }
    upload(g->tex[0], gw, gh, g->buf[0]);
    return true;
}

/* bright: into glow_a; blur x: glow_a to glow_b; blur y: back; add: onto the screen. */
bool dmr_glow_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    const dmr_glow *g = st;
    int gw, gh;
    half_size(f, &gw, &gh);
    if (ps->kind == DM_PASS_GLOW_ADD) *out = (dmr_output){f->screen_fbo, f->width, f->height, 0};
    else *out = (dmr_output){g->fbo[ps->kind == DM_PASS_GLOW_BLUR_U ? 1 : 0], gw, gh, 0};
    return true;
}

void dmr_glow_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)opt;
    dmr_glow *g = st;
    dm_pass_kind kind = ps->kind;
    int gw, gh;
    half_size(f, &gw, &gh);
    bool blur = kind == DM_PASS_GLOW_BLUR_U || kind == DM_PASS_GLOW_BLUR_V;
    if (g->cpu && blur) {
        if (blur_on_cpu(g, kind == DM_PASS_GLOW_BLUR_V, gw, gh)) return;
        g->cpu = false;
    }
    GLuint p = f->prog[kind];
    if (kind == DM_PASS_GLOW_BRIGHT) {
        dmg_bind(UNIT_SRC, GL_TEXTURE_2D, f->screen_tex);
        dmg_u1f(p, "u_threshold", f->scene.glow_threshold);
    } else if (blur) {
        bool along_y = kind == DM_PASS_GLOW_BLUR_V;
        float w[3], o[2];
        dm_glow_kernel(w, o);
        dmg_bind(UNIT_SRC, GL_TEXTURE_2D, g->tex[along_y ? 1 : 0]);
        dmg_u2f(p, "u_step", along_y ? 0.0f : 1.0f / (float)gw, along_y ? 1.0f / (float)gh : 0.0f);
        glUniform3fv(dmg_loc(p, "u_weight"), 1, w);
        glUniform2fv(dmg_loc(p, "u_offset"), 1, o);
    } else {
        dmg_bind(UNIT_SRC, GL_TEXTURE_2D, g->tex[0]);
        dmg_u1f(p, "u_intensity", f->scene.glow_intensity);
    }
    dmr_draw_fullscreen(f);
}
