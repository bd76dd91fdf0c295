#include "core/dm_level_sum.h"

#include <stddef.h>
#include <string.h>

#include "core/dm_parallel.h"

/* A texel's four floats as one vector (GCC and Clang vector extension): the same IEEE
 * operations per float, four at a time. */
typedef float v4 __attribute__((vector_size(16)));

static void rows(void *ctx, size_t begin, size_t end)
{
    const dm_level_sum_pass *p = ctx;
    /* alpha's weight 0: alpha / alpha is 1 (or the 0 of an empty texel), so the sum's alpha
     * stays as it is, bit for bit */
    const v4 w = {p->weight[0], p->weight[1], p->weight[2], 0.0f}, zero = {0, 0, 0, 0};
    for (size_t y = begin; y < end; ++y) {
        const float *t = p->level + (ptrdiff_t)y * p->stride;
        float *s = p->sum + y * (size_t)p->n * 4;
        for (int x = 0; x < p->n; ++x, t += 4, s += 4) {
            v4 l, sum;
            memcpy(&l, t, sizeof l);
            float a = l[3];
            /* dm_level: rgb / alpha where alpha > 1e-4, else 0; then sum += w · that */
            v4 v = a > 1e-4f ? l / a : zero;
            if (p->first) {
                sum = zero + w * v;
                sum[3] = a;
            } else {
                memcpy(&sum, s, sizeof sum);
                sum = sum + w * v;
            }
            if (p->last) sum = sum * (v4){sum[3], sum[3], sum[3], 1.0f};
            memcpy(s, &sum, sizeof sum);
        }
    }
}

bool dm_level_sum_add(const dm_level_sum_pass *p)
{
    if (!p || !p->sum || !p->level || p->n < 1 || p->stride < 4L * p->n) return false;
    dm_parallel_for((size_t)p->n, 0, p->thread_count, rows, (void *)p);
    return true;
}
