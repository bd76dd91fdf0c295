/* The texture-space blur on the CPU (lib/render/passes/dm_pass_blur_cpu.c, core/dm_level_blur.h)
 * against the same passes in GL (shaders/blur.glsl), on the synthetic sphere: every blur level
 * and the final picture agree to float rounding, with full-resolution and with reduced levels;
 * which path runs follows dm_render_desc.blur_path; a view that stops the chain early leaves
 * the next frame exact. (The core pass against a double-precision reference:
 * tests/unit/test_level_blur.c.) */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/render_fixture.h"
#include "render/dm_render_plan.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

/* The two paths sum the same taps in float; they differ in how a tap's texel coordinate is
 * rounded (the shader interpolates uv and the sampler scales it; the CPU scales once), ~1e-7
 * of a coordinate of ~100 texels, times the texel-to-texel change, and in the order of a few
 * additions: ~1e-6 of the level's range. 1e-4 of it passes that and fails a tap one texel
 * off or a wrong weight (~1e-2 on the sphere's shadow terminator). */
#define TOL 1e-4

/* max |a − b| over n RGBA texels, and the largest |a| */
static double max_diff(const float *a, const float *b, int n, double *range)
{
    double d = 0.0;
    *range = 0.0;
    for (int i = 0; i < 4 * n; ++i) {
        cr_assert(isfinite(a[i]) && isfinite(b[i]), "value %d not finite: %g, %g", i, (double)a[i], (double)b[i]);
        d = fmax(d, fabs((double)a[i] - b[i]));
        *range = fmax(*range, fabs((double)a[i]));
    }
    return d;
}

/* renders the final frame with the blur in GL and on the CPU, desc otherwise the same, and
 * compares every level target and the screen */
static void compare_paths(dm_render_desc d)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 32, .sphere_rings = 24});
    dm_renderer *r[2];
    dm_error err = {0};
    for (int path = 0; path < 2; ++path) {
        d.blur_path = path ? DM_BLUR_PATH_CPU : DM_BLUR_PATH_GL;
        cr_assert_eq(dm_renderer_create(&f.synth->assets, &d, &r[path], &err), DM_OK, "%s", err.detail);
        cr_assert_eq(dm_renderer_blur_on_cpu(r[path]), path == 1);
        f.r = r[path];
        frame(&f, DM_VIEW_FINAL, 0);
    }
    /* the diffusion pass's sum (in GL from the levels, on the CPU as they were made; with
     * reduced levels the final pass sums them per pixel, and there is none) and the glow's
     * blurred bright pass (the tonemap adds it) */
    const char *names[] = {"blur1", "blur2", "blur3", "blur4", "blur5", "diffusion", "glow_a", "screen"};
    int compared = 0;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
        dm_target_info info;
        float *px[2];
        f.r = r[0];
        if (dm_renderer_find_target(f.r, names[i]) < 0) continue;
        px[0] = read_target(&f, names[i], &info);
        f.r = r[1];
        px[1] = read_target(&f, names[i], &info);
        double range, diff = max_diff(px[1], px[0], info.width * info.height, &range);
        cr_expect_leq(diff, TOL * range, "%s (%dx%d): max |cpu - gl| %g of %g", names[i], info.width, info.height,
                      diff, range);
        cr_expect_gt(range, 0.0, "%s is black", names[i]);
        free(px[0]), free(px[1]);
        ++compared;
    }
    bool reduced = d.blur_reduce_from > 0;
    cr_expect_eq(dm_renderer_find_target(r[1], "diffusion") < 0, reduced);
    cr_expect_eq(compared, (int)(sizeof names / sizeof names[0]) - reduced);
    dm_renderer_destroy(r[0]);
    f.r = r[1];
    close_fixture(&f);
}

Test(render_blur_cpu, agrees_with_gl_to_float_rounding)
{
    compare_paths((dm_render_desc){.width = 96, .height = 72, .irradiance_size = 128, .shadow_size = 256});
}

Test(render_blur_cpu, agrees_with_gl_on_reduced_levels)
{
    /* level 2 on at 64 (its U pass reads 128 rows and writes 64 columns), and each level
     * at its own automatic size */
    compare_paths((dm_render_desc){.width = 96, .height = 72, .irradiance_size = 128, .shadow_size = 256,
                                   .blur_reduce_from = 2});
    compare_paths((dm_render_desc){.width = 96, .height = 72, .irradiance_size = 128, .shadow_size = 256,
                                   .blur_reduce_from = 3, .blur_reduce_shift = 2});
}

/* auto: the CPU where OpenGL is llvmpipe (these tests run on it) with float levels; half floats
 * stay in GL, and asking for the CPU with them is refused */
Test(render_blur_cpu, auto_picks_the_cpu_on_llvmpipe_with_float_levels)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE});
    const char *gl = (const char *)glGetString(GL_RENDERER);
    cr_assert(gl && strstr(gl, "llvmpipe"), "expected llvmpipe, got %s", gl ? gl : "(null)");
    open_renderer(&f, 32, 24, 64);
    cr_expect(dm_renderer_blur_on_cpu(f.r));
    dm_renderer_destroy(f.r);
    open_renderer_desc(&f, (dm_render_desc){.width = 32, .height = 24, .irradiance_size = 64, .blur_half_float = true});
    cr_expect_not(dm_renderer_blur_on_cpu(f.r));
    dm_renderer_destroy(f.r);
    f.r = NULL;
    dm_error err = {0};
    dm_renderer *r = NULL;
    cr_expect_eq(dm_renderer_create(&f.synth->assets,
                                    &(dm_render_desc){.width = 32, .height = 24, .irradiance_size = 64,
                                                      .blur_half_float = true, .blur_path = DM_BLUR_PATH_CPU},
                                    &r, &err),
                 DM_ERR_INVALID_ARGUMENT);
    cr_expect_null(r);
    cr_expect(strstr(err.detail, "half"), "%s", err.detail);
    cr_expect_eq(dm_renderer_create(&f.synth->assets, &(dm_render_desc){.blur_path = (dm_blur_path)7}, &r, &err),
                 DM_ERR_RANGE);
    close_fixture(&f);
}

/* a blur view runs the chain up to its level only, and the CPU keeps a level between passes:
 * after a view lit from elsewhere, the next frame must start again from its own irradiance
 * (the same bytes as before the view), not from a level the view left */
Test(render_blur_cpu, a_view_that_stops_early_leaves_the_next_frame_exact)
{
    fixture f;
    dm_error err = {0};
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE});
    open_renderer(&f, 64, 48, 64);
    cr_assert(dm_renderer_blur_on_cpu(f.r));
    frame(&f, DM_VIEW_FINAL, 0);
    dm_target_info info;
    /* the frame's own sum first: reading a level runs the chain again to upload it */
    const char *levels[] = {"diffusion", "blur1", "blur2", "blur3"};
    float *want[4], *moved;
    for (int k = 0; k < 4; ++k) want[k] = read_target(&f, levels[k], &info);
    size_t bytes = sizeof(float) * 4 * (size_t)info.width * info.height;
    dm_frame_options o = {.view = DM_VIEW_BLUR, .view_index = 2, .light_rotation_deg = 120.0f};
    cr_assert_eq(dm_render_frame(f.r, &o, &err), DM_OK, "%s", err.detail);
    moved = read_target(&f, "blur2", &info);
    cr_expect_neq(memcmp(want[2], moved, bytes), 0, "the view's light did not move its levels");
    frame(&f, DM_VIEW_FINAL, 0);
    for (int k = 0; k < 4; ++k) {
        float *got = read_target(&f, levels[k], &info);
        cr_expect_eq(memcmp(want[k], got, bytes), 0, "%s differs after the view", levels[k]);
        free(got), free(want[k]);
    }
    free(moved);
    close_fixture(&f);
}

/* final frames leave levels 1.. on the CPU (the diffusion pass's sum is all they need in GL);
 * a blur view that reuses texture space then shows the level uploaded on demand: the same bytes
 * as a renderer that made the view itself */
Test(render_blur_cpu, a_reused_blur_view_shows_the_level_a_final_frame_left_on_the_cpu)
{
    fixture f;
    dm_error err = {0};
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE});
    float *view[2];
    int w = 0, h = 0;
    for (int reuse = 0; reuse < 2; ++reuse) {
        open_renderer_desc(&f, (dm_render_desc){.width = 64, .height = 48, .irradiance_size = 64,
                                                .shadow_size = 256, .reuse_texture_space = reuse,
                                                .timings = true});
        cr_assert(dm_renderer_blur_on_cpu(f.r));
        if (reuse) frame(&f, DM_VIEW_FINAL, 0);
        frame(&f, DM_VIEW_BLUR, 3);
        double ms[DM_PLAN_MAX_PASSES], frame_ms;
        dm_renderer_last_timings(f.r, ms, &frame_ms);
        int irr = dm_render_plan_find(dm_renderer_plan(f.r), "irradiance");
        cr_assert_geq(irr, 0);
        cr_expect_eq(ms[irr] == 0.0, reuse == 1, "the irradiance pass %s", reuse ? "ran again" : "did not run");
        dm_renderer_view_size(f.r, &w, &h);
        view[reuse] = malloc(sizeof(float) * 4 * (size_t)w * h);
        cr_assert_eq(dm_renderer_read_view(f.r, view[reuse], &err), DM_OK, "%s", err.detail);
        dm_renderer_destroy(f.r);
        f.r = NULL;
    }
    double range = 0;
    for (int i = 0; i < 4 * w * h; ++i) range = fmax(range, fabs(view[0][i]));
    cr_expect_gt(range, 0.0);
    cr_expect_eq(memcmp(view[0], view[1], sizeof(float) * 4 * (size_t)w * h), 0,
                 "the reused blur view differs from one made by its own chain");
    free(view[0]), free(view[1]);
    close_fixture(&f);
}
