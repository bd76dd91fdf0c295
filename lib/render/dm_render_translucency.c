/* dm_render_translucency.c — light through thin parts (ears, nostrils, eyelids).
 *
 * Formulation: Jimenez, Whelan, Sundstedt & Gutierrez, "Real-Time Realistic Skin
 * Translucency" (IEEE CG&A 30(4), 2010), not d'Eon & Luebke's translucent shadow maps. Per
 * shaded point and casting light, the thickness d is the distance along the light between the
 * point (shrunk inward along its normal, as Jimenez does, so the lit surface's own depth is
 * not found) and the first surface the shadow map holds; the transmitted light is
 * C·I · T(d) · max(−N·L, 0) · intensity, with the profile's transmittance
 * T(d) = Σ_k w_k exp(−d²/2v_k) (weights normalised per channel, d in mm through mm_per_unit):
 * red, whose profile has the widest Gaussians, travels furthest. It is added to the diffuse
 * irradiance before the diffusion (texture-space irradiance pass, screen-space shade pass,
 * or the Lambert term without subsurface), so it scatters like any light.
 * Why this one: it needs nothing but the depth maps the shadows already render (one more
 * depth read per light and pixel), and works the same in texture space and on screen;
 * translucent shadow maps need irradiance, normals and UVs rendered from every light and a
 * convolution in the light's view, i.e. extra passes per light, for the texture-space path
 * only.
 *
 * The shadow maps are depth-compare textures; a sampler object without compare mode reads
 * their raw depth on the units the blur and view passes use (never bound in shading passes).
 */
#include <math.h>

#include "render/dm_render_internal.h"

void dmr_translucency_setup(dm_renderer *r)
{
    if (!r->plan.translucency_active) return;
    glGenSamplers(1, &r->tdepth_sampler);
    glSamplerParameteri(r->tdepth_sampler, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(r->tdepth_sampler, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(r->tdepth_sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(r->tdepth_sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(r->tdepth_sampler, GL_TEXTURE_COMPARE_MODE, GL_NONE);
}

void dmr_translucency_bind(const dm_renderer *r, GLuint p)
{
    if (!r->plan.translucency_active) return;
    for (int k = 0; k < r->plan.shadow_count; ++k) {
        dmr_bind(UNIT_TDEPTH0 + k, GL_TEXTURE_2D, r->shadow_tex[k]);
        glBindSampler((GLuint)(UNIT_TDEPTH0 + k), r->tdepth_sampler);
    }
    glUniform4fv(loc(p, "u_light_depth"), r->scene.light_count, &r->light_depth[0][0]);
    float var[DM_PROFILE_MAX_GAUSSIANS];
    for (int k = 0; k < r->profile.count; ++k) /* exp(−d²/2v) = exp2(d² · (−log2 e / 2v)); v ≥ 1e−12 mm² */
        var[k] = (float)(-1.4426950408889634 / (2.0 * fmax(r->profile.variance_mm2[k], 1e-12)));
    glUniform1fv(loc(p, "u_trans_var"), r->profile.count, var);
    glUniform3fv(loc(p, "u_trans_weight"), r->profile.count, &r->level_weight[0][0]);
    u1f(p, "u_mm_per_unit", (float)r->scene.mm_per_unit);
    u1f(p, "u_translucency", r->scene.translucency_intensity);
}

void dmr_translucency_unbind(const dm_renderer *r)
{
    if (!r->plan.translucency_active) return;
    for (int k = 0; k < r->plan.shadow_count; ++k) glBindSampler((GLuint)(UNIT_TDEPTH0 + k), 0);
}
