#include "core/dm_glow_blur.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_parallel.h"
#include "core/dm_v4.h"

void dm_glow_kernel(float weight[3], float offset[2])
{
    /* exp(−i²/8) normalised over i = −4..4: 0.20416, 0.18017, 0.12383, 0.06628, 0.02763 */
    const float g0 = 0.20416f, g1 = 0.18017f, g2 = 0.12383f, g3 = 0.06628f, g4 = 0.02763f;
    weight[0] = g0, weight[1] = g1 + g2, weight[2] = g3 + g4;
    offset[0] = (g1 + 2.0f * g2) / weight[1], offset[1] = (3.0f * g3 + 4.0f * g4) / weight[2];
}

/* Where a tap reads: the two texels (clamped to the edge) and the second's weight. */
typedef struct tap_at {
    int i0, i1;
    float f;
} tap_at;

static tap_at locate(float t, int n)
{
    float f0 = floorf(t);
    int i0 = (int)f0, i1 = i0 + 1;
    return (tap_at){i0 < 0 ? 0 : i0 >= n ? n - 1 : i0, i1 < 0 ? 0 : i1 >= n ? n - 1 : i1, t - f0};
}

typedef struct job {
    const float *src;
    float *dst;
    int w, h;
    bool along_y;
    float weight[3];
    const tap_at *at; /* [4][n]: taps +o1, −o1, +o2, −o2 at each texel along the axis */
} job;


/* Destination rows [begin, end). Along y a tap blends two rows (the same two for the whole
 * row), along x two texels of the row. Alpha is computed with the rest, then written 1. */
static void rows(void *ctx, size_t begin, size_t end)
{
    const job *j = ctx;
    size_t w = (size_t)j->w, n = j->along_y ? (size_t)j->h : w;
    const float w0 = j->weight[0], w1 = j->weight[1], w2 = j->weight[2];
    for (size_t y = begin; y < end; ++y) {
        const float *row = j->src + 4 * w * y;
        float *q = j->dst + 4 * w * y;
        const float *a[4], *b[4];
        float f[4];
        for (int k = 0; j->along_y && k < 4; ++k) {
            tap_at t = j->at[k * n + y];
            a[k] = j->src + 4 * w * (size_t)t.i0, b[k] = j->src + 4 * w * (size_t)t.i1, f[k] = t.f;
        }
        for (size_t x = 0; x < w; ++x) {
            dm_v4 v[4];
            for (int k = 0; k < 4; ++k) {
                if (j->along_y) {
                    v[k] = dm_v4_lerp(dm_v4_load(a[k] + 4 * x), dm_v4_load(b[k] + 4 * x), f[k]);
                } else {
                    tap_at t = j->at[k * n + x];
                    v[k] = dm_v4_lerp(dm_v4_load(row + 4 * (size_t)t.i0), dm_v4_load(row + 4 * (size_t)t.i1), t.f);
                }
            }
            dm_v4 s = w0 * dm_v4_load(row + 4 * x) + w1 * (v[0] + v[1]) + w2 * (v[2] + v[3]);
            dm_v4_store(q + 4 * x, s);
            q[4 * x + 3] = 1.0f;
        }
    }
}

bool dm_glow_blur(const float *src, float *dst, int w, int h, bool along_y, int thread_count)
{
    if (!src || !dst || w < 1 || h < 1) return false;
    int n = along_y ? h : w;
    tap_at *at = malloc(sizeof *at * 4 * (size_t)n);
    if (!at) return false;
    float o[2];
    job j = {src, dst, w, h, along_y, {0}, at};
    dm_glow_kernel(j.weight, o);
    for (int k = 0; k < 4; ++k)
        for (int i = 0; i < n; ++i) at[k * n + i] = locate((float)i + (k & 1 ? -o[k / 2] : o[k / 2]), n);
    dm_parallel_for((size_t)h, 0, thread_count, rows, &j);
    free(at);
    return true;
}
