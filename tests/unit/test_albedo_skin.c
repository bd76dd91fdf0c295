/* The diffuse colour from the skin model (bake/dm_albedo_skin.h) on a synthetic mesh whose
 * answers are known: out_c = T_c · Y / Ȳ with Y the BT.709 luminance of the decoded map and Ȳ
 * its mean weighted by the skin's area.
 *
 * The mesh is a 2 × 1 grid: its UV image covers the bottom half of an 8 × 8 map (rows 0–3),
 * the left cell columns 0–3, the right cell columns 4–7; in 3-D the right cell is 3 times as
 * wide, so a right texel stands for 3 times the skin of a left one. The top half is off the
 * charts: its white must count for nothing. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "bake/dm_albedo_skin.h"
#include "core/dm_srgb.h"
#include "../common/grid_mesh.h"

enum { W = 8, H = 8 };
static const double MM_PER_UNIT = 10.0;

static void pos(double s, double t, double out[3]) /* x: 0, 1, 4 at s = 0, 1/2, 1 */
{
    out[0] = s <= 0.5 ? 2.0 * s : 1.0 + 6.0 * (s - 0.5);
    out[1] = t;
    out[2] = 0.0;
}
static void uv(double s, double t, double out[3])
{
    out[0] = s;
    out[1] = 0.5 * t;
    out[2] = 0.0;
}

/* The map: left half of the charts greenish, right half reddish (BT.709 weighs them 0.7152 and
 * 0.2126: the luminance detail pins the coefficients), top half white. */
static const uint8_t LEFT[3] = {40, 180, 60}, RIGHT[3] = {200, 70, 50}, OFF[3] = {255, 255, 255};

static void make_map(uint8_t *rgba)
{
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const uint8_t *c = j >= H / 2 ? OFF : i < W / 2 ? LEFT : RIGHT;
            uint8_t *p = rgba + 4 * (j * W + i);
            memcpy(p, c, 3);
            p[3] = (uint8_t)(10 * i + j); /* alpha passes through */
        }
}

static double luma(const uint8_t c[3])
{
    return 0.2126 * dm_srgb_to_linear(c[0] / 255.0) + 0.7152 * dm_srgb_to_linear(c[1] / 255.0) +
           0.0722 * dm_srgb_to_linear(c[2] / 255.0);
}

/* Half an 8-bit step at code v, in linear: what rounding to the nearest code may move a value. */
static double half_step(uint8_t v)
{
    double lo = dm_srgb_to_linear((v > 0 ? v - 0.5 : 0.0) / 255.0), hi = dm_srgb_to_linear((v + 0.5) / 255.0);
    return 0.5 * (hi - lo) + 1e-12;
}

static float weight[W * H];
static dm_mesh mesh;

static void setup(void)
{
    grid_mesh(2, 1, pos, uv, &mesh);
    dm_error err = {0};
    double area = 0.0;
    cr_assert_eq(dm_albedo_skin_weights(&mesh, MM_PER_UNIT, W, H, 1, weight, &area, &err), DM_OK, "%s", err.detail);
    cr_assert_float_eq(area, 4.0 * 1.0 * MM_PER_UNIT * MM_PER_UNIT, 1e-3, "the skin's area: 4 x 1 units, %g mm^2", area);
}
static void teardown(void) { dm_mesh_free(&mesh); }

/* Each texel stands for its triangle's mm² over its UV texels: left 1·100/16, right 3·100/16
 * mm², none above. */
Test(albedo_skin, weights_are_the_skin_area_per_texel, .init = setup, .fini = teardown)
{
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            double want = j >= H / 2 ? 0.0 : (i < W / 2 ? 1.0 : 3.0) * MM_PER_UNIT * MM_PER_UNIT / 16.0;
            cr_assert_float_eq(weight[j * W + i], want, 1e-4, "texel (%d, %d): %g mm^2, expected %g", i, j,
                               weight[j * W + i], want);
        }
}

/* Every texel is T_c · Y / Ȳ with Ȳ = (1·Y_left + 3·Y_right)/4, to the nearest 8-bit code:
 * the decoded result within half a step of the exact value. Ȳ itself (before any rounding) to
 * 1e-12: each channel's mean is > 0 over the skin, so a luminance coefficient changed by
 * 5 % moves it by 0.1–3 %, and texel weights by the texel count instead of the area by 20 %. */
Test(albedo_skin, texels_are_total_times_area_weighted_luminance_detail, .init = setup, .fini = teardown)
{
    uint8_t map[W * H * 4], out[W * H * 4];
    make_map(map);
    const double total[3] = {0.19, 0.13, 0.10};
    dm_albedo_skin_stats st;
    dm_error err = {0};
    cr_assert_eq(dm_albedo_skin_apply(map, W, H, weight, total, "map", out, &st, &err), DM_OK, "%s", err.detail);
    const double y_mean = (1.0 * luma(LEFT) + 3.0 * luma(RIGHT)) / 4.0;
    cr_assert_float_eq(st.mean_luminance, y_mean, 1e-12);
    cr_assert_eq(st.covered_texels, W * H / 2);
    cr_assert_eq(st.clipped_texels, 0);
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const uint8_t *in = map + 4 * (j * W + i), *o = out + 4 * (j * W + i);
            for (int c = 0; c < 3; ++c) {
                double want = total[c] * luma(in) / y_mean;
                double got = dm_srgb_to_linear(o[c] / 255.0);
                cr_assert(fabs(got - fmin(want, 1.0)) <= half_step(o[c]), "texel (%d, %d) channel %d: %.5f, expected %.5f",
                          i, j, c, got, want);
            }
            cr_assert_eq(o[3], in[3], "alpha kept");
        }
}

/* The result's mean over the skin is T (what makes a preset's colour the model's): within
 * the mean half step of the rounding, about 0.4 % here. */
Test(albedo_skin, mean_over_the_skin_is_the_total_reflectance, .init = setup, .fini = teardown)
{
    uint8_t map[W * H * 4];
    make_map(map);
    const double totals[3][3] = {{0.42, 0.31, 0.26}, {0.19, 0.13, 0.10}, {0.039, 0.031, 0.024}};
    for (int k = 0; k < 3; ++k) {
        uint8_t out[W * H * 4];
        dm_albedo_skin_stats st;
        dm_error err = {0};
        cr_assert_eq(dm_albedo_skin_apply(map, W, H, weight, totals[k], "map", out, &st, &err), DM_OK, "%s", err.detail);
        for (int c = 0; c < 3; ++c) {
            double sum = 0, w_sum = 0, tol = 0;
            for (int i = 0; i < W * H; ++i) {
                sum += weight[i] * dm_srgb_to_linear(out[4 * i + c] / 255.0);
                tol += weight[i] * half_step(out[4 * i + c]);
                w_sum += weight[i];
            }
            cr_assert(fabs(sum / w_sum - totals[k][c]) <= tol / w_sum, "total %d channel %d: mean %.5f, expected %.5f +- %.5f",
                      k, c, sum / w_sum, totals[k][c], tol / w_sum);
            cr_assert_float_eq(st.mean_rgb[c], sum / w_sum, 1e-12, "the stats' mean is the result's");
        }
    }
}

/* The detail is the map's luminance ratio, whatever the skin: the right texel over the left
 * one is Y_right / Y_left in every channel (≈ 0.53 here), for a light and a dark skin. */
Test(albedo_skin, luminance_ratio_of_two_texels_is_kept, .init = setup, .fini = teardown)
{
    uint8_t map[W * H * 4], out[W * H * 4];
    make_map(map);
    const double want = luma(RIGHT) / luma(LEFT);
    cr_assert(want > 0.4 && want < 0.7, "a ratio far from 1 and from the channels' own: %g", want);
    const double totals[2][3] = {{0.42, 0.31, 0.26}, {0.05, 0.046, 0.037}};
    for (int k = 0; k < 2; ++k) {
        dm_error err = {0};
        cr_assert_eq(dm_albedo_skin_apply(map, W, H, weight, totals[k], "map", out, NULL, &err), DM_OK, "%s", err.detail);
        const uint8_t *l = out + 4 * (1 * W + 1), *r = out + 4 * (1 * W + 6);
        for (int c = 0; c < 3; ++c) {
            double gl = dm_srgb_to_linear(l[c] / 255.0), gr = dm_srgb_to_linear(r[c] / 255.0);
            /* the ratio of two rounded values: each off by at most half a step */
            double tol = want * (half_step(l[c]) / gl + half_step(r[c]) / gr);
            cr_assert(fabs(gr / gl - want) <= tol, "skin %d channel %d: ratio %.4f, expected %.4f +- %.4f", k, c, gr / gl,
                      want, tol);
        }
    }
}

/* The skin's tone replaces the map's: two maps of different tone but the same luminance detail
 * (one the other scaled) give the same result. */
Test(albedo_skin, the_map_tone_is_dropped, .init = setup, .fini = teardown)
{
    uint8_t a[W * H * 4], b[W * H * 4], oa[W * H * 4], ob[W * H * 4];
    for (int i = 0; i < W * H; ++i) {
        const uint8_t v = (uint8_t)(60 + 20 * (i % 5)); /* grey detail */
        uint8_t *p = a + 4 * i, *q = b + 4 * i;
        p[0] = p[1] = p[2] = v;
        q[0] = v; /* the same ratios in R only: a red map, its luminance 0.2126 of a's */
        q[1] = q[2] = 0;
        p[3] = q[3] = 255;
    }
    const double total[3] = {0.3, 0.2, 0.15};
    dm_error err = {0};
    cr_assert_eq(dm_albedo_skin_apply(a, W, H, weight, total, "a", oa, NULL, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_albedo_skin_apply(b, W, H, weight, total, "b", ob, NULL, &err), DM_OK, "%s", err.detail);
    for (int i = 0; i < W * H * 4; ++i) cr_assert(abs(oa[i] - ob[i]) <= 1, "byte %d: %d vs %d", i, oa[i], ob[i]);
}

/* Values above 1 clip (and are counted); a negative total is 0. */
Test(albedo_skin, clip_and_negative_totals, .init = setup, .fini = teardown)
{
    uint8_t map[W * H * 4], out[W * H * 4];
    make_map(map);
    const double total[3] = {0.9, 0.5, -0.004};
    dm_albedo_skin_stats st;
    dm_error err = {0};
    cr_assert_eq(dm_albedo_skin_apply(map, W, H, weight, total, "map", out, &st, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(st.clipped_texels, W * H / 4, "the left texels' red: 0.9 x %.2f", luma(LEFT) / st.mean_luminance);
    for (int i = 0; i < W * H; ++i) cr_assert_eq(out[4 * i + 2], 0);
}

/* Nothing to work on: a map the charts miss, or black over the skin. */
Test(albedo_skin, empty_skin_or_black_map_is_an_error, .init = setup, .fini = teardown)
{
    uint8_t map[W * H * 4], out[W * H * 4];
    float none[W * H] = {0};
    make_map(map);
    const double total[3] = {0.3, 0.2, 0.1};
    dm_error err = {0};
    cr_assert_eq(dm_albedo_skin_apply(map, W, H, none, total, "m.png", out, NULL, &err), DM_ERR_EMPTY);
    cr_assert(strstr(err.detail, "m.png") && strstr(err.detail, "cover none"), "%s", err.detail);
    memset(map, 0, sizeof map);
    cr_assert_eq(dm_albedo_skin_apply(map, W, H, weight, total, "m.png", out, NULL, &err), DM_ERR_EMPTY);
    cr_assert(strstr(err.detail, "m.png") && strstr(err.detail, "mean luminance 0"), "%s", err.detail);
}
