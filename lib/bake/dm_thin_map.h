/* dm_thin_map.h — where the surface is near in 3-D but far along the surface: the thin-part
 * map that lets texture-space diffusion carry light through thin parts (ear, nostril wall,
 * eyelid) and across folds (the lips, the eyelids across the slit) (issue #29, point 2).
 *
 * Texture-space diffusion blurs light along the UV atlas, so light whose path leaves the
 * surface — through a sheet of skin to its other side, or across the gap of a fold — never
 * arrives; the ground truth (dermis-reference, 3-D distances over the whole mesh) has it.
 * The thin map gives each covered texel up to DM_THIN_MAP_CANDIDATES points of the surface
 * across from it: the runtime adds, per candidate j, Σ_k w_k · exp(−d_j²/(2 v_k)) · L_k(uv'_j)
 * over the already-blurred levels L_k (Gaussian variances v_k). For two parallel sheets at
 * distance d this is exact: the 3-D Gaussian over the other sheet factors into the in-plane
 * blur (L_k at the point straight across) times the normal falloff exp(−d²/(2 v_k)).
 *
 * Per covered texel (centre ((i+½)/N, (j+½)/N), rows bottom-up, as dm_uv_raster.h): the
 * surface point p (mm) and normal n (the corner normals interpolated; the triangle's own
 * where the mesh has none or they cancel) at the centre's barycentrics
 * (dm_uv_raster_barycentrics). DM_THIN_MAP_RAYS rays leave p: along −n (through the part),
 * along +n (across a fold), and a ring of four tilted DM_THIN_MAP_TILT_DEG from each, at the
 * azimuths ±t1, ±t2 of the branchless orthonormal basis of n (Duff et al. 2017; for
 * n = +z: ±x, ±y), in that order: −n, +n, then −n's ring (+t1, −t1, +t2, −t2), then +n's. Each
 * searches [dm_raycast_epsilon_mm, reach_mm] for its closest hit q, either side of the hit
 * triangle (dm_raycast.h). A hit is a candidate when its triangle faces the other way
 * (n · n_q < 0, n_q the triangle's geometric normal), has UV area, and its UV (the hit
 * triangle's UVs at q's barycentrics) lands on a covered texel that is not within 1.5 texels
 * of the texel's own centre (its own surface, which the blur already holds). The candidate
 * is (u', v', d = |p − q| mm) with weight exp(−d²/(2 v_max)), v_max = (reach_mm / 3)².
 *
 * Distinct surfaces: candidates are taken heaviest first (ties: lower d, then ray order); one
 * is the same surface as one already taken — and left out, adding nothing — when its UV is
 * within 1.5 texels of the taken one's, or it lies on the taken one's tangent plane (its
 * offset along the taken normal under 1/4 of their distance, and the two normals within 45°):
 * a tilted ray's hit on a sheet an axial ray already found. The first DM_THIN_MAP_CANDIDATES
 * distinct surfaces are kept; the weight of the others is the texel's dropped weight.
 *
 * Deterministic: the same bytes for any thread count (rows in parallel, core/dm_parallel.h;
 * the stats summed afterwards in texel order).
 */
#ifndef DM_THIN_MAP_H
#define DM_THIN_MAP_H

#include <stdint.h>

#include "core/dm_prov.h"
#include "core/dm_result.h"
#include "mesh/dm_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    DM_THIN_MAP_CANDIDATES = 2,     /* candidates a texel holds: the layers of the map */
    DM_THIN_MAP_RAYS = 10,          /* ±n and a ring of 4 around each */
    DM_THIN_MAP_TILT_DEG = 30,      /* the ring's tilt from ±n */
    DM_THIN_MAP_SIZE_DEFAULT = 1024,
    DM_THIN_MAP_SIZE_MAX = 16384
};

typedef struct dm_thin_map_options {
    int size;           /* N: texels along u and v, 1..DM_THIN_MAP_SIZE_MAX */
    double mm_per_unit; /* > 0 */
    double reach_mm;    /* > 0: the rays' length, 3 σ of the profile's widest Gaussian
                         * (dm_seam_map_reach_mm); the weights' v_max = (reach_mm / 3)² */
    int threads;        /* 0: all cores; the result does not depend on it */
} dm_thin_map_options;

typedef struct dm_thin_map_stats {
    int64_t covered_texels;        /* texels a triangle covers (dm_uv_raster) */
    int64_t one_candidate_texels;  /* covered texels with exactly one candidate */
    int64_t two_candidate_texels;  /* ... with two */
    int64_t dropped_texels;        /* texels with more distinct surfaces than the map holds */
    double dropped_weight_sum;     /* Σ over texels of the dropped weight */
    double dropped_weight_max;     /* the largest one texel dropped */
    int64_t zero_uv_area_hits;     /* rays whose closest hit has no UV area: no candidate */
    int64_t lost_hits;             /* facing hits whose UV lands on no covered texel */
    double max_distance_mm;        /* over the kept candidates */
    double mean_distance_mm;       /* over the kept candidates (0 when none) */
} dm_thin_map_stats;

typedef struct dm_thin_map {
    int size;      /* N */
    float *texels; /* N × (DM_THIN_MAP_CANDIDATES · N) × 4, rows bottom-up: candidate k of texel
                    * (i, j) at ((k·N + j)·N + i)·4 — (u', v', d mm, 1), heaviest first, or
                    * (0, 0, 0, 0) when the texel has no k-th candidate */
    float *dropped; /* N × N: the weight of the texel's surfaces the map does not hold (0 mostly) */
} dm_thin_map;

/* Bakes the thin-part map of a mesh. DM_ERR_RANGE for bad options, a mesh that is not valid
 * (dm_mesh_validate's code), DM_ERR_OUT_OF_MEMORY, DM_ERR_INTERNAL (Embree). stats may be
 * NULL. Free with dm_thin_map_free (safe on a zeroed map; out is zeroed on failure). */
dm_result dm_thin_map_bake(const dm_mesh *m, const dm_thin_map_options *opt, dm_thin_map *out,
                           dm_thin_map_stats *stats, dm_error *err);
void dm_thin_map_free(dm_thin_map *map);
/* The stats as provenance keys (covered_texels, one_candidate_texels, …, mean_distance_mm):
 * what the pack entry and dermis-bake-thin's EXR both record. */
void dm_thin_map_stats_prov(const dm_thin_map_stats *s, dm_provenance *p);

#ifdef __cplusplus
}
#endif
#endif
