/* dm_thin_gather.h — the widest levels gathered in 3-D where the atlas blur cannot carry them
 * (issue #29, thin parts, folds and seams): per texel near a surface facing the other way or a
 * UV seam, the exact 3-D convolution of the irradiance as a sum over small patches of the surface.
 *
 * The thin-part map (dm_thin_map.h) adds, per texel, one or two parallel sheets across. On the
 * ears, the lips and the lids the surface is neither parallel nor flat within the widest
 * Gaussians' reach, and the texture-space truth (the 3-D convolution) differs from the atlas
 * blur plus those sheets by 16 % (level 4, σ 1.4 mm) and 25 % (level 5, σ 2.7 mm) on the head at
 * 1024² (docs/thin-map.md). Those two levels carry nearly all of the thin region's error: with
 * them exact, it is 1 %.
 *
 * So for a **gathering texel** x each gathered level k is computed directly, as the exact 3-D
 * convolution's quadrature over the surface's sites (bake/dm_gather_sites.h):
 *     S_k(x) = Σ_s min(G(v_k, |P(x) − P_s|) · A_s, 1 − e^(−A_s/2πv_k)) · I(uv_s)   over the sites s
 *                                                                    within reach_sigmas·σ_k
 * G the unit-integral radial Gaussian (core/dm_profile.h); the sites of level k are patches of
 * exact area A_s (mm²) grouped within cells of C_k × C_k texels (C_k the largest power of two with
 * C_k · h ≤ σ_k, h the median texel side in mm) and within cluster_sigmas·σ_k in 3-D, P_s their
 * mean point; I(uv_s) is level 0 read at the site's UV as the renderer's sampler reads it
 * (bilinear, coverage-normalised: core/dm_level_sum.h, diffusion.glsl), as the truth reads it. The
 * cap is the most light any patch of area A_s holds under the Gaussian (a disc around the
 * centre): it binds only for a site next to x. The weights are light-independent and baked here.
 * From split_sigmas·σ_k on, coarse sites take the fine ones' place (whole fine sites grouped in
 * 2C_k × 2C_k cells within coarse_cluster_sigmas·σ_k): one tap each, weighted by its fine sites'
 * exact sum for x, read at its own UV — the far part of the Gaussian in half the taps (the head at
 * 1024²: 16 M instead of 33 M; on levels 4–5 alone the seam region's error 0.28 → 0.30 %, the
 * thin region's 1.16 → 1.43 %, docs/thin-map.md).
 *
 * A texel gathers (a covered texel, P(x) its surface point at the texel centre):
 *   - near a surface facing away: a site of the widest level with n_s · n_x < 0 within near_mm
 *     (thin parts and folds: both sheets of an ear, a lip against the other); or
 *   - near a seam: a UV seam edge (mesh/dm_seam_edges.h: a cut, a boundary, a non-manifold edge)
 *     within seam_mm in 3-D. There the atlas blur reads the charts pressed against the cut, or
 *     their squashed rims, as the surface next door (docs/seam-map.md), and the widest levels
 *     carry nearly all of the seam region's error.
 *
 * Which levels: every level with σ_k ≥ 1 mm, the widest DM_THIN_GATHER_LEVELS of them (the
 * narrower ones the atlas carries within a texel or two). A fit with more Gaussians splits the
 * same wide light over more levels (skin1 with 8: 1.6, 4.5, 13 and 40 mm²), and a gather that
 * took only the widest two left the first two to the atlas blur: in the frame the fits ranked 5
 * Gaussians above 6, 7 and 8 (issue #27).
 *
 * Storage (pack entries "gather.index" and "gather.taps", rows bottom-up):
 *   index: N × N RGBA32F per texel (the row of its first tap, taps of gathered level 0, taps of
 *          gathered level 1, the column of its first tap: the tap t = row · 4096 + column); a
 *          texel gathers when its first two levels' tap counts are not both 0;
 *   taps:  DM_THIN_GATHER_TAPS_WIDTH × rows RG32F, 2 floats a tap. Taps 0 and 1 are the header:
 *          (first gathered level, gathered levels) and (DM_THIN_GATHER_FORMAT, sites). Then the
 *          sites, one a tap: (u, v), level 0's sites, level 1's, and so on. Then each gathering
 *          texel's run: with 3 or 4 gathered levels first a count tap (taps of gathered level 2,
 *          of level 3 or 0), then level 0's taps, level 1's, ...: (the site's tap index, weight).
 * Float indices and counts are exact below 2^24: the bake refuses more sites (DM_ERR_RANGE); the
 * taps themselves are addressed by row and column, and the bake refuses more than taps_max
 * (DM_THIN_GATHER_TAPS_MAX; DM_ERR_RANGE: a pack leaves the gather out).
 *
 * Blocks: where one run of taps per texel would pass taps_max (the head at 2048², or at 1024² for
 * a fit whose widest level reaches 20 mm), texels share runs in blocks of B × B (B = 2, then 4):
 * in each block a covered texel leads a group of the block's other covered texels within
 * join·B·h of it in 3-D (join 0.75: a regular 2 × 2 block's diagonal, 1.41 h, is in; a block across
 * a chart's edge, or a squashed chart's long texels, give groups of their own), the group gathers
 * when a member would, and each of its taps weighs the members' mean weight for that site (a
 * member's split and reach its own: a site near one member and coarse for another gives both
 * taps), so a member's sum is the mean of the group's exact sums: the exact sum box-filtered over
 * its group, whose error is second order in the members' spread over σ. Measured on the head at
 * 2048² against the texture-space truth (red, % mean): thin parts 2.16 with every texel alone
 * (64 M taps), 2.51 in blocks (28 M), 4.17 with a join of 2 (20 M); seams 0.57 / 0.61 / 1.00.
 * B = 1 is every texel alone, byte for byte the bake without blocks. Index entries of a group
 * point at the same run; the format is the same.
 *
 * Deterministic: the same bytes for any thread count (texels in parallel, each alone; groups made
 * in one thread; the offsets a prefix sum in texel order; the sites built in one thread). */
#ifndef DM_THIN_GATHER_H
#define DM_THIN_GATHER_H

#include <stdint.h>

#include "core/dm_level_sum.h"
#include "core/dm_prov.h"
#include "core/dm_result.h"
#include "mesh/dm_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    DM_THIN_GATHER_LEVELS = DM_LEVEL_SUM_GATHER_LEVELS, /* the profile's widest levels it gathers, at most */
    DM_THIN_GATHER_COUNT_TAPS = DM_LEVEL_SUM_COUNT_TAPS, /* a run's count tap, with 3 or 4 levels */
    DM_THIN_GATHER_TAPS_WIDTH = DM_LEVEL_SUM_TAPS_WIDTH, /* the taps texture's width */
    DM_THIN_GATHER_HEADER_TAPS = DM_LEVEL_SUM_HEADER_TAPS,
    DM_THIN_GATHER_SIZE_MAX = 4096,
    DM_THIN_GATHER_TAPS_MAX = 1 << 25, /* taps (8 bytes each) a gather may have: 256 MiB */
    DM_THIN_GATHER_BLOCK_MAX = 4,      /* the widest blocks of texels that share their taps */
    DM_THIN_GATHER_FORMAT = DM_LEVEL_SUM_GATHER_FORMAT /* the header's mark of this layout */
};
#define DM_THIN_GATHER_FLOAT_EXACT 16777216.0 /* 2^24: sites and counts a float counts exactly */
#define DM_THIN_GATHER_REACH_SIGMAS 3.5       /* sites within 3.5 σ_k: 99.8 % of a plane's mass */
#define DM_THIN_GATHER_CELL_SIGMAS 1.0        /* C_k · h ≤ σ_k */
#define DM_THIN_GATHER_CLUSTER_SIGMAS 0.6     /* a site's pieces within 0.6 σ_k of its first */
#define DM_THIN_GATHER_SPLIT_SIGMAS 2.0       /* from 2 σ_k on, coarse sites: */
#define DM_THIN_GATHER_COARSE_CLUSTER_SIGMAS 0.9 /* fine ones grouped in 2C × 2C cells within 0.9 σ_k */
#define DM_THIN_GATHER_JOIN 0.75               /* a block's group: members within 0.75 · B · h of its first */
#define DM_THIN_GATHER_SEAM_SIGMAS 1.1        /* seam_mm = 1.1 σ of the widest level (3.0 mm for gems3-skin) */

typedef struct dm_thin_gather_options {
    int size;                                      /* N, 1..DM_THIN_GATHER_SIZE_MAX */
    double mm_per_unit;                            /* > 0 */
    int first_level;                               /* k of the first gathered level in the profile */
    int level_count;                               /* 1..DM_THIN_GATHER_LEVELS */
    double variance_mm2[DM_THIN_GATHER_LEVELS];    /* v_k of the gathered levels, > 0 */
    double near_mm;                                /* > 0: a site facing away this near makes a texel gather */
    double seam_mm;                                /* ≥ 0: a seam edge this near makes a texel gather (0: none) */
    int threads;                                   /* 0: all cores; the result does not depend on it */
    int block;        /* texels share taps in blocks of block × block: 1, 2 or 4; 0: the smallest that fits taps_max */
    int64_t taps_max; /* the most taps (0: DM_THIN_GATHER_TAPS_MAX); more: DM_ERR_RANGE */
} dm_thin_gather_options;

typedef struct dm_thin_gather_stats {
    int64_t covered_texels, gathering_texels, taps;
    int64_t thin_texels, seam_texels;   /* gathering for a surface facing away, for a seam (both: thin) */
    int64_t sites[DM_THIN_GATHER_LEVELS]; /* per gathered level, 0 past the last */
    int cell[DM_THIN_GATHER_LEVELS];    /* C per gathered level */
    double texel_mm;                    /* h, the median texel side */
    double max_taps;                    /* the most taps one texel has (every level) */
    double dropped_mm2;                 /* sites' area with no covered texel near (widest level) */
    int block;                          /* the blocks' side */
} dm_thin_gather_stats;

typedef struct dm_thin_gather {
    int size, first_level, level_count, block;
    int cell[DM_THIN_GATHER_LEVELS];
    int64_t sites[DM_THIN_GATHER_LEVELS];
    float *index;      /* N × N × 4 */
    float *taps;       /* 2 × DM_THIN_GATHER_TAPS_WIDTH × rows */
    int taps_rows;     /* rows of the taps texture */
    int64_t tap_count; /* with the header and the sites */
} dm_thin_gather;

/* The options for a profile's widest levels (up to DM_THIN_GATHER_LEVELS, only those with
 * σ_k ≥ 1 mm: narrower ones the atlas carries) with near_mm = 2 σ and seam_mm = 1.1 σ of the widest,
 * block 0 (the smallest that fits DM_THIN_GATHER_TAPS_MAX);
 * level_count 0 when none qualifies. variance_mm2: the profile's count variances, ascending. */
void dm_thin_gather_options_for(const double *variance_mm2, int count, int size, double mm_per_unit,
                                dm_thin_gather_options *opt);

dm_result dm_thin_gather_bake(const dm_mesh *m, const dm_thin_gather_options *opt, dm_thin_gather *out,
                              dm_thin_gather_stats *stats, dm_error *err);
void dm_thin_gather_free(dm_thin_gather *g);
void dm_thin_gather_stats_prov(const dm_thin_gather_stats *s, dm_provenance *p);

#ifdef __cplusplus
}
#endif
#endif
