/* Screen-space separable SSS and translucency (issue 13): the kernel against an independent
 * reference, scene errors naming the key, and the hard cases on the synthetic sphere under
 * llvmpipe: a silhouette next to the background (no halo), a head filling the screen and one
 * of 20 pixels, zero thickness, a light exactly behind, a one-Gaussian profile; the
 * G-buffer the deferred shading reads, against the camera and the sphere. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_scene.h"
#include "core/dm_ssss_kernel.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_synth.h"

/* One Gaussian is separable: the product of its line-spread kernels is exact in 2-D too, at
 * every size of pixel. (The weights against bin masses: tests/unit/test_ssss_kernel_pin.c.) */
Test(ssss_kernel, one_gaussian_is_exact)
{
    dm_profile p = {.count = 1, .variance_mm2 = {2.0}, .weight = {{1, 1, 1}}};
    dm_ssss_kernel k;
    dm_error err = {0};
    cr_assert_eq(dm_ssss_kernel_fit(&p, 17, &k, &err), DM_OK, "%s", err.detail);
    for (int r = 0; r < k.rows; ++r)
        for (int c = 0; c < 3; ++c)
            cr_expect_lt(k.fit_error[r][c], 1e-9, "row %d channel %d error %g", r, c, k.fit_error[r][c]);
}

Test(ssss_kernel, skin_kernels_are_finite_symmetric_and_normalised)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    const int taps[] = DM_SCENE_SCREEN_TAPS_LIST;
    for (int t = 0; t < 3; ++t) {
        dm_ssss_kernel k;
        dm_error err = {0};
        cr_assert_eq(dm_ssss_kernel_fit(&p, taps[t], &k, &err), DM_OK, "%s", err.detail);
        for (int r = 0; r < k.rows; ++r)
            for (int c = 0; c < 3; ++c) {
                double sum = 0;
                for (int a = 0; a < k.taps; ++a) {
                    cr_assert(isfinite(k.weight[r][a][c]) && k.weight[r][a][c] >= 0);
                    cr_expect(fabsf(k.weight[r][a][c] - k.weight[r][k.taps - 1 - a][c]) < 1e-6f);
                    cr_expect(k.offset_px[r][a] == -k.offset_px[r][k.taps - 1 - a]);
                    sum += k.weight[r][a][c];
                }
                cr_expect(fabs(sum - 1) < 1e-6, "%d taps row %d channel %d sums to %g", taps[t], r, c, sum);
                cr_expect(k.fit_error[r][c] >= 0 && k.fit_error[r][c] < 1, "%d taps row %d channel %d error %g",
                          taps[t], r, c, k.fit_error[r][c]);
            }
        float tex[DM_SSSS_MAX_ROWS * DM_SSSS_MAX_TAPS * 4];
        dm_ssss_kernel_texels(&k, tex);
        dm_ssss_kernel back;
        const float sizes[2] = {(float)k.mm_per_px[0], (float)k.mm_per_px[1]};
        cr_assert_eq(dm_ssss_kernel_from_texels(tex, k.taps, k.rows, sizes, &back, &err), DM_OK, "%s", err.detail);
        cr_expect_eq(memcmp(back.offset_px, k.offset_px, sizeof k.offset_px), 0);
        cr_expect_eq(memcmp(back.weight, k.weight, sizeof k.weight), 0);
        /* the layout before the rows: one row, offsets in mm, read as a row at 1 mm per pixel */
        cr_assert_eq(dm_ssss_kernel_from_texels(tex, k.taps, 1, NULL, &back, &err), DM_OK, "%s", err.detail);
        cr_expect(back.rows == 1 && back.mm_per_px[0] == 1.0 && back.mm_per_px[1] == 1.0);
        cr_expect_eq(dm_ssss_kernel_from_texels(tex, k.taps, 2, NULL, &back, &err), DM_ERR_RANGE);
        cr_expect_eq(dm_ssss_kernel_from_texels(tex, k.taps, k.rows, (const float[2]){sizes[1], sizes[0]}, &back, &err),
                     DM_ERR_RANGE);
    }
    dm_ssss_kernel k;
    dm_error err = {0};
    cr_expect_eq(dm_ssss_kernel_fit(&p, 16, &k, &err), DM_ERR_RANGE);
}

static void expect_scene_error(const char *effects, const char *needle)
{
    char json[1024];
    snprintf(json, sizeof json, "{\"mesh\": {\"path\": \"head.obj\"}, \"effects\": {%s}}", effects);
    dm_scene s;
    dm_error err = {0};
    cr_assert_neq(dm_scene_parse(json, "/tmp/t.json", &s, &err), DM_OK, "%s accepted", effects);
    cr_expect(strstr(err.detail, needle), "'%s' not in: %s", needle, err.detail);
}

Test(ssss_scene, bad_values_name_the_key)
{
    expect_scene_error("\"subsurface\": {\"technique\": \"screen\"}", "$.effects.subsurface.technique");
    expect_scene_error("\"subsurface\": {\"technique\": 3}", "$.effects.subsurface.technique");
    expect_scene_error("\"subsurface\": {\"technique\": \"pre\"}", "\"pre-integrated\"");
    expect_scene_error("\"subsurface\": {\"screen_taps\": 13}", "$.effects.subsurface.screen_taps");
    expect_scene_error("\"subsurface\": {\"screen_taps\": 17.5}", "one of 11, 17, 25");
    expect_scene_error("\"translucency\": {\"intensity\": -1}", "$.effects.translucency.intensity");
    dm_scene s;
    dm_error err = {0};
    cr_assert_eq(dm_scene_parse("{\"mesh\": {\"path\": \"h.obj\"}, \"effects\": {\"subsurface\": {\"technique\": "
                                "\"screen-space\", \"screen_taps\": 25}, \"translucency\": true}}",
                                "/tmp/t.json", &s, &err),
                 DM_OK, "%s", err.detail);
    cr_expect_eq(s.sss_technique, DM_SSS_SCREEN_SPACE);
    cr_expect_eq(s.screen_taps, 25);
    cr_expect(s.effects[DM_EFFECT_TRANSLUCENCY]);
    dm_scene_defaults(&s);
    cr_expect(!s.effects[DM_EFFECT_TRANSLUCENCY], "translucency is off unless asked");
}

typedef struct fixture {
    dm_osmesa *ctx;
    dm_synth *synth;
    dm_renderer *r;
    int w, h;
} fixture;

static void open_fixture(fixture *f)
{
    dm_error err = {0};
    memset(f, 0, sizeof *f);
    dm_synth_options so = {.beckmann_size = 128, .directional_size = 16, .stretch_size = 64};
    cr_assert_eq(dm_osmesa_create(&f->ctx, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_synth_create(&so, &f->synth, &err), DM_OK, "%s", err.detail);
    f->synth->scene.sss_technique = DM_SSS_SCREEN_SPACE;
}

static float *render(fixture *f, int w, int h)
{
    dm_error err = {0};
    dm_render_desc d = {.width = w, .height = h, .shadow_size = 256};
    dm_renderer_destroy(f->r);
    cr_assert_eq(dm_renderer_create(&f->synth->assets, &d, &f->r, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_frame(f->r, &(dm_frame_options){0}, &err), DM_OK, "%s", err.detail);
    f->w = w, f->h = h;
    float *px = malloc((size_t)w * h * 4 * sizeof *px);
    cr_assert_eq(dm_renderer_read_linear(f->r, px, &err), DM_OK, "%s", err.detail);
    for (size_t i = 0; i < (size_t)w * h * 4; ++i) cr_assert(isfinite(px[i]), "value %zu is %g", i, (double)px[i]);
    /* every intermediate too */
    for (int t = 0; t < dm_renderer_target_count(f->r); ++t) {
        dm_target_info info;
        dm_renderer_target_info(f->r, t, &info);
        size_t n = (size_t)info.width * info.height * info.channels;
        float *v = malloc(n * sizeof *v);
        cr_assert_eq(dm_renderer_read_target(f->r, t, v, &err), DM_OK, "%s", err.detail);
        for (size_t i = 0; i < n; ++i) cr_assert(isfinite(v[i]), "target %s value %zu is %g", info.name, i, (double)v[i]);
        free(v);
    }
    return px;
}

static void close_fixture(fixture *f)
{
    dm_renderer_destroy(f->r);
    dm_synth_free(f->synth);
    dm_osmesa_destroy(f->ctx);
}

/* No background, no glow, no tonemap: pixels off the head must stay exactly 0 (no halo), and
 * the skin pixels on the silhouette stay within the range of skin values. */
Test(ssss_render, silhouette_next_to_background_has_no_halo)
{
    fixture f;
    open_fixture(&f);
    dm_scene *s = &f.synth->scene;
    s->effects[DM_EFFECT_GLOW] = s->effects[DM_EFFECT_TONEMAP] = false;
    s->env_background = false;
    float *px = render(&f, 160, 120);
    int bg = 0, edge = 0;
    for (int y = 1; y < f.h - 1; ++y)
        for (int x = 1; x < f.w - 1; ++x) {
            const float *p = &px[((size_t)y * f.w + x) * 4];
            if (p[3] == 0) {
                ++bg;
                cr_assert(p[0] == 0 && p[1] == 0 && p[2] == 0, "background pixel %d,%d is (%g %g %g)", x, y,
                          (double)p[0], (double)p[1], (double)p[2]);
            } else if (px[((size_t)y * f.w + x + 1) * 4 + 3] == 0 || px[((size_t)y * f.w + x - 1) * 4 + 3] == 0) {
                ++edge;
            }
        }
    cr_expect_gt(bg, 1000);
    cr_expect_gt(edge, 20);
    free(px);
    close_fixture(&f);
}

Test(ssss_render, head_filling_the_screen_and_head_of_20_pixels)
{
    fixture f;
    open_fixture(&f);
    dm_synth_scene(&f.synth->scene, 1.6f); /* the sphere (radius 1) fills the view */
    f.synth->scene.sss_technique = DM_SSS_SCREEN_SPACE;
    float *px = render(&f, 128, 96);
    int skin = 0;
    for (int i = 0; i < f.w * f.h; ++i) skin += px[i * 4 + 3] > 0;
    cr_expect_eq(skin, f.w * f.h, "filling: %d of %d pixels are skin", skin, f.w * f.h);
    free(px);
    dm_synth_scene(&f.synth->scene, 60.0f); /* about 20 pixels across at 256x192, fov 30 */
    f.synth->scene.sss_technique = DM_SSS_SCREEN_SPACE;
    px = render(&f, 256, 192);
    skin = 0;
    for (int i = 0; i < f.w * f.h; ++i) skin += px[i * 4 + 3] > 0;
    cr_expect(skin > 100 && skin < 600, "small head: %d skin pixels", skin);
    free(px);
    close_fixture(&f);
}

Test(ssss_render, one_gaussian_profile)
{
    fixture f;
    open_fixture(&f);
    dm_profile one = {.count = 1, .variance_mm2 = {1.0}, .weight = {{1, 1, 1}}};
    snprintf(one.name, sizeof one.name, "one");
    f.synth->scene.profile = one;
    f.synth->assets.profile = &f.synth->scene.profile;
    free(render(&f, 96, 72));
    close_fixture(&f);
}

static float *read_named(fixture *f, const char *name)
{
    dm_error err = {0};
    int t = dm_renderer_find_target(f->r, name);
    cr_assert_geq(t, 0, "no target %s", name);
    float *v = malloc((size_t)f->w * f->h * 4 * sizeof *v);
    cr_assert_eq(dm_renderer_read_target(f->r, t, v, &err), DM_OK, "%s", err.detail);
    return v;
}

/* The G-buffer the shading pass reads holds the visible surface at each pixel's centre,
 * checked against the camera and the sphere computed here: the stored position projects to
 * the pixel's centre and lies on the sphere (radius 1; a flat cell of 96 x 96 sags by up to
 * 1 - cos(pi/96) + 1 - cos(pi/192) = 6.7e-4), the
 * geometric normal is radial, the shading normal unit length, albedo, rho_s and roughness
 * the material's; the shade pass's eye depth is the position's distance along the view. */
Test(ssss_render, gbuffer_holds_the_surface_at_each_pixel_centre)
{
    fixture f;
    open_fixture(&f);
    dm_scene *s = &f.synth->scene;
    free(render(&f, 160, 120));
    float *g[4], *diff = read_named(&f, "ss_diffuse");
    for (int i = 0; i < 4; ++i) {
        char name[32];
        snprintf(name, sizeof name, "gbuffer%d", i);
        g[i] = read_named(&f, name);
    }
    double fw[3], rt[3], up[3], n = 0;
    for (int k = 0; k < 3; ++k) fw[k] = s->camera_target[k] - s->camera_eye[k], n += fw[k] * fw[k];
    for (int k = 0; k < 3; ++k) fw[k] /= sqrt(n);
    rt[0] = fw[1] * s->camera_up[2] - fw[2] * s->camera_up[1];
    rt[1] = fw[2] * s->camera_up[0] - fw[0] * s->camera_up[2];
    rt[2] = fw[0] * s->camera_up[1] - fw[1] * s->camera_up[0];
    n = sqrt(rt[0] * rt[0] + rt[1] * rt[1] + rt[2] * rt[2]);
    for (int k = 0; k < 3; ++k) rt[k] /= n;
    up[0] = rt[1] * fw[2] - rt[2] * fw[1], up[1] = rt[2] * fw[0] - rt[0] * fw[2], up[2] = rt[0] * fw[1] - rt[1] * fw[0];
    double t = tan(0.5 * s->fov_y_deg * 3.14159265358979323846 / 180.0), aspect = (double)f.w / f.h;
    int skin = 0;
    for (int y = 0; y < f.h; ++y)
        for (int x = 0; x < f.w; ++x) {
            size_t i = ((size_t)y * f.w + x) * 4;
            if (diff[i + 3] <= 0) continue;
            ++skin;
            const float *p = &g[0][i], *ng = &g[1][i], *sn = &g[2][i], *al = &g[3][i];
            double d[3], z = 0, r = 0, radial = 0, nn = 0;
            for (int k = 0; k < 3; ++k) d[k] = p[k] - s->camera_eye[k];
            for (int k = 0; k < 3; ++k) z += d[k] * fw[k], r += (double)p[k] * p[k];
            r = sqrt(r);
            /* The rasterised point on the pixel centre's ray, lifted along the normal towards
             * the smooth sphere (dm_smooth_point, #27) by half its depth below the corners'
             * tangent planes. On a sphere a chord's point of half-angle θ lies sin²θ below them
             * and 1 − cos θ ≈ θ²/2 (the sagitta) below the sphere: the lift is about the
             * sagitta, which the |position| bound below caps at 7e-4, so the point lies within
             * 7e-4 (+ float rounding) of the ray. */
            double ray[3], rl = 0, along = 0, off = 0;
            for (int k = 0; k < 3; ++k)
                ray[k] = fw[k] + ((2.0 * (x + 0.5) / f.w - 1) * t * aspect) * rt[k] + ((2.0 * (y + 0.5) / f.h - 1) * t) * up[k],
                rl += ray[k] * ray[k];
            for (int k = 0; k < 3; ++k) along += d[k] * ray[k] / sqrt(rl);
            for (int k = 0; k < 3; ++k) off += (d[k] - along * ray[k] / sqrt(rl)) * (d[k] - along * ray[k] / sqrt(rl));
            cr_assert_lt(sqrt(off), 7e-4 + 2e-6, "pixel %d,%d: its position lies %.3g off the pixel centre's ray", x,
                         y, sqrt(off));
            cr_assert(r > 1 - 7e-4 && r < 1 + 1e-5, "pixel %d,%d: |position| %.7f, not on the sphere", x, y, r);
            for (int k = 0; k < 3; ++k) radial += ng[k] * p[k] / r, nn += (double)sn[k] * sn[k];
            cr_assert_gt(radial, 0.999, "pixel %d,%d: geometric normal not radial (%.5f)", x, y, radial);
            cr_assert(fabs(nn - 1) < 1e-5, "pixel %d,%d: shading normal length^2 %.7f", x, y, nn);
            cr_assert(sn[3] >= 0 && sn[3] <= s->rho_s * (1 + 1e-6), "pixel %d,%d: rho_s %g", x, y, (double)sn[3]);
            for (int k = 0; k < 3; ++k) cr_assert(al[k] >= 0 && al[k] <= 1, "pixel %d,%d: albedo %g", x, y, (double)al[k]);
            cr_assert(fabs(al[3] - fmin(s->roughness, 1.0)) < 1e-6, "pixel %d,%d: roughness %g", x, y, (double)al[3]);
            cr_assert(fabs(diff[i + 3] - z) < 1e-5 * z, "pixel %d,%d: eye depth %g, expected %g", x, y,
                      (double)diff[i + 3], z);
        }
    cr_expect_gt(skin, 2000);
    for (int i = 0; i < 4; ++i) free(g[i]);
    free(diff);
    close_fixture(&f);
}

/* A light exactly behind the sphere (camera on +z, light towards −z): the visible side gets
 * only transmitted light, which is finite; on a sphere of 50 mm radius the thickness is tens
 * of mm, so T(d) is ~0 there, and a thin limb transmits red more than blue. Then zero
 * thickness: the same light with the sphere shrunk to 0.02 units (1 mm thick). */
Test(translucency, light_exactly_behind_and_zero_thickness)
{
    for (int tech = 0; tech < 2; ++tech) {
        fixture f;
        open_fixture(&f);
        dm_scene *s = &f.synth->scene;
        s->sss_technique = tech ? DM_SSS_SCREEN_SPACE : DM_SSS_TEXTURE_SPACE;
        s->effects[DM_EFFECT_TRANSLUCENCY] = true;
        s->effects[DM_EFFECT_ENVIRONMENT_LIGHTING] = s->effects[DM_EFFECT_GLOW] = s->effects[DM_EFFECT_TONEMAP] = false;
        s->lights[0].direction[0] = 0, s->lights[0].direction[1] = 0, s->lights[0].direction[2] = -1;
        s->lights[0].intensity = 10;
        float *px = render(&f, 96, 72);
        free(px);
        s->mm_per_unit = 0.02; /* 2 mm across: nearly zero thickness */
        px = render(&f, 96, 72);
        double red = 0, blue = 0;
        for (int i = 0; i < f.w * f.h; ++i) red += px[i * 4], blue += px[i * 4 + 2];
        cr_expect_gt(red, 0.0, "%s: a thin sphere lit from behind transmits light", tech ? "screen" : "texture");
        cr_expect_gt(red, blue, "red travels furthest");
        free(px);
        close_fixture(&f);
    }
}

/* The plan of a screen-space scene: its passes only, in order; explain names the technique;
 * texture-space views are refused naming it; translucency without a shadow map is noted. */
Test(ssss_plan, passes_explain_and_refused_views)
{
    dm_scene s;
    dm_synth_scene(&s, 4.5f);
    s.sss_technique = DM_SSS_SCREEN_SPACE;
    dm_render_plan p;
    dm_error err = {0};
    cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, &err), DM_OK, "%s", err.detail);
    char list[512] = "";
    for (int i = 0; i < p.pass_count; ++i)
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", i ? " " : "", p.passes[i].name);
    cr_expect_str_eq(list, "shadow0 gbuffer ss_shade ss_blur_h ss_blur_v background glow_bright glow_blur_u glow_blur_v "
                           "tonemap");
    char text[8192];
    dm_render_plan_explain(&p, text, sizeof text);
    cr_expect(strstr(text, "subsurface technique: screen-space"), "%s", text);
    cr_expect(!strstr(text, "blur_u1") && !strstr(text, "irradiance "), "texture-space passes listed:\n%s", text);
    cr_expect_eq(dm_render_plan_build(&s, DM_VIEW_IRRADIANCE, 0, &p, &err), DM_ERR_INVALID_ARGUMENT);
    cr_expect(strstr(err.detail, "screen-space"), "%s", err.detail);
    cr_expect_eq(dm_render_plan_build(&s, DM_VIEW_UV_TEST, 0, &p, &err), DM_OK, "%s", err.detail);
    s.effects[DM_EFFECT_TRANSLUCENCY] = true;
    s.effects[DM_EFFECT_SHADOWS] = false;
    cr_assert_eq(dm_render_plan_build(&s, DM_VIEW_FINAL, 0, &p, &err), DM_OK, "%s", err.detail);
    cr_expect(!p.translucency_active);
    dm_render_plan_explain(&p, text, sizeof text);
    cr_expect(strstr(text, "translucency is inactive"), "%s", text);
}
