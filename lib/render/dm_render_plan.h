/* dm_render_plan.h — the pass graph: which passes a scene's effects call for, in order,
 * and why (DESIGN.md promise 3: simulate only the effects a scene calls for).
 *
 * Pure data, no GL: tests check the pass list of a scene without a context.
 *
 * Passes, in frame order, and the rule that puts each in the plan:
 *   shadow L         shadows on, light L casts (one per casting light, the first
 *                    DM_PLAN_MAX_SHADOWS = 4 casting lights; explain notes any beyond)
 *   ts_gbuffer       subsurface on (texture space): the surface per texel (position, normals,
 *                    material) into a G-buffer; runs once, and again after a scene change
 *   irradiance       the same: each covered texel lit from it (lights, shadow, env SH, albedo^mix)
 *   blur_u k, blur_v k   subsurface on, k = 1..profile.count−1
 *   gbuffer          shaded views (final, specular, diffuse) whose shading evaluates lights
 *                    per pixel (specular on, or any technique but texture-space): the head's
 *                    surface per pixel (position, normals with the normal map, uv, albedo,
 *                    rho_s, roughness)
 *   final            always: shades each head pixel once from the G-buffer, or while
 *                    rasterising without one (diffuse, specular, environment terms; with the
 *                    pre-integrated technique its diffuse comes from the table); not with the
 *                    screen-space technique, except for the uv and wireframe views, where it
 *                    draws the mesh itself
 *   ss_shade         subsurface on, technique screen-space: each head pixel shaded from the
 *                    G-buffer into three screen targets (pre-scatter diffuse + eye depth,
 *                    post-scatter factor, specular)
 *   ss_blur_h, ss_blur_v   the same: the separable kernel along x, then y (+ combine), on
 *                    skin pixels only
 *   background       environment given and shown (scene->env_background), and
 *                    environment_lighting on
 *   glow_bright, glow_blur_u, glow_blur_v   glow on; glow_add too when tonemap is off
 *   tonemap          tonemap on (exposure, filmic, sRGB; adds the glow)
 * Debug views replace final..tonemap by the passes they need (a `view` pass copying the
 * texture to the screen for texture views; final with a mode for shaded views).
 * Effects that only change a shader (energy_conservation, environment_lighting's SH and
 * split-sum terms, specular, translucency) add no pass of their own; explain lists them per
 * pass. Translucency needs a shadow map (it reads the thickness from it): with no casting
 * light it is inactive, and explain says so.
 */
#ifndef DM_RENDER_PLAN_H
#define DM_RENDER_PLAN_H

#include <stdbool.h>
#include <stddef.h>

#include "core/dm_result.h"
#include "core/dm_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum dm_view {
    DM_VIEW_FINAL = 0,  /* the picture */
    DM_VIEW_IRRADIANCE, /* texture-space irradiance (level 0), coverage-normalised */
    DM_VIEW_BLUR,       /* blur level k (view_index, 1..count−1) */
    DM_VIEW_STRETCH,    /* stretch level k (u, v in red, green) */
    DM_VIEW_SHADOW,     /* shadow depth of casting light k */
    DM_VIEW_SPECULAR,   /* shaded, specular terms only */
    DM_VIEW_DIFFUSE,    /* shaded, diffuse terms only */
    DM_VIEW_UV_TEST,    /* a UV checker on the head (texture-space layout check) */
    DM_VIEW_WIREFRAME,  /* triangle edges */
    DM_VIEW_DIFFUSION,  /* texture-space diffusion result: sum_k w_k L_k over every level,
                         * each level coverage-normalised and the weights normalised per
                         * channel, exactly as the final pass samples it */
    DM_VIEW_CURVATURE,  /* the pre-integrated technique's mean curvature map (1/mm) */
    DM_VIEW_SEAM,       /* the seam map: the gutter texels it continues, coloured by mm beyond the
                         * chart's edge; the charts grey */
    DM_VIEW_THIN,       /* the thin-part map: the texels with a point across, coloured by its
                         * distance (the nearer of up to two), mm; the rest of the charts grey */
    DM_VIEW_GATHER,     /* the thin gather: the texels that gather, coloured by their taps (the
                         * first two gathered levels', which the index holds); the rest grey */
    DM_VIEW_COUNT
} dm_view;

/* "final", "irradiance", "blur", "stretch", "shadow", "specular", "diffuse", "uv",
 * "wireframe", "diffusion", "curvature", "seam", "thin", "gather"; NULL when out of range. */
const char *dm_view_name(dm_view v);
/* Parses "final", "irradiance", "blur3", "stretch0", "shadow1", ... (index defaults 0,
 * blur defaults to the last level). Returns false for an unknown name. */
bool dm_view_parse(const char *text, dm_view *view, int *index);

typedef enum dm_pass_kind {
    DM_PASS_SHADOW = 0,
    DM_PASS_IRRADIANCE,
    DM_PASS_BLUR_U,
    DM_PASS_BLUR_V,
    DM_PASS_FINAL,
    DM_PASS_BACKGROUND,
    DM_PASS_GLOW_BRIGHT,
    DM_PASS_GLOW_BLUR_U,
    DM_PASS_GLOW_BLUR_V,
    DM_PASS_GLOW_ADD,
    DM_PASS_TONEMAP,
    DM_PASS_VIEW,
    DM_PASS_SS_SHADE,
    DM_PASS_SS_BLUR_H,
    DM_PASS_SS_BLUR_V,
    DM_PASS_GBUFFER,
    DM_PASS_TS_GBUFFER,
    DM_PASS_FINAL_FORWARD,
    DM_PASS_DIFFUSION,
    DM_PASS_KIND_COUNT
} dm_pass_kind;

enum { DM_PLAN_MAX_SHADOWS = 4, DM_PLAN_MAX_PASSES = 48, DM_PLAN_NAME_SIZE = 32, DM_PLAN_WHY_SIZE = 320 };

typedef struct dm_pass {
    dm_pass_kind kind;
    int index;                    /* light (shadow), level (blur), 0 otherwise */
    char name[DM_PLAN_NAME_SIZE]; /* "shadow0", "blur_u3", "final", ... */
    char why[DM_PLAN_WHY_SIZE];   /* the effect (and setting) that needs it, and what it
                                   * adds to the pass: "subsurface: variance 0.139 mm²" */
} dm_pass;

typedef struct dm_render_plan {
    int pass_count;
    dm_pass passes[DM_PLAN_MAX_PASSES];
    bool effects[DM_EFFECT_COUNT]; /* as in the scene */
    bool energy_conservation_active; /* energy_conservation and specular both on */
    bool env_specular_active;        /* environment_lighting and specular both on */
    bool deferred;                   /* shaded views draw a G-buffer and shade from it (every
                                      * technique but texture-space without specular) */
    bool glow_in_tonemap;            /* glow and tonemap both on: the tonemap pass adds the glow
                                      * (no glow_add pass; the linear screen gets it when read) */
    int shadow_count;                /* casting lights given a shadow map, ≤ DM_PLAN_MAX_SHADOWS */
    int casting_lights;              /* all lights that cast (more than shadow_count: no map) */
    int shadow_light[DM_SCENE_MAX_LIGHTS]; /* their light indices */
    int unshadowed_count;            /* lights lit without a shadow map (shadows off, the light
                                      * casts none, or past DM_PLAN_MAX_SHADOWS) */
    int unshadowed_light[DM_SCENE_MAX_LIGHTS]; /* their light indices */
    int blur_levels;                 /* Gaussians (levels incl. level 0), 0 without texture-space subsurface */
    dm_sss_technique technique;      /* the scene's subsurface technique */
    bool texture_space;              /* subsurface on with the texture-space technique */
    bool screen_space;               /* subsurface on with the screen-space technique */
    bool pre_integrated;             /* subsurface on with the pre-integrated technique (final pass only) */
    bool translucency_active;        /* translucency on and at least one shadow map */
    bool translucency_by_thin_map;   /* translucency on, texture-space with the thin-part map:
                                      * the map carries that light, so none is added
                                      * (dm_render_plan_thin_map) */
    dm_view view;
    int view_index;
} dm_render_plan;

/* Whether the view shows a texture (irradiance, blur, stretch, shadow, diffusion) rather
 * than the head on screen: its full-precision output has the texture's size. */
bool dm_view_is_texture(dm_view v);

/* Builds the plan for `scene` showing `view` (index: level or light). Fails with
 * DM_ERR_INVALID_ARGUMENT, naming the view and the effect it needs, when the view cannot
 * be shown for this scene (e.g. blur without subsurface, shadow2 with two casters). */
dm_result dm_render_plan_build(const dm_scene *scene, dm_view view, int view_index, dm_render_plan *plan,
                               dm_error *err);

/* The pass list with one line per pass ("  3  blur_u1      subsurface: ..."), then the
 * effects that are off and what that removed. Writes at most out_size bytes (always
 * NUL-terminated); returns the length the full text needs. */
size_t dm_render_plan_explain(const dm_render_plan *plan, char *out, size_t out_size);

/* The index of the first pass with that name, or −1. */
int dm_render_plan_find(const dm_render_plan *plan, const char *name);

/* Takes the diffusion pass out of the plan (dm_render_desc.diffusion_per_pixel, or reduced
 * levels: the final pass and the diffusion view sum the levels per pixel instead). */
void dm_render_plan_sum_per_pixel(dm_render_plan *plan);

/* The renderer uses the pack's thin-part map (texture-space): it carries the light through
 * thin parts and across folds that translucency would add from the shadow map's thickness,
 * exactly for parallel sheets and by the profile's own falloff. Translucency on top counts
 * that light twice and measured worse against the ground truth in every region (head, 1024²,
 * % red: smooth 0.66 → 9.73, seam 3.49 → 24.9, thin 15.0 → 20.1; docs/thin-map.md), so it
 * is made inactive and the passes' descriptions and explain say why. */
void dm_render_plan_thin_map(dm_render_plan *plan);


#ifdef __cplusplus
}
#endif
#endif
