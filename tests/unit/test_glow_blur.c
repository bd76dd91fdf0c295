/* test_glow_blur.c — core/dm_glow_blur.h, the glow's Gaussian on the CPU, against the
 * shader's formula (shaders/glow_blur.glsl: 5 bilinear taps, clamp-to-edge) in double, and
 * the kernel against the 9-tap Gaussian exp(−i²/8) it stands for. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_glow_blur.h"

enum { W = 23, H = 17 };

static float *image(unsigned seed)
{
    float *p = malloc(sizeof(float) * 4 * W * H);
    cr_assert_not_null(p);
    for (int i = 0; i < 4 * W * H; ++i) {
        seed = seed * 1664525u + 1013904223u;
        p[i] = (float)(seed >> 8) / 16777216.0f * 8.0f;
    }
    return p;
}

/* the bilinear clamp-to-edge sample of channel c at texel coordinate t along x (row y) or y
 * (column x), in double */
static double sample(const float *p, int x, int y, bool along_y, double t, int c)
{
    int n = along_y ? H : W;
    double f0 = floor(t), f = t - f0;
    int i0 = (int)f0, i1 = i0 + 1;
    i0 = i0 < 0 ? 0 : i0 >= n ? n - 1 : i0;
    i1 = i1 < 0 ? 0 : i1 >= n ? n - 1 : i1;
    double a = along_y ? p[4 * (i0 * W + x) + c] : p[4 * (y * W + i0) + c];
    double b = along_y ? p[4 * (i1 * W + x) + c] : p[4 * (y * W + i1) + c];
    return a + f * (b - a);
}

Test(glow_blur, matches_the_shader_formula_in_double_along_x_and_y)
{
    float *src = image(7), *dst = malloc(sizeof(float) * 4 * W * H), w[3], o[2];
    dm_glow_kernel(w, o);
    for (int along_y = 0; along_y < 2; ++along_y) {
        cr_assert(dm_glow_blur(src, dst, W, H, along_y, 0));
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
                for (int c = 0; c < 4; ++c) {
                    double i = along_y ? y : x, ref = 1.0;
                    if (c < 3)
                        ref = w[0] * sample(src, x, y, along_y, i, c) +
                              w[1] * (sample(src, x, y, along_y, i + o[0], c) + sample(src, x, y, along_y, i - o[0], c)) +
                              w[2] * (sample(src, x, y, along_y, i + o[1], c) + sample(src, x, y, along_y, i - o[1], c));
                    double got = dst[4 * (y * W + x) + c];
                    /* float: ~10 roundings of 6e-8 on non-negative terms */
                    cr_assert(fabs(got - ref) <= 1e-6 * ref, "%s (%d, %d) channel %d: %.9g, expected %.9g",
                              along_y ? "y" : "x", x, y, c, got, ref);
                }
    }
    free(src), free(dst);
}

/* the five fetches are the nine taps: each pair's summed weight at its weighted mean offset
 * reproduces both taps wherever the signal is linear between them (bilinear) */
Test(glow_blur, kernel_is_the_nine_tap_gaussian)
{
    float w[3], o[2];
    dm_glow_kernel(w, o);
    double g[5], sum = 0;
    for (int i = 0; i < 5; ++i) g[i] = exp(-i * i / 8.0), sum += (i ? 2 : 1) * g[i];
    for (int i = 0; i < 5; ++i) g[i] /= sum;
    cr_expect(fabs(w[0] - g[0]) < 1e-5 && fabs(w[1] - (g[1] + g[2])) < 1e-5 && fabs(w[2] - (g[3] + g[4])) < 1e-5);
    cr_expect(fabs(o[0] - (g[1] + 2 * g[2]) / (g[1] + g[2])) < 1e-4);
    cr_expect(fabs(o[1] - (3 * g[3] + 4 * g[4]) / (g[3] + g[4])) < 1e-4);
    cr_expect(fabs(w[0] + 2 * w[1] + 2 * w[2] - 1.0) < 1e-4, "weights sum to 1");
}

Test(glow_blur, constant_stays_constant_and_edges_clamp)
{
    float *src = malloc(sizeof(float) * 4 * W * H), *dst = malloc(sizeof(float) * 4 * W * H), w[3], o[2];
    dm_glow_kernel(w, o);
    for (int i = 0; i < 4 * W * H; ++i) src[i] = 3.0f;
    cr_assert(dm_glow_blur(src, dst, W, H, true, 3));
    for (int i = 0; i < W * H; ++i)
        for (int c = 0; c < 3; ++c)
            cr_assert(fabs(dst[4 * i + c] - 3.0 * (w[0] + 2 * w[1] + 2 * w[2])) < 1e-5, "texel %d: %g", i, dst[4 * i + c]);
    cr_expect(!dm_glow_blur(NULL, dst, W, H, false, 0));
    cr_expect(!dm_glow_blur(src, dst, 0, H, false, 0));
    free(src), free(dst);
}

Test(glow_blur, is_byte_identical_on_any_thread_count)
{
    float *src = image(11), *a = malloc(sizeof(float) * 4 * W * H), *b = malloc(sizeof(float) * 4 * W * H);
    for (int along_y = 0; along_y < 2; ++along_y) {
        dm_glow_blur(src, a, W, H, along_y, 1);
        dm_glow_blur(src, b, W, H, along_y, 4);
        cr_expect(memcmp(a, b, sizeof(float) * 4 * W * H) == 0);
    }
    free(src), free(a), free(b);
}
