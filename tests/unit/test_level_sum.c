/* test_level_sum.c — core/dm_level_sum.h, the diffusion pass's sum on the CPU, against the
 * shader's formula (shaders/diffusion.glsl: Σ_k w_k (a_k > 1e-4 ? rgb_k / a_k : 0), times
 * level 0's coverage) evaluated independently in double. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_level_blur.h"
#include "core/dm_level_sum.h"

enum { N = 37, LEVELS = 4 };

/* level k in a padded buffer: premultiplied values, alpha from a pseudo-random sequence with
 * whole zero-alpha texels (off the charts), alphas under the 1e-4 threshold and level 0's
 * alpha 0 or 1 as the irradiance pass writes it */
static float *make_level(int k, float **px)
{
    float *buf = calloc(dm_level_blur_floats(N, N), sizeof(float));
    cr_assert_not_null(buf);
    *px = dm_level_blur_frame(buf, N, N);
    unsigned seed = 12345u + 977u * (unsigned)k;
    long stride = dm_level_blur_stride(N);
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
            float *t = *px + y * stride + 4 * x;
            seed = seed * 1664525u + 1013904223u;
            float u = (float)(seed >> 8) / 16777216.0f;
            float a = k == 0 ? (u < 0.8f ? 1.0f : 0.0f) : u < 0.1f ? 0.0f : u < 0.15f ? 5e-5f : u;
            for (int c = 0; c < 3; ++c) {
                seed = seed * 1664525u + 1013904223u;
                t[c] = a * (float)(seed >> 8) / 16777216.0f * 4.0f;
            }
            t[3] = a;
        }
    return buf;
}

static const float weight[LEVELS][3] = {{0.25f, 0.4f, 0.6f}, {0.25f, 0.3f, 0.2f}, {0.3f, 0.2f, 0.1f}, {0.2f, 0.1f, 0.1f}};

static void sum_levels(float *const px[LEVELS], float *sum, int threads)
{
    for (int k = 0; k < LEVELS; ++k)
        cr_assert(dm_level_sum_add(&(dm_level_sum_pass){sum, px[k], dm_level_blur_stride(N), N,
                                                        {weight[k][0], weight[k][1], weight[k][2]}, k == 0,
                                                        k == LEVELS - 1, threads}));
}

Test(level_sum, matches_the_shader_formula_in_double)
{
    float *buf[LEVELS], *px[LEVELS];
    for (int k = 0; k < LEVELS; ++k) buf[k] = make_level(k, &px[k]);
    float *sum = malloc(sizeof(float) * 4 * N * N);
    memset(sum, 0xff, sizeof(float) * 4 * N * N); /* NaN: the first level must overwrite it */
    sum_levels(px, sum, 0);
    long stride = dm_level_blur_stride(N);
    int covered = 0;
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
            const float *s = sum + 4 * (y * N + x);
            double cov = px[0][y * stride + 4 * x + 3];
            cr_assert_eq(s[3], (float)cov, "alpha is level 0's coverage");
            covered += cov > 0;
            for (int c = 0; c < 3; ++c) {
                double ref = 0.0;
                for (int k = 0; k < LEVELS; ++k) {
                    const float *t = px[k] + y * stride + 4 * x;
                    ref += (double)weight[k][c] * (t[3] > 1e-4f ? (double)t[c] / t[3] : 0.0);
                }
                ref *= cov;
                /* float: a division, a multiply and an addition per level round each to 6e-8
                 * relative; 4 levels: under 1e-6 of the sum (all terms are non-negative) */
                cr_assert(fabs(s[c] - ref) <= 1e-6 * fabs(ref) + 1e-30, "texel %d, %d, channel %d: %.9g, expected %.9g",
                          x, y, c, (double)s[c], ref);
            }
        }
    cr_expect_gt(covered, N * N / 2);
    cr_expect_lt(covered, N * N);
    for (int k = 0; k < LEVELS; ++k) free(buf[k]);
    free(sum);
}

Test(level_sum, is_byte_identical_on_any_thread_count)
{
    float *buf[LEVELS], *px[LEVELS];
    for (int k = 0; k < LEVELS; ++k) buf[k] = make_level(k, &px[k]);
    float *one = malloc(sizeof(float) * 4 * N * N), *many = malloc(sizeof(float) * 4 * N * N);
    sum_levels(px, one, 1);
    sum_levels(px, many, 5);
    cr_expect(memcmp(one, many, sizeof(float) * 4 * N * N) == 0);
    for (int k = 0; k < LEVELS; ++k) free(buf[k]);
    free(one), free(many);
}

Test(level_sum, refuses_what_breaks_the_rules)
{
    float level[4 * 4] = {0}, sum[4 * 4];
    cr_expect(!dm_level_sum_add(NULL));
    cr_expect(!dm_level_sum_add(&(dm_level_sum_pass){NULL, level, 8, 2, {1, 1, 1}, true, true, 0}));
    cr_expect(!dm_level_sum_add(&(dm_level_sum_pass){sum, NULL, 8, 2, {1, 1, 1}, true, true, 0}));
    cr_expect(!dm_level_sum_add(&(dm_level_sum_pass){sum, level, 8, 0, {1, 1, 1}, true, true, 0}));
    cr_expect(!dm_level_sum_add(&(dm_level_sum_pass){sum, level, 7, 2, {1, 1, 1}, true, true, 0}));
    cr_expect(dm_level_sum_add(&(dm_level_sum_pass){sum, level, 8, 2, {1, 1, 1}, true, true, 0}));
    for (int i = 0; i < 16; ++i) cr_expect(sum[i] == 0.0f && !signbit(sum[i]), "zero coverage: black, not NaN");
}
