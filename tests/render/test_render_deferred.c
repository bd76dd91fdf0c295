/* Deferred shading and the exact speed-ups around it, on the synthetic sphere: the
 * texture-space G-buffer holds the surface and follows set_scene; the glow added by the
 * tonemap pass leaves the linear picture as glow_add made it; the specular map in the normal
 * map's alpha gives the same frame as a separate texture. (The screen G-buffer:
 * test_render_ssss.c; lights in either order: test_render_head.c.) */
#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../common/render_fixture.h"
#include "render/dm_render_plan.h"

/* The texture-space G-buffer the irradiance pass lights: every texel a triangle covers holds a
 * point on the sphere (radius 1; 32 x 24 flat cells sag by up to 1 - cos(pi/32) +
 * 1 - cos(pi/48) = 7.0e-3) and a radial geometric normal, and the irradiance's coverage alpha
 * is 1 exactly there. It is made once per scene: after set_scene with another rho_s and
 * roughness the irradiance equals that of a renderer created with them, texel for texel. The
 * screen G-buffer exists only where the final pass defers (not without specular). */
Test(render, texture_space_gbuffer_holds_the_surface_and_follows_the_scene)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 32, .sphere_rings = 24});
    open_renderer(&f, 64, 48, 64);
    frame(&f, DM_VIEW_IRRADIANCE, 0);
    dm_target_info gi, ii;
    float *pos = read_target(&f, "ts_gbuffer0", &gi), *nrm = read_target(&f, "ts_gbuffer1", &gi);
    float *irr = read_target(&f, "irradiance", &ii);
    cr_assert(gi.width == ii.width && gi.height == ii.height);
    int covered = 0;
    for (int i = 0; i < gi.width * gi.height; ++i) {
        const float *p = &pos[i * 4], *n = &nrm[i * 4];
        cr_assert_eq(irr[i * 4 + 3] == 1.0f, p[3] == 1.0f, "texel %d: coverage %g, G-buffer %g", i,
                     (double)irr[i * 4 + 3], (double)p[3]);
        if (p[3] != 1.0f) continue;
        ++covered;
        double r = sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]);
        cr_assert(r > 1 - 7.1e-3 && r < 1 + 1e-5, "texel %d: |position| %.6f", i, r);
        double radial = (n[0] * p[0] + n[1] * p[1] + n[2] * p[2]) / r;
        cr_assert_gt(radial, 0.99, "texel %d: geometric normal not radial (%.4f)", i, radial);
    }
    cr_expect_gt(covered, gi.width * gi.height / 2);
    free(pos), free(nrm), free(irr);
    cr_expect_geq(dm_renderer_find_target(f.r, "gbuffer0"), 0, "specular on: the screen G-buffer is made");

    dm_error err = {0};
    dm_scene s = f.synth->scene;
    s.rho_s = 0.6f, s.roughness = 0.8f;
    cr_assert_eq(dm_renderer_set_scene(f.r, &s, &err), DM_OK, "%s", err.detail);
    frame(&f, DM_VIEW_IRRADIANCE, 0);
    float *changed = read_target(&f, "irradiance", &ii);
    dm_renderer_destroy(f.r);
    f.synth->scene = s;
    open_renderer(&f, 64, 48, 64);
    frame(&f, DM_VIEW_IRRADIANCE, 0);
    float *fresh = read_target(&f, "irradiance", &ii);
    cr_expect_eq(memcmp(changed, fresh, (size_t)ii.width * ii.height * 4 * sizeof *fresh), 0,
                 "irradiance after set_scene differs from a renderer made with that scene");
    free(changed), free(fresh);
    /* texture-space without specular shades while rasterising: no screen G-buffer made */
    dm_renderer_destroy(f.r);
    f.synth->scene.effects[DM_EFFECT_SPECULAR] = false;
    open_renderer(&f, 64, 48, 64);
    frame(&f, DM_VIEW_FINAL, 0);
    cr_expect_lt(dm_renderer_find_target(f.r, "gbuffer0"), 0, "specular off: a screen G-buffer was made");
    cr_expect_geq(dm_renderer_find_target(f.r, "ts_gbuffer0"), 0);
    close_fixture(&f);
}

/* With a tonemap the glow is added by the tonemap pass, and the linear screen gets it only when
 * read: that linear picture equals, float for float, the one of the same scene without a
 * tonemap, where the glow_add pass adds it during the frame. */
Test(render, glow_in_the_tonemap_leaves_the_linear_picture_unchanged)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 32, .sphere_rings = 24});
    f.synth->scene.glow_threshold = 0.05f; /* a glow that reaches most of the sphere */
    open_renderer(&f, 64, 48, 64);
    frame(&f, DM_VIEW_FINAL, 0);
    cr_assert(dm_renderer_plan(f.r)->glow_in_tonemap);
    cr_assert_lt(dm_render_plan_find(dm_renderer_plan(f.r), "glow_add"), 0);
    size_t n = 64 * 48 * 4;
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    dm_error err = {0};
    cr_assert_eq(dm_renderer_read_linear(f.r, a, &err), DM_OK, "%s", err.detail);
    dm_renderer_destroy(f.r);
    f.synth->scene.effects[DM_EFFECT_TONEMAP] = false;
    open_renderer(&f, 64, 48, 64);
    frame(&f, DM_VIEW_FINAL, 0);
    cr_assert_geq(dm_render_plan_find(dm_renderer_plan(f.r), "glow_add"), 0);
    cr_assert_eq(dm_renderer_read_linear(f.r, b, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(memcmp(a, b, n * sizeof *a), 0, "the linear picture changed with the glow in the tonemap");
    free(a), free(b);
    close_fixture(&f);
}

/* The specular map rides in the normal map's alpha when both are 8-bit maps of one size (one
 * trilinear fetch fewer): the frame equals, float for float, the one where the same specular
 * values come as a separate RGBA8 texture (which cannot ride), mip levels included (the
 * sphere is drawn small, so the maps are minified). */
Test(render, specular_in_the_normal_maps_alpha_changes_nothing)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 32, .sphere_rings = 24});
    enum { N = 64 };
    uint8_t *nm = malloc(N * N * 4), *sp = malloc(N * N), *sp4 = malloc(N * N * 4);
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
            int i = y * N + x;
            nm[i * 4 + 0] = (uint8_t)(128 + 40 * sin(x * 0.7)), nm[i * 4 + 1] = (uint8_t)(128 + 40 * cos(y * 0.5));
            nm[i * 4 + 2] = 230, nm[i * 4 + 3] = 255;
            sp[i] = (uint8_t)((x * 37 + y * 91) & 255);
            for (int c = 0; c < 4; ++c) sp4[i * 4 + c] = sp[i];
        }
    dm_render_assets *a = &f.synth->assets;
    a->normal_map = (dm_texture){DM_TEX_RGBA8, N, N, nm};
    a->specular_map = (dm_texture){DM_TEX_R8, N, N, sp};
    size_t n = 96 * 72 * 4;
    float *packed = malloc(n * sizeof *packed), *apart = malloc(n * sizeof *apart);
    dm_error err = {0};
    for (int k = 0; k < 2; ++k) {
        if (k == 1) a->specular_map = (dm_texture){DM_TEX_RGBA8, N, N, sp4};
        dm_renderer_destroy(f.r);
        f.r = NULL;
        open_renderer(&f, 96, 72, 64);
        frame(&f, DM_VIEW_FINAL, 0);
        cr_assert_eq(dm_renderer_read_linear(f.r, k ? apart : packed, &err), DM_OK, "%s", err.detail);
    }
    cr_expect_eq(memcmp(packed, apart, n * sizeof *packed), 0, "the frame changed with the specular map in alpha");
    double spec = 0;
    for (size_t i = 0; i < n; i += 4) spec += packed[i];
    cr_expect_gt(spec, 0.0);
    free(packed), free(apart), free(nm), free(sp), free(sp4);
    close_fixture(&f);
}
