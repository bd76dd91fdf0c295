/* dm_thin_gather.h — the widest levels gathered in 3-D where the atlas blur cannot carry them
 * (issue #29, thin parts and folds): per texel near a surface facing the other way, the exact
 * 3-D convolution of the irradiance as a sum over small atlas cells.
 *
 * The thin-part map (dm_thin_map.h) adds, per texel, one or two parallel sheets across. On the
 * ears, the lips and the lids the surface is neither parallel nor flat within the widest
 * Gaussians' reach, and the texture-space truth (the 3-D convolution) differs from the atlas
 * blur plus those sheets by 16 % (level 4, σ 1.4 mm) and 25 % (level 5, σ 2.7 mm) on the head at
 * 1024² (docs/thin-map.md). Those two levels carry nearly all of the thin region's error: with
 * them exact, it is 1 %.
 *
 * So for a **gathering texel** x — a covered texel with a cell facing away (n_c · n_x < 0)
 * within near_mm — each gathered level k is computed directly:
 *     S_k(x) = Σ_c min(G(v_k, |P(x) − P_c|) · A_c, 1 − e^(−A_c/2πv_k)) · Ī_c   over the cells c within
 *                                                                     reach_sigmas·σ_k
 * G the unit-integral radial Gaussian (core/dm_profile.h), cells the C_k × C_k blocks of the N × N
 * atlas (C_k the largest power of two with C_k · h ≤ σ_k, h the median texel side in mm,
 * at most N), P_c the mean of the surface points of its member texels (the covered ones: a
 * triangle of UV area and 3-D area covers the centre), A_c the sum of their skin areas (mm²),
 * Ī_c the mean of their irradiance, taken at run time (core/dm_level_sum.h). The cap is the most
 * light any patch of area A_c holds under the Gaussian (a disc around the centre): it binds only
 * for a cell near x or one far larger than σ (a squashed chart's texels). The weights
 * G · A_c are light-independent and baked here; a cell is a point of the quadrature, which for
 * a Gaussian sampled finer than its σ is exact to far below a float on a plane (the Poisson
 * sum), and everywhere follows the real 3-D distances: both sheets of an ear, a ridge's far side.
 *
 * Storage (pack entries "gather.index" and "gather.taps", rows bottom-up):
 *   index: N × N RGBA32F per texel (first tap, taps of gathered level 0, taps of gathered
 *          level 1, member 0/1); a texel gathers when its tap counts are not 0;
 *   taps:  DM_THIN_GATHER_TAPS_WIDTH × rows RG32F, 2 floats a tap: (cell index y·(N/C)+x, weight
 *          G · A_c); taps 0 and 1 are the header: (first gathered level, gathered levels) and
 *          (C of gathered level 0, C of gathered level 1). A texel's taps: level 0's, then 1's.
 * Float indices are exact below 2^24: the bake refuses more taps (DM_ERR_RANGE).
 * Deterministic: the same bytes for any thread count (texels in parallel, each alone; the
 * offsets a prefix sum in texel order). */
#ifndef DM_THIN_GATHER_H
#define DM_THIN_GATHER_H

#include <stdint.h>

#include "core/dm_prov.h"
#include "core/dm_result.h"
#include "mesh/dm_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    DM_THIN_GATHER_LEVELS = 2,         /* the profile's widest levels it gathers, at most */
    DM_THIN_GATHER_TAPS_WIDTH = 4096,  /* the taps texture's width */
    DM_THIN_GATHER_HEADER_TAPS = 2,
    DM_THIN_GATHER_SIZE_MAX = 4096
};
#define DM_THIN_GATHER_FLOAT_EXACT 16777216.0 /* 2^24: taps and cells a float counts exactly */
#define DM_THIN_GATHER_REACH_SIGMAS 3.5       /* cells within 3.5 σ_k: 99.8 % of a plane's mass */
#define DM_THIN_GATHER_CELL_SIGMAS 1.0        /* C_k · h ≤ σ_k */

typedef struct dm_thin_gather_options {
    int size;                                      /* N, 1..DM_THIN_GATHER_SIZE_MAX */
    double mm_per_unit;                            /* > 0 */
    int first_level;                               /* k of the first gathered level in the profile */
    int level_count;                               /* 1..DM_THIN_GATHER_LEVELS */
    double variance_mm2[DM_THIN_GATHER_LEVELS];    /* v_k of the gathered levels, > 0 */
    double near_mm;                                /* > 0: a cell facing away this near makes a texel gather */
    int threads;                                   /* 0: all cores; the result does not depend on it */
} dm_thin_gather_options;

typedef struct dm_thin_gather_stats {
    int64_t covered_texels, gathering_texels, taps;
    int cell[DM_THIN_GATHER_LEVELS]; /* C per gathered level */
    double texel_mm;                 /* h, the median texel side */
    double max_taps;                 /* the most taps one texel has (both levels) */
} dm_thin_gather_stats;

typedef struct dm_thin_gather {
    int size, first_level, level_count;
    int cell[DM_THIN_GATHER_LEVELS];
    float *index;      /* N × N × 4 */
    float *taps;       /* 2 × DM_THIN_GATHER_TAPS_WIDTH × rows */
    int taps_rows;     /* rows of the taps texture */
    int64_t tap_count; /* with the header */
} dm_thin_gather;

/* The options for a profile's widest levels (up to DM_THIN_GATHER_LEVELS, only those with
 * σ_k ≥ 0.5 mm: narrower ones the atlas carries) with near_mm = 2 σ of the widest; level_count
 * 0 when none qualifies. variance_mm2: the profile's count variances, ascending. */
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
