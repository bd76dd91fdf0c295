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

static const float variance[LEVELS] = {0.0064f, 0.0484f, 0.187f, 0.567f};

static void sum_levels_thin(float *const px[LEVELS], float *sum, int threads, const dm_level_sum_thin *thin)
{
    for (int k = 0; k < LEVELS; ++k)
        cr_assert(dm_level_sum_add(&(dm_level_sum_pass){sum, px[k], dm_level_blur_stride(N), N,
                                                        {weight[k][0], weight[k][1], weight[k][2]}, k == 0,
                                                        k == LEVELS - 1, threads, thin, variance[k], NULL, 0}));
}

static void sum_levels(float *const px[LEVELS], float *sum, int threads)
{
    sum_levels_thin(px, sum, threads, NULL);
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
    cr_expect(!dm_level_sum_add(&(dm_level_sum_pass){NULL, level, 8, 2, {1, 1, 1}, true, true, 0, NULL, 0, NULL, 0}));
    cr_expect(!dm_level_sum_add(&(dm_level_sum_pass){sum, NULL, 8, 2, {1, 1, 1}, true, true, 0, NULL, 0, NULL, 0}));
    cr_expect(!dm_level_sum_add(&(dm_level_sum_pass){sum, level, 8, 0, {1, 1, 1}, true, true, 0, NULL, 0, NULL, 0}));
    cr_expect(!dm_level_sum_add(&(dm_level_sum_pass){sum, level, 7, 2, {1, 1, 1}, true, true, 0, NULL, 0, NULL, 0}));
    cr_expect(dm_level_sum_add(&(dm_level_sum_pass){sum, level, 8, 2, {1, 1, 1}, true, true, 0, NULL, 0, NULL, 0}));
    for (int i = 0; i < 16; ++i) cr_expect(sum[i] == 0.0f && !signbit(sum[i]), "zero coverage: black, not NaN");
}

/* Level k at (u, v) in double: bilinear between the texel centres, zero outside the N × N
 * image, then rgb / alpha where alpha > 1e-4 (the shader's sampler and dm_level). */
static double level_at(const float *px, int c, double u, double v)
{
    long stride = dm_level_blur_stride(N);
    double x = u * N - 0.5, y = v * N - 0.5, fx = floor(x), fy = floor(y), t[4] = {0, 0, 0, 0};
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            int xi = (int)fx + dx, yi = (int)fy + dy;
            double wgt = (dx ? x - fx : 1 - (x - fx)) * (dy ? y - fy : 1 - (y - fy));
            if (xi < 0 || yi < 0 || xi >= N || yi >= N) continue;
            for (int q = 0; q < 4; ++q) t[q] += wgt * px[yi * stride + 4 * xi + q];
        }
    return t[3] > 1e-4 ? t[c] / t[3] : 0.0;
}

/* With a thin-part map: per texel up to two candidates (u', v', d), some at the image's edge
 * and corners (the zero border), some on uncovered texels; each level adds
 * w_k exp(-d^2 / 2 v_k) L_k(u', v') per candidate, evaluated here in double from the formula
 * of core/dm_level_sum.h. Texels without candidates are the plain sum, bit for bit. */
Test(level_sum, thin_candidates_match_the_formula_in_double)
{
    float *buf[LEVELS], *px[LEVELS];
    for (int k = 0; k < LEVELS; ++k) buf[k] = make_level(k, &px[k]);
    float *map = calloc((size_t)4 * N * 2 * N, sizeof(float));
    unsigned seed = 99u;
    for (int i = 0; i < 2 * N * N; ++i) {
        seed = seed * 1664525u + 1013904223u;
        if ((seed >> 24) % 3) continue; /* a third of the slots */
        float *c = map + 4 * i;
        seed = seed * 1664525u + 1013904223u;
        c[0] = (seed >> 20) % 7 == 0 ? 0.0f : (seed >> 20) % 7 == 1 ? 1.0f : (float)(seed >> 8) / 16777216.0f;
        seed = seed * 1664525u + 1013904223u;
        c[1] = (float)(seed >> 8) / 16777216.0f;
        seed = seed * 1664525u + 1013904223u;
        c[2] = 0.05f + (float)(seed >> 8) / 16777216.0f * 2.0f; /* 0.05..2.05 mm */
        c[3] = 1.0f;
    }
    dm_level_sum_thin thin;
    cr_assert(dm_level_sum_thin_make(map, N, &thin));
    cr_assert_gt(thin.count, (size_t)N * N / 2);
    float *sum = malloc(sizeof(float) * 4 * N * N), *plain = malloc(sizeof(float) * 4 * N * N);
    sum_levels_thin(px, sum, 0, &thin);
    sum_levels(px, plain, 0);
    long stride = dm_level_blur_stride(N);
    int with = 0;
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
            const float *s = sum + 4 * (y * N + x);
            const float *cand[2] = {map + 4 * (y * N + x), map + 4 * ((N + y) * N + x)};
            bool any = cand[0][3] > 0.5f || cand[1][3] > 0.5f;
            double cov = px[0][y * stride + 4 * x + 3];
            with += any && cov > 0;
            if (!any) {
                cr_assert(!memcmp(s, plain + 4 * (y * N + x), sizeof(float) * 4), "texel %d, %d: not the plain sum", x, y);
                continue;
            }
            for (int c = 0; c < 3; ++c) {
                double ref = 0.0;
                for (int k = 0; k < LEVELS; ++k) {
                    const float *t = px[k] + y * stride + 4 * x;
                    ref += (double)weight[k][c] * (t[3] > 1e-4f ? (double)t[c] / t[3] : 0.0);
                    for (int j = 0; j < 2; ++j)
                        if (cand[j][3] > 0.5f)
                            ref += (double)weight[k][c] * exp(-(double)cand[j][2] * cand[j][2] / (2.0 * variance[k])) *
                                   level_at(px[k], c, cand[j][0], cand[j][1]);
                }
                ref *= cov;
                /* float: each bilinear tap and division rounds to ~1e-7 of its value; 4 levels,
                 * up to 3 terms each, all non-negative: under 2e-6 of the sum */
                cr_assert(fabs(s[c] - ref) <= 2e-6 * fabs(ref) + 1e-30, "texel %d, %d, channel %d: %.9g, expected %.9g",
                          x, y, c, (double)s[c], ref);
            }
        }
    cr_expect_gt(with, N * N / 4);
    float *many = malloc(sizeof(float) * 4 * N * N);
    sum_levels_thin(px, many, 5, &thin);
    cr_expect(!memcmp(sum, many, sizeof(float) * 4 * N * N), "byte-identical on 5 threads");
    dm_level_sum_thin other = thin;
    other.n = N + 1;
    cr_expect(!dm_level_sum_add(&(dm_level_sum_pass){sum, px[0], stride, N, {1, 1, 1}, true, true, 0, &other, 1.0f, NULL, 0}));
    cr_expect(!dm_level_sum_add(&(dm_level_sum_pass){sum, px[0], stride, N, {1, 1, 1}, true, true, 0, &thin, 0.0f, NULL, 0}));
    dm_level_sum_thin_free(&thin);
    dm_level_sum_thin_free(&thin); /* twice: safe */
    for (int k = 0; k < LEVELS; ++k) free(buf[k]);
    free(map), free(sum), free(plain), free(many);
}

/* With a thin gather (the last `count` levels gathered, 300 sites at random UVs, some at the
 * image's edge): a quarter of the texels gather, with taps on random sites and random weights
 * (3 to 7 a level; with 3 levels each run behind its count tap; a third of them read the run
 * before, as a block's texels share one), the taps placed past 4096 so that the index's row and
 * column both count. The gathered levels of a gathering texel are, in double,
 * w_k Σ_t weight_t I(uv_s(t)), I level 0 read as the sampler reads it (level_at above); every
 * other term is the plain sum's, and a texel that does not gather is the plain sum bit for bit. */
static void check_gathered(int count)
{
    float *buf[LEVELS], *px[LEVELS];
    for (int k = 0; k < LEVELS; ++k) buf[k] = make_level(k, &px[k]);
    enum { SITES = 300, PER = 7, FIRST = 2 + SITES + 5000 };
    const int first = LEVELS - count;
    float *index = calloc((size_t)4 * N * N, sizeof(float)), *taps = calloc((size_t)2 * (FIRST + 4 * PER * N * N), sizeof(float));
    taps[0] = (float)first, taps[1] = (float)count, taps[2] = (float)DM_LEVEL_SUM_GATHER_FORMAT, taps[3] = (float)SITES;
    unsigned seed = 7u;
    for (int s = 0; s < SITES; ++s)
        for (int q = 0; q < 2; ++q) {
            seed = seed * 1664525u + 1013904223u;
            taps[2 * (2 + s) + q] = s % 17 == 0 ? (float)q : (float)(seed >> 8) / 16777216.0f;
        }
    int64_t t = FIRST;
    int last = -1, shared = 0;
    for (int i = 0; i < N * N; ++i) {
        seed = seed * 1664525u + 1013904223u;
        if ((seed >> 16) % 4) continue;
        if (last >= 0 && (seed >> 20) % 3 == 0) { /* shares the last run, as a block's texels do */
            memcpy(index + 4 * i, index + 4 * last, sizeof(float) * 4), ++shared;
            continue;
        }
        last = i;
        index[4 * i] = (float)(t / DM_LEVEL_SUM_TAPS_WIDTH), index[4 * i + 3] = (float)(t % DM_LEVEL_SUM_TAPS_WIDTH);
        float *counts = count > 2 ? taps + 2 * t : NULL;
        t += count > 2 ? DM_LEVEL_SUM_COUNT_TAPS : 0;
        for (int g = 0; g < count; ++g) {
            int per = 3 + (int)((unsigned)(i + g) % 5u);
            if (g < 2) index[4 * i + 1 + g] = (float)per;
            else counts[g - 2] = (float)per;
            for (int k = 0; k < per; ++k, ++t) {
                seed = seed * 1664525u + 1013904223u;
                taps[2 * t] = (float)(2 + (seed >> 8) % SITES);
                seed = seed * 1664525u + 1013904223u;
                taps[2 * t + 1] = (float)(seed >> 8) / 16777216.0f * 0.3f;
            }
        }
    }
    /* made from copies freed at once: the sums keep no pointer into the pack's arrays */
    float *index_copy = malloc(sizeof(float) * 4 * N * N), *taps_copy = malloc(sizeof(float) * 2 * (size_t)t);
    memcpy(index_copy, index, sizeof(float) * 4 * N * N), memcpy(taps_copy, taps, sizeof(float) * 2 * (size_t)t);
    dm_level_sum_gather g;
    cr_assert(dm_level_sum_gather_make(index_copy, N, taps_copy, t, LEVELS, &g));
    memset(index_copy, 0xff, sizeof(float) * 4 * N * N), memset(taps_copy, 0xff, sizeof(float) * 2 * (size_t)t);
    free(index_copy), free(taps_copy);
    cr_assert(g.slot_count > SITES * 9 / 10 && g.slot_count <= SITES);
    cr_assert(shared > 20 && g.run_count + (size_t)shared == g.gathering, "%d texels share a run: %zu runs for %zu texels",
              shared, g.run_count, g.gathering);
    float *sum = malloc(sizeof(float) * 4 * N * N), *plain = malloc(sizeof(float) * 4 * N * N);
    for (int k = 0; k < LEVELS; ++k)
        cr_assert(dm_level_sum_add(&(dm_level_sum_pass){sum, px[k], dm_level_blur_stride(N), N,
                                                        {weight[k][0], weight[k][1], weight[k][2]}, k == 0,
                                                        k == LEVELS - 1, 0, NULL, variance[k], &g, k}));
    sum_levels(px, plain, 0);
    long stride = dm_level_blur_stride(N);
    int gathering = 0;
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
            const float *ix = index + 4 * (y * N + x), *s = sum + 4 * (y * N + x);
            if (!(ix[1] > 0)) {
                cr_assert(!memcmp(s, plain + 4 * (y * N + x), sizeof(float) * 4), "texel %d, %d: not the plain sum", x, y);
                continue;
            }
            double cov = px[0][y * stride + 4 * x + 3];
            gathering += cov > 0;
            for (int c = 0; c < 3; ++c) {
                double e = 0;
                for (int k = 0; k < first; ++k) { /* the levels not gathered */
                    const float *q = px[k] + y * stride + 4 * x;
                    e += weight[k][c] * (q[3] > 1e-4f ? (double)q[c] / q[3] : 0.0);
                }
                int64_t tt = (int64_t)ix[0] * DM_LEVEL_SUM_TAPS_WIDTH + (int64_t)ix[3];
                const float per[3] = {ix[1], ix[2], count > 2 ? taps[2 * tt] : 0};
                tt += count > 2 ? 1 : 0;
                for (int l = 0; l < count; ++l) {
                    double gs = 0;
                    for (int k = 0; k < (int)per[l]; ++k, ++tt) {
                        const float *uv = taps + 2 * (int64_t)taps[2 * tt];
                        gs += taps[2 * tt + 1] * level_at(px[0], c, uv[0], uv[1]);
                    }
                    e += weight[first + l][c] * gs;
                }
                e *= cov;
                cr_assert(fabs(s[c] - e) <= 2e-6 * fmax(1.0, fabs(e)), "texel %d, %d channel %d: %.8g, expected %.8g", x,
                          y, c, s[c], e);
            }
            cr_assert_eq(s[3], (float)cov);
        }
    cr_assert_gt(gathering, N * N / 8);
    /* a header of the old layout, a tap past the sites and a site beyond them are refused */
    dm_level_sum_gather bad;
    taps[2] = 2.0f;
    cr_expect(!dm_level_sum_gather_make(index, N, taps, t, LEVELS, &bad));
    taps[2] = (float)DM_LEVEL_SUM_GATHER_FORMAT;
    cr_expect(!dm_level_sum_gather_make(index, N, taps, t - 1, LEVELS, &bad));
    const float last_tap = taps[2 * (t - 1)];
    taps[2 * (t - 1)] = (float)(2 + SITES);
    cr_expect(!dm_level_sum_gather_make(index, N, taps, t, LEVELS, &bad));
    cr_expect(bad.value == NULL && bad.taps == NULL);
    taps[2 * (t - 1)] = last_tap;
    cr_assert(dm_level_sum_gather_check(index, N, taps, t, LEVELS, NULL, NULL));
    if (count > 2) { /* a count tap that counts a fourth level of three */
        int64_t c0 = -1;
        for (int i = 0; i < N * N && c0 < 0; ++i)
            if (index[4 * i + 1] > 0) c0 = (int64_t)index[4 * i] * DM_LEVEL_SUM_TAPS_WIDTH + (int64_t)index[4 * i + 3];
        taps[2 * c0 + 1] = 1.0f;
        cr_expect(!dm_level_sum_gather_make(index, N, taps, t, LEVELS, &bad));
    }
    dm_level_sum_gather_free(&g);
    free(sum), free(plain), free(index), free(taps);
    for (int k = 0; k < LEVELS; ++k) free(buf[k]);
}

Test(level_sum, gathered_levels_match_the_formula_in_double) { check_gathered(2); }
Test(level_sum, three_gathered_levels_read_their_count_taps) { check_gathered(3); }

/* The thin candidates' cut (DM_LEVEL_SUM_THIN_CUT): a candidate adds to a level only where its
 * weight exp(−d²/2v) ≥ e^−18, i.e. d² ≤ 36 v (the value written out here, not the constant). One dark texel with one candidate on a texel of light 1e6: just inside the cut it
 * adds 1e6 · exp(−d²/2v) (≈ 0.015), just beyond it adds nothing, bit for bit. */
Test(level_sum, thin_candidates_stop_at_the_cut)
{
    float *buf = calloc(dm_level_blur_floats(N, N), sizeof(float)), *px = dm_level_blur_frame(buf, N, N);
    long stride = dm_level_blur_stride(N);
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) px[y * stride + 4 * x + 3] = 1.0f; /* covered, dark */
    const int ax = 5, ay = 7, bx = 20, by = 30;
    for (int c = 0; c < 3; ++c) px[by * stride + 4 * bx + c] = 1e6f;
    const float v = 0.187f;
    for (int side = 0; side < 2; ++side) { /* 0: inside, 1: beyond */
        float *map = calloc((size_t)4 * 2 * N * N, sizeof(float)), *c = map + 4 * (ay * N + ax);
        double d = sqrt(2.0 * 18.0 * (double)v) * (side ? 1.001 : 0.999); /* exp(−d²/2v) = e^−18 ∓ 0.2 % in d² */
        c[0] = (bx + 0.5f) / N, c[1] = (by + 0.5f) / N, c[2] = (float)d, c[3] = 1.0f;
        dm_level_sum_thin thin;
        cr_assert(dm_level_sum_thin_make(map, N, &thin));
        cr_assert_eq(thin.count, 1u);
        float *sum = calloc((size_t)4 * N * N, sizeof(float));
        cr_assert(dm_level_sum_add(&(dm_level_sum_pass){sum, px, stride, N, {1, 1, 1}, true, true, 0, &thin, v, NULL, 0}));
        double want = side ? 0.0 : 1e6 * exp(-(double)c[2] * c[2] / (2.0 * v));
        const float *s = sum + 4 * (ay * N + ax);
        if (side) cr_expect(s[0] == 0.0f && s[1] == 0.0f && s[2] == 0.0f, "beyond the cut: %g", (double)s[0]);
        else cr_expect(fabs(s[0] - want) <= 1e-5 * want && want > 0.01, "inside the cut: %.9g, expected %.9g", (double)s[0], want);
        dm_level_sum_thin_free(&thin);
        free(map), free(sum);
    }
    free(buf);
}
