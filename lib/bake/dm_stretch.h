/* dm_stretch.h — static UV stretch maps and their blurred chain (DESIGN.md "Stretch maps").
 *
 * A blur of standard deviation σ mm in texture space moves σ·s_u in u and σ·s_v in v,
 * where s_u = 1/|∂P/∂u| and s_v = 1/|∂P/∂v| are UV units per mm. On a triangle, P(u, v)
 * is affine, so its Jacobian is exact and constant:
 *   e1 = P1 − P0, e2 = P2 − P0, (du1, dv1), (du2, dv2) the UV edges, D = du1·dv2 − du2·dv1,
 *   ∂P/∂u = (e1·dv2 − e2·dv1) / D,   ∂P/∂v = (e2·du1 − e1·du2) / D   (× mm_per_unit).
 * The chapter (GPU Gems 3, ch. 14) measured this per frame with screen derivatives; here
 * it is computed once, exactly, per triangle.
 *
 * The bake:
 *  1. Rasterize the triangles in UV (dm_uv_raster.h): a covered texel takes its
 *     triangle's (s_u, s_v); mask = 1.
 *  2. Degenerate triangles cover nothing (mask = 0 where they lie) and are counted:
 *     zero UV area (|D| ≤ 1e-9 of the squared UV edge lengths: e.g. an island collapsed
 *     to a point), zero surface area (|e1 × e2| ≤ 1e-9 of the squared edge lengths, or
 *     a stretch above DM_PACK_STRETCH_MAX_PER_MM, pack/dm_pack_semantic.h: the atlas
 *     spanning less than a nanometre). Mirrored UVs (D < 0) are ordinary triangles:
 *     s_u, s_v do not depend on the sign of D; they are counted.
 *  3. Every uncovered texel takes the values of the nearest covered texel
 *     (dm_gutter.h), over the whole texture: no blur reach reads an empty texel.
 *  4. The chain, as the runtime blurs irradiance: level 0 is the base map (it stands for
 *     the profile's narrowest Gaussian, v_0); level k is level k−1 blurred by the
 *     variance v_k − v_{k−1} (mm²), separably, U then V, each a 7-tap Gaussian at
 *     offsets i·σ·s (i = −3..3, σ = √(v_k − v_{k−1}) mm) with s = the level k−1 stretch
 *     at the output texel (s_u·width texels in U, s_v·height in V), taps bilinear with
 *     clamp to edge, weights the Gaussian's mass over [i − ½, i + ½]σ renormalised
 *     (0.0062, 0.0606, 0.2417, 0.3829, ...), the chapter's kernel. The runtime blurs
 *     irradiance level k−1 → k with stretch level k−1.
 * Every value of every level is finite and > 0. Results do not depend on the thread
 * count, so bakes are byte-identical.
 */
#ifndef DM_STRETCH_H
#define DM_STRETCH_H

#include <stdint.h>

#include "mesh/dm_mesh.h"
#include "core/dm_profile.h"
#include "core/dm_prov.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    DM_STRETCH_SIZE_DEFAULT = 1024,
    DM_STRETCH_SIZE_MAX = 16384,
    DM_STRETCH_TAPS = 7 /* per blur pass, as the runtime's shader */
};
#define DM_STRETCH_MM_PER_UNIT_DEFAULT 50.0 /* the Lee Perry-Smith head (DESIGN.md) */

typedef struct dm_triangle_stretch {
    dm_triangle_kind kind;
    int mirrored;  /* 1 when D < 0 (and kind is OK) */
    double s_u, s_v; /* UV units per mm; 0 unless kind is OK */
} dm_triangle_stretch;

/* The exact stretch of triangle t of m (valid mesh), mm_per_unit > 0: from its UV
 * Jacobian (dm_mesh_uv_jacobian), s = 1 / |∂P/∂u| and 1 / |∂P/∂v| in mm. */
void dm_triangle_stretch_of(const dm_mesh *m, int32_t t, double mm_per_unit, dm_triangle_stretch *out);

/* Zero means the default for every field. */
typedef struct dm_stretch_options {
    int width, height;         /* texels, 1..DM_STRETCH_SIZE_MAX; default 1024 */
    double mm_per_unit;        /* > 0; default 50 */
    const dm_profile *profile; /* the Gaussian chain; default gems3-skin (dm_profile_gems3_skin) */
    int level_count;           /* maps to make, 1..profile->count; default profile->count */
    int thread_count;          /* default all cores */
    /* Called on the calling thread between stages with the fraction done (may be NULL). */
    void (*progress)(void *ctx, double fraction);
    void *progress_ctx;
} dm_stretch_options;

typedef struct dm_stretch_stats {
    int32_t triangle_count;
    int32_t zero_uv_area_triangles;
    int32_t zero_area_triangles;
    int32_t mirrored_triangles;
    int32_t out_of_range_triangles; /* a UV corner beyond ±2^20 texels: skipped */
    int32_t uv_islands;             /* dm_mesh_uv_islands */
    int64_t covered_texels;         /* mask = 1 */
    int64_t overlap_texels;         /* texels claimed again by an overlapping chart */
    int64_t gutter_texels;          /* mask = 0, filled */
    double coverage;                /* covered_texels / (width·height) */
    double s_u_percentile[5];       /* base s_u over covered texels at 1, 5, 50, 95, 99 % */
    double s_v_percentile[5];
    double s_u_max, s_v_max;        /* over covered texels */
    double fill_distance_max_texels;/* farthest gutter texel from its chart */
    double blur_reach_texels;       /* widest tap reach of the chain: 3σ·s·size at the
                                     * largest step and stretch (0 with one level) */
    double raster_ms, fill_ms, blur_ms, stats_ms;
} dm_stretch_stats;

typedef struct dm_stretch_map {
    int width, height, level_count;
    double variance_mm2[DM_PROFILE_MAX_GAUSSIANS]; /* the Gaussian each level stands for */
    float *s_u[DM_PROFILE_MAX_GAUSSIANS];          /* level_count planes, width*height, bottom-up */
    float *s_v[DM_PROFILE_MAX_GAUSSIANS];
    float *mask;                                   /* width*height, 1 covered, 0 gutter */
    dm_stretch_stats stats;
} dm_stretch_map;

/* Bakes the stretch map and its chain from a valid mesh (dm_mesh_validate). Fails with
 * DM_ERR_RANGE / DM_ERR_INVALID_ARGUMENT on bad options (naming the option and value),
 * DM_ERR_EMPTY when no triangle covers a texel, DM_ERR_OUT_OF_MEMORY. Memory: the output
 * (4·(2·level_count + 1) bytes per texel) plus 5 bytes per texel of scratch (8 during
 * the blur), plus ~100 bytes per triangle. Free with dm_stretch_map_free, also after a
 * failure. */
dm_result dm_stretch_bake(const dm_mesh *m, const dm_stretch_options *opt, dm_stretch_map *out, dm_error *err);
void dm_stretch_map_free(dm_stretch_map *map);
/* Reads what dermis-bake-stretch wrote (channels stretch<k>.u/.v and mask, the variances
 * from its provenance "variance_mm2_<k>") back into a map, and its provenance into prov.
 * Free with dm_stretch_map_free, also after a failure. */
dm_result dm_stretch_read(const char *path, dm_stretch_map *out, dm_provenance *prov, dm_error *err);

/* The 7 normalised tap weights (i = −3..3) of the chain's blur. */
void dm_stretch_blur_weights(double w[DM_STRETCH_TAPS]);

#ifdef __cplusplus
}
#endif
#endif
