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

/* Run r's sum of gathered level g: even and odd taps in two sums (the adds are not one chain),
 * then added, as diffusion.glsl's dm_gathered. */
static dm_v4 gathered(const dm_level_sum_gather *G, size_t r, int g)
{
    const int32_t *f = G->first + (G->run_count + 1) * (size_t)g + r;
    const dm_level_sum_tap *t = G->taps + f[0], *end = G->taps + f[1];
    const float *value = G->value;
    dm_v4 s0 = {0, 0, 0, 0}, s1 = s0;
    for (; t + 1 < end; t += 2) {
        s0 = s0 + t[0].weight * dm_v4_load(value + 4 * (size_t)t[0].slot);
        s1 = s1 + t[1].weight * dm_v4_load(value + 4 * (size_t)t[1].slot);
    }
    if (t < end) s0 = s0 + t->weight * dm_v4_load(value + 4 * (size_t)t->slot);
    s0 = s0 + s1;
    s0[3] = 0.0f;
    return s0;
}

/* This level's sum of each run with taps of it; each alone. */
static void run_values(void *ctx, size_t begin, size_t end)
{
    const dm_level_sum_pass *p = ctx;
    const dm_level_sum_gather *G = p->gather;
    for (size_t r = begin; r < end; ++r) dm_v4_store(G->run_value + 4 * r, gathered(G, r, p->level_index - G->first_level));
}

/* Level 0 at each slot's UV (level_at: the sampler's read); each alone. */
static void values(void *ctx, size_t begin, size_t end)
{
    const dm_level_sum_pass *p = ctx;
    const dm_level_sum_gather *G = p->gather;
    for (size_t s = begin; s < end; ++s) {
        dm_v4 v = level_at(p, G->uv[2 * s], G->uv[2 * s + 1]);
        v[3] = 0.0f;
        dm_v4_store(G->value + 4 * s, v);
    }
}

static void rows(void *ctx, size_t begin, size_t end)
{
    const dm_level_sum_pass *p = ctx;
    const dm_level_sum_gather *G = p->gather;
    const dm_level_sum_thin *th = p->thin;
    const int g = G ? p->level_index - G->first_level : -1;
    const bool gathers = G && g >= 0 && g < G->level_count;
    /* alpha's weight 0: alpha / alpha is 1 (or the 0 of an empty texel), so the sum's alpha
     * stays as it is, bit for bit */
    const dm_v4 w = {p->weight[0], p->weight[1], p->weight[2], 0.0f}, zero = {0, 0, 0, 0};
    for (size_t y = begin; y < end; ++y) {
        const float *t = p->level + (ptrdiff_t)y * p->stride;
        float *s = p->sum + y * (size_t)p->n * 4;
        /* the row's gathering texels and texels with thin candidates, walked beside x */
        size_t gj = gathers ? (size_t)G->row[y] : 0, gend = gathers ? (size_t)G->row[y + 1] : 0;
        size_t tj = th ? (size_t)th->row[y] : 0, tend = th ? (size_t)th->row[y + 1] : 0;
        for (int x = 0; x < p->n; ++x, t += 4, s += 4) {
            dm_v4 l = dm_v4_load(t), sum;
            float a = l[3];
            /* dm_level: rgb / alpha where alpha > 1e-4, else 0; then sum += w · that */
            dm_v4 v = a > 1e-4f ? l / a : zero;
            bool gathering = gj < gend && G->x[gj] == x, candidates = tj < tend && th->x[tj] == x;
            size_t here = gathering ? gj++ : 0, cands = candidates ? tj++ : 0;
            const size_t r = gathering ? (size_t)G->run[here] : 0;
            const int32_t *gf = gathering ? G->first + (G->run_count + 1) * (size_t)g + r : NULL;
            if (gf && gf[1] > gf[0]) {
                /* a gathered level: its 3-D sum (its run's) replaces the level and the candidates */
                dm_v4 gs = dm_v4_load(G->run_value + 4 * r);
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
            if (candidates) /* diffusion.glsl's DM_THIN: each candidate after the level's own term */
                for (int32_t j = th->first[cands]; j < th->first[cands + 1]; ++j) {
                    const float *c = th->cand + 4 * (size_t)j;
                    if (c[2] * c[2] > (float)DM_LEVEL_SUM_THIN_CUT * p->variance_mm2) continue; /* e < e^-18 */
                    float e = expf(-c[2] * c[2] / (2.0f * p->variance_mm2));
                    dm_v4 lc = level_at(p, c[0], c[1]);
                    float keep = sum[3];
                    sum = sum + w * (e * lc);
                    sum[3] = keep;
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
    if (p->gather && p->first) dm_parallel_for(p->gather->slot_count, 256, p->gather->thread_count, values, (void *)p);
    const int g = p->gather ? p->level_index - p->gather->first_level : -1;
    if (p->gather && g >= 0 && g < p->gather->level_count)
        dm_parallel_for(p->gather->run_count, 64, p->gather->thread_count, run_values, (void *)p);
    dm_parallel_for((size_t)p->n, 0, p->thread_count, rows, (void *)p);
    return true;
}

bool dm_level_sum_thin_make(const float *map, int n, dm_level_sum_thin *out)
{
    *out = (dm_level_sum_thin){0};
    if (!map || n < 1) return false;
    size_t nn = (size_t)n * (size_t)n, count = 0, texels = 0;
    for (size_t i = 0; i < nn; ++i) {
        int here = (map[4 * i + 3] > 0.5f) + (map[4 * (nn + i) + 3] > 0.5f);
        count += (size_t)here, texels += here > 0;
    }
    if (count >= INT32_MAX) return false;
    dm_level_sum_thin t = {n, malloc(sizeof(int32_t) * ((size_t)n + 1)), malloc(sizeof(int32_t) * (texels ? texels : 1)),
                           malloc(sizeof(int32_t) * (texels + 1)), malloc(sizeof(float) * 4 * (count ? count : 1)), count};
    if (!t.row || !t.x || !t.first || !t.cand) return dm_level_sum_thin_free(&t), false;
    size_t k = 0, j = 0;
    for (int y = 0; y < n; ++y) {
        t.row[y] = (int32_t)j;
        for (int x = 0; x < n; ++x) {
            size_t i = (size_t)y * (size_t)n + (size_t)x, before = k;
            for (size_t layer = 0; layer < 2; ++layer) {
                const float *c = map + 4 * (layer * nn + i);
                if (!(c[3] > 0.5f)) continue;
                t.cand[4 * k] = c[0], t.cand[4 * k + 1] = c[1], t.cand[4 * k + 2] = c[2], t.cand[4 * k + 3] = 0.0f;
                ++k;
            }
            if (k > before) t.x[j] = x, t.first[j++] = (int32_t)before;
        }
    }
    t.row[n] = (int32_t)j, t.first[j] = (int32_t)k;
    *out = t;
    return true;
}

void dm_level_sum_thin_free(dm_level_sum_thin *t)
{
    free(t->row), free(t->x), free(t->first), free(t->cand);
    *t = (dm_level_sum_thin){0};
}

/* A gathering texel's first tap (the index holds its row and column: exact in floats). */
static size_t first_tap(const float *ix)
{
    return (size_t)ix[0] * DM_LEVEL_SUM_TAPS_WIDTH + (size_t)ix[3];
}

static bool a_count(float c)
{
    return c >= 0.0f && c < 16777216.0f && c == floorf(c);
}

/* A gathering texel's run: its first level's first tap *t (past the count tap with 3 or 4
 * levels) and each level's taps n[l]; false when they lie outside the taps (or a count tap
 * counts a level there is not). */
static bool texel_run(const float *ix, const float *taps, int count, int64_t sites, int64_t tap_count, size_t *t,
                      size_t n[DM_LEVEL_SUM_GATHER_LEVELS])
{
    if (!(ix[0] >= 0.0f && ix[3] >= 0.0f && ix[3] < DM_LEVEL_SUM_TAPS_WIDTH && a_count(ix[1]) && a_count(ix[2])))
        return false;
    *t = first_tap(ix);
    if (*t < (size_t)(DM_LEVEL_SUM_HEADER_TAPS + sites)) return false;
    for (int l = 0; l < DM_LEVEL_SUM_GATHER_LEVELS; ++l) n[l] = 0;
    n[0] = (size_t)ix[1], n[1] = count > 1 ? (size_t)ix[2] : 0;
    if (count > 2) {
        if (*t + DM_LEVEL_SUM_COUNT_TAPS > (size_t)tap_count) return false;
        const float *c = taps + 2 * *t;
        if (!a_count(c[0]) || !a_count(c[1]) || (count < 4 && c[1] != 0.0f)) return false;
        n[2] = (size_t)c[0], n[3] = count > 3 ? (size_t)c[1] : 0, *t += DM_LEVEL_SUM_COUNT_TAPS;
    }
    size_t end = *t;
    for (int l = 0; l < count; ++l) end += n[l];
    return end <= (size_t)tap_count;
}

static size_t run_taps(const size_t n[DM_LEVEL_SUM_GATHER_LEVELS])
{
    size_t total = 0;
    for (int l = 0; l < DM_LEVEL_SUM_GATHER_LEVELS; ++l) total += n[l];
    return total;
}

typedef struct site_key {
    int64_t texel, site;
} site_key;

static int cmp_key(const void *a, const void *b)
{
    const site_key *p = a, *q = b;
    return p->texel != q->texel ? (p->texel > q->texel) - (p->texel < q->texel) : (p->site > q->site) - (p->site < q->site);
}

static bool gathers(const float *ix)
{
    return ix[1] > 0.0f || ix[2] > 0.0f;
}

bool dm_level_sum_gather_check(const float *index, int n, const float *taps, int64_t tap_count, int levels,
                               int *first_level, int *level_count)
{
    if (!index || !taps || n < 1 || tap_count < DM_LEVEL_SUM_HEADER_TAPS) return false;
    int first = (int)taps[0], count = (int)taps[1];
    int64_t sites = (int64_t)taps[3], total = 0;
    if (taps[2] != (float)DM_LEVEL_SUM_GATHER_FORMAT || first < 1 || count < 1 || count > DM_LEVEL_SUM_GATHER_LEVELS ||
        first + count > levels ||
        sites < 1 || DM_LEVEL_SUM_HEADER_TAPS + sites > tap_count)
        return false;
    for (size_t i = 0; i < (size_t)n * (size_t)n; ++i) {
        const float *ix = index + 4 * i;
        size_t t, c[DM_LEVEL_SUM_GATHER_LEVELS];
        if (!gathers(ix)) continue;
        if (!texel_run(ix, taps, count, sites, tap_count, &t, c) || (total += (int64_t)run_taps(c)) >= INT32_MAX)
            return false;
        for (size_t end = t + run_taps(c); t < end; ++t) {
            float s = taps[2 * t] - (float)DM_LEVEL_SUM_HEADER_TAPS;
            if (!(s >= 0.0f && s < (float)sites)) return false;
        }
    }
    if (first_level) *first_level = first;
    if (level_count) *level_count = count;
    return true;
}

bool dm_level_sum_gather_make(const float *index, int n, const float *taps, int64_t tap_count, int levels,
                              dm_level_sum_gather *out)
{
    *out = (dm_level_sum_gather){0};
    int first, count;
    if (!dm_level_sum_gather_check(index, n, taps, tap_count, levels, &first, &count)) return false;
    int64_t sites = (int64_t)taps[3];
    size_t nn = (size_t)n * (size_t)n, gathering = 0;
    for (size_t i = 0; i < nn; ++i) gathering += gathers(index + 4 * i);
    /* texels that share a run (blocks: bake/dm_thin_gather.h) share its sums: one run each, in
     * the order of the first texel that reads it */
    site_key *key = malloc(sizeof *key * (gathering ? gathering : 1)); /* (the run's first tap, the texel) */
    size_t *at = malloc(sizeof *at * (gathering ? gathering : 1)); /* gathering texel → its index texel */
    int32_t *run = malloc(sizeof(int32_t) * (gathering ? gathering : 1)), *lead = malloc(sizeof(int32_t) * (gathering ? gathering : 1));
    bool ok = key && at && run && lead;
    for (size_t i = 0, j = 0; ok && i < nn; ++i)
        if (gathers(index + 4 * i)) at[j] = i, key[j] = (site_key){(int64_t)first_tap(index + 4 * i), (int64_t)j}, ++j;
    if (ok) qsort(key, gathering, sizeof *key, cmp_key);
    for (size_t k = 0; ok && k < gathering; ++k) { /* the first texel of each start leads its run */
        bool same = k > 0 && key[k].texel == key[k - 1].texel;
        lead[key[k].site] = same ? lead[key[k - 1].site] : (int32_t)key[k].site;
        if (same && memcmp(index + 4 * at[key[k].site], index + 4 * at[lead[key[k].site]], sizeof(float) * 4))
            ok = false; /* one run read with other counts: not a pack this reads */
    }
    size_t runs = 0, total = 0;
    for (size_t j = 0; ok && j < gathering; ++j) {
        if (lead[j] == (int32_t)j) {
            size_t t, c[DM_LEVEL_SUM_GATHER_LEVELS];
            texel_run(index + 4 * at[j], taps, count, sites, tap_count, &t, c); /* checked above */
            total += run_taps(c), run[j] = (int32_t)runs++;
        } else {
            run[j] = run[lead[j]];
        }
    }
    free(key);
    dm_level_sum_gather g = {n, first, count, malloc(sizeof(int32_t) * ((size_t)n + 1)),
                             malloc(sizeof(int32_t) * (gathering ? gathering : 1)), run,
                             malloc(sizeof(int32_t) * ((runs + 1) * (size_t)count)),
                             malloc(sizeof(dm_level_sum_tap) * (total ? total : 1)), NULL, NULL,
                             malloc(sizeof(float) * 4 * (runs ? runs : 1)), gathering, runs, total, 0, 0};
    int32_t *slot = malloc(sizeof(int32_t) * (size_t)sites);
    ok = ok && g.row && g.x && g.run && g.first && g.taps && g.run_value && slot;
    for (int64_t s = 0; ok && s < sites; ++s) slot[s] = -1;
    for (size_t j = 0; ok && j < gathering; ++j) { /* the sites some tap reads */
        size_t t, c[DM_LEVEL_SUM_GATHER_LEVELS];
        if (lead[j] != (int32_t)j) continue;
        texel_run(index + 4 * at[j], taps, count, sites, tap_count, &t, c);
        for (size_t e = t + run_taps(c); t < e; ++t) slot[(size_t)(taps[2 * t] - (float)DM_LEVEL_SUM_HEADER_TAPS)] = 0;
    }
    /* numbered by the texel their UV falls in, row by row (ties: the pack's order), so that the
     * frame's values read level 0 in its own order */
    size_t used = 0;
    for (int64_t s = 0; ok && s < sites; ++s) used += slot[s] == 0;
    site_key *sk = ok ? malloc(sizeof *sk * (used ? used : 1)) : NULL;
    ok = ok && sk;
    for (int64_t s = 0, u = 0; ok && s < sites; ++s)
        if (slot[s] == 0) {
            const float *uv = taps + 2 * (DM_LEVEL_SUM_HEADER_TAPS + s);
            float x = floorf(uv[0] * (float)n), y = floorf(uv[1] * (float)n);
            x = x >= 0.0f ? x < (float)n ? x : (float)n : -1.0f, y = y >= 0.0f ? y < (float)n ? y : (float)n : -1.0f;
            sk[u++] = (site_key){(int64_t)(y + 1.0f) * (n + 2) + (int64_t)(x + 1.0f), s};
        }
    if (ok) qsort(sk, used, sizeof *sk, cmp_key);
    for (size_t u = 0; ok && u < used; ++u) slot[sk[u].site] = (int32_t)u;
    g.slot_count = ok ? used : 0;
    free(sk);
    for (size_t j = 0, y = 0; ok && y <= (size_t)n; ++y) { /* the rows' gathering texels */
        while (j < gathering && at[j] < y * (size_t)n) ++j;
        g.row[y] = (int32_t)j;
    }
    for (size_t j = 0; ok && j < gathering; ++j) g.x[j] = (int32_t)(at[j] % (size_t)n);
    size_t k = 0;
    for (int l = 0; ok && l < count; ++l) { /* level by level, the runs in order, each one's taps in the pack's order */
        int32_t *lf = g.first + (runs + 1) * (size_t)l;
        for (size_t j = 0; j < gathering; ++j) {
            size_t t, c[DM_LEVEL_SUM_GATHER_LEVELS];
            if (lead[j] != (int32_t)j) continue;
            texel_run(index + 4 * at[j], taps, count, sites, tap_count, &t, c);
            for (int m = 0; m < l; ++m) t += c[m];
            lf[run[j]] = (int32_t)k;
            for (size_t e = t + c[l]; t < e; ++t, ++k) {
                size_t s = (size_t)(taps[2 * t] - (float)DM_LEVEL_SUM_HEADER_TAPS);
                g.taps[k] = (dm_level_sum_tap){slot[s], taps[2 * t + 1]};
            }
        }
        lf[runs] = (int32_t)k;
    }
    if (ok) {
        g.uv = malloc(sizeof(float) * 2 * (g.slot_count ? g.slot_count : 1));
        g.value = calloc(4 * (g.slot_count ? g.slot_count : 1), sizeof(float));
        ok = g.uv && g.value;
    }
    for (int64_t s = 0; ok && s < sites; ++s)
        if (slot[s] >= 0) {
            const float *uv = taps + 2 * (DM_LEVEL_SUM_HEADER_TAPS + s);
            g.uv[2 * (size_t)slot[s]] = uv[0], g.uv[2 * (size_t)slot[s] + 1] = uv[1];
        }
    free(slot), free(at), free(lead);
    if (!ok) return dm_level_sum_gather_free(&g), false;
    *out = g;
    return true;
}

void dm_level_sum_gather_free(dm_level_sum_gather *g)
{
    free(g->row), free(g->x), free(g->run), free(g->first), free(g->taps), free(g->uv), free(g->value), free(g->run_value);
    *g = (dm_level_sum_gather){0};
}
