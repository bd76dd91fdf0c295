#include "core/dm_level_sum.h"

#include <math.h>
#include <stdlib.h>

#include "core/dm_parallel.h"
#include "core/dm_v4.h"

/* Level k at (u, v) as the shader's sampler reads it: bilinear between the four texel centres
 * around, zero beyond the image (the padding, DM_LEVEL_BLUR_PAD ≥ 1), then coverage-normalised. */
static dm_v4 level_at(const dm_level_sum_pass *p, float u, float v)
{
    const dm_v4 zero = {0, 0, 0, 0};
    float x = u * (float)p->n - 0.5f, y = v * (float)p->n - 0.5f;
    float fx = floorf(x), fy = floorf(y);
    if (!(fx >= -1.0f && fy >= -1.0f && fx <= (float)p->n - 1.0f && fy <= (float)p->n - 1.0f)) return zero;
    float ax = x - fx, ay = y - fy;
    const float *r0 = p->level + (ptrdiff_t)fy * p->stride + 4 * (ptrdiff_t)fx, *r1 = r0 + p->stride;
    dm_v4 top = dm_v4_load(r0) * (1.0f - ax) + dm_v4_load(r0 + 4) * ax;
    dm_v4 bottom = dm_v4_load(r1) * (1.0f - ax) + dm_v4_load(r1 + 4) * ax;
    dm_v4 t = top * (1.0f - ay) + bottom * ay;
    return t[3] > 1e-4f ? t / t[3] : zero;
}

static void rows(void *ctx, size_t begin, size_t end)
{
    const dm_level_sum_pass *p = ctx;
    /* alpha's weight 0: alpha / alpha is 1 (or the 0 of an empty texel), so the sum's alpha
     * stays as it is, bit for bit */
    const dm_v4 w = {p->weight[0], p->weight[1], p->weight[2], 0.0f}, zero = {0, 0, 0, 0};
    for (size_t y = begin; y < end; ++y) {
        const float *t = p->level + (ptrdiff_t)y * p->stride;
        float *s = p->sum + y * (size_t)p->n * 4;
        for (int x = 0; x < p->n; ++x, t += 4, s += 4) {
            dm_v4 l = dm_v4_load(t), sum;
            float a = l[3];
            /* dm_level: rgb / alpha where alpha > 1e-4, else 0; then sum += w · that */
            dm_v4 v = a > 1e-4f ? l / a : zero;
            if (p->first) {
                sum = zero + w * v;
                sum[3] = a;
            } else {
                sum = dm_v4_load(s) + w * v;
            }
            if (p->thin) { /* diffusion.glsl's DM_THIN: each candidate after the level's own term */
                size_t i = y * (size_t)p->n + (size_t)x;
                for (int32_t j = p->thin->first[i]; j < p->thin->first[i + 1]; ++j) {
                    const float *c = p->thin->cand + 4 * (size_t)j;
                    float g = expf(-c[2] * c[2] / (2.0f * p->variance_mm2));
                    dm_v4 lc = level_at(p, c[0], c[1]);
                    float keep = sum[3];
                    sum = sum + w * (g * lc);
                    sum[3] = keep;
                }
            }
            if (p->last) sum = sum * (dm_v4){sum[3], sum[3], sum[3], 1.0f};
            dm_v4_store(s, sum);
        }
    }
}

bool dm_level_sum_add(const dm_level_sum_pass *p)
{
    if (!p || !p->sum || !p->level || p->n < 1 || p->stride < 4L * p->n) return false;
    if (p->thin && (p->thin->n != p->n || !(p->variance_mm2 > 0.0f))) return false;
    dm_parallel_for((size_t)p->n, 0, p->thread_count, rows, (void *)p);
    return true;
}

bool dm_level_sum_thin_make(const float *map, int n, dm_level_sum_thin *out)
{
    *out = (dm_level_sum_thin){0};
    if (!map || n < 1) return false;
    size_t nn = (size_t)n * (size_t)n, count = 0;
    for (size_t i = 0; i < 2 * nn; ++i) count += map[4 * i + 3] > 0.5f;
    int32_t *first = malloc(sizeof *first * (nn + 1));
    float *cand = malloc(sizeof *cand * 4 * (count ? count : 1));
    if (!first || !cand) return free(first), free(cand), false;
    size_t k = 0;
    for (size_t i = 0; i < nn; ++i) {
        first[i] = (int32_t)k;
        for (size_t layer = 0; layer < 2; ++layer) {
            const float *c = map + 4 * (layer * nn + i);
            if (!(c[3] > 0.5f)) continue;
            cand[4 * k] = c[0], cand[4 * k + 1] = c[1], cand[4 * k + 2] = c[2], cand[4 * k + 3] = 0.0f;
            ++k;
        }
    }
    first[nn] = (int32_t)k;
    *out = (dm_level_sum_thin){n, first, cand, count};
    return true;
}

void dm_level_sum_thin_free(dm_level_sum_thin *t)
{
    free(t->first), free(t->cand);
    *t = (dm_level_sum_thin){0};
}
