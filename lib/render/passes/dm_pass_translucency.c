/* dm_pass_translucency.c — light through thin parts (ears, nostrils, eyelids).
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
 * No pass of its own: this module makes that sampler; the binder (frame/dm_frame_bind.c) binds
 * it, the depths and T(d)'s numbers for every pass that shades.
 */
#include "render/passes/dm_pass_translucency.h"

dm_result dmr_translucency_check(const dmr_frame *f, const dm_render_assets *a, dm_error *err)
{
    (void)a;
    return f->plan.translucency_active ? dm_profile_validate(&f->profile, "assets: profile", err) : DM_OK;
}

dm_result dmr_translucency_setup(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err)
{
    (void)st, (void)a, (void)err;
    if (!f->plan.translucency_active) return DM_OK;
    GLuint s = f->tdepth_sampler = dmg_make(&f->gpu, DMG_SAMPLER);
    glSamplerParameteri(s, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(s, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(s, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(s, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(s, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    return DM_OK;
}
