#include "core/dm_level_sum.h"

#include <math.h>
#include <stdint.h>
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

/* A gathering texel's first tap (the index holds its row and column: exact in floats). */
static size_t first_tap(const float *ix)
{
    return (size_t)ix[0] * DM_LEVEL_SUM_TAPS_WIDTH + (size_t)ix[3];
}

/* The gathered level g's sum at texel i, or −1 in alpha when i does not gather it. */
static dm_v4 gathered(const dm_level_sum_pass *p, size_t i)
{
    const dm_level_sum_gather *G = p->gather;
    int g = p->level_index - G->first_level;
    const float *ix = G->index + 4 * i;
    if (g < 0 || g >= G->level_count || !(ix[1 + g] > 0.0f)) return (dm_v4){0, 0, 0, -1.0f};
    size_t t = first_tap(ix) + (g ? (size_t)ix[1] : 0), end = t + (size_t)ix[1 + g];
    const float *value = G->value - 4 * DM_LEVEL_SUM_HEADER_TAPS; /* a site's tap index → its value */
    dm_v4 s0 = {0, 0, 0, 0}, s1 = s0; /* two sums: the adds are not one chain */
    const float *tp = G->taps + 2 * t;
    for (; t + 1 < end; t += 2, tp += 4) {
        s0 = s0 + tp[1] * dm_v4_load(value + 4 * (size_t)tp[0]);
        s1 = s1 + tp[3] * dm_v4_load(value + 4 * (size_t)tp[2]);
    }
    if (t < end) s0 = s0 + tp[1] * dm_v4_load(value + 4 * (size_t)tp[0]);
    s0 = s0 + s1;
    s0[3] = 0.0f;
    return s0;
}

/* Level 0 at the UV of each site some tap reads (level_at: the sampler's read); each alone. */
static void values(void *ctx, size_t begin, size_t end)
{
    const dm_level_sum_pass *p = ctx;
    const dm_level_sum_gather *G = p->gather;
    for (size_t u = begin; u < end; ++u) {
        size_t s = (size_t)G->used[u];
        const float *uv = G->taps + 2 * (DM_LEVEL_SUM_HEADER_TAPS + s);
        dm_v4 v = level_at(p, uv[0], uv[1]);
        v[3] = 0.0f;
        dm_v4_store(G->value + 4 * s, v);
    }
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
            dm_v4 gs = p->gather ? gathered(p, y * (size_t)p->n + (size_t)x) : (dm_v4){0, 0, 0, -1.0f};
            if (gs[3] == 0.0f) { /* a gathered level: its 3-D sum replaces the level and the candidates */
                float keep = dm_v4_load(s)[3];
                sum = dm_v4_load(s) + w * gs;
                sum[3] = keep;
                if (p->last) sum = sum * (dm_v4){sum[3], sum[3], sum[3], 1.0f};
                dm_v4_store(s, sum);
                continue;
            }
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
    if (p->gather && (p->gather->n != p->n || (p->first && p->gather->first_level == 0))) return false;
    if (p->gather && p->first) dm_parallel_for(p->gather->used_count, 256, p->gather->thread_count, values, (void *)p);
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

bool dm_level_sum_gather_make(const float *index, int n, const float *taps, int64_t tap_count, int levels,
                              dm_level_sum_gather *out)
{
    *out = (dm_level_sum_gather){0};
    if (!index || !taps || n < 1 || tap_count < DM_LEVEL_SUM_HEADER_TAPS) return false;
    int first = (int)taps[0], count = (int)taps[1];
    int64_t sites = (int64_t)taps[3];
    if (taps[2] != (float)DM_LEVEL_SUM_GATHER_FORMAT || first < 1 || count < 1 || count > 2 || first + count > levels ||
        sites < 1 || DM_LEVEL_SUM_HEADER_TAPS + sites > tap_count)
        return false;
    dm_level_sum_gather g = {n, first, count, index, taps, tap_count, sites, NULL, NULL, 0, 0};
    size_t nn = (size_t)n * n;
    uint8_t *mark = calloc((size_t)sites, 1);
    g.value = calloc(4 * (size_t)sites, sizeof(float));
    bool ok = mark && g.value;
    for (size_t i = 0; ok && i < nn; ++i) { /* the sites the taps read */
        const float *ix = index + 4 * i;
        if (!(ix[1] > 0.0f) && !(ix[2] > 0.0f)) continue;
        size_t t = first_tap(ix), end = t + (size_t)ix[1] + (count > 1 ? (size_t)ix[2] : 0);
        if (!(ix[0] >= 0.0f && ix[3] >= 0.0f && ix[3] < DM_LEVEL_SUM_TAPS_WIDTH) || t < (size_t)(DM_LEVEL_SUM_HEADER_TAPS + sites) ||
            end > (size_t)tap_count) {
            ok = false;
            break;
        }
        for (; t < end; ++t) {
            float s = taps[2 * t] - (float)DM_LEVEL_SUM_HEADER_TAPS;
            if (!(s >= 0.0f && s < (float)sites)) {
                ok = false;
                break;
            }
            mark[(size_t)s] = 1;
        }
    }
    for (int64_t s = 0; ok && s < sites; ++s) g.used_count += mark[s];
    if (ok && !(g.used = malloc(sizeof(int32_t) * (g.used_count ? g.used_count : 1)))) ok = false;
    for (int64_t s = 0, u = 0; ok && s < sites; ++s)
        if (mark[s]) g.used[u++] = (int32_t)s;
    free(mark);
    if (!ok) return dm_level_sum_gather_free(&g), false;
    *out = g;
    return true;
}

void dm_level_sum_gather_free(dm_level_sum_gather *g)
{
    free(g->value), free(g->used);
    *g = (dm_level_sum_gather){0};
}
