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
 * after its own term, per candidate j of the texel (u′_j, v′_j, d_j mm):
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
 * added (dm_level_sum_gather); diffusion.glsl's DM_GATHER makes the same sums in GL.
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
enum { DM_LEVEL_SUM_TAPS_WIDTH = 4096, DM_LEVEL_SUM_HEADER_TAPS = 2, DM_LEVEL_SUM_GATHER_FORMAT = -2 };

/* A thin-part map's candidates per texel: texel i = x + y·n has candidates first[i] ..
 * first[i + 1] − 1 of cand, 4 floats each (u′, v′, d mm, 0), layer 0's before layer 1's. */
typedef struct dm_level_sum_thin {
    int n;
    int32_t *first; /* n·n + 1 */
    float *cand;
    size_t count;
} dm_level_sum_thin;

/* A thin gather's baked index and taps (bake/dm_thin_gather.h, as the pack holds them) and the
 * per-frame light of the sites it reads. */
typedef struct dm_level_sum_gather {
    int n, first_level, level_count;
    const float *index; /* n·n·4: first tap's row, taps of gathered level 0, of level 1, first tap's column */
    const float *taps;  /* 2 floats a tap: the header, the sites' (u, v), the texels' (site, weight) */
    int64_t tap_count, site_count;
    float *value;       /* per site 4: level 0 at its UV this frame (owned) */
    int32_t *used;      /* the sites some tap reads, ascending (owned) */
    size_t used_count;
    int thread_count;   /* for the values; 0 = every core */
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

/* A gather over a pack's entries: index n × n × 4, taps (2 per tap, header first; its count
 * tap_count). False (out empty) when the header is not this layout's (DM_THIN_GATHER_FORMAT) or
 * does not fit the levels (first_level + level_count ≤ levels), a texel's taps or a tap's site lie
 * outside, or out of memory. Free with dm_level_sum_gather_free. */
bool dm_level_sum_gather_make(const float *index, int n, const float *taps, int64_t tap_count, int levels,
                              dm_level_sum_gather *out);
void dm_level_sum_gather_free(dm_level_sum_gather *g);

#ifdef __cplusplus
}
#endif
#endif
