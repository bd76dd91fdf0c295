/* The real head, end to end: each bundled scene (assets/scenes/) is packed by
 * dermis-pack at a reduced size (irradiance 256², 160×120 output, so a test takes a few
 * seconds on llvmpipe), opened through the verified pack reader and rendered.
 * Checks: no GL error and no NaN/Inf in any intermediate target; golden images; the
 * specular-only scene runs exactly its passes; light from behind the head. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <criterion/criterion.h>
#include <limits.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../common/render_fixture.h"
#include "../common/tmpdir.h"
#include "pack/dm_pack.h"
#include "core/dm_scene.h"
#include "dm_golden.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_pack.h"

enum { W = 160, H = 120, IRR = 256 };

typedef struct head {
    char dir[64];
    dm_pack pack;
    dm_scene scene;
    dm_profile profile;
    dm_render_assets assets;
    dm_osmesa *ctx;
    dm_renderer *r;
} head;

/* The test size's renderer over assets (the pack's, or a copy with another scene). */
static void create_renderer(head *h, const dm_render_assets *a)
{
    dm_error err = {0};
    dm_render_desc d = {.width = W, .height = H, .irradiance_size = IRR, .shadow_size = 512};
    cr_assert_eq(dm_renderer_create(a, &d, &h->r, &err), DM_OK, "%s", err.detail);
}

/* Reads the bundled scene, shrinks it, lets `edit` change it, packs it with dermis-pack. */
static void pack_scene(head *h, const char *name, void (*edit)(dm_scene *))
{
    memset(h, 0, sizeof *h);
    cr_assert(test_tmpdir(h->dir, sizeof h->dir));
    char rel[256], abs_path[PATH_MAX], scene_path[128], pack_path[128], cmd[1024], log[160];
    snprintf(rel, sizeof rel, "assets/scenes/%s.json", name);
    cr_assert(realpath(rel, abs_path), "%s: run from the repository root", rel);
    dm_scene s;
    dm_error err = {0};
    cr_assert_eq(dm_scene_read(abs_path, &s, &err), DM_OK, "%s", err.detail);
    s.irradiance_size = IRR;
    s.width = W;
    s.height = H;
    if (edit) edit(&s);
    char *json = NULL;
    cr_assert_eq(dm_scene_to_json(&s, &json, &err), DM_OK, "%s", err.detail);
    snprintf(scene_path, sizeof scene_path, "%s/scene.json", h->dir);
    FILE *f = fopen(scene_path, "w");
    cr_assert(f);
    fputs(json, f);
    fclose(f);
    free(json);
    snprintf(pack_path, sizeof pack_path, "%s/head.dpk", h->dir);
    snprintf(log, sizeof log, "%s/pack.log", h->dir);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack %s -o %s --quiet", scene_path, pack_path);
    int rc = test_run(cmd, log);
    char *text = rc ? test_slurp(log) : NULL;
    cr_assert_eq(rc, 0, "dermis-pack failed: %s", text ? text : "");
    cr_assert_eq(dm_pack_open(pack_path, &h->pack, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_assets_from_pack(&h->pack, &h->scene, &h->profile, &h->assets, &err), DM_OK, "%s",
                 err.detail);
    cr_assert_eq(dm_osmesa_create(&h->ctx, &err), DM_OK, "%s", err.detail);
    create_renderer(h, &h->assets);
}

static void close_head(head *h)
{
    dm_renderer_destroy(h->r);
    dm_osmesa_destroy(h->ctx);
    dm_pack_close(&h->pack);
}

static void render(head *h, dm_view view, int index)
{
    dm_error err = {0};
    dm_frame_options o = {.view = view, .view_index = index};
    cr_assert_eq(dm_render_frame(h->r, &o, &err), DM_OK, "%s", err.detail);
}

static float *head_target(head *h, const char *name, dm_target_info *info)
{
    return read_renderer_target(h->r, name, info);
}

static void expect_targets_finite(head *h, const char *when)
{
    for (int t = 0; t < dm_renderer_target_count(h->r); ++t) {
        dm_target_info info;
        dm_renderer_target_info(h->r, t, &info);
        float *px = head_target(h, info.name, &info);
        size_t n = (size_t)info.width * info.height * info.channels, bad = 0;
        for (size_t i = 0; i < n; ++i) bad += !isfinite(px[i]);
        cr_expect_eq(bad, 0, "%s: target %s holds %zu NaN/Inf values", when, info.name, bad);
        free(px);
    }
}

Test(head, all_effects_every_view_no_gl_error_and_every_target_finite, .timeout = 120)
{
    head h;
    pack_scene(&h, "lps", NULL);
    render(&h, DM_VIEW_FINAL, 0);
    expect_targets_finite(&h, "final");
    /* every debug view the scene offers renders without a GL error */
    const struct {
        dm_view v;
        int first, last; /* view_index range: blur levels 1..5, stretch levels 0..5 */
    } views[] = {{DM_VIEW_IRRADIANCE, 0, 0}, {DM_VIEW_BLUR, 1, 5},    {DM_VIEW_STRETCH, 0, 5},
                 {DM_VIEW_SHADOW, 0, 0},     {DM_VIEW_SPECULAR, 0, 0}, {DM_VIEW_DIFFUSE, 0, 0},
                 {DM_VIEW_UV_TEST, 0, 0},    {DM_VIEW_WIREFRAME, 0, 0}};
    for (size_t k = 0; k < sizeof views / sizeof *views; ++k)
        for (int i = views[k].first; i <= views[k].last; ++i) render(&h, views[k].v, i);
    expect_targets_finite(&h, "after every view");
    close_head(&h);
}

static void golden_scene(const char *name)
{
    head h;
    pack_scene(&h, name, NULL);
    render(&h, DM_VIEW_FINAL, 0);
    uint8_t *rgba = malloc((size_t)W * H * 4);
    dm_error err = {0};
    cr_assert_eq(dm_renderer_read_display(h.r, rgba, &err), DM_OK, "%s", err.detail);
    char msg[1024], golden[64];
    snprintf(golden, sizeof golden, "head-%s", name);
    /* Tolerance: 6 of 255 per channel, 0.5 mean; llvmpipe is deterministic on one machine,
     * this absorbs LLVM code-generation differences (the sphere golden uses the same). */
    cr_expect(golden_check(golden, W, H, rgba, (golden_tolerance){6, 0.5}, msg, sizeof msg), "%s", msg);
    free(rgba);
    close_head(&h);
}

Test(head, golden_lps, .timeout = 120) { golden_scene("lps"); }
Test(head, golden_lps_specular, .timeout = 120) { golden_scene("lps-specular"); }
Test(head, golden_lps_sss, .timeout = 120) { golden_scene("lps-sss"); }
Test(head, golden_lps_env, .timeout = 120) { golden_scene("lps-env"); }
Test(head, golden_lps_screen_space, .timeout = 120) { golden_scene("lps-screen-space"); }
Test(head, golden_lps_backlit, .timeout = 120) { golden_scene("lps-backlit"); }
Test(head, golden_lps_pre_integrated, .timeout = 120) { golden_scene("lps-pre-integrated"); }

/* The ear seen from the side, lit from behind (lps-backlit), with and without translucency. */
static void ear_camera(dm_scene *s)
{
    const float eye[3] = {9.0f, 1.0f, 4.0f}, target[3] = {1.3f, 0.9f, -0.2f};
    memcpy(s->camera_eye, eye, sizeof eye);
    memcpy(s->camera_target, target, sizeof target);
}
static void ear_without(dm_scene *s)
{
    ear_camera(s);
    s->effects[DM_EFFECT_TRANSLUCENCY] = false;
}
static void ear_screen_space(dm_scene *s)
{
    ear_camera(s);
    s->sss_technique = DM_SSS_SCREEN_SPACE;
}
static void ear_screen_space_without(dm_scene *s)
{
    ear_without(s);
    s->sss_technique = DM_SSS_SCREEN_SPACE;
}

/* The ear's picture; thin_map false: the pack's thin-part map left out (dermis-render
 * --no-thin-map); gather false: its thin gather (--no-thin-gather). */
static uint8_t *ear_picture_with(void (*edit)(dm_scene *), bool thin_map, bool gather)
{
    head h;
    pack_scene(&h, "lps-backlit", edit);
    if (!thin_map || !gather) {
        dm_renderer_destroy(h.r);
        dm_render_assets a = h.assets;
        if (!thin_map) a.thin = a.thin_half = (dm_texture){0};
        if (!gather) a.gather_index = a.gather_taps = a.gather_half_index = a.gather_half_taps = (dm_texture){0};
        create_renderer(&h, &a);
    }
    render(&h, DM_VIEW_FINAL, 0);
    /* the frame's own plan keeps what the renderer chose at create: no translucency where the
     * thin-part map is used (the texture-space head), translucency where it is asked and not */
    const dm_render_plan *p = dm_renderer_plan(h.r);
    bool uses_map = dm_renderer_thin_map(h.r);
    cr_assert_eq(uses_map, thin_map && p->texture_space);
    cr_assert_eq(p->translucency_active, h.scene.effects[DM_EFFECT_TRANSLUCENCY] && !uses_map);
    uint8_t *rgba = malloc((size_t)W * H * 4);
    dm_error err = {0};
    cr_assert_eq(dm_renderer_read_display(h.r, rgba, &err), DM_OK, "%s", err.detail);
    close_head(&h);
    return rgba;
}

static uint8_t *ear_picture(void (*edit)(dm_scene *), bool thin_map)
{
    return ear_picture_with(edit, thin_map, false);
}

/* A light behind the head visibly reddens the ear: pixels gain at least 8 display steps of
 * red (measured: the helix and the rim), and over the picture red gains more than green,
 * green more than blue (the profile's red Gaussians are the widest). */
static void ears_redden_as(const uint8_t *on, const uint8_t *off, const char *what, bool only_adds)
{
    long gain[3] = {0, 0, 0};
    int visible = 0;
    for (int i = 0; i < W * H; ++i) {
        int d[3];
        for (int c = 0; c < 3; ++c) {
            d[c] = (int)on[i * 4 + c] - (int)off[i * 4 + c];
            if (only_adds) cr_assert_geq(d[c], -1, "pixel %d channel %d darker with %s (%d)", i, c, what, d[c]);
            gain[c] += d[c];
        }
        visible += d[0] >= 8 && d[0] > d[1] && d[1] >= d[2];
    }
    cr_expect_gt(visible, 10, "%s: only %d pixels redden visibly", what, visible);
    cr_expect(gain[0] > gain[1] && gain[1] >= gain[2], "%s: gains R %ld G %ld B %ld", what, gain[0], gain[1], gain[2]);
}

static void ears_redden(const uint8_t *on, const uint8_t *off, const char *what)
{
    ears_redden_as(on, off, what, true);
}

/* Texture space: the thin-part map carries the light through the ear (the back's irradiance,
 * each level by exp(-d^2/2v)), and translucency adds nothing on top of it (the same picture
 * bit for bit: dm_render_plan_thin_map); without the map, translucency's shadow-map thickness
 * reddens it instead, as before the map. With the thin gather too (the widest levels the 3-D
 * sum, which also takes light away where the atlas blur had too much) the ear still reddens. */
Test(head, backlit_ear_reddens_texture_space, .timeout = 240)
{
    uint8_t *map = ear_picture(ear_without, true), *none = ear_picture(ear_without, false);
    ears_redden(map, none, "the thin-part map");
    uint8_t *gathered = ear_picture_with(ear_without, true, true);
    cr_assert(memcmp(gathered, map, (size_t)W * H * 4), "the gather changed nothing");
    ears_redden_as(gathered, none, "the thin-part map and the gather", false);
    free(gathered);
    uint8_t *both = ear_picture(ear_camera, true);
    cr_assert_eq(memcmp(both, map, (size_t)W * H * 4), 0, "translucency changed the picture with the thin-part map");
    uint8_t *transl = ear_picture(ear_camera, false);
    ears_redden(transl, none, "translucency");
    free(map), free(none), free(both), free(transl);
}

Test(head, backlit_ear_reddens_screen_space, .timeout = 180)
{
    uint8_t *on = ear_picture(ear_screen_space, true), *off = ear_picture(ear_screen_space_without, true);
    ears_redden(on, off, "translucency");
    free(on), free(off);
}

Test(head, specular_scene_runs_exactly_the_specular_passes)
{
    char abs_path[PATH_MAX];
    cr_assert(realpath("assets/scenes/lps-specular.json", abs_path));
    dm_scene s;
    dm_error err = {0};
    cr_assert_eq(dm_scene_read(abs_path, &s, &err), DM_OK, "%s", err.detail);
    for (int e = 0; e < DM_EFFECT_COUNT; ++e)
        cr_expect_eq(s.effects[e], e == DM_EFFECT_SPECULAR, "%s", dm_effect_name((dm_effect)e));
    dm_render_plan plan;
    cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &plan, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(plan.pass_count, 2, "specular alone is the G-buffer and final passes only, got %d passes",
                 plan.pass_count);
    cr_expect_str_eq(plan.passes[0].name, "gbuffer");
    cr_expect_str_eq(plan.passes[1].name, "final");
}

static void light_from_behind(dm_scene *s)
{
    /* the head faces +Z: the light comes from −Z; no environment, so every light is it */
    s->effects[DM_EFFECT_ENVIRONMENT_LIGHTING] = false;
    s->environment[0] = '\0';
    s->env_alternative_count = 0;
    s->light_count = 1;
    s->lights[0].type = DM_LIGHT_DIRECTIONAL;
    s->lights[0].direction[0] = 0.0f;
    s->lights[0].direction[1] = 0.0f;
    s->lights[0].direction[2] = -1.0f;
    s->lights[0].intensity = 50.0f;
    s->lights[0].casts_shadow = true;
}

Test(head, light_behind_no_specular_on_the_face_no_irradiance_on_the_unlit_side, .timeout = 120)
{
    head h;
    pack_scene(&h, "lps", light_from_behind);

    /* Specular, screen space: the face (the middle third of the picture, where normals face
     * the camera and so point away from the light) receives exactly nothing. Rims at the
     * silhouette may legitimately catch light from behind. */
    render(&h, DM_VIEW_SPECULAR, 0);
    dm_target_info info;
    float *scr = head_target(&h, "screen", &info);
    float worst = 0.0f;
    for (int y = info.height / 3; y < 2 * info.height / 3; ++y)
        for (int x = info.width / 3; x < 2 * info.width / 3; ++x)
            for (int c = 0; c < 3; ++c) worst = fmaxf(worst, fabsf(scr[((size_t)y * info.width + x) * 4 + c]));
    cr_expect_eq(worst, 0.0f, "specular %g on the face with the light behind", (double)worst);
    free(scr);

    /* Irradiance, texture space: at the UV centroid of every triangle whose three vertex
     * normals face away from the light by more than 53° (n·L ≤ −0.6, beyond what the normal
     * map tilts), nothing arrives. */
    render(&h, DM_VIEW_FINAL, 0);
    float *irr = head_target(&h, "irradiance", &info);
    const float *v = h.assets.vertices;
    const uint32_t *ix = h.assets.indices;
    int checked = 0, lit = 0;
    for (int t = 0; t < h.assets.index_count / 3; ++t) {
        int away = 1;
        double u = 0, w = 0;
        for (int c = 0; c < 3; ++c) {
            const float *p = v + (size_t)ix[3 * t + c] * DM_VERTEX_FLOATS;
            away &= -p[DM_VERTEX_NORMAL + 2] <= -0.6f; /* n·L with L = (0, 0, −1) */
            u += p[DM_VERTEX_UV] / 3.0;
            w += p[DM_VERTEX_UV + 1] / 3.0;
        }
        if (!away) continue;
        int x = (int)(u * info.width), y = (int)(w * info.height);
        if (x < 0 || y < 0 || x >= info.width || y >= info.height) continue;
        const float *px = irr + ((size_t)y * info.width + x) * 4;
        ++checked;
        if (px[0] + px[1] + px[2] != 0.0f) ++lit;
    }
    cr_expect_gt(checked, 1000, "only %d triangles face away from the light", checked);
    cr_expect_eq(lit, 0, "%d of %d texels facing away from the light received irradiance", lit, checked);
    free(irr);
    close_head(&h);
}

/* The lights' facts are compiled into the shaders (DM_LIGHT_SHADOW, DM_LIGHT_POINT,
 * DM_SHADOW_LIGHT): a shadow-casting directional light and a point light give the same floats
 * in either order, to rounding, for every technique; the same pair with no shadow differs (the
 * shadow is in the picture, so a shadow on the wrong light would show). To rounding, 4 float
 * epsilons: held bit for bit while translucency ran in every technique; in texture space, where
 * the thin-part map now takes its place, the swapped lights differ by up to 1.9e-7 relative
 * (1.6 epsilons, in 104 values: the order the light sums are rounded in, e.g. fused
 * multiply-adds), while a shadow on the wrong light changes hundreds of values by > 0.1 %. */
static void two_lights(dm_scene *s)
{
    s->light_count = 2;
    s->effects[DM_EFFECT_TRANSLUCENCY] = true;
    s->lights[0] = (dm_light){.type = DM_LIGHT_DIRECTIONAL, .direction = {0.8f, 0.3f, 0.5f}, .color = {1, 0.9f, 0.8f},
                              .intensity = 3.0f, .casts_shadow = true};
    s->lights[1] = (dm_light){.type = DM_LIGHT_POINT, .position = {-8.0f, 3.0f, -5.0f}, .color = {0.8f, 0.9f, 1},
                              .intensity = 6.0f, .casts_shadow = false};
}

static float *two_light_screen(head *h, dm_sss_technique technique, bool swap, bool shadow)
{
    dm_renderer_destroy(h->r);
    dm_scene s = h->scene;
    s.sss_technique = technique;
    s.lights[0].casts_shadow = shadow;
    if (swap) {
        dm_light t = s.lights[0];
        s.lights[0] = s.lights[1];
        s.lights[1] = t;
    }
    dm_render_assets a = h->assets;
    a.scene = &s;
    create_renderer(h, &a);
    render(h, DM_VIEW_FINAL, 0);
    dm_target_info info;
    return head_target(h, "screen", &info);
}

static void same_floats_either_order(head *h, dm_sss_technique technique, const char *name)
{
    size_t n = (size_t)W * H * 4, differ = 0, shadowed = 0;
    float *a = two_light_screen(h, technique, false, true), *b = two_light_screen(h, technique, true, true);
    float *c = two_light_screen(h, technique, false, false);
    double worst = 0;
    for (size_t i = 0; i < n; ++i) {
        double scale = fmax(fabs((double)a[i]), fabs((double)b[i])), d = fabs((double)a[i] - b[i]);
        worst = fmax(worst, scale > 0 ? d / scale : 0);
        differ += d > 4 * FLT_EPSILON * scale, shadowed += fabs((double)a[i] - c[i]) > 1e-3 * fabs((double)c[i]);
    }
    cr_log_info("%s: largest relative difference with the lights swapped %.3g", name, worst);
    cr_expect_eq(differ, 0, "%s: %zu values differ by more than 4 float epsilons with the lights swapped", name, differ);
    cr_expect_gt(shadowed, 200, "%s: the shadow changes only %zu values by more than 0.1 %%", name, shadowed);
    free(a), free(b), free(c);
}

Test(head, lights_in_either_order_give_the_same_floats, .timeout = 180)
{
    head h;
    pack_scene(&h, "lps", two_lights);
    same_floats_either_order(&h, DM_SSS_TEXTURE_SPACE, "texture-space");
    same_floats_either_order(&h, DM_SSS_SCREEN_SPACE, "screen-space");
    close_head(&h);
    pack_scene(&h, "lps-pre-integrated", two_lights);
    same_floats_either_order(&h, DM_SSS_PRE_INTEGRATED, "pre-integrated");
    close_head(&h);
}
