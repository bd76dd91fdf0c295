/* dm_frame_bind.c — the one binder of shading inputs (dm_frame_bind.h). */
#include "render/frame/dm_frame_bind.h"

#include <math.h>

#include "core/dm_math.h"

static void bind_camera(const dmr_frame *f, GLuint p, bool mode0)
{
    glUniformMatrix4fv(dmg_loc(p, "u_view_proj"), 1, GL_FALSE, f->view_proj);
    glUniform3fv(dmg_loc(p, "u_eye"), 1, f->eye);
    dmg_u1i(p, "u_mode", mode0 ? 0 : dmr_view_mode(f));
    if (f->plan.screen_space) glUniform3fv(dmg_loc(p, "u_cam_forward"), 1, f->cam_fwd);
}

static void bind_lights(const dmr_frame *f, GLuint p)
{
    const dm_scene *s = &f->scene;
    glUniform4fv(dmg_loc(p, "u_light_pos"), s->light_count, &f->light_pos[0][0]);
    glUniform3fv(dmg_loc(p, "u_light_color"), s->light_count, &f->light_color[0][0]);
    glUniformMatrix4fv(dmg_loc(p, "u_light_matrix"), s->light_count, GL_FALSE, &f->light_matrix[0][0]);
    dmg_u1f(p, "u_shadow_normal_offset", 3.0f * f->radius / (float)f->shadow_edge);
    dmg_u1f(p, "u_shadow_texel", 1.0f / (float)f->shadow_edge);
}

static GLuint or_default(GLuint tex, GLuint fallback)
{
    return tex ? tex : fallback;
}

static void bind_surface(const dmr_frame *f, GLuint p)
{
    const dm_scene *s = &f->scene;
    dmg_u1f(p, "u_roughness", s->roughness);
    dmg_u1f(p, "u_roughness_scale", f->roughness_scale);
    dmg_u1f(p, "u_rho_s", s->rho_s);
    glUniform3fv(dmg_loc(p, "u_sh"), DM_RENDER_SH_COUNT, &f->env_sh[0][0]);
    dmg_u1f(p, "u_env_intensity", s->env_intensity);
    dmg_u1f(p, "u_env_rotation", (float)(s->env_rotation_deg * DM_PI / 180.0));
    dmg_u1f(p, "u_mix", s->mix);
    dmg_bind(UNIT_ALBEDO, GL_TEXTURE_2D, or_default(f->tex_albedo, f->tex_white));
    dmg_bind(UNIT_NORMAL, GL_TEXTURE_2D, or_default(f->tex_normal, f->tex_white));
    dmg_bind(UNIT_SPECULAR, GL_TEXTURE_2D, or_default(f->tex_spec, f->tex_white));
    dmg_bind(UNIT_ROUGHNESS, GL_TEXTURE_2D, or_default(f->tex_rough, f->tex_white));
    dmg_bind(UNIT_BECKMANN, GL_TEXTURE_2D, or_default(f->tex_beckmann, f->tex_black));
    dmg_bind(UNIT_RHO_DT, GL_TEXTURE_2D, or_default(f->tex_rho_dt, f->tex_black));
    dmg_bind(UNIT_ENV_BRDF, GL_TEXTURE_2D, or_default(f->tex_env_brdf, f->tex_black));
    for (int k = 0; k < DM_RENDER_ENV_LEVELS_MAX; ++k)
        dmg_bind(UNIT_ENV_LEVEL0 + k, GL_TEXTURE_2D, or_default(f->tex_env_level[k], f->tex_black));
    for (int k = 0; k < DM_PLAN_MAX_SHADOWS; ++k)
        if (f->shadow_tex[k]) dmg_bind(UNIT_SHADOW + k, GL_TEXTURE_2D, f->shadow_tex[k]);
    if (f->tex_env_array) dmg_bind(UNIT_ENV_ARRAY, GL_TEXTURE_2D_ARRAY, f->tex_env_array);
}

/* The levels and their weights for dm_level_sum, and the diffusion pass's sum for
 * dm_diffusion (common.glsl); absent levels read black. */
static void bind_levels(const dmr_frame *f, GLuint p)
{
    int levels = f->plan.texture_space ? f->profile.count : 0;
    if (levels) glUniform3fv(dmg_loc(p, "u_level_weight"), levels, &f->level_weight[0][0]);
    for (int k = 0; k < DM_PROFILE_MAX_GAUSSIANS; ++k)
        dmg_bind(UNIT_LEVEL0 + k, GL_TEXTURE_2D, k < levels ? f->level_tex[k] : f->tex_black);
    dmg_bind(UNIT_DIFFUSION, GL_TEXTURE_2D, f->diff_tex && levels ? f->diff_tex : f->tex_black);
}

static void bind_preint(const dmr_frame *f, GLuint p)
{
    if (!f->plan.pre_integrated) return;
    dmg_bind(UNIT_PREINT, GL_TEXTURE_2D, f->preint.table);
    dmg_bind(UNIT_CURVATURE, GL_TEXTURE_2D, f->preint.curvature);
    dmg_u1f(p, "u_preint_kmax", f->preint.kmax);
    dmg_u1f(p, "u_preint_height", (float)f->preint.height);
    glUniform3fv(dmg_loc(p, "u_preint_blend"), 1, f->preint.blend);
}

/* Translucency's raw shadow depths (the sampler object reads them without compare) and the
 * profile's transmittance T(d) = Σ_k w_k exp(−d²/2v_k). */
static void bind_translucency(const dmr_frame *f, GLuint p)
{
    if (!f->plan.translucency_active) return;
    for (int k = 0; k < f->plan.shadow_count; ++k) {
        dmg_bind(UNIT_TDEPTH0 + k, GL_TEXTURE_2D, f->shadow_tex[k]);
        glBindSampler((GLuint)(UNIT_TDEPTH0 + k), f->tdepth_sampler);
    }
    glUniform4fv(dmg_loc(p, "u_light_depth"), f->scene.light_count, &f->light_depth[0][0]);
    float var[DM_PROFILE_MAX_GAUSSIANS];
    for (int k = 0; k < f->profile.count; ++k) /* exp(−d²/2v) = exp2(d² · (−log2 e / 2v)); v ≥ 1e−12 mm² */
        var[k] = (float)(-1.4426950408889634 / (2.0 * fmax(f->profile.variance_mm2[k], 1e-12)));
    glUniform1fv(dmg_loc(p, "u_trans_var"), f->profile.count, var);
    glUniform3fv(dmg_loc(p, "u_trans_weight"), f->profile.count, &f->level_weight[0][0]);
    dmg_u1f(p, "u_mm_per_unit", (float)f->scene.mm_per_unit);
    dmg_u1f(p, "u_translucency", f->scene.translucency_intensity);
}

void dmr_bind_inputs(const dmr_frame *f, GLuint p, unsigned what)
{
    glUseProgram(p);
    if (what & DMR_BIND_CAMERA) bind_camera(f, p, what & DMR_BIND_MODE0);
    if (what & DMR_BIND_LIGHTS) bind_lights(f, p);
    if (what & DMR_BIND_SURFACE) bind_surface(f, p);
    if (what & DMR_BIND_ENV_LEVELS) glUniform1fv(dmg_loc(p, "u_env_level_m"), DM_RENDER_ENV_LEVELS_MAX, f->env_level_m);
    if (what & DMR_BIND_LEVELS) bind_levels(f, p);
    if (what & DMR_BIND_PREINT) bind_preint(f, p); /* after the levels: it takes two of their units */
    if (what & DMR_BIND_TRANSLUCENCY) bind_translucency(f, p);
}

void dmr_unbind_inputs(const dmr_frame *f, unsigned what)
{
    if (!(what & DMR_BIND_TRANSLUCENCY) || !f->plan.translucency_active) return;
    for (int k = 0; k < f->plan.shadow_count; ++k) glBindSampler((GLuint)(UNIT_TDEPTH0 + k), 0);
}

int dmr_gbuffer_unit(GLuint p)
{
    return glGetUniformLocation(p, "u_level_weight") >= 0 ? UNIT_SRC : UNIT_LEVEL0;
}

void dmr_bind_gbuffer(GLuint p, const GLuint tex[4])
{
    int unit = dmr_gbuffer_unit(p);
    for (int i = 0; i < 4; ++i) dmg_bind(unit + i, GL_TEXTURE_2D, tex[i]);
}
