/* The pass graph: which passes each scene's effects call for (no GL needed). */
#include <criterion/criterion.h>
#include <string.h>

#include "render/dm_render_plan.h"
#include "render/dm_render_synth.h"

static void scene_with(dm_scene *s, const dm_effect *on, int n)
{
    dm_synth_scene(s, 4.5f);
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) s->effects[e] = false;
    for (int i = 0; i < n; ++i) s->effects[on[i]] = true;
}

static void names(const dm_render_plan *p, char *out, size_t size)
{
    out[0] = '\0';
    for (int i = 0; i < p->pass_count; ++i) {
        if (i) strncat(out, " ", size - strlen(out) - 1);
        strncat(out, p->passes[i].name, size - strlen(out) - 1);
    }
}

static void plan_of(const dm_scene *s, char *out, size_t size)
{
    dm_render_plan p;
    dm_error err = {0};
    cr_assert_eq(dm_render_plan_build(s, DM_VIEW_FINAL, 0, &p, &err), DM_OK, "%s", err.detail);
    names(&p, out, size);
}

Test(render_plan, specular_only_runs_exactly_the_specular_passes)
{
    dm_scene s;
    dm_effect on[] = {DM_EFFECT_SPECULAR};
    scene_with(&s, on, 1);
    char list[1024];
    plan_of(&s, list, sizeof list);
    cr_expect_str_eq(list, "gbuffer final");
    dm_render_plan p;
    cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, NULL), DM_OK);
    cr_expect(!p.energy_conservation_active && !p.env_specular_active && p.blur_levels == 0);
}

Test(render_plan, all_effects_full_chain)
{
    dm_scene s;
    dm_synth_scene(&s, 4.5f);
    char list[1024];
    plan_of(&s, list, sizeof list);
    cr_expect_str_eq(list, "shadow0 ts_gbuffer irradiance blur_u1 blur_v1 blur_u2 blur_v2 blur_u3 blur_v3 blur_u4 blur_v4 "
                           "blur_u5 blur_v5 diffusion gbuffer final background glow_bright glow_blur_u glow_blur_v tonemap");
}

/* Turning off each effect removes exactly its passes (and nothing else; turning the tonemap off
 * brings glow_add back, since with a tonemap that pass adds the glow). */
Test(render_plan, each_effect_off_removes_its_passes)
{
    static const char *expect[DM_EFFECT_COUNT] = {
        /* texture-space without specular shades while rasterising: no G-buffer */
        [DM_EFFECT_SPECULAR] = "shadow0 ts_gbuffer irradiance blur_u1 blur_v1 blur_u2 blur_v2 blur_u3 blur_v3 blur_u4 blur_v4 "
                               "blur_u5 blur_v5 diffusion final background glow_bright glow_blur_u glow_blur_v tonemap",
        [DM_EFFECT_SUBSURFACE] = "shadow0 gbuffer final background glow_bright glow_blur_u glow_blur_v tonemap",
        [DM_EFFECT_ENERGY_CONSERVATION] = "shadow0 ts_gbuffer irradiance blur_u1 blur_v1 blur_u2 blur_v2 blur_u3 blur_v3 "
                                          "blur_u4 blur_v4 blur_u5 blur_v5 diffusion gbuffer final background glow_bright "
                                          "glow_blur_u glow_blur_v tonemap",
        [DM_EFFECT_SHADOWS] = "ts_gbuffer irradiance blur_u1 blur_v1 blur_u2 blur_v2 blur_u3 blur_v3 blur_u4 blur_v4 blur_u5 "
                              "blur_v5 diffusion gbuffer final background glow_bright glow_blur_u glow_blur_v tonemap",
        [DM_EFFECT_ENVIRONMENT_LIGHTING] = "shadow0 ts_gbuffer irradiance blur_u1 blur_v1 blur_u2 blur_v2 blur_u3 blur_v3 "
                                           "blur_u4 blur_v4 blur_u5 blur_v5 diffusion gbuffer final glow_bright glow_blur_u "
                                           "glow_blur_v tonemap",
        [DM_EFFECT_GLOW] = "shadow0 ts_gbuffer irradiance blur_u1 blur_v1 blur_u2 blur_v2 blur_u3 blur_v3 blur_u4 blur_v4 "
                           "blur_u5 blur_v5 diffusion gbuffer final background tonemap",
        [DM_EFFECT_TONEMAP] = "shadow0 ts_gbuffer irradiance blur_u1 blur_v1 blur_u2 blur_v2 blur_u3 blur_v3 blur_u4 blur_v4 "
                              "blur_u5 blur_v5 diffusion gbuffer final background glow_bright glow_blur_u glow_blur_v glow_add",
        /* translucency adds no pass (it changes the irradiance shader): off changes nothing */
        [DM_EFFECT_TRANSLUCENCY] = "shadow0 ts_gbuffer irradiance blur_u1 blur_v1 blur_u2 blur_v2 blur_u3 blur_v3 blur_u4 "
                                   "blur_v4 blur_u5 blur_v5 diffusion gbuffer final background glow_bright glow_blur_u glow_blur_v "
                                   "tonemap",
    };
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) {
        dm_scene s;
        dm_synth_scene(&s, 4.5f);
        s.effects[e] = false;
        char list[1024];
        plan_of(&s, list, sizeof list);
        cr_expect_str_eq(list, expect[e], "with %s off", dm_effect_name((dm_effect)e));
        dm_render_plan p;
        dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, NULL);
        if (e == DM_EFFECT_SPECULAR || e == DM_EFFECT_ENERGY_CONSERVATION)
            cr_expect(!p.energy_conservation_active, "energy conservation still active with %s off",
                      dm_effect_name((dm_effect)e));
        if (e == DM_EFFECT_SPECULAR || e == DM_EFFECT_ENVIRONMENT_LIGHTING) cr_expect(!p.env_specular_active);
        /* deferred unless texture-space without specular; subsurface off: Lambert, deferred */
        cr_expect_eq(p.deferred, e != DM_EFFECT_SPECULAR, "deferred with %s off", dm_effect_name((dm_effect)e));
    }
}

Test(render_plan, shadow_pass_per_casting_light_only)
{
    dm_scene s;
    dm_synth_scene(&s, 4.5f);
    s.light_count = 3;
    s.lights[1] = s.lights[0];
    s.lights[2] = s.lights[0];
    s.lights[1].casts_shadow = false;
    dm_render_plan p;
    cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, NULL), DM_OK);
    cr_expect_eq(p.shadow_count, 2);
    cr_expect_eq(p.shadow_light[0], 0);
    cr_expect_eq(p.shadow_light[1], 2);
    cr_expect_geq(dm_render_plan_find(&p, "shadow1"), 0);
    cr_expect_lt(dm_render_plan_find(&p, "shadow2"), 0);
}

Test(render_plan, profile_count_sets_the_blur_chain)
{
    dm_scene s;
    dm_synth_scene(&s, 4.5f);
    s.profile.count = 3;
    dm_render_plan p;
    cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, NULL), DM_OK);
    cr_expect_geq(dm_render_plan_find(&p, "blur_v2"), 0);
    cr_expect_lt(dm_render_plan_find(&p, "blur_u3"), 0);
}

Test(render_plan, views_refuse_what_the_scene_lacks)
{
    dm_scene s;
    dm_effect on[] = {DM_EFFECT_SPECULAR};
    scene_with(&s, on, 1);
    dm_render_plan p;
    dm_error err = {0};
    cr_expect_eq(dm_render_plan_build(&s, DM_VIEW_IRRADIANCE, 0, &p, &err), DM_ERR_INVALID_ARGUMENT);
    cr_expect(strstr(err.detail, "subsurface") != NULL, "%s", err.detail);
    cr_expect_eq(dm_render_plan_build(&s, DM_VIEW_SHADOW, 0, &p, &err), DM_ERR_INVALID_ARGUMENT);
    dm_synth_scene(&s, 4.5f);
    cr_expect_eq(dm_render_plan_build(&s, DM_VIEW_BLUR, 6, &p, &err), DM_ERR_INVALID_ARGUMENT);
    cr_expect_eq(dm_render_plan_build(&s, DM_VIEW_BLUR, 0, &p, &err), DM_ERR_INVALID_ARGUMENT);
    cr_expect_eq(dm_render_plan_build(&s, DM_VIEW_BLUR, -1, &p, &err), DM_OK); /* -1: the last level */
    cr_expect_eq(p.view_index, 5);
    cr_expect_eq(dm_render_plan_build(&s, DM_VIEW_BLUR, 2, &p, &err), DM_OK);
    char list[1024];
    names(&p, list, sizeof list);
    cr_expect_str_eq(list, "shadow0 ts_gbuffer irradiance blur_u1 blur_v1 blur_u2 blur_v2 view");
    cr_expect_eq(dm_render_plan_build(&s, DM_VIEW_STRETCH, 0, &p, &err), DM_OK);
    names(&p, list, sizeof list);
    cr_expect_str_eq(list, "view");
}

Test(render_plan, view_names_parse)
{
    dm_view v;
    int k;
    cr_expect(dm_view_parse("blur3", &v, &k) && v == DM_VIEW_BLUR && k == 3);
    cr_expect(dm_view_parse("blur", &v, &k) && v == DM_VIEW_BLUR && k == -1);
    cr_expect(dm_view_parse("shadow0", &v, &k) && v == DM_VIEW_SHADOW && k == 0);
    cr_expect(dm_view_parse("wireframe", &v, &k) && v == DM_VIEW_WIREFRAME);
    cr_expect(!dm_view_parse("final2", &v, &k));
    cr_expect(!dm_view_parse("blurx", &v, &k));
    cr_expect(!dm_view_parse("nonsense", &v, &k));
}

Test(render_plan, explain_names_every_pass_and_every_effect_off)
{
    dm_scene s;
    dm_effect on[] = {DM_EFFECT_SPECULAR, DM_EFFECT_SUBSURFACE};
    scene_with(&s, on, 2);
    dm_render_plan p;
    cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, NULL), DM_OK);
    char text[8192];
    size_t n = dm_render_plan_explain(&p, text, sizeof text);
    cr_assert_lt(n, sizeof text);
    for (int i = 0; i < p.pass_count; ++i) cr_expect(strstr(text, p.passes[i].name) != NULL);
    cr_expect(strstr(text, "glow") && strstr(text, "tonemap") && strstr(text, "shadows"), "%s", text);
    char tiny[8];
    cr_expect_eq(dm_render_plan_explain(&p, tiny, sizeof tiny), n); /* truncated, length still reported */
    cr_expect_eq(strlen(tiny), sizeof tiny - 1);
}

/* With the thin-part map in use (texture-space), translucency adds no light: inactive, gone
 * from the irradiance pass's description, and explain says why; the screen-space and
 * pre-integrated plans, which have no map, keep it. */
Test(render_plan, thin_map_takes_translucency_s_place_in_texture_space)
{
    dm_scene s;
    dm_synth_scene(&s, 4.5f);
    s.effects[DM_EFFECT_TRANSLUCENCY] = true;
    dm_render_plan p;
    cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, NULL), DM_OK);
    int irr = dm_render_plan_find(&p, "irradiance");
    cr_assert(p.translucency_active && irr >= 0 && strstr(p.passes[irr].why, "[translucency]"));
    dm_render_plan_thin_map(&p);
    cr_expect(!p.translucency_active && p.translucency_by_thin_map);
    cr_expect_null(strstr(p.passes[irr].why, "translucency"), "%s", p.passes[irr].why);
    char text[8192];
    dm_render_plan_explain(&p, text, sizeof text);
    cr_expect(strstr(text, "note: translucency adds no light: the thin-part map carries the light"), "%s", text);
    for (int t = 0; t < 2; ++t) {
        s.sss_technique = t ? DM_SSS_PRE_INTEGRATED : DM_SSS_SCREEN_SPACE;
        cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, NULL), DM_OK);
        dm_render_plan_thin_map(&p);
        cr_expect(p.translucency_active && !p.translucency_by_thin_map, "%s", dm_sss_technique_name(s.sss_technique));
    }
}

/* A light without a shadow map lights what the head hides from it (inside the eye slits and
 * nostrils) and the texture-space blur carries that light out (docs/crevices.md): explain
 * names every such light in texture space — one that casts none, all of them with shadows
 * off — and none when each light has its map or the technique has no texture-space blur. */
Test(render_plan, explain_names_the_lights_without_a_shadow_map)
{
    dm_scene s;
    dm_synth_scene(&s, 4.5f);
    s.light_count = 3;
    s.lights[1] = s.lights[0], s.lights[2] = s.lights[0];
    s.lights[1].casts_shadow = false;
    dm_render_plan p;
    char text[8192];
    cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, NULL), DM_OK);
    cr_expect(p.unshadowed_count == 1 && p.unshadowed_light[0] == 1);
    dm_render_plan_explain(&p, text, sizeof text);
    cr_expect(strstr(text, "note: light 1 has no shadow map: it also lights what the head hides from it"), "%s", text);
    s.effects[DM_EFFECT_SHADOWS] = false;
    cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, NULL), DM_OK);
    dm_render_plan_explain(&p, text, sizeof text);
    cr_expect(strstr(text, "note: lights 0, 1, 2 have no shadow map: they also light what the head hides from them"), "%s", text);
    s.effects[DM_EFFECT_SHADOWS] = true, s.lights[1].casts_shadow = true;
    cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, NULL), DM_OK);
    dm_render_plan_explain(&p, text, sizeof text);
    cr_expect(p.unshadowed_count == 0 && !strstr(text, "no shadow map"), "%s", text);
    s.light_count = DM_PLAN_MAX_SHADOWS + 2; /* every one casts, the last two past the maps */
    for (int i = 0; i < s.light_count; ++i) s.lights[i] = s.lights[0];
    cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, NULL), DM_OK);
    cr_expect(p.unshadowed_count == 2 && p.unshadowed_light[0] == DM_PLAN_MAX_SHADOWS &&
              p.unshadowed_light[1] == DM_PLAN_MAX_SHADOWS + 1);
    s.light_count = 3, s.lights[1].casts_shadow = false, s.sss_technique = DM_SSS_SCREEN_SPACE;
    cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, NULL), DM_OK);
    dm_render_plan_explain(&p, text, sizeof text);
    cr_expect(!strstr(text, "no shadow map"), "%s", text);
}
