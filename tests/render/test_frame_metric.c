/* The instrument's own test (issue #27): the transport metric of dm_ref_frame_compare.h,
 * renderer against the ground-truth frame on a small scene, must rank a deliberately worse
 * setting worse. A 50 mm sphere lit from the side, white albedo, subsurface only (the
 * transport run of bench/accuracy): texture-space diffusion at irradiance 256 against the
 * same at 32 (texels of 10 mm: the blur cannot resolve the terminator), against a profile a quarter as wide
 * (variances / 16: the light does not travel far enough) and against no subsurface at all,
 * which must score 1 (its own definition: no better than leaving subsurface out). Measured
 * (normalised, R/G/B): 256 0.30/0.25/0.21, a quarter as wide 0.72/0.31/0.30, 32 7–18, none 1. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../common/render_fixture.h"
#include "reference/dm_ref_frame.h"
#include "reference/dm_ref_frame_compare.h"

enum { W = 96, H = 96 };

/* One point sample per pixel, as the renderer takes it (no MSAA): the Lambert of both then
 * agree to rounding and no subsurface scores 1 (with 2 × 2 samples the average over the
 * terminator's kink differs from the centre's value: 1.05–1.2). */
static float *reference(const dm_synth *s, const dm_scene *scene)
{
    dm_ref_surface_desc d = {.scene = scene, .vertices = s->assets.vertices, .vertex_count = s->assets.vertex_count,
                             .indices = s->assets.indices, .index_count = s->assets.index_count};
    dm_ref_frame_options o = {.width = W, .height = H, .atlas_size = 256, .atlas_samples = 2, .pixel_samples = 1};
    float *rgba = malloc(sizeof *rgba * 4 * W * H);
    dm_error err = {0};
    cr_assert_eq(dm_ref_frame_render_desc(&d, &o, rgba, &err), DM_OK, "%s", err.detail);
    return rgba;
}

static float *render(dm_synth *s, int irradiance)
{
    dm_renderer *r = NULL;
    dm_error err = {0};
    float *px = malloc(sizeof *px * 4 * W * H);
    cr_assert_eq(dm_renderer_create(&s->assets, &(dm_render_desc){.width = W, .height = H, .irradiance_size = irradiance},
                                    &r, &err),
                 DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_frame(r, &(dm_frame_options){0}, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_renderer_read_linear(r, px, &err), DM_OK, "%s", err.detail);
    dm_renderer_destroy(r);
    return px;
}

static double score(const float *ref, const float *flat, const float *px, const char *what)
{
    float *w = malloc(sizeof *w * W * H);
    dm_ref_frame_interior(ref, px, W, H, w);
    dm_ref_transport_stats st;
    dm_error err = {0};
    cr_assert_eq(dm_ref_transport_compute(ref, flat, px, w, NULL, -1, (size_t)W * H, 0, &st, &err), DM_OK, "%s",
                 err.detail);
    free(w);
    cr_log_info("%-28s normalised %.3f %.3f %.3f, mean %.4f %.4f %.4f over %ld/%ld/%ld signal pixels", what,
                st.normalised[0], st.normalised[1], st.normalised[2], st.mean[0], st.mean[1], st.mean[2], st.signal[0],
                st.signal[1], st.signal[2]);
    cr_expect_gt(st.signal[0], 200, "%s: %ld red signal pixels: subsurface barely shows", what, st.signal[0]);
    return st.normalised_rgb;
}

Test(frame_metric, ranks_a_worse_setting_worse, .timeout = 120)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 48, .sphere_rings = 32});
    dm_synth *s = f.synth;
    dm_effect on[] = {DM_EFFECT_SUBSURFACE};
    only(&s->scene, on, 1);
    s->assets.albedo = (dm_texture){0}; /* white, as the reference's absent albedo */
    dm_light *l = &s->scene.lights[0];
    const double d[3] = {1.0, 0.3, 0.2}, len = sqrt(1.0 + 0.09 + 0.04);
    for (int c = 0; c < 3; ++c) l->direction[c] = (float)(d[c] / len);
    dm_scene flat_scene = s->scene;
    flat_scene.effects[DM_EFFECT_SUBSURFACE] = false;
    float *ref = reference(s, &s->scene), *flat = reference(s, &flat_scene);

    float *good = render(s, 256), *coarse = render(s, 32);
    dm_profile narrow = s->scene.profile;
    for (int k = 0; k < narrow.count; ++k) narrow.variance_mm2[k] /= 16;
    s->assets.profile = &narrow;
    float *thin = render(s, 256);
    s->assets.profile = NULL;
    s->scene.effects[DM_EFFECT_SUBSURFACE] = false;
    float *none = render(s, 256);

    double e_good = score(ref, flat, good, "irradiance 256"), e_coarse = score(ref, flat, coarse, "irradiance 32");
    double e_thin = score(ref, flat, thin, "profile a quarter as wide"), e_none = score(ref, flat, none, "no subsurface");
    cr_expect_lt(e_good, 0.5 * e_coarse, "irradiance 256 scores %.3f, 32 %.3f", e_good, e_coarse);
    cr_expect_lt(e_good, 0.75 * e_thin, "the right profile scores %.3f, a quarter as wide %.3f", e_good, e_thin);
    cr_expect_lt(e_thin, e_none, "a narrow profile %.3f scores worse than none %.3f", e_thin, e_none);
    cr_expect(fabs(e_none - 1) < 0.01, "no subsurface scores %.3f, not 1", e_none);
    cr_expect_lt(e_good, 0.4, "the technique recovers only %.0f %% of what subsurface changes", 100 * (1 - e_good));
    free(ref), free(flat), free(good), free(coarse), free(thin), free(none);
    close_fixture(&f);
}
