#include "render/dm_render_plan.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *view_names[DM_VIEW_COUNT] = {"final",    "irradiance", "blur", "stretch",  "shadow",
                                                "specular", "diffuse",    "uv",   "wireframe", "diffusion",
                                                "curvature", "seam", "thin", "gather"};

const char *dm_view_name(dm_view v)
{
    return (unsigned)v < DM_VIEW_COUNT ? view_names[v] : NULL;
}

bool dm_view_is_texture(dm_view v)
{
    return v == DM_VIEW_IRRADIANCE || v == DM_VIEW_BLUR || v == DM_VIEW_STRETCH || v == DM_VIEW_SHADOW ||
           v == DM_VIEW_DIFFUSION || v == DM_VIEW_CURVATURE || v == DM_VIEW_SEAM || v == DM_VIEW_THIN ||
           v == DM_VIEW_GATHER;
}

bool dm_view_parse(const char *text, dm_view *view, int *index)
{
    for (int v = 0; v < DM_VIEW_COUNT; ++v) {
        size_t n = strlen(view_names[v]);
        if (strncmp(text, view_names[v], n) != 0) continue;
        const char *rest = text + n;
        bool indexed = v == DM_VIEW_BLUR || v == DM_VIEW_STRETCH || v == DM_VIEW_SHADOW;
        if (*rest == '\0') {
            *view = (dm_view)v;
            *index = v == DM_VIEW_BLUR ? -1 : 0; /* −1: the last level */
            return true;
        }
        if (!indexed) continue;
        char *end = NULL;
        long k = strtol(rest, &end, 10);
        /* any index up to 999 parses; dm_render_plan_build says which exist */
        if (*end || k < 0 || k > 999 || rest[0] < '0' || rest[0] > '9') return false;
        *view = (dm_view)v;
        *index = (int)k;
        return true;
    }
    return false;
}

static void add(dm_render_plan *p, dm_pass_kind kind, int index, const char *name, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;
static void add(dm_render_plan *p, dm_pass_kind kind, int index, const char *name, const char *fmt, ...)
{
    dm_pass *ps = &p->passes[p->pass_count++];
    ps->kind = kind;
    ps->index = index;
    snprintf(ps->name, sizeof ps->name, "%s", name);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(ps->why, sizeof ps->why, fmt, ap);
    va_end(ap);
}

#define TRANSMITTED " + transmitted light (shadow-map thickness, profile T(d)) [translucency]"

dm_result dm_render_plan_build(const dm_scene *s, dm_view view, int view_index, dm_render_plan *p, dm_error *err)
{
    memset(p, 0, sizeof *p);
    memcpy(p->effects, s->effects, sizeof p->effects);
    const bool *fx = s->effects;
    const bool sss_on = fx[DM_EFFECT_SUBSURFACE], spec = fx[DM_EFFECT_SPECULAR];
    const bool sss = sss_on && s->sss_technique == DM_SSS_TEXTURE_SPACE; /* texture-space passes */
    const bool ssss = sss_on && s->sss_technique == DM_SSS_SCREEN_SPACE;
    const bool env = fx[DM_EFFECT_ENVIRONMENT_LIGHTING];
    p->energy_conservation_active = fx[DM_EFFECT_ENERGY_CONSERVATION] && spec;
    p->env_specular_active = env && spec;
    p->blur_levels = sss ? s->profile.count : 0;
    p->technique = s->sss_technique;
    p->texture_space = sss;
    p->screen_space = ssss;
    p->pre_integrated = sss_on && s->sss_technique == DM_SSS_PRE_INTEGRATED;
    const bool pre = p->pre_integrated;
    p->view = view;
    if (view == DM_VIEW_BLUR && view_index < 0) view_index = p->blur_levels - 1;
    p->view_index = view_index;

    if (fx[DM_EFFECT_SHADOWS])
        for (int i = 0; i < s->light_count && i < DM_SCENE_MAX_LIGHTS; ++i)
            if (s->lights[i].casts_shadow && p->casting_lights++ < DM_PLAN_MAX_SHADOWS)
                p->shadow_light[p->shadow_count++] = i;
    for (int i = 0; i < s->light_count && i < DM_SCENE_MAX_LIGHTS; ++i) {
        bool mapped = false;
        for (int k = 0; k < p->shadow_count; ++k) mapped |= p->shadow_light[k] == i;
        if (!mapped) p->unshadowed_light[p->unshadowed_count++] = i;
    }
    p->translucency_active = fx[DM_EFFECT_TRANSLUCENCY] && p->shadow_count > 0;
    const char *trans = p->translucency_active ? TRANSMITTED : "";
    /* the view's requirements */
    const char *vname = dm_view_name(view);
    if (!vname) return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "view %d: unknown view", (int)view);
    if ((view == DM_VIEW_IRRADIANCE || view == DM_VIEW_BLUR || view == DM_VIEW_STRETCH || view == DM_VIEW_DIFFUSION ||
         view == DM_VIEW_SEAM || view == DM_VIEW_THIN || view == DM_VIEW_GATHER) &&
        !sss)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "view %s: needs the subsurface effect with the texture-space technique%s",
                       vname, ssss  ? " (this scene uses screen-space)"
                              : pre ? " (this scene uses pre-integrated)"
                                    : ", which this scene turns off");
    if (view == DM_VIEW_BLUR && (view_index < 1 || view_index >= p->blur_levels))
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "view blur%d: blur levels are 1..%d", view_index,
                       p->blur_levels - 1);
    if (view == DM_VIEW_STRETCH && (view_index < 0 || view_index >= p->blur_levels))
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "view stretch%d: stretch levels are 0..%d", view_index,
                       p->blur_levels - 1);
    if (view == DM_VIEW_CURVATURE && !pre)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                       "view curvature: needs the pre-integrated technique's curvature map (this scene uses %s)",
                       sss ? "texture-space" : ssss ? "screen-space" : "no subsurface");
    if (view == DM_VIEW_SHADOW && (view_index < 0 || view_index >= p->shadow_count))
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                       "view shadow%d: this scene has %d shadow map(s) (shadows %s, casting lights)", view_index,
                       p->shadow_count, fx[DM_EFFECT_SHADOWS] ? "on" : "off");

    const bool texture_view = dm_view_is_texture(view);
    char name[DM_PLAN_NAME_SIZE];

    /* shadows feed the irradiance pass and the final pass's lights */
    const bool want_shadows = view != DM_VIEW_STRETCH && view != DM_VIEW_CURVATURE && view != DM_VIEW_UV_TEST &&
                              view != DM_VIEW_WIREFRAME && view != DM_VIEW_SEAM && view != DM_VIEW_THIN &&
                              view != DM_VIEW_GATHER;
    if (want_shadows)
        for (int i = 0; i < p->shadow_count; ++i) {
            if (view == DM_VIEW_SHADOW && i != view_index) continue;
            snprintf(name, sizeof name, "shadow%d", i);
            add(p, DM_PASS_SHADOW, i, name, "shadows: light %d casts; depth map filtered by 3x3 PCF",
                p->shadow_light[i]);
        }
    if (view == DM_VIEW_SHADOW) {
        add(p, DM_PASS_VIEW, view_index, "view", "debug view: shadow depth of light %d", p->shadow_light[view_index]);
        return DM_OK;
    }
    if (view == DM_VIEW_STRETCH) {
        add(p, DM_PASS_VIEW, view_index, "view",
            "debug view: stretch level %d (values: UV units per mm, u, v; shown: mm per texel, colour scale)",
            view_index);
        return DM_OK;
    }
    if (view == DM_VIEW_CURVATURE) {
        add(p, DM_PASS_VIEW, 0, "view", "debug view: mean curvature, 1/mm (colour scale)");
        return DM_OK;
    }
    if (view == DM_VIEW_SEAM || view == DM_VIEW_THIN || view == DM_VIEW_GATHER) { /* the map over the charts */
        add(p, DM_PASS_TS_GBUFFER, 0, "ts_gbuffer", "debug view: the charts' coverage per texel");
        add(p, DM_PASS_VIEW, 0, "view",
            view == DM_VIEW_SEAM   ? "debug view: the seam map, the texels it continues by mm beyond the chart's edge "
                                     "(colour scale), the charts grey"
            : view == DM_VIEW_THIN ? "debug view: the thin-part map, the texels with a point across by its distance, mm "
                                     "(colour scale), the rest of the charts grey"
                                   : "debug view: the thin gather, the texels that gather the widest levels in 3-D by "
                                     "their taps (colour scale), the rest of the charts grey");
        return DM_OK;
    }

    const bool shaded_view = !texture_view && view != DM_VIEW_UV_TEST && view != DM_VIEW_WIREFRAME;
    if (sss && (shaded_view || view == DM_VIEW_IRRADIANCE || view == DM_VIEW_BLUR || view == DM_VIEW_DIFFUSION) &&
        view != DM_VIEW_SPECULAR) {
        add(p, DM_PASS_TS_GBUFFER, 0, "ts_gbuffer",
            "subsurface: the surface per texel (position, normals with the normal map, albedo, rho_s, "
            "roughness) for the irradiance pass; made once, again after a scene change (0 ms otherwise)");
        add(p, DM_PASS_IRRADIANCE, 0, "irradiance",
            "subsurface: lights x N.L (normal map)%s%s%s%s, pre-scatter albedo^%.2g; each covered texel once",
            p->shadow_count ? " x shadow" : "",
            p->energy_conservation_active ? " x (1 - rho_s rho_dt) [energy_conservation]" : "",
            env ? " + SH diffuse [environment_lighting]" : "", trans, (double)s->mix);
        int last = view == DM_VIEW_IRRADIANCE ? 0 : view == DM_VIEW_BLUR ? view_index : p->blur_levels - 1;
        for (int k = 1; k <= last; ++k) {
            double dv = s->profile.variance_mm2[k] - s->profile.variance_mm2[k - 1];
            snprintf(name, sizeof name, "blur_u%d", k);
            add(p, DM_PASS_BLUR_U, k, name, "subsurface: level %d from %d, variance %.4g mm^2 along u, %d taps", k,
                k - 1, dv, s->blur_taps);
            snprintf(name, sizeof name, "blur_v%d", k);
            add(p, DM_PASS_BLUR_V, k, name, "subsurface: level %d from %d, variance %.4g mm^2 along v, %d taps", k,
                k - 1, dv, s->blur_taps);
        }
        if (view != DM_VIEW_IRRADIANCE && view != DM_VIEW_BLUR)
            add(p, DM_PASS_DIFFUSION, 0, "diffusion",
                "subsurface: the %d levels' weighted sum per texel, coverage-normalised, into one texture: "
                "the final pass reads it once per pixel instead of %d levels",
                p->blur_levels, p->blur_levels);
    }
    if (view == DM_VIEW_IRRADIANCE || view == DM_VIEW_BLUR) {
        add(p, DM_PASS_VIEW, view_index, "view", "debug view: %s level %d (coverage-normalised)",
            view == DM_VIEW_IRRADIANCE ? "irradiance" : "blur", view == DM_VIEW_IRRADIANCE ? 0 : view_index);
        return DM_OK;
    }
    if (view == DM_VIEW_DIFFUSION) {
        add(p, DM_PASS_VIEW, 0, "view",
            "debug view: texture-space diffusion, the %d levels weighted per channel as the final pass sums them",
            p->blur_levels);
        return DM_OK;
    }

    const char *mode = view == DM_VIEW_FINAL      ? ""
                       : view == DM_VIEW_SPECULAR ? " [debug view: specular only]"
                       : view == DM_VIEW_DIFFUSE  ? " [debug view: diffuse only]"
                       : view == DM_VIEW_UV_TEST  ? " [debug view: UV checker]"
                                                  : " [debug view: wireframe]";
    const bool ss_view = ssss && (view == DM_VIEW_FINAL || view == DM_VIEW_SPECULAR || view == DM_VIEW_DIFFUSE);
    /* Deferred shading pays where the per-pixel shading outweighs the G-buffer (a raster into
     * four float targets): lights evaluated per pixel, i.e. specular, or the diffuse of every
     * technique but texture-space, whose diffuse is the levels' sum. Texture-space without
     * specular shades while rasterising: six level fetches and the albedo cost less. A property
     * of the scene, so that the renderer makes the G-buffer and its programs only for it. */
    p->deferred = !sss || spec;
    const bool deferred = shaded_view && p->deferred;
    if (deferred)
        add(p, DM_PASS_GBUFFER, 0, "gbuffer",
            "always: the head's surface per pixel (position, normals with the normal map, uv, albedo, rho_s, "
            "roughness), for %s to shade each pixel once", ss_view ? "ss_shade" : "final");
    if (ss_view) {
        add(p, DM_PASS_SS_SHADE, 0, "ss_shade",
            "subsurface [screen-space]: lights x N.L%s%s%s%s, pre-scatter albedo^%.2g, eye depth; post-scatter "
            "albedo^(1-mix)%s; specular%s%s apart%s",
            p->shadow_count ? " x shadow" : "",
            p->energy_conservation_active ? " x (1 - rho_s rho_dt) [energy_conservation]" : "",
            env ? " + SH diffuse [environment_lighting]" : "", trans, (double)s->mix,
            p->energy_conservation_active ? " x (1 - rho_s rho_dt(N.V))" : "", spec ? " (KS [specular])" : " (none)",
            p->env_specular_active ? " + env split-sum [environment_lighting]" : "", mode);
        add(p, DM_PASS_SS_BLUR_H, 0, "ss_blur_h",
            "subsurface [screen-space]: %d-tap kernel fitted to the profile along x, width in mm from mm_per_unit "
            "and depth, follow-surface, skin pixels only",
            s->screen_taps);
        add(p, DM_PASS_SS_BLUR_V, 0, "ss_blur_v",
            "subsurface [screen-space]: the same along y, x post-scatter albedo, + specular");
    } else if (shaded_view)
        add(p, deferred ? DM_PASS_FINAL : DM_PASS_FINAL_FORWARD, 0, "final", "always: %s diffuse%s%s%s%s%s%s%s",
            sss   ? "the levels' weighted sum x post-scatter albedo^(1-mix)"
            : pre ? "pre-integrated (Penner): lights x table(N.L per channel, curvature) x shadow, x albedo "
                    "[subsurface, pre-integrated]"
                  : "Lambert (subsurface off) x albedo",
            spec ? " + KS specular (Beckmann LUT, Schlick F0 0.028, spec map) [specular]" : "",
            p->energy_conservation_active ? " x (1 - rho_s rho_dt(N.V)) [energy_conservation]" : "",
            p->env_specular_active ? " + env split-sum specular [environment_lighting]" : "",
            env && !sss ? " + SH diffuse [environment_lighting]" : "", !sss ? trans : "",
            deferred ? "; each pixel once, from the G-buffer" : "; while rasterising", mode);
    else
        add(p, DM_PASS_FINAL_FORWARD, 0, "final", "always: draws the mesh%s", mode);
    if (env && s->env_background && s->environment[0] && shaded_view)
        add(p, DM_PASS_BACKGROUND, 0, "background",
            "environment_lighting with env_background: equirect radiance behind the head");
    if (fx[DM_EFFECT_GLOW] && shaded_view) {
        add(p, DM_PASS_GLOW_BRIGHT, 0, "glow_bright", "glow: max(c - %.3g, 0) at half resolution",
            (double)s->glow_threshold);
        add(p, DM_PASS_GLOW_BLUR_U, 0, "glow_blur_u", "glow: Gaussian along x at half resolution");
        add(p, DM_PASS_GLOW_BLUR_V, 0, "glow_blur_v", "glow: Gaussian along y at half resolution");
        p->glow_in_tonemap = fx[DM_EFFECT_TONEMAP];
        if (!p->glow_in_tonemap)
            add(p, DM_PASS_GLOW_ADD, 0, "glow_add", "glow: adds %.3g x the blurred bright pass",
                (double)s->glow_intensity);
    }
    if (fx[DM_EFFECT_TONEMAP] && shaded_view)
        add(p, DM_PASS_TONEMAP, 0, "tonemap", "tonemap: exposure %+.2g stops, filmic curve, sRGB%s",
            (double)s->exposure,
            p->glow_in_tonemap ? "; first adds the glow (its intensity x the blurred bright pass) [glow]" : "");
    return DM_OK;
}

int dm_render_plan_find(const dm_render_plan *plan, const char *name)
{
    for (int i = 0; i < plan->pass_count; ++i)
        if (strcmp(plan->passes[i].name, name) == 0) return i;
    return -1;
}

typedef struct sbuf {
    char *out;
    size_t size, len;
} sbuf;

static void put(sbuf *b, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static void put(sbuf *b, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    size_t room = b->len < b->size ? b->size - b->len : 0;
    int n = vsnprintf(room ? b->out + b->len : NULL, room, fmt, ap);
    va_end(ap);
    if (n > 0) b->len += (size_t)n;
}

size_t dm_render_plan_explain(const dm_render_plan *p, char *out, size_t out_size)
{
    sbuf b = {out, out_size, 0};
    if (out_size) out[0] = '\0';
    put(&b, "view %s", dm_view_name(p->view));
    if (p->view == DM_VIEW_BLUR || p->view == DM_VIEW_STRETCH || p->view == DM_VIEW_SHADOW)
        put(&b, "%d", p->view_index);
    put(&b, ": %d passes\n", p->pass_count);
    for (int i = 0; i < p->pass_count; ++i)
        put(&b, "  %2d  %-12s %s\n", i, p->passes[i].name, p->passes[i].why);
    static const char *removes[DM_EFFECT_COUNT] = {
        "no specular term, no Beckmann LUT",
        "no irradiance texture, no blur passes: Lambert diffuse in the final pass",
        "no 1 - rho_s rho_dt factor",
        "no shadow passes",
        "no SH diffuse, no environment specular, no background",
        "no glow passes",
        "no tonemap pass: linear radiance clamped and sRGB-encoded on readback",
        "no transmitted light through thin parts",
    };
    bool any_off = false;
    for (int e = 0; e < DM_EFFECT_COUNT; ++e)
        if (!p->effects[e]) {
            if (!any_off) put(&b, "effects off:\n");
            any_off = true;
            put(&b, "      %-20s %s\n", dm_effect_name((dm_effect)e), removes[e]);
        }
    if (p->effects[DM_EFFECT_ENERGY_CONSERVATION] && !p->effects[DM_EFFECT_SPECULAR])
        put(&b, "note: energy_conservation is inactive without specular (no light is taken by the surface)\n");
    if (p->casting_lights > p->shadow_count && p->shadow_count > 0)
        put(&b, "note: %d lights cast; only the first %d get shadow maps\n", p->casting_lights, p->shadow_count);
    if (p->effects[DM_EFFECT_SUBSURFACE])
        put(&b, "subsurface technique: %s\n", dm_sss_technique_name(p->technique));
    if (p->translucency_by_thin_map)
        put(&b, "note: translucency adds no light: the thin-part map carries the light through thin parts "
                "(texture-space; on top it would count it twice)\n");
    else if (p->effects[DM_EFFECT_TRANSLUCENCY] && !p->translucency_active)
        put(&b, "note: translucency is inactive: it reads thickness from a shadow map, and no light has one\n");
    if (p->texture_space && p->unshadowed_count > 0) {
        put(&b, "note: light%s", p->unshadowed_count > 1 ? "s" : "");
        for (int k = 0; k < p->unshadowed_count; ++k) put(&b, "%s%d", k ? ", " : " ", p->unshadowed_light[k]);
        put(&b, " %s no shadow map: %s what the head hides from %s (inside the eye slits, the nostrils, the mouth), "
                "and the texture-space blur carries that light out: a red line along the lids and rims where a light "
                "comes from behind (docs/crevices.md)\n",
            p->unshadowed_count > 1 ? "have" : "has", p->unshadowed_count > 1 ? "they also light" : "it also lights",
            p->unshadowed_count > 1 ? "them" : "it");
    }
    if (p->effects[DM_EFFECT_SHADOWS] && p->shadow_count == 0)
        put(&b, "note: shadows on but no light casts: no shadow pass\n");
    return b.len;
}

void dm_render_plan_sum_per_pixel(dm_render_plan *plan)
{
    int i = dm_render_plan_find(plan, "diffusion");
    if (i < 0) return;
    memmove(&plan->passes[i], &plan->passes[i + 1], sizeof plan->passes[0] * (size_t)(plan->pass_count - i - 1));
    --plan->pass_count;
}

void dm_render_plan_thin_map(dm_render_plan *plan)
{
    if (!plan->texture_space || !plan->translucency_active) return;
    plan->translucency_active = false, plan->translucency_by_thin_map = true;
    const size_t n = strlen(TRANSMITTED);
    for (int i = 0; i < plan->pass_count; ++i) {
        char *w = strstr(plan->passes[i].why, TRANSMITTED);
        if (w) memmove(w, w + n, strlen(w + n) + 1);
    }
}
