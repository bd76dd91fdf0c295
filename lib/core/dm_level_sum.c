#include "core/dm_level_sum.h"

#include <stddef.h>

#include "core/dm_parallel.h"
#include "core/dm_v4.h"

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
            if (p->last) sum = sum * (dm_v4){sum[3], sum[3], sum[3], 1.0f};
            dm_v4_store(s, sum);
        }
    }
}

bool dm_level_sum_add(const dm_level_sum_pass *p)
{
    if (!p || !p->sum || !p->level || p->n < 1 || p->stride < 4L * p->n) return false;
    dm_parallel_for((size_t)p->n, 0, p->thread_count, rows, (void *)p);
    return true;
}
