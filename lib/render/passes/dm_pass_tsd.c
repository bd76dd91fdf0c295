/* dm_pass_tsd.c — texture-space diffusion (d'Eon & Luebke, GPU Gems 3 ch. 14) on the GPU: the
 * ts_gbuffer pass unwraps the surface into the UV atlas once per scene, the irradiance pass
 * lights each covered texel of it every frame, then each Gaussian level k is made from level
 * k−1 by a U and a V blur of variance v_k − v_{k−1}, tap offsets in mm (the frame's kernel)
 * turned into UV by the stretch chain. The diffusion pass (dm_pass_diffusion.c) sums the
 * levels; the blurs may run on the CPU instead (dm_pass_blur_cpu.c). Owns the stretch
 * uploads and the level targets, and with a seam map each texel's 3-D point and the atlas's
 * cuts, by which the blurs leave out taps that jump to another place of the surface. */
#include <stdio.h>
#include <stdlib.h>

#include "core/dm_level_blur.h"
#include "core/dm_level_sum.h"

#include "render/frame/dm_frame_bind.h"
#include "render/gpu/dm_gpu_target.h"
#include "render/input/dm_render_estimate.h"
#include "render/passes/dm_pass_tsd.h"

dm_result dmr_tsd_check(const dmr_frame *f, const dm_render_assets *a, dm_error *err)
{
    if (!f->plan.texture_space) return DM_OK;
    dm_result rc = dm_profile_validate(&f->profile, "assets: profile", err);
    if (rc == DM_OK && (a->stretch_level_count < 1 || a->stretch_level_count > DM_PROFILE_MAX_GAUSSIANS))
        return dm_fail(err, DM_ERR_MISMATCH, "assets: %d stretch levels, subsurface needs 1..%d",
                       a->stretch_level_count, DM_PROFILE_MAX_GAUSSIANS);
    for (int k = 0; k < a->stretch_level_count && rc == DM_OK; ++k) {
        rc = dmr_need_texture(&a->stretch[k], "a stretch level", "subsurface", err);
        if (rc == DM_OK && a->stretch[k].format != DM_TEX_RG32F && a->stretch[k].format != DM_TEX_RG16F)
            rc = dm_fail(err, DM_ERR_UNSUPPORTED, "assets: stretch level %d is %s, expected rg32f or rg16f", k,
                         dmr_format_name(a->stretch[k].format));
    }
    const dm_texture *maps[3] = {&a->seam, &a->thin, &a->thin_half};
    static const char *const names[3] = {"seam", "thin-part", "half-size thin-part"};
    for (int k = 0; k < 3 && rc == DM_OK; ++k)
        if (maps[k]->texels && maps[k]->format != DM_TEX_RGBA32F)
            rc = dm_fail(err, DM_ERR_UNSUPPORTED, "assets: the %s map is %s, expected rgba32f", names[k],
                         dmr_format_name(maps[k]->format));
    int taps = a->scene->blur_taps;
    if (rc == DM_OK && (taps < 3 || taps > DM_BLUR_TAPS_MAX || taps % 2 == 0))
        rc = dm_fail(err, DM_ERR_RANGE, "scene: blur_taps = %d, expected an odd integer in [3, %d]", taps,
                     DM_BLUR_TAPS_MAX);
    return rc;
}

bool dmr_tsd_thin_usable(const dmr_frame *f, const dm_render_assets *a)
{
    return f->plan.texture_space && f->diffusion_sum && dm_render_assets_thin_map(a, f->irr_edge);
}

dm_result dmr_tsd_upload(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err)
{
    (void)st;
    if (!f->plan.texture_space) return DM_OK;
    dm_result rc = DM_OK;
    f->stretch_count = a->stretch_level_count;
    for (int k = 0; k < a->stretch_level_count && rc == DM_OK; ++k)
        rc = dmr_upload(f, &a->stretch[k], "stretch", false, GL_LINEAR, &f->tex_stretch[k], err);
    if (rc == DM_OK && a->stretch_mask.texels)
        rc = dmr_upload(f, &a->stretch_mask, "stretch_mask", false, GL_LINEAR, &f->tex_mask, err);
    /* the thin gather, checked once for both sums (dm_pass_diffusion.c in GL, dm_pass_blur_cpu.c):
     * with the thin-part map, where the levels are summed per texel */
    const dm_texture *gt, *gi = dm_render_assets_gather(a, f->irr_edge, &gt);
    f->gather_ok = dmr_gather_wanted(a, f->irr_edge, f->diffusion_sum) &&
                   dm_level_sum_gather_check(gi->texels, f->irr_edge, gt->texels, (int64_t)gt->width * gt->height,
                                             f->plan.blur_levels, &f->gather_first, &f->gather_count);
    /* the seam map, read at texel centres (nearest): the irradiance pass lights the gutter
     * texels it continues (DM_SEAM; dm_renderer_seam_map). Only at the size it was baked for:
     * at another the gutters are other texels, and its continuations (a texel centre's, half a
     * texel off) measured worse than none (head, 1024² map at 512²: seam p95 26 -> 63 %). Also
     * beside the thin gather, which takes only the widest levels (docs/seam-map.md: the frame
     * truth's seam region 67 -> 31 % at 1024², along the bust's cut). */
    const dm_texture *seam = dm_render_assets_seam_map(a, f->irr_edge);
    if (rc == DM_OK && seam) rc = dmr_upload(f, seam, "seam", false, GL_NEAREST, &f->tex_seam, err);
    /* the thin-part map, read at texel centres (nearest) by the diffusion pass (DM_THIN;
     * dm_renderer_thin_map): only at the size it was baked for, and only where the levels are
     * summed per texel (a per-pixel sum has no texel to read its candidates at). On the CPU
     * blur path the sum is made in C from the same texels. */
    if (rc == DM_OK && dmr_tsd_thin_usable(f, a))
        rc = dmr_upload(f, dm_render_assets_thin_map(a, f->irr_edge), "thin", false, GL_NEAREST, &f->tex_thin, err);
    return rc;
}

dm_result dmr_tsd_targets(dmr_frame *f, void *st, dm_error *err)
{
    dmr_tsd *t = st;
    const dm_render_plan *p = &f->plan;
    if (!p->texture_space) return DM_OK;
    dm_result rc = DM_OK;
    char name[32];
    for (int k = 0; k < p->blur_levels && rc == DM_OK; ++k) {
        snprintf(name, sizeof name, k == 0 ? "irradiance" : "blur%d", k);
        rc = dmg_color_target(&f->gpu, name, f->level_edge[k], f->level_edge[k], f->level_format, GL_CLAMP_TO_BORDER,
                              &f->level_tex[k], &f->level_fbo[k], err);
    }
    /* the U pass of level k writes at level k's width and level k−1's height: its input still
     * holds detail along V that only the V pass may filter away. One target per size. */
    for (int k = 1; k < p->blur_levels && rc == DM_OK; ++k) {
        int w = f->level_edge[k], h = f->level_edge[k - 1], j = 1;
        while (j < k && !(f->level_edge[j] == w && f->level_edge[j - 1] == h)) ++j;
        if (j < k) {
            t->tmp_tex[k] = t->tmp_tex[j], t->tmp_fbo[k] = t->tmp_fbo[j];
            continue;
        }
        snprintf(name, sizeof name, "blur_tmp%d", k);
        rc = dmg_color_target(&f->gpu, name, w, h, f->level_format, GL_CLAMP_TO_BORDER, &t->tmp_tex[k], &t->tmp_fbo[k],
                              err);
    }
    /* the sum in float32 even over half-float levels: the sum per pixel was float too */
    if (rc == DM_OK && f->diffusion_sum)
        rc = dmg_color_target(&f->gpu, "diffusion", f->irr_edge, f->irr_edge, GL_RGBA32F, GL_CLAMP_TO_BORDER,
                              &f->diff_tex, &f->diff_fbo, err);
    if (rc != DM_OK) return rc;
    /* the G-buffer's depth marks covered texels (0.5; 1 in gutters); the irradiance target
     * shares it, and keeps its once-cleared gutters (frames write covered texels only) */
    t->depth = dmg_depth_buffer(&f->gpu, f->irr_edge, f->irr_edge);
    rc = dmg_gbuffer_targets(&f->gpu, "ts_gbuffer", f->irr_edge, f->irr_edge, t->depth, t->gbuf_tex, &t->gbuf_fbo, err);
    f->ts_cover_tex = t->gbuf_tex[0]; /* the views' chart coverage: the level alphas are 1 on the seam band too */
    if (rc == DM_OK && f->tex_seam)
        rc = dmg_color_target(&f->gpu, "seam_points", f->irr_edge, f->irr_edge, GL_RGBA32F, GL_CLAMP_TO_BORDER,
                              &f->tex_seam_points, &f->seam_points_fbo, err);
    if (rc == DM_OK && f->tex_seam) { /* the cuts, uploaded once the points are read back */
        f->tex_seam_cuts = dmg_texture_2d(&f->gpu, f->irr_edge, f->irr_edge, GL_RGBA16I, GL_RGBA_INTEGER, GL_SHORT, NULL,
                                          false, GL_NEAREST);
        rc = dmg_check("seam cuts", err);
    }
    if (rc == DM_OK) rc = dmg_attach_depth(f->level_fbo[0], t->depth, "irradiance", err);
    if (rc != DM_OK) return rc;
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    return DM_OK;
}

/* With a seam map: the programs that give the texels it continues the coverage depth, and every
 * texel its point. */
dm_result dmr_tsd_setup(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err)
{
    (void)a;
    dmr_tsd *t = st;
    if (!f->plan.texture_space || !f->tex_seam) return DM_OK;
    dm_result rc = dmr_frame_program(f, "seam_mark.glsl", NULL, &t->seam_mark, err);
    return rc == DM_OK ? dmr_frame_program(f, "seam_points.glsl", NULL, &t->seam_points, err) : rc;
}

/* The mesh unwrapped into the atlas (irradiance.glsl with DM_GBUFFER): what each texel's
 * lighting needs that no light, camera or frame setting changes. Depth test ALWAYS with writes
 * (the row's state), so that where triangles overlap in UV the last one drawn holds the texel,
 * as the colour does. Made once; dm_renderer_set_scene (material values) makes it stale. */
bool dmr_ts_gbuffer_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    (void)ps;
    const dmr_tsd *t = st;
    *out = (dmr_output){t->gbuf_fbo, f->irr_edge, f->irr_edge, 4};
    return !t->gbuf_valid;
}

/* The seam points read back, and the atlas's cuts between them (core/dm_level_blur.h) made and
 * uploaded. Out of memory: no check at all (the plain blur, as without the points). */
static void find_cuts(dmr_frame *f)
{
    int n = f->irr_edge;
    size_t floats = 4 * (size_t)n * (size_t)n;
    if (!f->seam_points) f->seam_points = malloc(sizeof(float) * floats);
    if (!f->seam_cuts) f->seam_cuts = malloc(sizeof(int16_t) * floats);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, f->seam_points_fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    if (f->seam_points) glReadPixels(0, 0, n, n, GL_RGBA, GL_FLOAT, f->seam_points);
    if (!f->seam_points || !f->seam_cuts || dm_level_blur_cuts(f->seam_points, n, f->seam_cuts) < 0) {
        free(f->seam_points), free(f->seam_cuts);
        f->seam_points = NULL, f->seam_cuts = NULL;
        return;
    }
    glBindTexture(GL_TEXTURE_2D, f->tex_seam_cuts);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, n, n, GL_RGBA_INTEGER, GL_SHORT, f->seam_cuts);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
}

void dmr_tsd_free(dmr_frame *f, void *st)
{
    (void)st;
    free(f->seam_points), free(f->seam_cuts);
    f->seam_points = NULL, f->seam_cuts = NULL;
}

void dmr_ts_gbuffer_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    dmr_tsd *t = st;
    dmr_draw_mesh(f);
    if (t->seam_mark) { /* the continued gutter texels take the coverage depth (seam_mark.glsl) */
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glUseProgram(t->seam_mark);
        dmg_bind(UNIT_SEAM, GL_TEXTURE_2D, f->tex_seam);
        dmr_draw_fullscreen(f);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    }
    if (t->seam_points) { /* each texel's point, as the irradiance pass will light it (seam_points.glsl) */
        glBindFramebuffer(GL_FRAMEBUFFER, f->seam_points_fbo);
        glUseProgram(t->seam_points);
        dmr_bind_gbuffer(t->seam_points, t->gbuf_tex);
        dmg_bind(UNIT_SEAM, GL_TEXTURE_2D, f->tex_seam);
        glUniform1f(dmg_loc(t->seam_points, "u_mm"), (float)f->scene.mm_per_unit);
        dmr_draw_fullscreen(f);
        find_cuts(f);
        glBindFramebuffer(GL_FRAMEBUFFER, t->gbuf_fbo);
    }
    t->gbuf_valid = true;
}

/* Each covered texel lit from the G-buffer (irradiance.glsl with DM_DEFERRED): the full-screen
 * triangle at the far plane, depth test GREATER against the coverage depth. */
bool dmr_irradiance_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    (void)st, (void)ps;
    *out = (dmr_output){f->level_fbo[0], f->irr_edge, f->irr_edge, 0};
    return true;
}

void dmr_irradiance_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    dmr_bind_gbuffer(f->prog[DM_PASS_IRRADIANCE], ((const dmr_tsd *)st)->gbuf_tex);
    if (f->tex_seam) dmg_bind(UNIT_SEAM, GL_TEXTURE_2D, f->tex_seam);
    dmr_draw_fullscreen(f);
}

/* The U pass writes at level k's width and level k−1's height (the taps read by UV). */
bool dmr_blur_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    const dmr_tsd *t = st;
    int k = ps->index, n = f->level_edge[k];
    if (ps->kind == DM_PASS_BLUR_V) *out = (dmr_output){f->level_fbo[k], n, n, 0};
    else *out = (dmr_output){t->tmp_fbo[k], n, f->level_edge[k - 1], 0};
    return !f->blur_cpu;
}

void dmr_blur_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)opt;
    const dmr_tsd *t = st;
    int k = ps->index;
    bool along_v = ps->kind == DM_PASS_BLUR_V;
    GLuint p = f->prog[ps->kind];
    int s = k - 1 < f->stretch_count - 1 ? k - 1 : f->stretch_count - 1;
    dmg_bind(UNIT_SRC, GL_TEXTURE_2D, along_v ? t->tmp_tex[k] : f->level_tex[k - 1]);
    dmg_bind(UNIT_STRETCH, GL_TEXTURE_2D, f->tex_stretch[s]);
    dmg_u2f(p, "u_dir", along_v ? 0.0f : 1.0f, along_v ? 1.0f : 0.0f);
    if (f->tex_seam_points) { /* the jump check on the irradiance's own grid (core/dm_level_blur.h) */
        dmg_bind(UNIT_POINTS, GL_TEXTURE_2D, f->tex_seam_points);
        dmg_bind(UNIT_CUTS, GL_TEXTURE_2D, f->tex_seam_cuts);
        glUniform1i(dmg_loc(p, "u_check"), dmr_frame_blur_checks(f, k) ? 1 : 0);
        dmg_u2f(p, "u_jump", DM_LEVEL_BLUR_JUMP_FACTOR, DM_LEVEL_BLUR_JUMP_MM);
    }
    glUniform1fv(dmg_loc(p, "u_offset_mm"), f->taps, f->kernel.offset_mm[k]);
    glUniform1fv(dmg_loc(p, "u_weight"), f->taps, f->kernel.weight);
    dmr_draw_fullscreen(f);
}
