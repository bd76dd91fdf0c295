/* dm_pass_ssss.c — screen-space separable subsurface scattering (Jimenez et al. 2015).
 *
 *   ss_shade   each head pixel of the G-buffer (dm_pass_shade.c's gbuffer pass) shaded by
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

#include "core/dm_math.h"
#include "render/frame/dm_frame_bind.h"
#include "render/gpu/dm_gpu_target.h"
#include "render/passes/dm_pass_ssss.h"

dm_result dmr_ssss_check(const dmr_frame *f, const dm_render_assets *a, dm_error *err)
{
    (void)a;
    return f->plan.screen_space ? dm_profile_validate(&f->profile, "assets: profile", err) : DM_OK;
}

dm_result dmr_ssss_setup(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err)
{
    if (!f->plan.screen_space) return DM_OK;
    dmr_ssss *s = st;
    dm_ssss_kernel k;
    dm_result rc;
    if (a->ss_kernel)
        rc = dm_ssss_kernel_from_texels(a->ss_kernel, a->ss_kernel_taps, a->ss_kernel_rows, a->ss_kernel_mm_per_px, &k,
                                        err);
    else
        rc = dm_ssss_kernel_fit(&f->profile, f->scene.screen_taps, &k, err);
    if (rc != DM_OK) return rc;
    f->ss_taps = k.taps;
    f->ss_rows = k.rows;
    dm_ssss_kernel_texels(&k, &s->kernel[0][0]);
    /* one row: any spacing (the coordinate is clamped to 0 and the offsets stretched) */
    s->rows_per_octave = k.rows > 1 ? (float)((k.rows - 1) / log2(k.mm_per_px[1] / k.mm_per_px[0])) : 1.0f;
    s->row0_log2_mm_per_px = (float)log2(k.mm_per_px[0]);
    return DM_OK;
}

/* The targets; the G-buffer and the shade pass's post-scatter and specular targets are cleared
 * here once: frames write and read only the head's pixels of them, the rest stays defined. */
dm_result dmr_ssss_targets(dmr_frame *f, void *st, dm_error *err)
{
    if (!f->plan.screen_space) return DM_OK;
    dmr_ssss *s = st;
    dmg *g = &f->gpu;
    GLuint fbo_aux = 0, fbo_spec = 0;
    dm_result rc =
        dmg_color_target(g, "ss_diffuse", f->width, f->height, GL_RGBA32F, GL_CLAMP_TO_EDGE, &s->diff_tex, &s->fbo, err);
    if (rc == DM_OK)
        rc = dmg_color_target(g, "ss_aux", f->width, f->height, GL_RGBA16F, GL_CLAMP_TO_EDGE, &s->aux_tex, &fbo_aux, err);
    if (rc == DM_OK)
        rc = dmg_color_target(g, "ss_specular", f->width, f->height, GL_RGBA32F, GL_CLAMP_TO_EDGE, &s->spec_tex,
                              &fbo_spec, err);
    if (rc == DM_OK)
        rc = dmg_color_target(g, "ss_tmp", f->width, f->height, GL_RGBA32F, GL_CLAMP_TO_EDGE, &s->tmp_tex, &s->tmp_fbo,
                              err);
    if (rc != DM_OK) return rc;
    /* the single-target FBOs stay for read-back (dm_renderer_read_target); the shade pass
     * writes all three through its fbo, which shares the screen's depth buffer */
    glBindFramebuffer(GL_FRAMEBUFFER, s->fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, s->aux_tex, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT2, GL_TEXTURE_2D, s->spec_tex, 0);
    rc = dmg_attach_depth(s->fbo, f->screen_depth, "ss_diffuse+aux+specular", err);
    if (rc != DM_OK) return rc;
    glDrawBuffers(3, dmg_draw_buffers);
    glClear(GL_COLOR_BUFFER_BIT);
    rc = dmg_attach_depth(s->tmp_fbo, f->screen_depth, "ss_tmp", err);
    return rc == DM_OK ? dmg_check("screen-space targets", err) : rc;
}

/* Each head pixel shaded from the G-buffer (final.glsl with DM_DEFERRED): the full-screen
 * triangle at the far plane, depth test GREATER against the head's depth. The row clears
 * ss_diffuse only (alpha 0: no skin, which the blurs' taps read); the post-scatter and
 * specular targets are read on the head's pixels alone, all written here. */
bool dmr_ss_shade_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    (void)ps;
    *out = (dmr_output){((const dmr_ssss *)st)->fbo, f->width, f->height, 3};
    return true;
}

void dmr_ss_shade_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)st, (void)ps, (void)opt;
    dmr_bind_gbuffer(f->prog[DM_PASS_SS_SHADE], f->gbuf_tex);
    dmr_draw_fullscreen(f);
}

/* x: ss_diffuse into ss_tmp (cleared: alpha 0 off the skin, which the V pass's taps read);
 * y: ss_tmp, times ss_aux, plus ss_spec, into the screen. */
bool dmr_ss_blur_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    bool along_y = ps->kind == DM_PASS_SS_BLUR_V;
    *out = (dmr_output){along_y ? f->screen_fbo : ((const dmr_ssss *)st)->tmp_fbo, f->width, f->height, 0};
    return true;
}

void dmr_ss_blur_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    const dmr_ssss *s = st;
    bool along_y = ps->kind == DM_PASS_SS_BLUR_V;
    GLuint p = f->prog[ps->kind];
    dmg_bind(UNIT_SRC, GL_TEXTURE_2D, along_y ? s->tmp_tex : s->diff_tex);
    dmg_bind(UNIT_SS_AUX, GL_TEXTURE_2D, s->aux_tex);
    dmg_bind(UNIT_SS_SPEC, GL_TEXTURE_2D, s->spec_tex);
    dmg_u2f(p, "u_dir", along_y ? 0.0f : 1.0f, along_y ? 1.0f : 0.0f);
    dmg_u2f(p, "u_texel", 1.0f / (float)f->width, 1.0f / (float)f->height);
    glUniform4fv(dmg_loc(p, "u_kernel"), f->ss_taps * f->ss_rows, &s->kernel[0][0]);
    /* pixels per mm at eye depth 1 mesh unit; the shader divides by the pixel's depth */
    float blur_scale = opt->blur_scale > 0 ? opt->blur_scale : 1.0f;
    float t = tanf((float)(0.5 * f->scene.fov_y_deg * DM_PI / 180.0));
    float px_per_mm = sqrtf(blur_scale) * 0.5f * (float)f->height / (t * (float)f->scene.mm_per_unit);
    dmg_u1f(p, "u_px_per_mm", px_per_mm);
    /* the row coordinate is linear in log2 of the pixel's mm per pixel, depth / px_per_mm:
     * u = log2(depth)·k + b */
    dmg_u2f(p, "u_row", s->rows_per_octave, -s->rows_per_octave * (log2f(px_per_mm) + s->row0_log2_mm_per_px));
    dmg_u1f(p, "u_ss_mm_per_unit", (float)f->scene.mm_per_unit);
    static const int modes[DM_VIEW_COUNT] = {[DM_VIEW_SPECULAR] = 1, [DM_VIEW_DIFFUSE] = 2};
    dmg_u1i(p, "u_mode", modes[f->plan.view]);
    dmr_draw_fullscreen(f);
}
