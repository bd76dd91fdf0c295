/* dm_render.c — the renderer's life cycle and its frame loop: create (plan, asset checks,
 * uploads, targets, one program per shader file), destroy, set_scene, and dm_render_frame,
 * which runs the plan's passes through the pass table (dm_render_passes.c), timing each.
 * The passes themselves live in one file per technique or effect (dm_render_internal.h). */
#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_math.h"
#include "render/dm_render_internal.h"

static dm_result dmr_need_texture(const dm_texture *t, const char *what, const char *effect, dm_error *err)
{
    if (!t->texels)
        return dm_fail(err, DM_ERR_MISMATCH, "assets: %s is missing, and the %s effect needs it", what, effect);
    return DM_OK;
}

static dm_result check_assets(const dm_render_assets *a, const dm_render_plan *p, const dm_profile *prof,
                              dm_error *err)
{
    if (!a->vertices || a->vertex_count < 3 || !a->indices || a->index_count < 3 || a->index_count % 3)
        return dm_fail(err, DM_ERR_EMPTY, "assets: mesh has %d vertices and %d indices, expected >= 3 and a multiple of 3",
                       a->vertex_count, a->index_count);
    for (int i = 0; i < a->index_count; ++i)
        if (a->indices[i] >= (uint32_t)a->vertex_count)
            return dm_fail(err, DM_ERR_RANGE, "assets: index %d is %u, expected < vertex_count %d", i,
                           (unsigned)a->indices[i], a->vertex_count);
    dm_result rc = DM_OK;
    if (p->effects[DM_EFFECT_SPECULAR]) rc = dmr_need_texture(&a->beckmann, "the Beckmann LUT", "specular", err);
    if (rc == DM_OK && p->energy_conservation_active)
        rc = dmr_need_texture(&a->rho_dt, "the rho_dt LUT", "energy_conservation", err);
    if (rc == DM_OK && p->effects[DM_EFFECT_ENVIRONMENT_LIGHTING] && !a->has_env_sh)
        rc = dm_fail(err, DM_ERR_MISMATCH, "assets: the environment SH is missing, and environment_lighting needs it");
    if (rc == DM_OK && p->env_specular_active) {
        if (a->env_level_count < 1 || a->env_level_count > DM_RENDER_ENV_LEVELS_MAX)
            return dm_fail(err, DM_ERR_MISMATCH,
                           "assets: %d prefiltered environment levels, environment_lighting with specular needs 1..%d",
                           a->env_level_count, DM_RENDER_ENV_LEVELS_MAX);
        for (int k = 0; k < a->env_level_count && rc == DM_OK; ++k) {
            rc = dmr_need_texture(&a->env_levels[k], "a prefiltered environment level", "environment_lighting", err);
            if (rc == DM_OK && k > 0 && !(a->env_level_m[k] > a->env_level_m[k - 1]))
                rc = dm_fail(err, DM_ERR_RANGE, "assets: env_level_m[%d] = %g, expected more than env_level_m[%d] = %g",
                             k, (double)a->env_level_m[k], k - 1, (double)a->env_level_m[k - 1]);
        }
        if (rc == DM_OK) rc = dmr_need_texture(&a->env_brdf, "the env-BRDF LUT", "environment_lighting", err);
    }
    if (rc == DM_OK && dm_render_plan_find(p, "background") >= 0)
        rc = dmr_need_texture(&a->env_background, "the environment background", "environment_lighting", err);
    if (rc == DM_OK && p->texture_space) rc = dmr_tsd_check(a, prof, err);
    if (rc == DM_OK && (p->screen_space || p->translucency_active)) rc = dm_profile_validate(prof, "assets: profile", err);
    if (rc == DM_OK && p->pre_integrated) rc = dmr_preint_check(a, err);
    return rc;
}

/* The normal map, and the specular map in its alpha when both are there at one size (the
 * normal map's alpha is unused): one trilinear fetch fewer wherever the surface is read, and
 * the same values (both linear 8-bit; mip levels are made per channel). */
static dm_result upload_normal_specular(dm_renderer *r, const dm_render_assets *a, dm_error *err)
{
    const dm_texture *nm = &a->normal_map, *sp = &a->specular_map;
    r->spec_in_normal = nm->texels && sp->texels && nm->format == DM_TEX_RGBA8 && sp->format == DM_TEX_R8 &&
                        nm->width == sp->width && nm->height == sp->height;
    if (!r->spec_in_normal) {
        dm_result rc = DM_OK;
        if (nm->texels) rc = dmr_upload(nm, "normal_map", true, GL_LINEAR, &r->tex_normal, err);
        if (rc == DM_OK && sp->texels) rc = dmr_upload(sp, "specular_map", true, GL_LINEAR, &r->tex_spec, err);
        return rc;
    }
    size_t n = (size_t)nm->width * (size_t)nm->height;
    uint8_t *both = malloc(n * 4);
    if (!both) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "normal map with specular: %zu bytes", n * 4);
    memcpy(both, nm->texels, n * 4);
    for (size_t i = 0; i < n; ++i) both[i * 4 + 3] = ((const uint8_t *)sp->texels)[i];
    dm_texture t = *nm;
    t.texels = both;
    dm_result rc = dmr_upload(&t, "normal map with specular", true, GL_LINEAR, &r->tex_normal, err);
    free(both);
    return rc;
}

static dm_result upload_assets(dm_renderer *r, const dm_render_assets *a, dm_error *err)
{
    glGenVertexArrays(1, &r->vao_mesh);
    glBindVertexArray(r->vao_mesh);
    glGenBuffers(1, &r->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)a->vertex_count * DM_VERTEX_STRIDE, a->vertices, GL_STATIC_DRAW);
    glGenBuffers(1, &r->ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)a->index_count * 4, a->indices, GL_STATIC_DRAW);
    const int offs[4] = {DM_VERTEX_POSITION, DM_VERTEX_NORMAL, DM_VERTEX_TANGENT, DM_VERTEX_UV};
    const int sizes[4] = {3, 3, 4, 2};
    for (int i = 0; i < 4; ++i) {
        glEnableVertexAttribArray((GLuint)i);
        glVertexAttribPointer((GLuint)i, sizes[i], GL_FLOAT, GL_FALSE, DM_VERTEX_STRIDE,
                              (const void *)(size_t)(offs[i] * 4));
    }
    glBindVertexArray(0);
    glGenVertexArrays(1, &r->vao_empty);
    r->index_count = a->index_count;
    dmr_mesh_bounds(r, a->vertices, a->vertex_count);

    r->tex_white = dmr_solid_texture(255);
    r->tex_black = dmr_solid_texture(0);
    dm_result rc = DM_OK;
#define UP(field, what, mips, filt, dst)                                                                          \
    if (rc == DM_OK && a->field.texels) rc = dmr_upload(&a->field, what, mips, filt, &r->dst, err)
    UP(albedo, "albedo", true, GL_LINEAR, tex_albedo);
    if (rc == DM_OK) rc = upload_normal_specular(r, a, err);
    UP(roughness_map, "roughness_map", true, GL_LINEAR, tex_rough);
    const dm_render_plan *p = &r->plan;
    if (p->effects[DM_EFFECT_SPECULAR]) UP(beckmann, "beckmann", false, GL_LINEAR, tex_beckmann);
    if (p->energy_conservation_active) UP(rho_dt, "rho_dt", false, GL_LINEAR, tex_rho_dt);
#undef UP
    if (rc == DM_OK) rc = dmr_env_upload(r, a, err);
    if (rc == DM_OK && p->texture_space) rc = dmr_tsd_upload(r, a, err);
    if (rc == DM_OK && p->pre_integrated) rc = dmr_preint_upload(r, a, err);
    r->has_normal_map = a->normal_map.texels != NULL;
    r->has_roughness_map = a->roughness_map.texels != NULL;
    r->has_mask = a->stretch_mask.texels != NULL;
    if (a->has_env_sh) memcpy(r->env_sh, a->env_sh, sizeof r->env_sh);
    if (rc != DM_OK) return rc;
    return dmr_gl_check("upload", err);
}


dm_result dm_renderer_create(const dm_render_assets *a, const dm_render_desc *desc, dm_renderer **out,
                             dm_error *err)
{
    assert(a && a->scene && desc && out);
    *out = NULL;
    dm_renderer *r = calloc(1, sizeof *r);
    if (!r) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "renderer: cannot allocate");
    r->scene = *a->scene;
    r->profile = a->profile ? *a->profile : a->scene->profile;
    r->desc = *desc;
    if (desc->shader_dir) snprintf(r->shader_dir, sizeof r->shader_dir, "%s", desc->shader_dir);
    r->desc.shader_dir = NULL;
    dmr_sizes sz;
    dmr_resolve_sizes(a, desc, &sz);
    r->width = sz.width, r->height = sz.height, r->irr_edge = sz.irr_edge, r->shadow_edge = sz.shadow_edge;
    memcpy(r->level_edge, sz.level_edge, sizeof r->level_edge);
    r->taps = a->scene->blur_taps;
    r->scene.profile = r->profile;
    r->shadow_taps = desc->shadow_pcf_taps > 0 ? desc->shadow_pcf_taps : 4;
    r->level_format = desc->blur_half_float ? GL_RGBA16F : GL_RGBA32F;
    int shift = desc->blur_reduce_shift > 0 ? desc->blur_reduce_shift : 1;

    dm_result rc = DM_OK;
    if (r->width < 1 || r->height < 1 || r->width > 16384 || r->height > 16384)
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: output size %dx%d, expected 1..16384 per side", r->width,
                     r->height);
    else if (a->scene->effects[DM_EFFECT_SUBSURFACE] && a->scene->sss_technique == DM_SSS_TEXTURE_SPACE &&
             (r->irr_edge < 8 || r->irr_edge > 8192))
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: irradiance size %d, expected 8..8192", r->irr_edge);
    else if (r->shadow_edge < 16 || r->shadow_edge > 8192)
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: shadow size %d, expected 16..8192", r->shadow_edge);
    else if (r->shadow_taps != 1 && r->shadow_taps != 4 && r->shadow_taps != 9)
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: shadow_pcf_taps %d, expected 0 (4), 1, 4 or 9", r->shadow_taps);
    else if (desc->blur_reduce_from < 0 || desc->blur_reduce_from >= DM_PROFILE_MAX_GAUSSIANS)
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: blur_reduce_from %d, expected 0 (off) or a level 1..%d",
                     desc->blur_reduce_from, DM_PROFILE_MAX_GAUSSIANS - 1);
    else if (desc->blur_reduce_shift < 0 || desc->blur_reduce_shift > 3)
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: blur_reduce_shift %d, expected 0 (1), 1, 2 or 3",
                     desc->blur_reduce_shift);
    else if (desc->blur_reduce_from > 0 && a->scene->effects[DM_EFFECT_SUBSURFACE] &&
             a->scene->sss_technique == DM_SSS_TEXTURE_SPACE && (r->irr_edge >> shift) < 8)
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: irradiance size %d >> blur_reduce_shift %d is below 8 texels",
                     r->irr_edge, shift);
    if (rc == DM_OK) rc = dm_render_plan_build(&r->scene, DM_VIEW_FINAL, 0, &r->plan, err);
    /* the levels' sum per texel: exact at the texel centres only where every level has them
     * (reduced levels would be interpolated twice: to the centres, then to the pixel) */
    r->diffusion_sum = dmr_diffusion_summed(&r->plan, desc);
    if (rc == DM_OK && !r->diffusion_sum) dm_render_plan_sum_per_pixel(&r->plan);
    if (rc == DM_OK) rc = check_assets(a, &r->plan, &r->profile, err);
    for (int i = 0; rc == DM_OK && i < r->plan.pass_count; ++i)
        r->ts_pass_count += dmr_pass_get(r->plan.passes[i].kind)->texture_space;
    if (rc == DM_OK && r->plan.texture_space) dmr_auto_level_edges(a, desc, &r->profile, r->irr_edge, r->level_edge);
    if (rc == DM_OK) {
        const char *name = (const char *)glGetString(GL_RENDERER);
        snprintf(r->gl_name, sizeof r->gl_name, "%s", name ? name : "unknown");
        r->timing_cpu = strstr(r->gl_name, "llvmpipe") || strstr(r->gl_name, "softpipe") ||
                        strstr(r->gl_name, "Software") || strstr(r->gl_name, "swrast");
        glGetError(); /* a context may start with a stale error */
        rc = dmr_check_limits(r, a, err); /* before the first texture: sizes this GL makes, memory */
    }
    if (rc != DM_OK) {
        free(r);
        return rc;
    }

    rc = upload_assets(r, a, err);
    if (rc == DM_OK) rc = dmr_make_targets(r, err);
    if (rc == DM_OK) rc = dmr_blur_cpu_setup(r, a, err);
    if (rc == DM_OK && r->plan.screen_space) rc = dmr_ssss_setup(r, a, err);
    if (rc == DM_OK) dmr_profile_weights(r);
    if (rc == DM_OK) dmr_translucency_setup(r);
    /* one program per shader file and extra defines among the kinds the plan needs */
    for (int k = 0; k < DM_PASS_KIND_COUNT && rc == DM_OK; ++k) {
        if (!dmr_pass_needed(r, (dm_pass_kind)k)) continue;
        const dmr_pass_info *pk = dmr_pass_get((dm_pass_kind)k);
        for (int j = 0; j < k && !r->prog[k]; ++j) {
            const dmr_pass_info *pj = dmr_pass_get((dm_pass_kind)j);
            if (r->prog[j] && strcmp(pj->shader, pk->shader) == 0 &&
                strcmp(pj->defines ? pj->defines : "", pk->defines ? pk->defines : "") == 0)
                r->prog[k] = r->prog[j];
        }
        if (!r->prog[k]) rc = dmr_build_program(r, pk->shader, pk->defines, &r->prog[k], err);
    }
    if (rc == DM_OK) {
        if (!r->timing_cpu) glGenQueries(DM_PLAN_MAX_PASSES, r->queries);
        if (r->plan.texture_space) dmr_prepare_blur(r, 1.0f);
        rc = dmr_gl_check("renderer setup", err);
    }
    if (rc != DM_OK) {
        dm_renderer_destroy(r);
        return rc;
    }
    *out = r;
    return DM_OK;
}

void dm_renderer_destroy(dm_renderer *r)
{
    if (!r) return;
    dmr_blur_cpu_free(r);
    dmr_glow_free(r);
    for (int k = 0; k < DM_PASS_KIND_COUNT; ++k) {
        bool first = r->prog[k] != 0;
        for (int j = 0; j < k && first; ++j) first = r->prog[j] != r->prog[k];
        if (first) glDeleteProgram(r->prog[k]);
    }
    GLuint tex[] = {r->tex_albedo,    r->tex_normal,     r->tex_spec,   r->tex_rough,      r->tex_beckmann,
                    r->tex_rho_dt,    r->tex_env_brdf, r->tex_mask,     r->tex_background,
                    r->tex_white,     r->tex_black, r->tex_env_array,      r->screen_tex, r->view_tex, r->blit_tex,
                    r->glow_tex[0],   r->glow_tex[1],    r->display_tex, r->ss_diff_tex, r->ss_aux_tex, r->ss_spec_tex,
                    r->ss_tmp_tex, r->tex_preint, r->tex_curvature, r->gbuf_tex[0], r->gbuf_tex[1],
                    r->gbuf_tex[2], r->gbuf_tex[3], r->ts_gbuf_tex[0], r->ts_gbuf_tex[1],
                    r->ts_gbuf_tex[2], r->ts_gbuf_tex[3]};
    for (size_t i = 0; i < sizeof tex / sizeof tex[0]; ++i)
        if (tex[i]) glDeleteTextures(1, &tex[i]);
    for (int k = 0; k < DM_PROFILE_MAX_GAUSSIANS; ++k) {
        if (r->tex_stretch[k]) glDeleteTextures(1, &r->tex_stretch[k]);
        if (r->irr_tex[k]) glDeleteTextures(1, &r->irr_tex[k]);
        if (r->irr_fbo[k]) glDeleteFramebuffers(1, &r->irr_fbo[k]);
        if (k == 0 && r->diff_tex) glDeleteTextures(1, &r->diff_tex);
        if (k == 0 && r->diff_fbo) glDeleteFramebuffers(1, &r->diff_fbo);
        bool first = true; /* the U targets are shared between levels of one size */
        for (int j = 1; j < k; ++j) first = first && r->tmp_fbo[j] != r->tmp_fbo[k];
        if (first && r->tmp_fbo[k]) glDeleteFramebuffers(1, &r->tmp_fbo[k]);
        if (first && r->tmp_tex[k]) glDeleteTextures(1, &r->tmp_tex[k]);
    }
    for (int k = 0; k < DM_RENDER_ENV_LEVELS_MAX; ++k)
        if (r->tex_env_level[k]) glDeleteTextures(1, &r->tex_env_level[k]);
    for (int k = 0; k < DM_PLAN_MAX_SHADOWS; ++k) {
        if (r->shadow_fbo[k]) glDeleteFramebuffers(1, &r->shadow_fbo[k]);
        if (r->shadow_tex[k]) glDeleteTextures(1, &r->shadow_tex[k]);
    }
    GLuint fbo[] = {r->screen_fbo, r->glow_fbo[0],
                    r->glow_fbo[1], r->display_fbo,   r->view_fbo, r->ss_fbo, r->ss_tmp_fbo, r->gbuf_fbo, r->ts_gbuf_fbo,
                    r->blit_fbo};
    for (size_t i = 0; i < sizeof fbo / sizeof fbo[0]; ++i)
        if (fbo[i]) glDeleteFramebuffers(1, &fbo[i]);
    if (r->screen_depth) glDeleteRenderbuffers(1, &r->screen_depth);
    if (r->ts_depth) glDeleteRenderbuffers(1, &r->ts_depth);
    if (r->vbo) glDeleteBuffers(1, &r->vbo);
    if (r->ebo) glDeleteBuffers(1, &r->ebo);
    if (r->vao_mesh) glDeleteVertexArrays(1, &r->vao_mesh);
    if (r->vao_empty) glDeleteVertexArrays(1, &r->vao_empty);
    if (r->tdepth_sampler) glDeleteSamplers(1, &r->tdepth_sampler);
    if (!r->timing_cpu && r->queries[0]) glDeleteQueries(DM_PLAN_MAX_PASSES, r->queries);
    free(r);
}

dm_result dm_render_frame(dm_renderer *r, const dm_frame_options *opt, dm_error *err)
{
    assert(r && opt);
    dm_render_plan plan;
    dm_result rc = dm_render_plan_build(&r->scene, opt->view, opt->view_index, &plan, err);
    if (rc != DM_OK) return rc;
    if (!r->diffusion_sum) dm_render_plan_sum_per_pixel(&plan);
    r->plan = plan;
    float blur_scale = opt->blur_scale > 0 ? opt->blur_scale : 1.0f;
    if (plan.texture_space && blur_scale != r->blur_scale) dmr_prepare_blur(r, blur_scale);
    r->roughness_scale = opt->roughness_scale > 0 ? opt->roughness_scale : 1.0f;
    dmr_frame_lights(r, opt->light_rotation_deg);
    dmr_frame_camera(r);
    glGetError();
    double t_frame;
    dmr_timing_frame_begin(r, &t_frame);
    r->tonemapped = false;
    r->glow_pending = false;
    r->view_in_target = false;
    /* reuse_texture_space: the shadow maps, irradiance and blur levels depend on the scene
     * (dm_renderer_set_scene invalidates them), the light rotation and the blur and
     * roughness scales; the camera and the view do not enter texture space. */
    bool reuse = r->desc.reuse_texture_space && r->ts_valid && r->ts_rotation == opt->light_rotation_deg &&
                 r->ts_blur_scale == blur_scale && r->ts_roughness_scale == r->roughness_scale;
    int ts_passes = 0;
    bool skipped[DM_PLAN_MAX_PASSES] = {false};
    for (int i = 0; i < plan.pass_count; ++i) {
        const dm_pass *ps = &plan.passes[i];
        const dmr_pass_info *info = dmr_pass_get(ps->kind);
        ts_passes += info->texture_space;
        if (info->texture_space && reuse) {
            r->pass_ms[i] = 0.0;
            skipped[i] = true;
            continue;
        }
        double t0;
        dmr_timing_pass_begin(r, i, &t0);
        info->run(r, ps, opt);
        dmr_timing_pass_end(r, i, t0);
        if (ps->kind == DM_PASS_TONEMAP) r->tonemapped = true;
        rc = dmr_gl_check(ps->name, err);
        if (rc != DM_OK) return rc;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    r->has_frame = true;
    r->glow_pending = r->plan.glow_in_tonemap && r->tonemapped;
    if (!reuse) { /* valid only when this frame made every texture-space result */
        r->ts_valid = ts_passes == r->ts_pass_count;
        r->ts_rotation = opt->light_rotation_deg;
        r->ts_blur_scale = blur_scale;
        r->ts_roughness_scale = r->roughness_scale;
    }
    dmr_timing_frame_end(r, t_frame, skipped);
    return dmr_gl_check("frame end", err);
}

dm_result dm_renderer_set_scene(dm_renderer *r, const dm_scene *s, dm_error *err)
{
    assert(r && s);
    const dm_scene *o = &r->scene;
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
    r->scene = *s;
    r->ts_valid = false; /* lights, material, environment: texture space is stale */
    r->ts_gbuf_valid = false;
    r->scene.profile = r->profile;
    return DM_OK;
}
