/* dm_level_sum.h — the diffusion pass's sum (shaders/diffusion.glsl) on the CPU, built level by
 * level as the blur on the CPU makes the levels (lib/render/passes/dm_pass_blur_cpu.c): per texel
 * of the irradiance grid
 *     sum = Σ_k w_k · (a_k > 1e-4 ? rgb_k / a_k : 0)     (per channel, in level order)
 * then rgb · c, alpha c, with c level 0's alpha (its chart coverage, 0 or 1). The same float
 * operations in the same order as the shader's dm_level_sum, so the two agree to float
 * rounding (tests/render/test_render_blur_cpu.c); levels at the grid's own size only (the
 * renderer sums reduced levels per pixel instead).
 *
 * Deterministic: each texel alone, byte-identical for any thread count. */
#ifndef DM_LEVEL_SUM_H
#define DM_LEVEL_SUM_H

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_level_sum_pass {
    float *sum;         /* RGBA, n × n, unpadded: the sum so far (alpha: c once started) */
    const float *level; /* RGBA, n × n, rows `stride` floats apart (a padded level image:
                         * core/dm_level_blur.h), premultiplied by its coverage in alpha */
    long stride;
    int n;
    float weight[3];  /* w_k per channel */
    bool first;       /* level 0: starts the sum and takes its alpha as the coverage c */
    bool last;        /* the last level: multiplies the sum by c */
    int thread_count; /* 0 = every core */
} dm_level_sum_pass;

/* Adds one level. False (nothing written) when a pointer is NULL, n < 1 or stride < 4 n. */
bool dm_level_sum_add(const dm_level_sum_pass *p);

#ifdef __cplusplus
}
#endif
#endif
