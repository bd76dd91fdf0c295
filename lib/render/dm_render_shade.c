/* dm_render_shade.c — the head on screen: the G-buffer pass (the surface per pixel) and the
 * final pass, which shades each head pixel once from it (or, where that is cheaper, while
 * rasterising) with the diffuse term of the active technique (texture-space levels, the
 * pre-integrated table, or Lambert without subsurface), KS specular, environment specular;
 * the specular/diffuse/uv/wireframe debug modes. Screen-space subsurface shades from the same
 * G-buffer in its own pass (dm_render_ssss.c), from the same shader file. */
#include <math.h>
#include <stdlib.h>

#include "render/dm_render_internal.h"
#include "core/dm_sort.h"

void dmr_shade_begin(dm_renderer *r, GLuint p, int mode)
{
    glUseProgram(p);
    glUniformMatrix4fv(loc(p, "u_view_proj"), 1, GL_FALSE, r->view_proj);
    glUniform3fv(loc(p, "u_eye"), 1, r->eye);
    u1i(p, "u_mode", mode);
    dmr_set_light_uniforms(r, p);
    dmr_set_surface_uniforms(r, p);
    dmr_bind_surface(r);
    glUniform1fv(loc(p, "u_env_level_m"), DM_RENDER_ENV_LEVELS_MAX, r->env_level_m);
    dmr_bind_levels(r, p);
    dmr_preint_bind(r, p); /* after the levels: it takes two of their units */
    if (r->plan.screen_space) glUniform3fv(loc(p, "u_cam_forward"), 1, r->cam_fwd);
    dmr_translucency_bind(r, p);
}

void dmr_shade_head(dm_renderer *r, GLuint p, int mode)
{
    dmr_shade_begin(r, p, mode);
    dmr_draw_mesh(r);
    dmr_translucency_unbind(r);
}

/* The specular view exposed to be read: the head's specular is a few percent of its
 * radiance, dark at the scene's exposure. Its pixels (alpha 1) are scaled so their 99th
 * percentile (largest channel) lands near display white: tonemap input 4 (0.92 of white
 * through the filmic curve) after the scene's exposure, or 0.9 without a tonemap. The
 * background keeps its exposure; the gain is reported (dm_renderer_view_gain). */
static void expose_specular(dm_renderer *r)
{
    size_t n = (size_t)r->width * r->height, k = 0;
    float *px = malloc(n * 4 * sizeof *px), *v = malloc(n * sizeof *v);
    if (px && v) {
        glBindTexture(GL_TEXTURE_2D, r->screen_tex);
        glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, px);
        for (size_t i = 0; i < n; ++i)
            if (px[4 * i + 3] >= 0.5f) v[k++] = fmaxf(px[4 * i], fmaxf(px[4 * i + 1], px[4 * i + 2]));
        if (k) {
            dm_sort_floats(v, k);
            float top = v[k - 1 - k / 100], white = r->plan.effects[DM_EFFECT_TONEMAP] ? 4.0f / exp2f(r->scene.exposure) : 0.9f;
            r->view_gain = top > 1e-12f && isfinite(top) ? fminf(white / top, 1e6f) : 1.0f;
            for (size_t i = 0; i < n; ++i)
                if (px[4 * i + 3] >= 0.5f)
                    for (int c = 0; c < 3; ++c) px[4 * i + c] *= r->view_gain;
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, r->width, r->height, GL_RGBA, GL_FLOAT, px);
        }
    }
    free(px), free(v);
}

static const int view_modes[DM_VIEW_COUNT] = {[DM_VIEW_FINAL] = 0,   [DM_VIEW_SPECULAR] = 1,
                                              [DM_VIEW_DIFFUSE] = 2, [DM_VIEW_UV_TEST] = 3,
                                              [DM_VIEW_WIREFRAME] = 4};

/* The head's nearest surface per pixel (final.glsl with DM_GBUFFER): position and uv,
 * geometric and shading normal, albedo, rho_s and roughness, and the screen's depth. The
 * colour is not cleared: the passes after it read only the pixels drawn here. */
void dmr_pass_gbuffer(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    dmr_target_begin(r->gbuf_fbo, r->width, r->height);
    glDrawBuffers(4, dmr_draw_buffers);
    glDepthMask(GL_TRUE);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    dmr_shade_head(r, r->prog[DM_PASS_GBUFFER], 0);
    glDisable(GL_CULL_FACE);
    glDisable(GL_DEPTH_TEST);
}

/* Each head pixel shaded once from the G-buffer (final.glsl with DM_DEFERRED): the full-screen
 * triangle at the far plane, depth test GREATER against the head's depth. */
void dmr_pass_final(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    int mode = view_modes[r->plan.view];
    GLuint p = r->prog[DM_PASS_FINAL];
    dmr_target_begin(r->screen_fbo, r->width, r->height);
    dmr_screen_clear(r, 0); /* alpha: 1 where the head is drawn, 0 elsewhere (coverage) */
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_FALSE);
    dmr_shade_begin(r, p, mode);
    dmr_bind_gbuffer(p, r->gbuf_tex);
    dmr_draw_fullscreen(r);
    dmr_translucency_unbind(r);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
    r->view_gain = 1.0f;
    if (mode == 1) expose_specular(r);
}

/* The head shaded while rasterising (final.glsl without DM_DEFERRED): where its shading is
 * cheaper than a G-buffer (texture-space without specular), and the uv and wireframe views
 * (modes 3 and 4), which draw the mesh itself. */
void dmr_pass_final_forward(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    int mode = view_modes[r->plan.view];
    dmr_target_begin(r->screen_fbo, r->width, r->height);
    glDepthMask(GL_TRUE);
    dmr_screen_clear(r, GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    if (mode == 4) {
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    } else {
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
    }
    dmr_shade_head(r, r->prog[DM_PASS_FINAL_FORWARD], mode);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_CULL_FACE);
    glDisable(GL_DEPTH_TEST);
    r->view_gain = 1.0f;
    if (mode == 1) expose_specular(r);
}
