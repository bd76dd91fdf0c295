/* dm_pass_shade.c — the head on screen: the G-buffer pass (the surface per pixel) and the
 * final pass, which shades each head pixel once from it (or, where that is cheaper, while
 * rasterising) with the diffuse term of the active technique (texture-space levels, the
 * pre-integrated table, or Lambert without subsurface), KS specular, environment specular;
 * the specular/diffuse/uv/wireframe debug modes. Screen-space subsurface shades from the same
 * G-buffer in its own pass (dm_pass_ssss.c), from the same shader file. Every input comes
 * from the binder (DMR_BIND_SHADE); depth, culling and clears from the rows. */
#include <math.h>
#include <stdlib.h>

#include "core/dm_sort.h"
#include "render/frame/dm_frame_bind.h"
#include "render/passes/dm_pass_shade.h"

/* The specular view exposed to be read: the head's specular is a few percent of its
 * radiance, dark at the scene's exposure. Its pixels (alpha 1) are scaled so their 99th
 * percentile (largest channel) lands near display white: tonemap input 4 (0.92 of white
 * through the filmic curve) after the scene's exposure, or 0.9 without a tonemap. The
 * background keeps its exposure; the gain is reported (dm_renderer_view_gain). */
static void expose_specular(dmr_frame *f)
{
    size_t n = (size_t)f->width * f->height, k = 0;
    float *px = malloc(n * 4 * sizeof *px), *v = malloc(n * sizeof *v);
    if (px && v) {
        glBindTexture(GL_TEXTURE_2D, f->screen_tex);
        glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, px);
        for (size_t i = 0; i < n; ++i)
            if (px[4 * i + 3] >= 0.5f) v[k++] = fmaxf(px[4 * i], fmaxf(px[4 * i + 1], px[4 * i + 2]));
        if (k) {
            dm_sort_floats(v, k);
            float top = v[k - 1 - k / 100], white = f->plan.effects[DM_EFFECT_TONEMAP] ? 4.0f / exp2f(f->scene.exposure) : 0.9f;
            f->view_gain = top > 1e-12f && isfinite(top) ? fminf(white / top, 1e6f) : 1.0f;
            for (size_t i = 0; i < n; ++i)
                if (px[4 * i + 3] >= 0.5f)
                    for (int c = 0; c < 3; ++c) px[4 * i + c] *= f->view_gain;
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, f->width, f->height, GL_RGBA, GL_FLOAT, px);
        }
    }
    free(px), free(v);
}

/* The head's nearest surface per pixel (final.glsl with DM_GBUFFER): position and uv,
 * geometric and shading normal, albedo, rho_s and roughness, and the screen's depth. The
 * colour is not cleared: the passes after it read only the pixels drawn here. */
bool dmr_gbuffer_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    (void)st, (void)ps;
    *out = (dmr_output){f->gbuf_fbo, f->width, f->height, 4};
    return true;
}

void dmr_gbuffer_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)st, (void)ps, (void)opt;
    dmr_draw_mesh(f);
}

/* The screen: alpha 1 where the head is drawn, 0 elsewhere (coverage). */
bool dmr_final_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    (void)st, (void)ps;
    *out = (dmr_output){f->screen_fbo, f->width, f->height, 0};
    return true;
}

/* Each head pixel shaded once from the G-buffer (final.glsl with DM_DEFERRED): the full-screen
 * triangle at the far plane, depth test GREATER against the head's depth. */
void dmr_final_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)st, (void)ps, (void)opt;
    dmr_bind_gbuffer(f->prog[DM_PASS_FINAL], f->gbuf_tex);
    dmr_draw_fullscreen(f);
    f->view_gain = 1.0f;
    if (dmr_view_mode(f) == 1) expose_specular(f);
}

/* The head shaded while rasterising (final.glsl without DM_DEFERRED): where its shading is
 * cheaper than a G-buffer (texture-space without specular), and the uv and wireframe views
 * (modes 3 and 4), which draw the mesh itself. */
void dmr_final_forward_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)st, (void)ps, (void)opt;
    dmr_draw_mesh(f);
    f->view_gain = 1.0f;
    if (dmr_view_mode(f) == 1) expose_specular(f);
}

int dmr_final_forward_variant(const dmr_frame *f, const void *st)
{
    (void)st;
    return dmr_view_mode(f) == 4;
}
