/* The decomposed frame comparison (dm_ref_frame_compare, issue #27) on hand-computed cases:
 * the interior mask, the transport statistics (signal pixels, relative and normalised error,
 * regions, empty and bad input), the region labels projected into a frame of two UV charts
 * seen from the front, and the reference frame's diffusion sampled over the pixel
 * (dm_ref_frame_options.diffusion_at_centre) where the answer is known. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../common/ref_synth.h"
#include "reference/dm_ref_frame.h"
#include "reference/dm_ref_frame_compare.h"

static void px(float *f, int i, double r, double g, double b, double a)
{
    f[4 * i] = (float)r, f[4 * i + 1] = (float)g, f[4 * i + 2] = (float)b, f[4 * i + 3] = (float)a;
}

/* 5 × 4 frame, skin everywhere but (3, 1) in the render: interior = not on the border and not
 * (3, 1) or its four neighbours. */
Test(frame_compare, interior_leaves_out_the_border_and_the_silhouette)
{
    enum { W = 5, H = 4 };
    float ref[W * H * 4], ren[W * H * 4], w[W * H];
    for (int i = 0; i < W * H; ++i) px(ref, i, 1, 1, 1, 1), px(ren, i, 1, 1, 1, 1);
    ren[4 * (1 * W + 3) + 3] = 0.0f;
    dm_ref_frame_interior(ref, ren, W, H, w);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            bool border = x == 0 || y == 0 || x == W - 1 || y == H - 1;
            bool near = abs(x - 3) + abs(y - 1) <= 1;
            cr_expect_eq(w[y * W + x], border || near ? 0.0f : 1.0f, "pixel %d,%d", x, y);
        }
}

/* Four pixels, hand-computed. ref 1; flat 0.9 / 0.99 (below the 2 % signal) / 0.5 / 1.2;
 * render 0.95 / 0.5 / 0.75 / 1.0 (red). Signal pixels 0, 2, 3: mean |X − R|/R =
 * (0.05 + 0.25 + 0) / 3, normalised (0.05 + 0.25 + 0) / (0.1 + 0.5 + 0.2). */
Test(frame_compare, transport_statistics_by_hand)
{
    float ref[16], flat[16], ren[16];
    const double F[4] = {0.9, 0.99, 0.5, 1.2}, X[4] = {0.95, 0.5, 0.75, 1.0};
    for (int i = 0; i < 4; ++i) px(ref, i, 1, 2, 4, 1), px(flat, i, F[i], 2 * F[i], 4, 1), px(ren, i, X[i], 2 * F[i], 4, 1);
    dm_ref_transport_stats st;
    dm_error err = {0};
    cr_assert_eq(dm_ref_transport_compute(ref, flat, ren, NULL, NULL, -1, 4, 0, &st, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(st.signal[0], 3);
    cr_expect(fabs(st.mean[0] - 0.30 / 3) < 1e-6, "mean %g", st.mean[0]);
    cr_expect(fabs(st.normalised[0] - 0.30 / 0.80) < 1e-6, "normalised %g", st.normalised[0]);
    /* green: the render is the flat frame (no subsurface): normalised exactly 1 */
    cr_expect_eq(st.signal[1], 3);
    cr_expect(fabs(st.normalised[1] - 1.0) < 1e-6, "no subsurface scores %g, not 1", st.normalised[1]);
    /* blue: subsurface changes nothing: no signal pixel, zero */
    cr_expect_eq(st.signal[2], 0);
    cr_expect_eq(st.normalised[2], 0.0);
    /* all channels: red's sums and green's (blue has none): (0.30 + 0.80 · 2) / (0.80 + 0.80 · 2) */
    cr_expect(fabs(st.normalised_rgb - 1.90 / 2.40) < 1e-6, "all channels %g", st.normalised_rgb);
    /* a weight and a label select: only pixel 2 (label 1) of the weighted ones */
    const float w[4] = {1, 1, 1, 0};
    const uint8_t label[4] = {0, 1, 1, 1};
    cr_assert_eq(dm_ref_transport_compute(ref, flat, ren, w, label, 1, 4, 0, &st, &err), DM_OK);
    cr_expect_eq(st.signal[0], 1);
    cr_expect(fabs(st.normalised[0] - 0.5) < 1e-6, "%g", st.normalised[0]);
    /* a higher threshold drops pixel 0 (10 % change) */
    cr_assert_eq(dm_ref_transport_compute(ref, flat, ren, NULL, NULL, -1, 4, 0.15, &st, &err), DM_OK);
    cr_expect_eq(st.signal[0], 2);
    /* nothing changes: DM_ERR_EMPTY; a bad threshold: DM_ERR_RANGE */
    cr_expect_eq(dm_ref_transport_compute(ref, ref, ren, NULL, NULL, -1, 4, 0, &st, &err), DM_ERR_EMPTY);
    cr_expect_eq(dm_ref_transport_compute(ref, flat, ren, NULL, NULL, -1, 4, 1.5, &st, &err), DM_ERR_RANGE);
    cr_expect_eq(dm_ref_transport_compute(ref, flat, ren, NULL, NULL, -1, 4, NAN, &st, &err), DM_ERR_RANGE);
}

/* Non-finite render values are not averaged in (they count as no signal pixel). */
Test(frame_compare, non_finite_render_values_are_left_out)
{
    float ref[8], flat[8], ren[8];
    px(ref, 0, 1, 1, 1, 1), px(ref, 1, 1, 1, 1, 1);
    px(flat, 0, 0.5, 0.5, 0.5, 1), px(flat, 1, 0.5, 0.5, 0.5, 1);
    px(ren, 0, NAN, INFINITY, 1, 1), px(ren, 1, 1, 1, 1, 1);
    dm_ref_transport_stats st;
    cr_assert_eq(dm_ref_transport_compute(ref, flat, ren, NULL, NULL, -1, 2, 0, &st, NULL), DM_OK);
    for (int c = 0; c < 3; ++c) cr_expect(isfinite(st.mean[c]) && isfinite(st.normalised[c]));
    cr_expect_eq(st.signal[0], 1);
}

/* Two 30 × 40 mm charts meeting at x = 0 (equal positions, different UVs: a seam), seen from
 * +Z: each pixel's label is seam within 3 mm of the cut or the outer boundary (the atlas
 * ends there too), else smooth; misses are background. The expected label comes from the
 * hit's own position (the mesh's vertices, independent of dm_ref_regions). */
Test(frame_compare, labels_follow_each_pixels_triangle)
{
    enum { W = 96, H = 64 };
    synth sy;
    synth_init(&sy);
    synth_quad(&sy, (double[3]){-30, -20, 0}, (double[3]){30, 0, 0}, (double[3]){0, 40, 0}, 12, (double[4]){0.05, 0.05, 0.45, 0.95});
    synth_quad(&sy, (double[3]){0, -20, 0}, (double[3]){30, 0, 0}, (double[3]){0, 40, 0}, 12, (double[4]){0.55, 0.05, 0.95, 0.95});
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    dm_ref_surface *s = synth_surface(&d);
    dm_ref_regions *rg = NULL;
    dm_error err = {0};
    cr_assert_eq(dm_ref_regions_create(&s->mesh, s->mm_per_unit, NULL, &rg, &err), DM_OK, "%s", err.detail);
    uint8_t *label = malloc(W * H);
    dm_reference_target *hit = malloc(W * H * sizeof *hit);
    cr_assert_eq(dm_ref_frame_labels(s, rg, W, H, 0, label, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_ref_frame_hits(s, W, H, 1, hit, &err), DM_OK);
    int counts[3] = {0}, misses = 0;
    for (int i = 0; i < W * H; ++i) {
        if (hit[i].triangle < 0) {
            cr_expect_eq(label[i], DM_REF_LABEL_BACKGROUND);
            ++misses;
            continue;
        }
        const uint32_t *t = &sy.ix[3 * hit[i].triangle];
        double b[3] = {1.0 - hit[i].b1 - hit[i].b2, hit[i].b1, hit[i].b2}, p[2] = {0, 0};
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 2; ++c) p[c] += b[k] * sy.v[(size_t)t[k] * DM_REF_VERTEX_FLOATS + (size_t)c];
        double dist = fmin(fabs(p[0]), fmin(30 - fabs(p[0]), 20 - fabs(p[1])));
        if (fabs(dist - 3) < 0.05) continue;
        cr_expect_eq(label[i], dist < 3 ? DM_REF_REGION_SEAM : DM_REF_REGION_SMOOTH, "pixel %d: %.2f mm from a seam", i, dist);
        ++counts[label[i]];
    }
    cr_expect_gt(counts[DM_REF_REGION_SEAM], 200);
    cr_expect_gt(counts[DM_REF_REGION_SMOOTH], 1000);
    cr_expect_gt(misses, 100);
    cr_expect_eq(counts[DM_REF_REGION_THIN], 0);
    free(label), free(hit);
    dm_ref_regions_destroy(rg);
    dm_ref_surface_destroy(s);
    synth_free(&sy);
}

static float *frame(const dm_ref_surface_desc *d, int w, int h, int k, bool at_centre)
{
    float *rgba = malloc((size_t)w * h * 4 * sizeof *rgba);
    dm_ref_frame_options o = {.width = w, .height = h, .atlas_size = 64, .atlas_samples = 1, .pixel_samples = k,
                              .diffusion_at_centre = at_centre};
    dm_error err = {0};
    cr_assert_eq(dm_ref_frame_render_desc(d, &o, rgba, &err), DM_OK, "%s", err.detail);
    return rgba;
}

/* A sphere lit from the side through the exact convolution: with one sample per pixel the
 * diffusion over the pixel is the diffusion at the centre, bit for bit; with 3 × 3 the two
 * differ (the diffusion varies across a pixel of this 24 × 16 frame), and over the pixel is
 * the mean of what the finer frame (3 × the size, one sample, pixels at the sub-pixel rays'
 * positions) sees over each 3 × 3 block, where all nine are skin. */
Test(frame_compare, diffusion_sampled_over_the_pixel)
{
    enum { W = 24, H = 16, K = 3 };
    synth sy;
    synth_init(&sy);
    synth_sphere(&sy, (double[3]){0, 0, 0}, 20, 48, 24, (double[4]){0, 0, 1, 1});
    synth_light(&sy, 1, 0.2, 0.3, 1.0, false);
    sy.scene.effects[DM_EFFECT_SUBSURFACE] = true;
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    float *c1 = frame(&d, W, H, 1, true), *p1 = frame(&d, W, H, 1, false);
    cr_expect_eq(memcmp(c1, p1, (size_t)W * H * 4 * sizeof *c1), 0, "one sample: at the centre and over the pixel differ");
    float *c3 = frame(&d, W, H, K, true), *p3 = frame(&d, W, H, K, false), *fine = frame(&d, W * K, H * K, 1, false);
    double most = 0, worst = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float *a = c3 + 4 * (y * W + x), *b = p3 + 4 * (y * W + x);
            if (b[3] < 0.5f) continue;
            double sum[3] = {0, 0, 0};
            bool all = true;
            for (int j = 0; j < K; ++j)
                for (int i = 0; i < K; ++i) {
                    const float *f = fine + 4 * ((y * K + j) * W * K + x * K + i);
                    all &= f[3] >= 0.5f;
                    for (int c = 0; c < 3; ++c) sum[c] += f[c] / (K * K);
                }
            for (int c = 0; c < 3; ++c) {
                most = fmax(most, fabs(a[c] - b[c]) / fmax(b[c], 1e-3));
                if (all) worst = fmax(worst, fabs(sum[c] - b[c]) / fmax(b[c], 1e-3));
            }
        }
    cr_expect_gt(most, 1e-3, "the diffusion at the centre and over the pixel agree to %.2g: not exercised", most);
    cr_expect_lt(worst, 1e-5, "over the pixel differs from the finer frame's block mean by %.2g", worst);
    free(c1), free(p1), free(c3), free(p3), free(fine);
    synth_free(&sy);
}
