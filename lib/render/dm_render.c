/* dm_render.c — the renderer's life cycle and its frame loop: create (sizes, plan, asset
 * checks, uploads, targets, setup, one program per shader file), destroy, set_scene, and
 * dm_render_frame, which runs the plan's passes through the pass table (dm_render_passes.c),
 * timing each. Create and destroy walk the table's hooks; the passes live in passes/, one file
 * per technique or effect (dm_render_internal.h). */
#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/dm_render_internal.h"
#include "render/gpu/dm_gpu_target.h"
#include "render/input/dm_render_estimate.h"

/* The sizes and options create takes from the assets and desc, checked. */
static dm_result resolve(dmr_frame *f, const dm_render_assets *a, const dm_render_desc *desc, dm_error *err)
{
    f->scene = *a->scene;
    f->profile = a->profile ? *a->profile : a->scene->profile;
    f->level_scale[0] = f->level_scale[1] = f->level_scale[2] = 1.0;
    f->desc = *desc;
    if (desc->shader_dir) snprintf(f->shader_dir, sizeof f->shader_dir, "%s", desc->shader_dir);
    f->desc.shader_dir = NULL;
    dmr_sizes sz;
    dmr_resolve_sizes(a, desc, &sz);
    f->width = sz.width, f->height = sz.height, f->irr_edge = sz.irr_edge, f->shadow_edge = sz.shadow_edge;
    memcpy(f->level_edge, sz.level_edge, sizeof f->level_edge);
    f->taps = a->scene->blur_taps;
    f->scene.profile = f->profile;
    f->shadow_taps = desc->shadow_pcf_taps > 0 ? desc->shadow_pcf_taps : 4;
    f->level_format = desc->blur_half_float ? GL_RGBA16F : GL_RGBA32F;
    int shift = desc->blur_reduce_shift > 0 ? desc->blur_reduce_shift : 1;
    bool tsd = a->scene->effects[DM_EFFECT_SUBSURFACE] && a->scene->sss_technique == DM_SSS_TEXTURE_SPACE;
    if (f->width < 1 || f->height < 1 || f->width > 16384 || f->height > 16384)
        return dm_fail(err, DM_ERR_RANGE, "renderer: output size %dx%d, expected 1..16384 per side", f->width,
                       f->height);
    if (tsd && (f->irr_edge < 8 || f->irr_edge > 8192))
        return dm_fail(err, DM_ERR_RANGE, "renderer: irradiance size %d, expected 8..8192", f->irr_edge);
    if (f->shadow_edge < 16 || f->shadow_edge > 8192)
        return dm_fail(err, DM_ERR_RANGE, "renderer: shadow size %d, expected 16..8192", f->shadow_edge);
    if (f->shadow_taps != 1 && f->shadow_taps != 4 && f->shadow_taps != 9)
        return dm_fail(err, DM_ERR_RANGE, "renderer: shadow_pcf_taps %d, expected 0 (4), 1, 4 or 9", f->shadow_taps);
    if (desc->blur_reduce_from < 0 || desc->blur_reduce_from >= DM_PROFILE_MAX_GAUSSIANS)
        return dm_fail(err, DM_ERR_RANGE, "renderer: blur_reduce_from %d, expected 0 (off) or a level 1..%d",
                       desc->blur_reduce_from, DM_PROFILE_MAX_GAUSSIANS - 1);
    if (desc->blur_reduce_shift < 0 || desc->blur_reduce_shift > 3)
        return dm_fail(err, DM_ERR_RANGE, "renderer: blur_reduce_shift %d, expected 0 (1), 1, 2 or 3",
                       desc->blur_reduce_shift);
    if (desc->blur_reduce_from > 0 && tsd && (f->irr_edge >> shift) < 8)
        return dm_fail(err, DM_ERR_RANGE, "renderer: irradiance size %d >> blur_reduce_shift %d is below 8 texels",
                       f->irr_edge, shift);
    return DM_OK;
}

/* What the renderer chose at create, applied to a plan of the scene (at create and each
 * frame's): the levels summed per pixel where not per texel; no translucency on top of the
 * thin-part map. */
static void plan_choices(const dmr_frame *f, dm_render_plan *p)
{
    if (!f->diffusion_sum) dm_render_plan_sum_per_pixel(p);
    if (f->thin_map) dm_render_plan_thin_map(p);
}

/* Before any GL object: the plan, the assets it needs (every row's check), the limits. */
static dm_result plan_and_check(dm_renderer *r, const dm_render_assets *a, dm_error *err)
{
    dmr_frame *f = &r->f;
    dm_result rc = dm_render_plan_build(&f->scene, DM_VIEW_FINAL, 0, &f->plan, err);
    /* the levels' sum per texel: exact at the texel centres only where every level has them
     * (reduced levels would be interpolated twice: to the centres, then to the pixel) */
    f->diffusion_sum = dmr_diffusion_summed(&f->plan, &f->desc);
    f->thin_map = rc == DM_OK && dmr_tsd_thin_usable(f, a);
    if (rc == DM_OK) plan_choices(f, &f->plan);
    if (rc == DM_OK) rc = dmr_frame_check(f, a, err);
    int n;
    const dmr_pass_row *rows = dmr_pass_rows(&n);
    for (int i = 0; i < n && rc == DM_OK; ++i)
        if (rows[i].check) rc = rows[i].check(f, a, err);
    for (int i = 0; rc == DM_OK && i < f->plan.pass_count; ++i)
        r->ts_pass_count += dmr_pass_first(f->plan.passes[i].kind)->texture_space;
    if (rc == DM_OK && f->plan.texture_space) dmr_auto_level_edges(a, &f->desc, &f->profile, f->irr_edge, f->level_edge);
    if (rc != DM_OK) return rc;
    const char *name = (const char *)glGetString(GL_RENDERER);
    snprintf(r->gl_name, sizeof r->gl_name, "%s", name ? name : "unknown");
    f->software_gl = strstr(r->gl_name, "llvmpipe") || strstr(r->gl_name, "softpipe") ||
                     strstr(r->gl_name, "Software") || strstr(r->gl_name, "swrast");
    glGetError(); /* a context may start with a stale error */
    return dmr_check_limits(r, a, err); /* before the first texture: sizes this GL makes, memory */
}

/* The table's create hooks in turn: every upload, every target (the screen's before the first
 * row past texture space), every setup. */
static dm_result walk_create(dm_renderer *r, const dm_render_assets *a, dm_error *err)
{
    dmr_frame *f = &r->f;
    int n;
    const dmr_pass_row *rows = dmr_pass_rows(&n);
    dm_result rc = dmr_frame_upload(f, a, err);
    for (int i = 0; i < n && rc == DM_OK; ++i)
        if (rows[i].upload) rc = rows[i].upload(f, dmr_pass_state(r, &rows[i]), a, err);
    if (rc == DM_OK) rc = dmg_check("upload", err);
    bool screen = false;
    for (int i = 0; i < n && rc == DM_OK; ++i) {
        if (!rows[i].targets) continue;
        if (!rows[i].texture_space && !screen) rc = dmr_frame_targets(f, err), screen = true;
        if (rc == DM_OK) rc = rows[i].targets(f, dmr_pass_state(r, &rows[i]), err);
    }
    if (rc == DM_OK && !screen) rc = dmr_frame_targets(f, err);
    dmr_level_weights(&f->profile, f->level_scale, f->level_weight);
    for (int i = 0; i < n && rc == DM_OK; ++i)
        if (rows[i].setup) rc = rows[i].setup(f, dmr_pass_state(r, &rows[i]), a, err);
    return rc;
}

/* One program per shader file and extra defines among the kinds the plan needs. */
static dm_result make_programs(dm_renderer *r, dm_error *err)
{
    dmr_frame *f = &r->f;
    dm_result rc = DM_OK;
    for (int k = 0; k < DM_PASS_KIND_COUNT && rc == DM_OK; ++k) {
        if (!dmr_pass_needed(r, (dm_pass_kind)k)) continue;
        const dmr_pass_row *pk = dmr_pass_first((dm_pass_kind)k);
        for (int j = 0; j < k && !f->prog[k]; ++j) {
            const dmr_pass_row *pj = dmr_pass_first((dm_pass_kind)j);
            if (f->prog[j] && strcmp(pj->shader, pk->shader) == 0 &&
                strcmp(pj->defines ? pj->defines : "", pk->defines ? pk->defines : "") == 0)
                f->prog[k] = f->prog[j];
        }
        if (!f->prog[k]) rc = dmr_frame_program(f, pk->shader, pk->defines, &f->prog[k], err);
    }
    return rc;
}

dm_result dm_renderer_create(const dm_render_assets *a, const dm_render_desc *desc, dm_renderer **out,
                             dm_error *err)
{
    assert(a && a->scene && desc && out);
    *out = NULL;
    dm_renderer *r = calloc(1, sizeof *r);
    if (!r) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "renderer: cannot allocate");
    dm_result rc = resolve(&r->f, a, desc, err);
    if (rc == DM_OK) rc = plan_and_check(r, a, err);
    if (rc != DM_OK) {
        free(r);
        return rc;
    }
    rc = walk_create(r, a, err);
    if (rc == DM_OK) rc = make_programs(r, err);
    if (rc == DM_OK) {
        for (int i = 0; i < DM_PLAN_MAX_PASSES && !r->f.software_gl; ++i) r->queries[i] = dmg_make(&r->f.gpu, DMG_QUERY);
        if (r->f.plan.texture_space) dmr_frame_blur(&r->f, 1.0f);
        rc = dmg_check("renderer setup", err);
    }
    if (rc == DM_OK) *out = r;
    else dm_renderer_destroy(r);
    return rc;
}

void dm_renderer_destroy(dm_renderer *r)
{
    if (!r) return;
    int n;
    const dmr_pass_row *rows = dmr_pass_rows(&n);
    for (int i = 0; i < n; ++i)
        if (rows[i].free) rows[i].free(&r->f, dmr_pass_state(r, &rows[i]));
    dmg_free_all(&r->f.gpu);
    free(r);
}

dm_result dm_render_frame(dm_renderer *r, const dm_frame_options *opt, dm_error *err)
{
    assert(r && opt);
    dmr_frame *f = &r->f;
    dm_render_plan plan;
    dm_result rc = dm_render_plan_build(&f->scene, opt->view, opt->view_index, &plan, err);
    if (rc != DM_OK) return rc;
    plan_choices(f, &plan);
    f->plan = plan;
    float blur_scale = opt->blur_scale > 0 ? opt->blur_scale : 1.0f;
    if (plan.texture_space && blur_scale != f->kernel.scale) dmr_frame_blur(f, blur_scale);
    f->roughness_scale = opt->roughness_scale > 0 ? opt->roughness_scale : 1.0f;
    dmr_frame_lights(f, opt->light_rotation_deg);
    dmr_frame_camera(f);
    glGetError();
    double t_frame;
    dmr_timing_frame_begin(r, &t_frame);
    r->tonemapped = false;
    r->glow_pending = false;
    f->view_in_target = false;
    /* reuse_texture_space: the shadow maps, irradiance and blur levels depend on the scene
     * (dm_renderer_set_scene invalidates them), the light rotation and the blur and
     * roughness scales; the camera and the view do not enter texture space. */
    bool reuse = f->desc.reuse_texture_space && r->ts_valid && r->ts_rotation == opt->light_rotation_deg &&
                 r->ts_blur_scale == blur_scale && r->ts_roughness_scale == f->roughness_scale;
    int ts_passes = 0;
    bool skipped[DM_PLAN_MAX_PASSES] = {false};
    for (int i = 0; i < plan.pass_count; ++i) {
        const dm_pass *ps = &plan.passes[i];
        bool texture_space = dmr_pass_first(ps->kind)->texture_space;
        ts_passes += texture_space;
        if (texture_space && reuse) {
            r->pass_ms[i] = 0.0;
            skipped[i] = true;
            continue;
        }
        double t0;
        dmr_timing_pass_begin(r, i, &t0);
        dmr_run_pass(r, ps, opt);
        dmr_timing_pass_end(r, i, t0);
        if (ps->kind == DM_PASS_TONEMAP) r->tonemapped = true;
        rc = dmg_check(ps->name, err);
        if (rc != DM_OK) return rc;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    r->has_frame = true;
    r->glow_pending = f->plan.glow_in_tonemap && r->tonemapped;
    if (!reuse) { /* valid only when this frame made every texture-space result */
        r->ts_valid = ts_passes == r->ts_pass_count;
        r->ts_rotation = opt->light_rotation_deg;
        r->ts_blur_scale = blur_scale;
        r->ts_roughness_scale = f->roughness_scale;
    }
    dmr_timing_frame_end(r, t_frame, skipped);
    return dmg_check("frame end", err);
}

dm_result dm_renderer_set_scene(dm_renderer *r, const dm_scene *s, dm_error *err)
{
    assert(r && s);
    const dm_scene *o = &r->f.scene;
    const char *what = NULL;
    for (int e = 0; e < DM_EFFECT_COUNT && !what; ++e)
        if (s->effects[e] != o->effects[e]) what = dm_effect_name((dm_effect)e);
    if (!what && s->light_count != o->light_count) what = "light count";
    for (int i = 0; i < s->light_count && !what; ++i)
        if (s->lights[i].type != o->lights[i].type || s->lights[i].casts_shadow != o->lights[i].casts_shadow)
            what = "a light's type or shadow casting";
    if (!what && s->env_background != o->env_background) what = "environment background";
    if (!what && s->blur_taps != o->blur_taps) what = "blur taps";
    if (!what && s->sss_technique != o->sss_technique) what = "subsurface technique";
    if (!what && s->screen_taps != o->screen_taps) what = "screen-space taps";
    if (what)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                       "renderer: the new scene changes %s, which the pass list depends on; recreate the renderer",
                       what);
    r->f.scene = *s;
    r->ts_valid = false; /* lights, material, environment: texture space is stale */
    r->tsd.gbuf_valid = false;
    r->f.scene.profile = r->f.profile;
    return DM_OK;
}

dm_result dm_renderer_set_profile_weights(dm_renderer *r, const dm_profile *p, const double scale_rgb[3], dm_error *err)
{
    dmr_frame *f = &r->f;
    dm_result rc = dm_profile_validate(p, "renderer: profile weights", err);
    if (rc != DM_OK) return rc;
    if (p->count != f->profile.count)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                       "renderer: the new profile has %d Gaussians, the renderer's %d: recreate the renderer", p->count,
                       f->profile.count);
    for (int k = 0; k < p->count; ++k)
        if (p->variance_mm2[k] != f->profile.variance_mm2[k])
            return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                           "renderer: the new profile's variance_mm2[%d] = %.17g, the renderer's %.17g (the blur chain "
                           "depends on it): recreate the renderer",
                           k, p->variance_mm2[k], f->profile.variance_mm2[k]);
    for (int c = 0; scale_rgb && c < 3; ++c)
        if (!(scale_rgb[c] >= 0.0 && scale_rgb[c] <= DM_PROFILE_SCALE_MAX))
            return dm_fail(err, DM_ERR_RANGE, "renderer: scale_rgb[%d] = %g, expected a value in [0, %g]", c,
                           scale_rgb[c], DM_PROFILE_SCALE_MAX);
    if (f->scene.effects[DM_EFFECT_SUBSURFACE] && f->scene.sss_technique != DM_SSS_TEXTURE_SPACE)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                       "renderer: the %s technique made its %s from the profile at create: recreate the renderer",
                       f->scene.sss_technique == DM_SSS_SCREEN_SPACE ? "screen-space" : "pre-integrated",
                       f->scene.sss_technique == DM_SSS_SCREEN_SPACE ? "kernel" : "table");
    memcpy(f->profile.weight, p->weight, sizeof f->profile.weight);
    f->scene.profile = f->profile;
    for (int c = 0; c < 3; ++c) f->level_scale[c] = scale_rgb ? scale_rgb[c] : 1.0;
    dmr_level_weights(&f->profile, f->level_scale, f->level_weight);
    r->ts_valid = false; /* the diffusion pass sums the levels with these weights */
    return DM_OK;
}
