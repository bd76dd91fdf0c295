/* dm_level_sum.h — the diffusion pass's sum (shaders/diffusion.glsl) on the CPU, built level by
 * level as the blur on the CPU makes the levels (lib/render/passes/dm_pass_blur_cpu.c): per texel
 * of the irradiance grid
 *     sum = Σ_k w_k · (a_k > 1e-4 ? rgb_k / a_k : 0)     (per channel, in level order)
 * then rgb · c, alpha c, with c level 0's alpha (its chart coverage, 0 or 1). The same float
 * operations in the same order as the shader's dm_level_sum, so the two agree to float
 * rounding (tests/render/test_render_blur_cpu.c); levels at the grid's own size only (the
 * renderer sums reduced levels per pixel instead).
 *
 * With a thin-part map (bake/dm_thin_map.h, DM_THIN in the shader) each level k also adds, right
 * after its own term, per candidate j of the texel (u′_j, v′_j, d_j mm) within the cut below:
 *     w_k · (exp(−d_j²/(2 v_k)) · L_k(u′_j, v′_j))
 * L_k read as the shader's sampler reads it: bilinear at the texel centres, zero outside the
 * image, then coverage-normalised as above. The candidates come in a compact form
 * (dm_level_sum_thin_make).
 *
 * With a thin gather (bake/dm_thin_gather.h) the gathered levels k of a gathering texel take,
 * instead of their own term and the thin candidates',
 *     w_k · Σ_t weight_t · I(uv_s(t))
 * I level 0 read at the site's UV as the shader's sampler reads it (level_at above: bilinear,
 * coverage-normalised), computed once per frame for the sites some tap reads when level 0 is
 * added (dm_level_sum_gather); diffusion.glsl's DM_GATHER makes the same sums in GL. A texel's
 * taps are summed in two alternating sums (even taps, odd taps), then added, as the shader does.
 *
 * Deterministic: each texel alone, byte-identical for any thread count. */
#ifndef DM_LEVEL_SUM_H
#define DM_LEVEL_SUM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The thin gather's layout (bake/dm_thin_gather.h names them too): its taps texture's width, the
 * header's taps, and the header's mark of this layout (sites read at their UV; first taps by row
 * and column). */
enum {
    DM_LEVEL_SUM_TAPS_WIDTH = 4096,
    DM_LEVEL_SUM_HEADER_TAPS = 2,
    DM_LEVEL_SUM_GATHER_FORMAT = -2,
    DM_LEVEL_SUM_GATHER_LEVELS = 4, /* gathered levels, at most */
    DM_LEVEL_SUM_COUNT_TAPS = 1     /* a run's count tap (levels 2 and 3's taps), with 3 or 4 levels */
};

/* A thin candidate adds to level k only where d² ≤ DM_LEVEL_SUM_THIN_CUT · v_k: beyond, its
 * weight exp(−d²/2v_k) is below e^−18 = 1.5e-8, under a float's rounding of a sum it shares
 * with light of its size (diffusion.glsl reads the same cut as DM_THIN_CUT). The narrow levels
 * skip almost every candidate: a thin part is millimetres across, level 0's σ 0.08 mm. */
enum { DM_LEVEL_SUM_THIN_CUT = 36 };

/* A thin-part map's candidates, compact: the texels with any, row by row (row y's are
 * [row[y], row[y + 1]), their columns ascending in x), texel j's candidates first[j] ..
 * first[j + 1] − 1 of cand, 4 floats each (u′, v′, d mm, 0), layer 0's before layer 1's. The sum
 * walks a row's list beside its texels, so a texel without candidates costs one compare. */
typedef struct dm_level_sum_thin {
    int n;
    int32_t *row;   /* n + 1 */
    int32_t *x;     /* per texel with candidates: its column */
    int32_t *first; /* per texel with candidates, + 1 */
    float *cand;
    size_t count;   /* candidates */
} dm_level_sum_thin;

/* A thin gather as the sums read it, made from the pack's entries (dm_level_sum_gather_make) and
 * owned: the gathering texels row by row (as the thin candidates above), each one's run (texels
 * in a block share one: bake/dm_thin_gather.h; its sums are made once, before the texels read
 * them), each run's taps per gathered level, a tap (slot, weight); a slot is a site some tap
 * reads, numbered in the order the texels first read them (neighbouring texels read neighbouring
 * slots), its UV and its light this frame. The same weights and sites, in the same order, as the
 * pack's taps. */
typedef struct dm_level_sum_tap {
    int32_t slot;
    float weight;
} dm_level_sum_tap;

typedef struct dm_level_sum_gather {
    int n, first_level, level_count;
    int32_t *row;           /* n + 1: row y's gathering texels are [row[y], row[y + 1]) */
    int32_t *x;             /* per gathering texel: its column, ascending within a row */
    int32_t *run;           /* per gathering texel: its run, numbered in the order texels first read them */
    int32_t *first;         /* per gathered level, per run, + 1: run r's taps of level g are
                             * first[g·(runs + 1) + r] .. first[g·(runs + 1) + r + 1] − 1: a level's
                             * taps are one stream in run order, as its pass reads them
                             * (interleaved with the other level's, the hardware prefetch lost the
                             * stream: 2.3 ns a tap against 0.5 on the 2-core machine) */
    dm_level_sum_tap *taps;
    float *uv;              /* per slot 2: the site's (u, v) */
    float *value;           /* per slot 4: level 0 at its UV this frame */
    float *run_value;       /* per run 4: the level being added's sum */
    size_t gathering, run_count, tap_count, slot_count;
    int thread_count;       /* for the values; 0 = every core */
} dm_level_sum_gather;

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
    const dm_level_sum_thin *thin; /* NULL: none; else its n is this n */
    float variance_mm2;            /* v_k, with thin */
    dm_level_sum_gather *gather;   /* NULL: none; else its n is this n; level 0 fills its values */
    int level_index;               /* k, with gather */
} dm_level_sum_pass;

/* Adds one level. False (nothing written) when a pointer is NULL, n < 1, stride < 4 n, or a
 * thin map of another size or a variance ≤ 0 with one. */
bool dm_level_sum_add(const dm_level_sum_pass *p);

/* The compact candidates of a thin-part map's texels (RGBA, n × 2n: layer j in rows
 * [j·n, (j + 1)·n); a candidate where alpha > 0.5). False when out of memory (out left
 * empty) or n < 1. Free with dm_level_sum_thin_free (safe on a zeroed one). */
bool dm_level_sum_thin_make(const float *map, int n, dm_level_sum_thin *out);
void dm_level_sum_thin_free(dm_level_sum_thin *t);

/* Checks a pack's gather entries: index n × n × 4 (first tap's row, taps of gathered level 0, of
 * level 1, first tap's column), taps 2 floats each (the header, the sites' (u, v), the texels'
 * runs: with 3 or 4 levels a count tap (taps of level 2, of level 3), then (site, weight) level by
 * level), tap_count of them. False when the header is not this layout's
 * (DM_LEVEL_SUM_GATHER_FORMAT) or does not fit the levels (first_level + level_count ≤ levels), a
 * texel's taps or a tap's site lie outside, or there are 2^31 taps or more; else its first gathered
 * level and their count (either pointer may be NULL). */
bool dm_level_sum_gather_check(const float *index, int n, const float *taps, int64_t tap_count, int levels,
                               int *first_level, int *level_count);
/* The sums' own compact copy of them (the caller may free its arrays afterwards). False (out
 * empty) when dm_level_sum_gather_check refuses them or out of memory. Free with
 * dm_level_sum_gather_free (safe on a zeroed one). */
bool dm_level_sum_gather_make(const float *index, int n, const float *taps, int64_t tap_count, int levels,
                              dm_level_sum_gather *out);
void dm_level_sum_gather_free(dm_level_sum_gather *g);

#ifdef __cplusplus
}
#endif
#endif
