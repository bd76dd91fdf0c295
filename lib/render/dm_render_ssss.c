/* dm_render_ssss.c — screen-space separable subsurface scattering (Jimenez et al. 2015).
 *
 *   ss_shade   each head pixel of the G-buffer (dm_render_shade.c's gbuffer pass) shaded by
 *              final.glsl with DM_SCREEN_SPACE and DM_DEFERRED into three targets at once:
 *              ss_diffuse = diffuse irradiance x albedo^mix (same lights, shadows, energy
 *              conservation, SH and translucency as the texture-space irradiance pass), alpha =
 *              eye depth in mesh units (0: no skin); ss_aux = albedo^(1-mix) x (1 - rho_s
 *              rho_dt(N.V)); ss_spec = KS + environment specular. The G-buffer pass left the
 *              head's depth in the screen's depth buffer, which every pass after tests.
 *   ss_blur_h  ss_diffuse blurred along x into ss_tmp;
 *   ss_blur_v  ss_tmp blurred along y, times ss_aux, plus ss_spec, into "screen".
 * The 1-D kernel (core/dm_ssss_kernel.h) comes from the pack (dermis-pack fits it to the
 * profile) or is fitted here from the same profile. Its offsets are millimetres on the
 * surface, turned into pixels per pixel from mm_per_unit and that pixel's eye depth z:
 * px = offset_mm / mm_per_unit · (height/2) / (z · tan(fov/2)). Follow-surface: a tap whose
 * depth differs from the centre's by more than its own lateral distance (a surface steeper
 * than 45° to the view, or another surface across a silhouette) fades to the centre's value,
 * fully at twice that distance, so light does not bleed across silhouettes and energy stays.
 * Both blur passes draw a full-screen triangle at the far plane with depth test GREATER
 * against the head's depth: only skin pixels run the kernel (the others keep their clear). */
#include <math.h>
#include <string.h>

#include "core/dm_math.h"
#include "render/dm_render_internal.h"

dm_result dmr_ssss_setup(dm_renderer *r, const dm_render_assets *a, dm_error *err)
{
    dm_ssss_kernel k;
    dm_result rc;
    if (a->ss_kernel)
        rc = dm_ssss_kernel_from_texels(a->ss_kernel, a->ss_kernel_taps, &k, err);
    else
        rc = dm_ssss_kernel_fit(&r->profile, r->scene.screen_taps, &k, err);
    if (rc != DM_OK) return rc;
    r->ss_taps = k.taps;
    for (int i = 0; i < k.taps; ++i) {
        for (int c = 0; c < 3; ++c) r->ss_kernel[i][c] = k.weight[i][c];
        r->ss_kernel[i][3] = k.offset_mm[i];
    }
    return DM_OK;
}

/* The targets; the G-buffer and the shade pass's post-scatter and specular targets are cleared
 * here once: frames write and read only the head's pixels of them, the rest stays defined. */
dm_result dmr_ssss_targets(dm_renderer *r, dm_error *err)
{
    GLuint fbo_aux = 0, fbo_spec = 0;
    dm_result rc = dmr_color_target(r, "ss_diffuse", r->width, r->height, GL_RGBA32F, GL_CLAMP_TO_EDGE,
                                    &r->ss_diff_tex, &r->ss_fbo, err);
    if (rc == DM_OK)
        rc = dmr_color_target(r, "ss_aux", r->width, r->height, GL_RGBA16F, GL_CLAMP_TO_EDGE, &r->ss_aux_tex, &fbo_aux,
                              err);
    if (rc == DM_OK)
        rc = dmr_color_target(r, "ss_specular", r->width, r->height, GL_RGBA32F, GL_CLAMP_TO_EDGE, &r->ss_spec_tex,
                              &fbo_spec, err);
    if (rc == DM_OK)
        rc = dmr_color_target(r, "ss_tmp", r->width, r->height, GL_RGBA32F, GL_CLAMP_TO_EDGE, &r->ss_tmp_tex,
                              &r->ss_tmp_fbo, err);
    if (rc != DM_OK) return rc;
    /* the single-target FBOs stay for read-back (dm_renderer_read_target); the shade pass
     * writes all three through ss_fbo, which shares the screen's depth buffer */
    glBindFramebuffer(GL_FRAMEBUFFER, r->ss_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, r->ss_aux_tex, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT2, GL_TEXTURE_2D, r->ss_spec_tex, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->screen_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return dm_fail(err, DM_ERR_GL, "target ss_diffuse+aux+specular: framebuffer incomplete");
    glDrawBuffers(3, dmr_draw_buffers);
    glClear(GL_COLOR_BUFFER_BIT);
    glBindFramebuffer(GL_FRAMEBUFFER, r->ss_tmp_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->screen_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return dm_fail(err, DM_ERR_GL, "target ss_tmp with depth: framebuffer incomplete");
    return dmr_gl_check("screen-space targets", err);
}

/* Each head pixel shaded from the G-buffer (final.glsl with DM_DEFERRED): the full-screen
 * triangle at the far plane, depth test GREATER against the head's depth. */
void dmr_pass_ss_shade(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    GLuint p = r->prog[DM_PASS_SS_SHADE];
    dmr_target_begin(r->ss_fbo, r->width, r->height);
    glDrawBuffers(3, dmr_draw_buffers);
    /* ss_diffuse only (alpha 0: no skin, which the blurs' taps read); the post-scatter and
     * specular targets are read on the head's pixels alone, all written here */
    static const float zero[4] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, zero);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_FALSE);
    dmr_shade_begin(r, p, 0);
    dmr_bind_gbuffer(p, r->gbuf_tex);
    dmr_draw_fullscreen(r);
    dmr_translucency_unbind(r);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
}

void dmr_pass_ss_blur(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    bool along_y = ps->kind == DM_PASS_SS_BLUR_V;
    GLuint p = r->prog[ps->kind];
    dmr_target_begin(along_y ? r->screen_fbo : r->ss_tmp_fbo, r->width, r->height);
    if (along_y) {
        dmr_screen_clear(r, 0);
    } else { /* alpha 0 off the skin: the V pass's taps read it */
        glClearColor(0, 0, 0, 0);
        glClear(GL_COLOR_BUFFER_BIT);
    }
    glEnable(GL_DEPTH_TEST); /* skin pixels only: the triangle sits at the far plane */
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_FALSE);
    glUseProgram(p);
    dmr_bind(UNIT_SRC, GL_TEXTURE_2D, along_y ? r->ss_tmp_tex : r->ss_diff_tex);
    dmr_bind(UNIT_SS_AUX, GL_TEXTURE_2D, r->ss_aux_tex);
    dmr_bind(UNIT_SS_SPEC, GL_TEXTURE_2D, r->ss_spec_tex);
    u2f(p, "u_dir", along_y ? 0.0f : 1.0f, along_y ? 1.0f : 0.0f);
    u2f(p, "u_texel", 1.0f / (float)r->width, 1.0f / (float)r->height);
    glUniform4fv(loc(p, "u_kernel"), r->ss_taps, &r->ss_kernel[0][0]);
    /* pixels per mm at eye depth 1 mesh unit; the shader divides by the pixel's depth */
    float blur_scale = opt->blur_scale > 0 ? opt->blur_scale : 1.0f;
    float t = tanf((float)(0.5 * r->scene.fov_y_deg * DM_PI / 180.0));
    u1f(p, "u_px_per_mm", sqrtf(blur_scale) * 0.5f * (float)r->height / (t * (float)r->scene.mm_per_unit));
    u1f(p, "u_ss_mm_per_unit", (float)r->scene.mm_per_unit);
    static const int modes[DM_VIEW_COUNT] = {[DM_VIEW_SPECULAR] = 1, [DM_VIEW_DIFFUSE] = 2};
    u1i(p, "u_mode", modes[r->plan.view]);
    dmr_draw_fullscreen(r);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
}
