/* dm_render_tsd.c — texture-space diffusion (d'Eon & Luebke, GPU Gems 3 ch. 14): the
 * ts_gbuffer pass unwraps the surface into the UV atlas once per scene, the irradiance pass
 * lights each covered texel of it every frame, then each Gaussian level k is made
 * from level k−1 by a U and a V blur of variance v_k − v_{k−1}, tap offsets in mm turned into
 * UV by the stretch chain. The diffusion pass sums the levels once per texel (diffusion.glsl)
 * for the final pass to read (dm_diffusion, shaders/common.glsl); with diffusion_per_pixel the
 * final pass sums them itself. Owns the stretch uploads, the level targets and the blur kernel. */
#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_half.h"
#include "core/dm_sort.h"
#include "render/dm_render_internal.h"

/* The tested tap weights of lib/core (dm_blur_taps: bin masses of the unit Gaussian, each
 * end bin running to infinity), taps spread over ±3σ. */
double dm_render_blur_kernel(int taps, float *offsets_sigma, float *weights)
{
    assert(taps >= 3 && taps <= DM_BLUR_TAPS_MAX && taps % 2 == 1);
    int h = (taps - 1) / 2;
    double step = 3.0 / h, var = 0.0, w[DM_BLUR_TAPS_MAX];
    dm_result rc = dm_blur_taps(taps, step, 1, w, NULL, NULL);
    assert(rc == DM_OK);
    (void)rc;
    for (int i = 0; i < taps; ++i) {
        double x = (i - h) * step;
        offsets_sigma[i] = (float)x;
        weights[i] = (float)w[i];
        var += w[i] * x * x;
    }
    return var;
}

static dm_result need_texture(const dm_texture *t, const char *what, const char *effect, dm_error *err)
{
    if (!t->texels)
        return dm_fail(err, DM_ERR_MISMATCH, "assets: %s is missing, and the %s effect needs it", what, effect);
    return DM_OK;
}

dm_result dmr_tsd_check(const dm_render_assets *a, const dm_profile *prof, dm_error *err)
{
    dm_result rc = dm_profile_validate(prof, "assets: profile", err);
    if (rc == DM_OK && (a->stretch_level_count < 1 || a->stretch_level_count > DM_PROFILE_MAX_GAUSSIANS))
        return dm_fail(err, DM_ERR_MISMATCH, "assets: %d stretch levels, subsurface needs 1..%d",
                       a->stretch_level_count, DM_PROFILE_MAX_GAUSSIANS);
    for (int k = 0; k < a->stretch_level_count && rc == DM_OK; ++k) {
        rc = need_texture(&a->stretch[k], "a stretch level", "subsurface", err);
        if (rc == DM_OK && a->stretch[k].format != DM_TEX_RG32F && a->stretch[k].format != DM_TEX_RG16F)
            rc = dm_fail(err, DM_ERR_UNSUPPORTED, "assets: stretch level %d is %s, expected rg32f or rg16f", k,
                         dmr_format_name(a->stretch[k].format));
    }
    int taps = a->scene->blur_taps;
    if (rc == DM_OK && (taps < 3 || taps > DM_BLUR_TAPS_MAX || taps % 2 == 0))
        rc = dm_fail(err, DM_ERR_RANGE, "scene: blur_taps = %d, expected an odd integer in [3, %d]", taps,
                     DM_BLUR_TAPS_MAX);
    return rc;
}

float dmr_stretch_value(const dm_texture *t, size_t i)
{
    return t->format == DM_TEX_RG32F ? ((const float *)t->texels)[i] : dm_half_to_float(((const uint16_t *)t->texels)[i]);
}

bool dm_render_stretch_median(const dm_render_assets *a, float med[2])
{
    const dm_texture *t = &a->stretch[0];
    med[0] = med[1] = 0.0f;
    if (a->stretch_level_count < 1 || !t->texels || (t->format != DM_TEX_RG32F && t->format != DM_TEX_RG16F))
        return false;
    size_t n = (size_t)t->width * (size_t)t->height, k = 0;
    const uint8_t *mask = a->stretch_mask.texels && a->stretch_mask.width == t->width &&
                                  a->stretch_mask.height == t->height ? a->stretch_mask.texels : NULL;
    float *u = malloc(sizeof *u * n), *v = malloc(sizeof *v * n);
    for (size_t i = 0; u && v && i < n; ++i) {
        float su = dmr_stretch_value(t, 2 * i), sv = dmr_stretch_value(t, 2 * i + 1);
        if ((mask ? mask[i] > 0 : su > 0) && isfinite(su) && isfinite(sv)) u[k] = su, v[k++] = sv;
    }
    if (k) {
        dm_sort_floats(u, k), dm_sort_floats(v, k);
        med[0] = u[k / 2], med[1] = v[k / 2];
    }
    free(u), free(v);
    return k > 0;
}

void dmr_auto_level_edges(const dm_render_assets *a, const dm_render_desc *d, const dm_profile *prof, int irr_edge,
                          int level_edge[DM_PROFILE_MAX_GAUSSIANS])
{
    float med[2];
    if (!d->blur_auto_resolution || d->blur_reduce_from != 0 || !dm_render_stretch_median(a, med)) return;
    double uv_per_mm = fmin(med[0], med[1]);
    int j = 0;
    for (int k = 1; k < prof->count && uv_per_mm > 0; ++k) {
        double sigma_texels = sqrt(prof->variance_mm2[k]) * uv_per_mm * irr_edge;
        while (j < 3 && (irr_edge >> (j + 1)) >= 8 && sigma_texels / (1 << (j + 1)) >= DM_BLUR_AUTO_SIGMA) ++j;
        level_edge[k] = irr_edge >> j;
    }
}

dm_result dmr_tsd_upload(dm_renderer *r, const dm_render_assets *a, dm_error *err)
{
    dm_result rc = DM_OK;
    r->stretch_count = a->stretch_level_count;
    for (int k = 0; k < a->stretch_level_count && rc == DM_OK; ++k)
        rc = dmr_upload(&a->stretch[k], "stretch", false, GL_LINEAR, &r->tex_stretch[k], err);
    if (rc == DM_OK && a->stretch_mask.texels)
        rc = dmr_upload(&a->stretch_mask, "stretch_mask", false, GL_LINEAR, &r->tex_mask, err);
    return rc;
}

dm_result dmr_tsd_targets(dm_renderer *r, dm_error *err)
{
    const dm_render_plan *p = &r->plan;
    dm_result rc = DM_OK;
    char name[32];
    for (int k = 0; k < p->blur_levels && rc == DM_OK; ++k) {
        snprintf(name, sizeof name, k == 0 ? "irradiance" : "blur%d", k);
        rc = dmr_color_target(r, name, r->level_edge[k], r->level_edge[k], r->level_format, GL_CLAMP_TO_BORDER,
                              &r->irr_tex[k], &r->irr_fbo[k], err);
    }
    /* the U pass of level k writes at level k's width and level k−1's height: its input still
     * holds detail along V that only the V pass may filter away. One target per size. */
    for (int k = 1; k < p->blur_levels && rc == DM_OK; ++k) {
        int w = r->level_edge[k], h = r->level_edge[k - 1], j = 1;
        while (j < k && !(r->level_edge[j] == w && r->level_edge[j - 1] == h)) ++j;
        if (j < k) {
            r->tmp_tex[k] = r->tmp_tex[j], r->tmp_fbo[k] = r->tmp_fbo[j];
            continue;
        }
        snprintf(name, sizeof name, "blur_tmp%d", k);
        rc = dmr_color_target(r, name, w, h, r->level_format, GL_CLAMP_TO_BORDER, &r->tmp_tex[k], &r->tmp_fbo[k],
                              err);
    }
    /* the sum in float32 even over half-float levels: the sum per pixel was float too */
    if (rc == DM_OK && r->diffusion_sum)
        rc = dmr_color_target(r, "diffusion", r->irr_edge, r->irr_edge, GL_RGBA32F, GL_CLAMP_TO_BORDER, &r->diff_tex,
                              &r->diff_fbo, err);
    if (rc != DM_OK) return rc;
    /* the G-buffer's depth marks covered texels (0.5; 1 in gutters); the irradiance target
     * shares it, and keeps its once-cleared gutters (frames write covered texels only) */
    glGenRenderbuffers(1, &r->ts_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, r->ts_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, r->irr_edge, r->irr_edge);
    rc = dmr_gbuffer_targets(r, "ts_gbuffer", r->irr_edge, r->irr_edge, r->ts_depth, r->ts_gbuf_tex, &r->ts_gbuf_fbo,
                             err);
    if (rc != DM_OK) return rc;
    glBindFramebuffer(GL_FRAMEBUFFER, r->irr_fbo[0]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->ts_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return dm_fail(err, DM_ERR_GL, "target irradiance with depth: framebuffer incomplete");
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    return DM_OK;
}

void dmr_prepare_blur(dm_renderer *r, float scale)
{
    float off_sigma[DM_BLUR_TAPS_MAX];
    double var = dm_render_blur_kernel(r->taps, off_sigma, r->blur_weight);
    r->blur_scale = scale;
    for (int k = 1; k < r->profile.count; ++k) {
        double dv = (r->profile.variance_mm2[k] - r->profile.variance_mm2[k - 1]) * (double)scale;
        /* scale so that the discrete kernel's variance is exactly dv */
        double s = sqrt(dv / var);
        for (int i = 0; i < r->taps; ++i) r->blur_offset[k][i] = (float)(off_sigma[i] * s);
    }
    dmr_profile_weights(r);
}

void dmr_profile_weights(dm_renderer *r)
{
    for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (int k = 0; k < r->profile.count; ++k) sum += r->profile.weight[k][c];
        for (int k = 0; k < r->profile.count; ++k)
            r->level_weight[k][c] = sum > 0 ? (float)(r->profile.weight[k][c] / sum) : 0.0f;
    }
}

/* The mesh unwrapped into the atlas (irradiance.glsl with DM_GBUFFER): what each texel's
 * lighting needs that no light, camera or frame setting changes. Depth test ALWAYS with writes,
 * so that where triangles overlap in UV the last one drawn holds the texel, as the colour
 * does. Made once; dm_renderer_set_scene (material values) makes it stale. */
void dmr_pass_ts_gbuffer(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    if (r->ts_gbuf_valid) return;
    GLuint p = r->prog[DM_PASS_TS_GBUFFER];
    dmr_target_begin(r->ts_gbuf_fbo, r->irr_edge, r->irr_edge);
    glDrawBuffers(4, dmr_draw_buffers);
    glClearColor(0, 0, 0, 0);
    glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDisable(GL_CULL_FACE);
    glUseProgram(p);
    dmr_set_surface_uniforms(r, p);
    dmr_bind_surface(r);
    dmr_draw_mesh(r);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
    r->ts_gbuf_valid = true;
}

/* Each covered texel lit from the G-buffer (irradiance.glsl with DM_DEFERRED): the full-screen
 * triangle at the far plane, depth test GREATER against the coverage depth. */
void dmr_pass_irradiance(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    GLuint p = r->prog[DM_PASS_IRRADIANCE];
    dmr_target_begin(r->irr_fbo[0], r->irr_edge, r->irr_edge);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_FALSE);
    glDisable(GL_CULL_FACE);
    glUseProgram(p);
    dmr_set_light_uniforms(r, p);
    dmr_set_surface_uniforms(r, p);
    dmr_bind_surface(r);
    dmr_bind_gbuffer(p, r->ts_gbuf_tex);
    dmr_translucency_bind(r, p);
    dmr_draw_fullscreen(r);
    dmr_translucency_unbind(r);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
}

void dmr_pass_blur(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)opt;
    if (r->blur_cpu) {
        dmr_blur_cpu_pass(r, ps);
        return;
    }
    int k = ps->index;
    bool along_v = ps->kind == DM_PASS_BLUR_V;
    GLuint p = r->prog[DM_PASS_BLUR_U];
    /* the U pass writes at level k's width and level k−1's height (the taps read by UV) */
    int n = r->level_edge[k], h = r->level_edge[k - 1];
    if (along_v) dmr_target_begin(r->irr_fbo[k], n, n);
    else dmr_target_begin(r->tmp_fbo[k], n, h);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(p);
    int s = k - 1 < r->stretch_count - 1 ? k - 1 : r->stretch_count - 1;
    dmr_bind(UNIT_SRC, GL_TEXTURE_2D, along_v ? r->tmp_tex[k] : r->irr_tex[k - 1]);
    dmr_bind(UNIT_STRETCH, GL_TEXTURE_2D, r->tex_stretch[s]);
    u2f(p, "u_dir", along_v ? 0.0f : 1.0f, along_v ? 1.0f : 0.0f);
    glUniform1fv(loc(p, "u_offset_mm"), r->taps, r->blur_offset[k]);
    glUniform1fv(loc(p, "u_weight"), r->taps, r->blur_weight);
    dmr_draw_fullscreen(r);
}

/* The levels' weighted sum at each texel of the irradiance grid (diffusion.glsl), times
 * coverage: from the blur on the CPU, which summed the levels as it made them, or in GL. */
void dmr_pass_diffusion(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    if (r->blur_cpu && dmr_blur_cpu_diffusion(r)) return;
    dmr_blur_cpu_sync(r); /* the levels in GL (after a chain that waited to upload them) */
    GLuint p = r->prog[DM_PASS_DIFFUSION];
    dmr_target_begin(r->diff_fbo, r->irr_edge, r->irr_edge);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(p);
    dmr_bind_levels(r, p);
    u2f(p, "u_size", (float)r->irr_edge, (float)r->irr_edge);
    dmr_draw_fullscreen(r);
}

/* The levels and their weights for dm_level_sum, and the diffusion pass's sum for
 * dm_diffusion (common.glsl): in the final pass, the diffusion pass and view alike; absent
 * levels read black. */
void dmr_bind_levels(const dm_renderer *r, GLuint p)
{
    int levels = r->plan.texture_space ? r->profile.count : 0;
    if (levels) glUniform3fv(loc(p, "u_level_weight"), levels, &r->level_weight[0][0]);
    for (int k = 0; k < DM_PROFILE_MAX_GAUSSIANS; ++k) dmr_bind(UNIT_LEVEL0 + k, GL_TEXTURE_2D, k < levels ? r->irr_tex[k] : r->tex_black);
    dmr_bind(UNIT_DIFFUSION, GL_TEXTURE_2D, r->diff_tex && levels ? r->diff_tex : r->tex_black);
}
