/* dm_render_passes.c — the one table of pass kinds: the shader each runs, the module that owns
 * it, its run function, and whether it belongs to texture space (its result depends only on
 * the scene and the lights, so reuse_texture_space may skip it). The plan
 * (dm_render_plan.c) decides which passes a scene's effects call for and why; --explain
 * prints the plan, the timings are per plan pass, and create compiles the programs of the
 * kinds the plan holds, all through this table. Kinds that share a shader file and its
 * extra defines share one program. */
#include <string.h>

#include "render/dm_render_internal.h"

static const dmr_pass_info table[DM_PASS_KIND_COUNT] = {
    [DM_PASS_SHADOW] = {"shadow.glsl", "dm_render_shadow.c", dmr_pass_shadow, true},
    [DM_PASS_TS_GBUFFER] = {"irradiance.glsl", "dm_render_tsd.c", dmr_pass_ts_gbuffer, true, "#define DM_GBUFFER 1\n"},
    [DM_PASS_IRRADIANCE] = {"irradiance.glsl", "dm_render_tsd.c", dmr_pass_irradiance, true,
                            "#define DM_DEFERRED 1\n#define DM_FULLSCREEN 1\n"},
    [DM_PASS_BLUR_U] = {"blur.glsl", "dm_render_tsd.c", dmr_pass_blur, true},
    [DM_PASS_BLUR_V] = {"blur.glsl", "dm_render_tsd.c", dmr_pass_blur, true},
    [DM_PASS_DIFFUSION] = {"diffusion.glsl", "dm_render_tsd.c", dmr_pass_diffusion, true, "#define DM_DIFFUSION_PASS 1\n"},
    [DM_PASS_GBUFFER] = {"final.glsl", "dm_render_shade.c", dmr_pass_gbuffer, false, "#define DM_GBUFFER 1\n"},
    [DM_PASS_FINAL] = {"final.glsl", "dm_render_shade.c", dmr_pass_final, false,
                       "#define DM_DEFERRED 1\n#define DM_FULLSCREEN 1\n"},
    [DM_PASS_FINAL_FORWARD] = {"final.glsl", "dm_render_shade.c", dmr_pass_final_forward, false},
    [DM_PASS_BACKGROUND] = {"background.glsl", "dm_render_env.c", dmr_pass_background, false},
    [DM_PASS_GLOW_BRIGHT] = {"glow_bright.glsl", "dm_render_glow.c", dmr_pass_glow, false},
    [DM_PASS_GLOW_BLUR_U] = {"glow_blur.glsl", "dm_render_glow.c", dmr_pass_glow, false},
    [DM_PASS_GLOW_BLUR_V] = {"glow_blur.glsl", "dm_render_glow.c", dmr_pass_glow, false},
    [DM_PASS_GLOW_ADD] = {"glow_add.glsl", "dm_render_glow.c", dmr_pass_glow, false},
    [DM_PASS_TONEMAP] = {"tonemap.glsl", "dm_render_tonemap.c", dmr_pass_tonemap, false},
    [DM_PASS_VIEW] = {"view.glsl", "dm_render_view.c", dmr_pass_view, false},
    [DM_PASS_SS_SHADE] = {"final.glsl", "dm_render_ssss.c", dmr_pass_ss_shade, false,
                          "#define DM_DEFERRED 1\n#define DM_FULLSCREEN 1\n"},
    [DM_PASS_SS_BLUR_H] = {"ss_blur.glsl", "dm_render_ssss.c", dmr_pass_ss_blur, false},
    [DM_PASS_SS_BLUR_V] = {"ss_blur.glsl", "dm_render_ssss.c", dmr_pass_ss_blur, false, "#define DM_SS_COMBINE 1\n"},
};

const dmr_pass_info *dmr_pass_get(dm_pass_kind kind)
{
    return (unsigned)kind < DM_PASS_KIND_COUNT ? &table[kind] : NULL;
}

bool dmr_pass_needed(const dm_renderer *r, dm_pass_kind k)
{
    const dm_render_plan *p = &r->plan;
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
    case DM_PASS_DIFFUSION: return r->diffusion_sum;
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
