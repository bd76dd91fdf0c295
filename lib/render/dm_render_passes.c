/* dm_render_passes.c — the one table: every pass kind's rows, each with its shader and extra
 * defines, its module, whether it belongs to texture space (its result depends only on the
 * scene and the lights, so reuse_texture_space may skip it), the inputs the binder binds, its
 * GL state and clears, and its hooks (frame/dm_frame_pass.h). The plan (input/dm_render_plan.c)
 * decides which passes a scene's effects call for and why; --explain prints the plan, the
 * timings are per plan pass, create walks these rows and compiles the programs of the kinds
 * the plan holds, and the frame loop runs each pass through dmr_run_pass. Kinds that share a
 * shader file and its extra defines share one program. A kind with two rows has two
 * implementations (the blurs in GL or on the CPU; the diffusion sum uploaded from the CPU's
 * chain, else made in GL): the first whose prepare takes the pass runs. Rows sit in the order
 * create makes their targets (texture space's, then the screen's, the screen passes'). */
#include <stddef.h>

#include "render/dm_render_internal.h"
#include "render/frame/dm_frame_bind.h"
#include "render/gpu/dm_gpu_target.h"
#include "render/passes/dm_pass_diffusion.h"
#include "render/passes/dm_pass_preint.h"
#include "render/passes/dm_pass_shade.h"
#include "render/passes/dm_pass_translucency.h"

#define ST(member) offsetof(struct dm_renderer, member)
#define DEFERRED "#define DM_DEFERRED 1\n#define DM_FULLSCREEN 1\n"
#define NO_PASS DM_PASS_KIND_COUNT

static const dmr_pass_row rows[] = {
    {DM_PASS_BACKGROUND, "background.glsl", NULL, "passes/dm_pass_env.c", false, 0, {{GL_LEQUAL, .depth_read_only = true}}, ST(env),
     .check = dmr_env_check, .upload = dmr_env_upload, .prepare = dmr_background_prepare, .run = dmr_background_run},
    {DM_PASS_SHADOW, "shadow.glsl", NULL, "passes/dm_pass_shadow.c", true, 0,
     {{GL_LESS, .polygon_offset = {1.5f, 4.0f}, .clear = DMR_CLEAR_DEPTH}}, ST(shadow), .targets = dmr_shadow_targets,
     .prepare = dmr_shadow_prepare, .run = dmr_shadow_run},
    /* Depth test ALWAYS with writes: where triangles overlap in UV the last one drawn holds the texel */
    {DM_PASS_TS_GBUFFER, "irradiance.glsl", "#define DM_GBUFFER 1\n", "passes/dm_pass_tsd.c", true, DMR_BIND_SURFACE,
     {{GL_ALWAYS, .clear = DMR_CLEAR_COLOR | DMR_CLEAR_DEPTH}}, ST(tsd), .check = dmr_tsd_check,
     .upload = dmr_tsd_upload, .targets = dmr_tsd_targets, .setup = dmr_tsd_setup, .prepare = dmr_ts_gbuffer_prepare,
     .run = dmr_ts_gbuffer_run, .free = dmr_tsd_free},
    {DM_PASS_IRRADIANCE, "irradiance.glsl", DEFERRED, "passes/dm_pass_tsd.c", true,
     DMR_BIND_LIGHTS | DMR_BIND_SURFACE | DMR_BIND_TRANSLUCENCY, {{GL_GREATER, .depth_read_only = true}}, ST(tsd),
     .prepare = dmr_irradiance_prepare, .run = dmr_irradiance_run},
    {DM_PASS_BLUR_U, "blur.glsl", NULL, "passes/dm_pass_tsd.c", true, 0, {{0}}, ST(tsd), .prepare = dmr_blur_prepare,
     .run = dmr_blur_run},
    {DM_PASS_BLUR_V, "blur.glsl", NULL, "passes/dm_pass_tsd.c", true, 0, {{0}}, ST(tsd), .prepare = dmr_blur_prepare,
     .run = dmr_blur_run},
    {DM_PASS_BLUR_U, "blur.glsl", NULL, "passes/dm_pass_blur_cpu.c", true, 0, {{0}}, ST(blur_cpu),
     .setup = dmr_blur_cpu_setup, .free = dmr_blur_cpu_free, .prepare = dmr_blur_cpu_prepare, .run = dmr_blur_cpu_run},
    {DM_PASS_BLUR_V, "blur.glsl", NULL, "passes/dm_pass_blur_cpu.c", true, 0, {{0}}, ST(blur_cpu),
     .prepare = dmr_blur_cpu_prepare, .run = dmr_blur_cpu_run},
    {DM_PASS_DIFFUSION, "diffusion.glsl", "#define DM_DIFFUSION_PASS 1\n", "passes/dm_pass_blur_cpu.c", true, 0, {{0}},
     ST(blur_cpu), .prepare = dmr_blur_cpu_sum_prepare, .run = dmr_blur_cpu_sum_run},
    {DM_PASS_DIFFUSION, "diffusion.glsl", "#define DM_DIFFUSION_PASS 1\n", "passes/dm_pass_diffusion.c", true,
     DMR_BIND_LEVELS, {{0}}, 0, .setup = dmr_diffusion_setup, .prepare = dmr_diffusion_prepare, .run = dmr_diffusion_run},
    /* the screen's targets (frame/dm_frame_targets.c) are made here, before the next targets hook */
    {DM_PASS_GBUFFER, "final.glsl", "#define DM_GBUFFER 1\n", "passes/dm_pass_shade.c", false,
     DMR_BIND_SHADE | DMR_BIND_MODE0, {{GL_LESS, .cull_back = true, .clear = DMR_CLEAR_DEPTH}}, 0,
     .prepare = dmr_gbuffer_prepare, .run = dmr_gbuffer_run},
    {DM_PASS_FINAL, "final.glsl", DEFERRED, "passes/dm_pass_shade.c", false, DMR_BIND_SHADE,
     {{GL_GREATER, .depth_read_only = true, .clear = DMR_CLEAR_SCREEN}}, 0, .prepare = dmr_final_prepare, .run = dmr_final_run},
    {DM_PASS_FINAL_FORWARD, "final.glsl", NULL, "passes/dm_pass_shade.c", false, DMR_BIND_SHADE,
     {{GL_LESS, .cull_back = true, .clear = DMR_CLEAR_DEPTH | DMR_CLEAR_SCREEN},
      {GL_LESS, .wireframe = true, .clear = DMR_CLEAR_DEPTH | DMR_CLEAR_SCREEN}},
     0, .variant = dmr_final_forward_variant, .prepare = dmr_final_prepare, .run = dmr_final_forward_run},
    {DM_PASS_SS_SHADE, "final.glsl", DEFERRED, "passes/dm_pass_ssss.c", false, DMR_BIND_SHADE | DMR_BIND_MODE0,
     {{GL_GREATER, .depth_read_only = true, .clear = DMR_CLEAR_COLOR0}}, ST(ssss), .check = dmr_ssss_check, .targets = dmr_ssss_targets,
     .setup = dmr_ssss_setup, .prepare = dmr_ss_shade_prepare, .run = dmr_ss_shade_run},
    {DM_PASS_SS_BLUR_H, "ss_blur.glsl", NULL, "passes/dm_pass_ssss.c", false, 0,
     {{GL_GREATER, .depth_read_only = true, .clear = DMR_CLEAR_COLOR}}, ST(ssss), .prepare = dmr_ss_blur_prepare, .run = dmr_ss_blur_run},
    {DM_PASS_SS_BLUR_V, "ss_blur.glsl", "#define DM_SS_COMBINE 1\n", "passes/dm_pass_ssss.c", false, 0,
     {{GL_GREATER, .depth_read_only = true, .clear = DMR_CLEAR_SCREEN}}, ST(ssss), .prepare = dmr_ss_blur_prepare,
     .run = dmr_ss_blur_run},
    {NO_PASS, NULL, NULL, "passes/dm_pass_translucency.c", false, 0, {{0}}, 0, .check = dmr_translucency_check,
     .setup = dmr_translucency_setup},
    {NO_PASS, NULL, NULL, "passes/dm_pass_preint.c", false, 0, {{0}}, 0, .check = dmr_preint_check,
     .upload = dmr_preint_upload},
    {DM_PASS_GLOW_BRIGHT, "glow_bright.glsl", NULL, "passes/dm_pass_glow.c", false, 0, {{0}}, ST(glow),
     .targets = dmr_glow_targets, .free = dmr_glow_free, .prepare = dmr_glow_prepare, .run = dmr_glow_run},
    {DM_PASS_GLOW_BLUR_U, "glow_blur.glsl", NULL, "passes/dm_pass_glow.c", false, 0, {{0}}, ST(glow),
     .prepare = dmr_glow_prepare, .run = dmr_glow_run},
    {DM_PASS_GLOW_BLUR_V, "glow_blur.glsl", NULL, "passes/dm_pass_glow.c", false, 0, {{0}}, ST(glow),
     .prepare = dmr_glow_prepare, .run = dmr_glow_run},
    {DM_PASS_GLOW_ADD, "glow_add.glsl", NULL, "passes/dm_pass_glow.c", false, 0, {{.blend_add = true}}, ST(glow),
     .prepare = dmr_glow_prepare, .run = dmr_glow_run},
    {DM_PASS_TONEMAP, "tonemap.glsl", NULL, "passes/dm_pass_tonemap.c", false, 0,
     {{GL_GREATER, .depth_read_only = true, .clear = DMR_CLEAR_COLOR, .clear_color = {0, 0, 0, 1}}, {0}}, ST(tonemap),
     .targets = dmr_tonemap_targets, .variant = dmr_tonemap_variant, .prepare = dmr_tonemap_prepare,
     .run = dmr_tonemap_run},
    {DM_PASS_VIEW, "view.glsl", NULL, "passes/dm_pass_view.c", false, DMR_BIND_LEVELS, {{0}}, ST(view),
     .prepare = dmr_view_prepare, .run = dmr_view_run},
};

const dmr_pass_row *dmr_pass_rows(int *count)
{
    *count = (int)(sizeof rows / sizeof rows[0]);
    return rows;
}

const dmr_pass_row *dmr_pass_first(dm_pass_kind kind)
{
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; ++i)
        if (rows[i].kind == kind) return &rows[i];
    return NULL;
}

void *dmr_pass_state(dm_renderer *r, const dmr_pass_row *row)
{
    return row->state_offset ? (char *)r + row->state_offset : NULL;
}

bool dmr_pass_needed(const dm_renderer *r, dm_pass_kind k)
{
    const dm_render_plan *p = &r->f.plan;
    switch (k) {
    case DM_PASS_GBUFFER: return p->deferred;
    case DM_PASS_FINAL: return p->deferred && !p->screen_space; /* screen-space shades in ss_shade */
    case DM_PASS_FINAL_FORWARD:
    case DM_PASS_VIEW: return true; /* debug views need them whatever the effects */
    case DM_PASS_SHADOW: return p->shadow_count > 0;
    case DM_PASS_TS_GBUFFER:
    case DM_PASS_IRRADIANCE:
    case DM_PASS_BLUR_U:
    case DM_PASS_BLUR_V: return p->texture_space;
    case DM_PASS_DIFFUSION: return r->f.diffusion_sum;
    case DM_PASS_SS_SHADE:
    case DM_PASS_SS_BLUR_H:
    case DM_PASS_SS_BLUR_V: return p->screen_space;
    case DM_PASS_BACKGROUND: return dm_render_plan_find(p, "background") >= 0;
    case DM_PASS_GLOW_BRIGHT:
    case DM_PASS_GLOW_BLUR_U:
    case DM_PASS_GLOW_BLUR_V:
    case DM_PASS_GLOW_ADD: return p->effects[DM_EFFECT_GLOW];
    case DM_PASS_TONEMAP: return p->effects[DM_EFFECT_TONEMAP];
    case DM_PASS_KIND_COUNT: break;
    }
    return false;
}

void dmr_run_pass(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    dmr_frame *f = &r->f;
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; ++i) {
        const dmr_pass_row *row = &rows[i];
        if (row->kind != ps->kind) continue;
        void *st = dmr_pass_state(r, row);
        dmr_output out = {0};
        if (row->prepare && !row->prepare(f, st, ps, &out)) continue;
        if (out.fbo) dmg_target_begin(out.fbo, out.width, out.height);
        if (out.fbo && out.draw_buffers > 1) glDrawBuffers(out.draw_buffers, dmg_draw_buffers);
        dmr_state_apply(f, &row->state[row->variant ? row->variant(f, st) : 0]);
        GLuint p = f->prog[ps->kind];
        glUseProgram(p);
        if (row->binds) dmr_bind_inputs(f, p, row->binds);
        row->run(f, st, ps, opt);
        if (row->binds) dmr_unbind_inputs(f, row->binds);
        dmr_state_reset();
        return;
    }
}

void dmr_glow_settle(dm_renderer *r)
{
    if (!r->glow_pending) return;
    r->glow_pending = false;
    dmr_run_pass(r, &(dm_pass){.kind = DM_PASS_GLOW_ADD}, NULL);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}
