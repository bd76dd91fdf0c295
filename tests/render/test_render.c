/* The renderer on llvmpipe (OSMesa): no GL error, finite intermediates, the blur chain's
 * invariants, light from behind, writers, golden image. Small sizes keep it fast. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image/dm_exr.h"
#include "core/dm_cli.h"
#include "image/dm_image.h"
#include "dm_golden.h"
#include "../common/render_fixture.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_image.h"
#include "render/dm_render_synth.h"

static void expect_all_targets_finite(fixture *f, const char *when)
{
    dm_error err = {0};
    for (int t = 0; t < dm_renderer_target_count(f->r); ++t) {
        dm_target_info info;
        dm_renderer_target_info(f->r, t, &info);
        size_t n = (size_t)info.width * info.height * info.channels;
        float *px = malloc(n * sizeof *px);
        cr_assert_eq(dm_renderer_read_target(f->r, t, px, &err), DM_OK, "%s", err.detail);
        size_t bad = 0, first = 0;
        for (size_t i = 0; i < n; ++i)
            if (!isfinite(px[i]) && bad++ == 0) first = i;
        cr_expect_eq(bad, 0, "%s: target %s has %zu non-finite values (first at value %zu)", when, info.name, bad,
                     first);
        free(px);
    }
}

Test(render, all_effects_no_gl_error_and_every_target_finite)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 32, .sphere_rings = 24});
    open_renderer(&f, 160, 90, 128);
    frame(&f, DM_VIEW_FINAL, 0);
    expect_all_targets_finite(&f, "final");
    /* every debug view renders and leaves everything finite */
    static const struct {
        dm_view v;
        int k;
    } views[] = {{DM_VIEW_IRRADIANCE, 0}, {DM_VIEW_BLUR, 1},     {DM_VIEW_BLUR, 5},     {DM_VIEW_STRETCH, 0},
                 {DM_VIEW_STRETCH, 5},   {DM_VIEW_SHADOW, 0},   {DM_VIEW_SPECULAR, 0}, {DM_VIEW_DIFFUSE, 0},
                 {DM_VIEW_UV_TEST, 0},   {DM_VIEW_WIREFRAME, 0}};
    for (size_t i = 0; i < sizeof views / sizeof views[0]; ++i) {
        frame(&f, views[i].v, views[i].k);
        expect_all_targets_finite(&f, dm_view_name(views[i].v));
    }
    close_fixture(&f);
}

/* Hard cases in the mesh: zero-UV-area triangles, zero tangents, a huge light. */
Test(render, degenerate_uvs_zero_tangents_huge_light_stay_finite)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 16, .sphere_rings = 12});
    float *v = f.synth->vertices;
    for (int i = 0; i < f.synth->assets.vertex_count; i += 3) {
        float *x = v + (size_t)i * DM_VERTEX_FLOATS;
        x[DM_VERTEX_TANGENT] = x[DM_VERTEX_TANGENT + 1] = x[DM_VERTEX_TANGENT + 2] = 0.0f;
        x[DM_VERTEX_UV] = x[DM_VERTEX_UV + 1] = 0.5f; /* collapses the UVs of every triangle using it */
    }
    f.synth->scene.lights[0].intensity = 6e4f; /* half-float targets top out at 65504 */
    open_renderer(&f, 96, 64, 64);
    frame(&f, DM_VIEW_FINAL, 0);
    expect_all_targets_finite(&f, "degenerate");
    close_fixture(&f);
}

/* Uniform irradiance on a flat quad of constant stretch: every blur level equals level 0.
 * Tolerance 1e-3 (relative): half-float storage rounds to 2^-11 ≈ 4.9e-4 relative; the
 * weights sum to 1 to float precision and coverage is exactly 1 inside the chart. Each level
 * is read at its own size. With the automatic blur resolution (full = false, 1.2 texels,
 * dm_render_desc.blur_auto_resolution):
 * 64 mm side on 128 texels is 2 texels per mm, so σ_4 = 1.41 mm is 2.8 texels (1.4 at half
 * size) and σ_5 = 2.72 mm is 5.4 (1.4 at a quarter): levels 4 and 5 at 1/2 and 1/4; with the
 * chart inset by 0.25 (1 texel per mm) only level 5, at 1/2. */
static void constant_case(float inset, bool full)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_QUAD, .quad_uv_inset = inset, .stretch_size = 128});
    dm_effect on[] = {DM_EFFECT_SUBSURFACE};
    only(&f.synth->scene, on, 1);
    f.synth->scene.lights[0].direction[0] = 0, f.synth->scene.lights[0].direction[1] = 0;
    f.synth->scene.lights[0].direction[2] = 1;
    f.synth->scene.lights[0].intensity = 0.8f;
    static const uint8_t white[4] = {255, 255, 255, 255};
    f.synth->assets.albedo = (dm_texture){DM_TEX_RGBA8_SRGB, 1, 1, white};
    open_renderer_desc(&f, (dm_render_desc){.width = 64, .height = 64, .irradiance_size = 128, .shadow_size = 256,
                                            .blur_auto_resolution = !full});
    frame(&f, DM_VIEW_FINAL, 0);
    dm_target_info info;
    float *l0 = read_target(&f, "irradiance", &info);
    int n0 = info.width;
    const float *a = l0 + ((size_t)(n0 / 2) * n0 + n0 / 2) * 4; /* level 0 is the constant everywhere inside */
    int inside = 0;
    for (int k = 1; k < 6; ++k) {
        char name[16];
        snprintf(name, sizeof name, "blur%d", k);
        float *lk = read_target(&f, name, &info);
        int n = info.width;
        int shift = full ? 0 : inset > 0 ? (int[]){0, 0, 0, 0, 0, 1}[k] : (int[]){0, 0, 0, 0, 1, 2}[k];
        cr_expect_eq(n, n0 >> shift, "level %d stored at %d texels, expected %d", k, n, n0 >> shift);
        double worst = 0;
        inside = 0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                double u = (i + 0.5) / n, v = (j + 0.5) / n;
                if (u <= inset || u >= 1 - inset || v <= inset || v >= 1 - inset) continue; /* gutter */
                const float *b = lk + ((size_t)j * n + i) * 4;
                cr_assert_gt(b[3], 0.0f, "level %d: no coverage inside the chart at (%d, %d)", k, i, j);
                for (int c = 0; c < 3; ++c) {
                    double ref = a[c] / a[3], got = b[c] / b[3];
                    worst = fmax(worst, fabs(got - ref) / ref);
                }
                ++inside;
            }
        cr_expect_leq(worst, 1e-3, "level %d: relative deviation %.3g inside the chart (inset %.2f)", k, worst,
                      (double)inset);
        free(lk);
    }
    cr_expect_gt(inside, n0 * n0 / 5 / (full ? 1 : 16));
    cr_expect_float_eq(a[0] / a[3], 0.8f, 5e-4f);
    free(l0);
    close_fixture(&f);
}

Test(render, blur_chain_preserves_a_constant)
{
    constant_case(0.0f, true);
}

/* A chart surrounded by an empty gutter: the seam must not darken (coverage renormalises). */
Test(render, blur_chain_preserves_a_constant_up_to_the_seam)
{
    constant_case(0.25f, true);
}

/* The same with the automatic blur resolution: the reduced level keeps the constant too. */
Test(render, reduced_blur_levels_preserve_a_constant_up_to_the_seam)
{
    constant_case(0.0f, false);
    constant_case(0.25f, false);
}

/* A single lit texel spreads with the profile's variances, measured in mm through the
 * stretch map. The kernel is scaled so its discrete variance is exactly v_k − v_{k−1};
 * what remains is bilinear interpolation of the taps, which convolves each pass with
 * [1−f, f] (variance f(1−f) ≤ 1/4 texel²): at most 5 passes × 0.25 × (0.25 mm)² ≈ 0.078
 * mm² per axis; plus 0.5 % for half-float storage of the spread values. */
static void single_point_spread(float blur_scale)
{
    fixture f;
    const float side_mm = 64.0f;
    const int n = 256;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_QUAD, .quad_side_mm = side_mm, .stretch_size = 64});
    dm_scene *s = &f.synth->scene;
    dm_effect on[] = {DM_EFFECT_SUBSURFACE};
    only(s, on, 1);
    s->lights[0].direction[0] = 0, s->lights[0].direction[1] = 0, s->lights[0].direction[2] = 1;
    s->lights[0].intensity = 1.0f;
    s->mix = 1.0f; /* all albedo before scattering: irradiance = the albedo texel */
    uint8_t *albedo = calloc((size_t)n * n * 4, 1);
    albedo[((size_t)(n / 2) * n + n / 2) * 4 + 0] = 255;
    f.synth->assets.albedo = (dm_texture){DM_TEX_RGBA8_SRGB, n, n, albedo};
    open_renderer(&f, 32, 32, n);
    dm_error err = {0};
    dm_frame_options fo = {.blur_scale = blur_scale};
    cr_assert_eq(dm_render_frame(f.r, &fo, &err), DM_OK, "%s", err.detail);
    const double scale = blur_scale > 0 ? blur_scale : 1.0;
    double var0[2] = {0, 0};
    for (int k = 0; k < 6; ++k) {
        char name[16];
        snprintf(name, sizeof name, k ? "blur%d" : "irradiance", k);
        dm_target_info info;
        float *px = read_target(&f, name, &info);
        double m0 = 0, mu = 0, mv = 0, muu = 0, mvv = 0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                double w = px[((size_t)j * n + i) * 4], x = (i + 0.5) / n * side_mm, y = (j + 0.5) / n * side_mm;
                m0 += w, mu += w * x, mv += w * y, muu += w * x * x, mvv += w * y * y;
            }
        free(px);
        cr_assert_gt(m0, 0.0);
        double var_u = muu / m0 - (mu / m0) * (mu / m0), var_v = mvv / m0 - (mv / m0) * (mv / m0);
        if (k == 0) {
            var0[0] = var_u, var0[1] = var_v;
            continue;
        }
        double expect = (s->profile.variance_mm2[k] - s->profile.variance_mm2[0]) * scale;
        double tol = 0.078 + 0.005 * expect;
        if (expect < 0.5) continue; /* below 2 texels of σ the bilinear bound dominates: not informative */
        cr_expect(fabs(var_u - var0[0] - expect) <= tol, "level %d along u: %.4f mm², expected %.4f ± %.3f", k,
                  var_u - var0[0], expect, tol);
        cr_expect(fabs(var_v - var0[1] - expect) <= tol, "level %d along v: %.4f mm², expected %.4f ± %.3f", k,
                  var_v - var0[1], expect, tol);
    }
    free(albedo);
    close_fixture(&f);
}

Test(render, single_point_spreads_with_the_profile_variance_in_mm) { single_point_spread(0.0f); }

/* blur_scale multiplies every variance: the same bound as above, on the scaled variances
 * (σ of the widest level grows to 3.9 mm, 3σ still well inside the 32 mm half side). */
Test(render, blur_scale_multiplies_every_variance) { single_point_spread(2.0f); }

/* The viewer's knobs at their neutral values leave the picture exactly as it was: zero and
 * one are the same frame, byte for byte; a set_scene with the same scene changes nothing. */
Test(render, neutral_scales_and_same_scene_give_identical_frames)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 32, .sphere_rings = 24});
    open_renderer(&f, 64, 48, 64);
    size_t n = 64 * 48 * 4;
    uint8_t *a = malloc(n), *b = malloc(n);
    dm_error err = {0};
    frame(&f, DM_VIEW_FINAL, 0);
    cr_assert_eq(dm_renderer_read_display(f.r, a, &err), DM_OK, "%s", err.detail);
    dm_frame_options one = {.blur_scale = 1.0f, .roughness_scale = 1.0f};
    cr_assert_eq(dm_renderer_set_scene(f.r, &f.synth->scene, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_frame(f.r, &one, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_renderer_read_display(f.r, b, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(memcmp(a, b, n), 0, "scale 1 differs from the default frame");
    /* a rougher surface changes the specular picture */
    dm_frame_options rough = {.roughness_scale = 2.0f};
    cr_assert_eq(dm_render_frame(f.r, &rough, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_renderer_read_display(f.r, b, &err), DM_OK, "%s", err.detail);
    cr_expect_neq(memcmp(a, b, n), 0, "roughness_scale 2 changed nothing");
    free(a), free(b);
    close_fixture(&f);
}

/* Mean of channel c over the covered pixels (alpha > 0) of a linear read-back. */
static double mean_channel(const float *px, size_t n, int c)
{
    double sum = 0;
    size_t k = 0;
    for (size_t i = 0; i < n; ++i)
        if (px[4 * i + 3] > 0) sum += px[4 * i + c], ++k;
    return k ? sum / k : 0;
}

/* Live weights (dm_renderer_set_profile_weights, the viewer's skin sliders): the create
 * profile with no scale is the same frame, byte for byte; other weights change it; a scale
 * of 1/2 on green and blue halves their diffuse light (the lit sphere's mean falls, red's
 * stays within the specular's share); a variance or count that differs is refused. */
Test(render, profile_weights_change_live)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 32, .sphere_rings = 24});
    open_renderer(&f, 64, 48, 64);
    size_t n = 64 * 48;
    float *a = malloc(n * 4 * sizeof *a), *b = malloc(n * 4 * sizeof *b);
    dm_error err = {0};
    frame(&f, DM_VIEW_FINAL, 0);
    cr_assert_eq(dm_renderer_read_linear(f.r, a, &err), DM_OK, "%s", err.detail);
    dm_profile p = f.synth->assets.profile ? *f.synth->assets.profile : f.synth->scene.profile;
    cr_assert_eq(dm_renderer_set_profile_weights(f.r, &p, NULL, &err), DM_OK, "%s", err.detail);
    frame(&f, DM_VIEW_FINAL, 0);
    cr_assert_eq(dm_renderer_read_linear(f.r, b, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(memcmp(a, b, n * 4 * sizeof *a), 0, "the create profile again changed the frame");
    double half[3] = {1.0, 0.5, 0.5};
    cr_assert_eq(dm_renderer_set_profile_weights(f.r, &p, half, &err), DM_OK, "%s", err.detail);
    frame(&f, DM_VIEW_DIFFUSE, 0);
    cr_assert_eq(dm_renderer_read_linear(f.r, b, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_renderer_set_profile_weights(f.r, &p, NULL, &err), DM_OK, "%s", err.detail);
    frame(&f, DM_VIEW_DIFFUSE, 0);
    cr_assert_eq(dm_renderer_read_linear(f.r, a, &err), DM_OK, "%s", err.detail);
    for (int c = 0; c < 3; ++c) { /* the diffuse view is linear in the level weights: exact to float rounding */
        double ratio = mean_channel(b, n, c) / mean_channel(a, n, c);
        cr_expect(fabs(ratio - half[c]) < 1e-4, "channel %d: diffuse ratio %g, expected %g", c, ratio, half[c]);
    }
    dm_profile wide = p; /* every channel's light in the widest Gaussian: a different picture */
    for (int k = 0; k < wide.count; ++k)
        for (int c = 0; c < 3; ++c) wide.weight[k][c] = k == wide.count - 1 ? 1.0 : 0.0;
    cr_assert_eq(dm_renderer_set_profile_weights(f.r, &wide, NULL, &err), DM_OK, "%s", err.detail);
    frame(&f, DM_VIEW_DIFFUSE, 0);
    cr_assert_eq(dm_renderer_read_linear(f.r, b, &err), DM_OK, "%s", err.detail);
    cr_expect_neq(memcmp(a, b, n * 4 * sizeof *a), 0, "other weights changed nothing");
    dm_profile moved = p;
    moved.variance_mm2[2] *= 1.01;
    cr_expect_eq(dm_renderer_set_profile_weights(f.r, &moved, NULL, &err), DM_ERR_INVALID_ARGUMENT);
    cr_expect(strstr(err.detail, "variance_mm2[2]") != NULL, "%s", err.detail);
    moved = p, moved.count = p.count - 1;
    cr_expect_eq(dm_renderer_set_profile_weights(f.r, &moved, NULL, &err), DM_ERR_INVALID_ARGUMENT);
    double bad[3] = {1, -1, 1};
    cr_expect_eq(dm_renderer_set_profile_weights(f.r, &p, bad, &err), DM_ERR_RANGE);
    cr_expect(strstr(err.detail, "scale_rgb[1]") != NULL, "%s", err.detail);
    free(a), free(b);
    close_fixture(&f);
}

Test(render, set_scene_moves_the_camera_and_refuses_structural_changes)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 32, .sphere_rings = 24});
    open_renderer(&f, 64, 48, 64);
    size_t n = 64 * 48 * 4;
    uint8_t *a = malloc(n), *b = malloc(n);
    dm_error err = {0};
    frame(&f, DM_VIEW_FINAL, 0);
    cr_assert_eq(dm_renderer_read_display(f.r, a, &err), DM_OK, "%s", err.detail);
    dm_scene s = f.synth->scene;
    s.camera_eye[0] += 1.0f;
    s.exposure = 1.0f;
    cr_assert_eq(dm_renderer_set_scene(f.r, &s, &err), DM_OK, "%s", err.detail);
    frame(&f, DM_VIEW_FINAL, 0);
    cr_assert_eq(dm_renderer_read_display(f.r, b, &err), DM_OK, "%s", err.detail);
    cr_expect_neq(memcmp(a, b, n), 0, "moving the camera changed nothing");
    dm_scene t = f.synth->scene;
    t.effects[DM_EFFECT_GLOW] = !t.effects[DM_EFFECT_GLOW];
    cr_expect_eq(dm_renderer_set_scene(f.r, &t, &err), DM_ERR_INVALID_ARGUMENT);
    cr_expect(strstr(err.detail, "glow") != NULL, "message does not name the effect: %s", err.detail);
    t = f.synth->scene;
    t.lights[0].casts_shadow = !t.lights[0].casts_shadow;
    cr_expect_eq(dm_renderer_set_scene(f.r, &t, &err), DM_ERR_INVALID_ARGUMENT);
    free(a), free(b);
    close_fixture(&f);
}

/* Light straight behind the sphere (camera in front): no specular anywhere on screen,
 * and zero irradiance wherever the surface faces away from the light. */
Test(render, light_behind_gives_no_specular_and_no_irradiance_on_the_unlit_side)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 48, .sphere_rings = 32});
    dm_scene *s = &f.synth->scene;
    dm_effect on[] = {DM_EFFECT_SPECULAR, DM_EFFECT_SUBSURFACE, DM_EFFECT_SHADOWS, DM_EFFECT_ENERGY_CONSERVATION};
    only(s, on, 4);
    s->lights[0].direction[0] = 0, s->lights[0].direction[1] = 0, s->lights[0].direction[2] = -1;
    s->lights[0].intensity = 100.0f;
    open_renderer(&f, 96, 64, 128);
    frame(&f, DM_VIEW_SPECULAR, 0);
    dm_target_info info;
    float *scr = read_target(&f, "screen", &info);
    float worst = 0;
    for (size_t i = 0; i < (size_t)info.width * info.height * 4; ++i)
        if (i % 4 != 3) worst = fmaxf(worst, fabsf(scr[i]));
    cr_expect_eq(worst, 0.0f, "specular %g on screen with the light behind", (double)worst);
    free(scr);

    frame(&f, DM_VIEW_FINAL, 0);
    float *irr = read_target(&f, "irradiance", &info);
    int n = info.width, unlit = 0, lit_nonzero = 0, lit = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double th = (j + 0.5) / n * 3.14159265358979, ph = (i + 0.5) / n * 6.28318530717959;
            double nz = sin(th) * cos(ph); /* n·L = −nz */
            const float *p = irr + ((size_t)j * n + i) * 4;
            if (nz > 0.05) {
                ++unlit;
                cr_expect_eq(p[0] + p[1] + p[2], 0.0f, "irradiance %g at texel (%d, %d), n.L = %.3f",
                             (double)(p[0] + p[1] + p[2]), i, j, -nz);
            } else if (nz < -0.3) {
                ++lit;
                lit_nonzero += p[0] > 0;
            }
        }
    cr_expect_gt(unlit, n * n / 4);
    cr_expect_eq(lit_nonzero, lit, "the lit side must be lit (%d of %d texels)", lit_nonzero, lit);
    free(irr);
    close_fixture(&f);
}

Test(render, missing_asset_is_refused_naming_it)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_QUAD});
    f.synth->assets.beckmann.texels = NULL;
    dm_error err = {0};
    dm_render_desc d = {.width = 16, .height = 16, .irradiance_size = 16};
    cr_expect_eq(dm_renderer_create(&f.synth->assets, &d, &f.r, &err), DM_ERR_MISMATCH);
    cr_expect(strstr(err.detail, "Beckmann") && strstr(err.detail, "specular"), "%s", err.detail);
    f.synth->scene.effects[DM_EFFECT_SPECULAR] = false; /* not needed any more: accepted */
    cr_expect_eq(dm_renderer_create(&f.synth->assets, &d, &f.r, &err), DM_OK, "%s", err.detail);
    close_fixture(&f);
}

Test(render, shader_dir_override_reads_from_disk)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_QUAD});
    dm_error err = {0};
    dm_render_desc d = {.width = 16, .height = 16, .irradiance_size = 16, .shader_dir = "/nonexistent-dermis"};
    cr_expect_neq(dm_renderer_create(&f.synth->assets, &d, &f.r, &err), DM_OK);
    cr_expect(strstr(err.detail, "/nonexistent-dermis/") != NULL, "%s", err.detail);
    close_fixture(&f);
}

Test(render, blur_kernel_is_the_chapter_kernel_at_seven_taps)
{
    float off[63], w[63];
    double var = dm_render_blur_kernel(7, off, w);
    static const double chapter[7] = {0.006, 0.061, 0.242, 0.382, 0.242, 0.061, 0.006};
    double sum = 0, var_ref = 0;
    for (int i = 0; i < 7; ++i) {
        /* the chapter prints 3 decimals, its centre lowered so the seven sum to 1 */
        cr_expect(fabs(w[i] - chapter[i]) < 1e-3, "tap %d: %.4f, chapter %.3f", i, (double)w[i], chapter[i]);
        cr_expect_float_eq(off[i], (float)(i - 3), 1e-6f);
        sum += w[i];
        var_ref += w[i] * (double)off[i] * off[i];
    }
    cr_expect(fabs(sum - 1.0) < 1e-6);
    cr_expect(fabs(var - var_ref) < 1e-6 && fabs(var - 1.08) < 0.01, "variance %.4f", var);
    var = dm_render_blur_kernel(63, off, w);
    cr_expect(fabs(var - 1.0) < 0.02, "63 taps: variance %.4f σ²", var); /* ±3σ, tails folded */
}

Test(render, png_and_exr_writers_round_trip_with_provenance)
{
    const int w = 5, h = 3;
    uint8_t px[5 * 3 * 4];
    float fx[5 * 3 * 4];
    for (int i = 0; i < w * h * 4; ++i) px[i] = (uint8_t)(i * 7), fx[i] = (float)i * 0.25f - 3.0f;
    dm_provenance prov;
    dm_prov_init(&prov, "dermis-render");
    dm_prov_add_string(&prov, "view", "final");
    char png[64], exr[64];
    snprintf(png, sizeof png, "/tmp/dm_render_test_%d.png", (int)getpid());
    snprintf(exr, sizeof exr, "/tmp/dm_render_test_%d.exr", (int)getpid());
    dm_error err = {0};
    cr_assert_eq(dm_render_write_png(png, w, h, px, &prov, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_write_exr(exr, w, h, fx, &prov, &err), DM_OK, "%s", err.detail);
    dm_image img = {0};
    cr_assert_eq(dm_image_read(png, DM_PIXEL_U8, &img, &err), DM_OK, "%s", err.detail);
    cr_expect(img.width == w && img.height == h && img.channels == 4);
    cr_expect_eq(memcmp(img.pixels, px, sizeof px), 0);
    cr_expect(img.has_provenance && strcmp(img.prov.tool, "dermis-render") == 0);
    dm_image_free(&img);
    dm_exr_image e = {0};
    cr_assert_eq(dm_exr_read(exr, &e, &err), DM_OK, "%s", err.detail);
    static const char *names[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c) {
        const float *plane = dm_exr_find(&e, names[c]);
        cr_assert_not_null(plane);
        for (int i = 0; i < w * h; ++i) cr_expect_eq(plane[i], fx[i * 4 + c], "%s[%d]", names[c], i);
    }
    cr_expect(e.has_provenance && dm_prov_find(&e.prov, "view") != NULL);
    dm_exr_free(&e);
    unlink(png);
    unlink(exr);
}

/* Golden image of the synthetic sphere, all effects. Tolerance: 6 steps max, 0.5 mean:
 * llvmpipe is deterministic for one Mesa/LLVM build; other builds differ in the last bits
 * of transcendental functions and in rasterization rules at triangle edges. */
Test(render, golden_synthetic_sphere)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 48, .sphere_rings = 32});
    open_renderer(&f, 160, 90, 128);
    frame(&f, DM_VIEW_FINAL, 0);
    uint8_t *rgba = malloc(160 * 90 * 4);
    dm_error err = {0};
    cr_assert_eq(dm_renderer_read_display(f.r, rgba, &err), DM_OK, "%s", err.detail);
    char msg[1024];
    cr_expect(golden_check("synthetic-sphere", 160, 90, rgba, (golden_tolerance){6, 0.5}, msg, sizeof msg), "%s",
              msg);
    free(rgba);
    close_fixture(&f);
}

/* The default 4-tap PCF takes the same 3x3-bilinear (4x4-texel) filter as the 9 reference
 * taps: irradiance equal to float rounding of the tap weights (1e-5 absolute on values
 * near 1: a few ulps of the position arithmetic, far below a texel's shadow step of
 * 1/9). One bilinear compare is a different filter: it must differ somewhere, or the
 * scene would not exercise shadows at all. A bowl (synth_bowl) lit from 40° above its rim:
 * the wall casts a shadow with a long edge across the inside (a convex sphere casts none). */
static float *irradiance_with_taps(int taps, dm_target_info *info)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 48, .sphere_rings = 32});
    dm_effect on[] = {DM_EFFECT_SUBSURFACE, DM_EFFECT_SHADOWS};
    only(&f.synth->scene, on, 2);
    synth_bowl(f.synth);
    float *l = f.synth->scene.lights[0].direction;
    l[0] = cosf(40.0f * 3.14159265f / 180.0f), l[1] = 0.0f, l[2] = sinf(40.0f * 3.14159265f / 180.0f);
    dm_error err = {0};
    dm_render_desc d = {.width = 32, .height = 32, .irradiance_size = 256, .shadow_size = 256, .shadow_pcf_taps = taps};
    cr_assert_eq(dm_renderer_create(&f.synth->assets, &d, &f.r, &err), DM_OK, "%s", err.detail);
    dm_frame_options o = {0};
    cr_assert_eq(dm_render_frame(f.r, &o, &err), DM_OK, "%s", err.detail);
    float *px = read_target(&f, "irradiance", info);
    close_fixture(&f);
    return px;
}

Test(render, four_tap_pcf_equals_the_nine_tap_filter)
{
    dm_target_info info;
    float *ref = irradiance_with_taps(9, &info), *four = irradiance_with_taps(4, &info),
          *one = irradiance_with_taps(1, &info);
    double d4 = 0, d1 = 0;
    for (size_t i = 0; i < (size_t)info.width * info.height * 4; ++i) {
        d4 = fmax(d4, fabs((double)four[i] - ref[i]));
        d1 = fmax(d1, fabs((double)one[i] - ref[i]));
    }
    cr_expect_leq(d4, 1e-5, "4 taps differ from 9 by %.3g", d4);
    cr_expect_gt(d1, 1e-3, "1 tap differs from 9 by only %.3g: shadows not exercised", d1);
    cr_log_info("largest difference from 9 taps: 4 taps %.3g, 1 tap %.3g", d4, d1);
    free(ref), free(four), free(one);
}

/* Reusing texture space gives the frame it would have recomputed, and recomputes when the
 * light turns. */
Test(render, reuse_texture_space_is_exact_and_follows_every_change)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 32, .sphere_rings = 24});
    dm_error err = {0};
    dm_renderer *reuse = NULL;
    dm_render_desc d = {.width = 64, .height = 48, .irradiance_size = 128, .shadow_size = 256};
    cr_assert_eq(dm_renderer_create(&f.synth->assets, &d, &f.r, &err), DM_OK, "%s", err.detail);
    d.reuse_texture_space = true;
    d.timings = true; /* skipped passes read exactly 0 ms: whether they ran, not how fast */
    cr_assert_eq(dm_renderer_create(&f.synth->assets, &d, &reuse, &err), DM_OK, "%s", err.detail);
    /* Each change that feeds texture space must recompute it; each repeat must reuse it. */
    const struct {
        float turn, blur_scale, roughness_scale, mix; /* mix < 0: leave the scene alone */
        bool recompute;
    } frames[] = {{0, 0, 0, -1, true},    {0, 0, 0, -1, false},    {45, 0, 0, -1, true},  {45, 0, 0, -1, false},
                  {45, 2, 0, -1, true},   {45, 2, 0, -1, false},   {45, 2, 1.5f, -1, true}, {45, 2, 1.5f, -1, false},
                  {45, 2, 1.5f, 0.2f, true}, {45, 2, 1.5f, -1, false}};
    size_t n = 64 * 48 * 4;
    float *pa = malloc(n * sizeof *pa), *pb = malloc(n * sizeof *pb);
    for (size_t i = 0; i < sizeof frames / sizeof *frames; ++i) {
        if (frames[i].mix >= 0) {
            dm_scene s = f.synth->scene;
            s.mix = frames[i].mix;
            cr_assert_eq(dm_renderer_set_scene(f.r, &s, &err), DM_OK, "%s", err.detail);
            cr_assert_eq(dm_renderer_set_scene(reuse, &s, &err), DM_OK, "%s", err.detail);
        }
        dm_frame_options o = {.light_rotation_deg = frames[i].turn,
                              .blur_scale = frames[i].blur_scale,
                              .roughness_scale = frames[i].roughness_scale};
        cr_assert_eq(dm_render_frame(f.r, &o, &err), DM_OK, "%s", err.detail);
        cr_assert_eq(dm_render_frame(reuse, &o, &err), DM_OK, "%s", err.detail);
        cr_assert_eq(dm_renderer_read_linear(f.r, pa, &err), DM_OK, "%s", err.detail);
        cr_assert_eq(dm_renderer_read_linear(reuse, pb, &err), DM_OK, "%s", err.detail);
        cr_expect_eq(memcmp(pa, pb, n * sizeof *pa), 0, "frame %zu differs from the exact renderer", i);
        double ms[DM_PLAN_MAX_PASSES];
        dm_renderer_last_timings(reuse, ms, NULL);
        int irr = dm_render_plan_find(dm_renderer_plan(reuse), "irradiance");
        cr_assert_geq(irr, 0);
        if (frames[i].recompute) cr_expect_gt(ms[irr], 0.0, "frame %zu: irradiance skipped after a change", i);
        else cr_expect_eq(ms[irr], 0.0, "frame %zu: irradiance ran although nothing changed", i);
    }
    free(pa), free(pb);
    dm_renderer_destroy(reuse);
    close_fixture(&f);
}

/* Timings measure the clock they name: a frame's wall-clock time fits inside the wall time
 * around dm_render_frame, its CPU time (timings_cpu) inside the process CPU time around it.
 * (Wall time reported as CPU time exceeds the wall time around the call whenever llvmpipe's
 * threads run at once, as on an idle multi-core machine.) */
static void timing_case(bool cpu)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE});
    /* large enough that llvmpipe spreads it over its threads: wall and CPU time differ */
    open_renderer_desc(&f, (dm_render_desc){.width = 640, .height = 360, .irradiance_size = 512, .shadow_size = 256,
                                            .timings = true, .timings_cpu = cpu});
    dm_error err = {0};
    for (int i = 0; i < 3; ++i) {
        double w0 = dm_now_ms(), c0 = dm_cpu_ms();
        cr_assert_eq(dm_render_frame(f.r, &(dm_frame_options){0}, &err), DM_OK, "%s", err.detail);
        double wall = dm_now_ms() - w0, used = dm_cpu_ms() - c0, frame_ms = -1;
        dm_renderer_last_timings(f.r, NULL, &frame_ms);
        cr_expect(frame_ms >= 0 && frame_ms <= (cpu ? used : wall) + 0.5, "%s frame %.2f ms, around it %.2f ms",
                  cpu ? "CPU" : "wall", frame_ms, cpu ? used : wall);
    }
    close_fixture(&f);
}

Test(render, wall_timings_are_wall_time)
{
    timing_case(false);
}

Test(render, cpu_timings_are_process_cpu_time)
{
    timing_case(true);
}
