#include "core/dm_level_sum.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_parallel.h"

/* A texel's four floats as one vector (GCC and Clang vector extension): the same IEEE
 * operations per float, four at a time. */
typedef float v4 __attribute__((vector_size(16)));

/* Where a grid texel's centre falls on a reduced level: the texel below and the weight of
 * the one after (as a texture unit computes them: (x + ½)/n · level_n − ½). */
typedef struct place {
    int i;
    float f;
} place;

typedef struct job {
    const dm_level_sum_pass *p;
    int level_n;
    const place *at; /* per grid column (and row), for a reduced level */
} job;

static inline v4 load(const float *p)
{
    v4 v;
    memcpy(&v, p, sizeof v);
    return v;
}

static inline v4 lerp(v4 a, v4 b, float f)
{
    return a + f * (b - a);
}

static void rows(void *ctx, size_t begin, size_t end)
{
    const job *j = ctx;
    const dm_level_sum_pass *p = j->p;
    bool reduced = j->level_n != p->n;
    /* alpha's weight 0: alpha / alpha is 1 (or the 0 of an empty texel), so the sum's alpha
     * stays as it is, bit for bit */
    const v4 w = {p->weight[0], p->weight[1], p->weight[2], 0.0f}, zero = {0, 0, 0, 0};
    for (size_t y = begin; y < end; ++y) {
        const float *t = p->level + (ptrdiff_t)y * p->stride;
        const float *r0 = reduced ? p->level + (ptrdiff_t)j->at[y].i * p->stride : NULL, *r1 = r0 ? r0 + p->stride : NULL;
        float fy = reduced ? j->at[y].f : 0.0f;
        float *s = p->sum + y * (size_t)p->n * 4;
        for (int x = 0; x < p->n; ++x, t += 4, s += 4) {
            v4 l, sum;
            if (reduced) { /* bilinear: along x on both rows, then along y */
                const place px = j->at[x];
                l = lerp(lerp(load(r0 + 4 * px.i), load(r0 + 4 * px.i + 4), px.f),
                         lerp(load(r1 + 4 * px.i), load(r1 + 4 * px.i + 4), px.f), fy);
            } else {
                l = load(t);
            }
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
    if (!p || !p->sum || !p->level || p->n < 1) return false;
    int m = p->level_n > 0 ? p->level_n : p->n;
    if (m > p->n || (p->first && m != p->n) || p->stride < 4L * m) return false;
    job j = {p, m, NULL};
    place *at = NULL;
    if (m != p->n) {
        if (!(at = malloc(sizeof *at * (size_t)p->n))) return false;
        for (int i = 0; i < p->n; ++i) {
            float c = ((float)i + 0.5f) / (float)p->n * (float)m - 0.5f, f0 = floorf(c);
            at[i] = (place){(int)f0, c - f0}; /* −1 .. m − 1: the border is the padding's zeros */
        }
        j.at = at;
    }
    dm_parallel_for((size_t)p->n, 0, p->thread_count, rows, &j);
    free(at);
    return true;
}
