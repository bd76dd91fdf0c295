/* dm_curvature.h — mean curvature of a mesh, baked per texel, for pre-integrated skin
 * (dm_preintegrated.h looks its table up by N·L and this curvature).
 *
 * Per vertex, from the geometry once (not from screen derivatives per frame):
 *  1. Weld: vertices within 1e-6 of the bounding box's diagonal of each other (transitively)
 *     are one vertex (glTF and OBJ exports split vertices at UV seams and hard normals, with
 *     copies that may differ in the last bit; curvature must not see a boundary there).
 *  2. The cotangent Laplacian (Meyer, Desbrun, Schröder, Barr, "Discrete Differential-
 *     Geometry Operators for Triangulated 2-Manifolds", 2003):
 *       K_i = 1/(2 A_i) Σ_j (cot α_ij + cot β_ij)(x_i − x_j),   H_i = ½ K_i·n_i
 *     with A_i the mixed Voronoi area and n_i the area-weighted face normal (the mesh's
 *     winding: counter-clockwise seen from outside). Sign: H > 0 on convex surfaces (a
 *     sphere with outward normals has H = +1/R), 0 on a plane, mm⁻¹ (positions × mm_per_unit).
 *  3. Degenerate triangles (area ≤ 1e-12 of the squared longest edge, or two corners
 *     welded together) add nothing. Vertices on a boundary edge (one triangle) or a
 *     non-manifold edge (three or more) have an incomplete ring: they take the mean of
 *     their ring's interior vertices (repeated up to 8 rings inwards; 0 if none).
 *  4. Smoothing over the profile's scale: a Gaussian of σ = smooth_mm (mm) over the
 *     vertices within 3σ in 3D (Euclidean, not geodesic: across a gap thinner than σ, e.g.
 *     the lips, both sides mix), weighted by vertex area. A constant stays constant, so a
 *     sphere stays 1/R and a plane 0.
 * Per texel: the covering triangle (dm_uv_raster.h, so mirrored UVs are ordinary
 * triangles and UV seams are shared-value edges) interpolates its corners' H
 * barycentrically in UV at the texel centre; mask 1. Uncovered texels take the nearest
 * covered texel's value (dm_gutter.h), mask 0. Deterministic for any thread count.
 */
#ifndef DM_CURVATURE_H
#define DM_CURVATURE_H

#include <stdint.h>

#include "mesh/dm_mesh.h"
#include "core/dm_profile.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_CURVATURE_SIZE_DEFAULT = 1024, DM_CURVATURE_SIZE_MAX = 16384 };
#define DM_CURVATURE_SMOOTH_MAX_MM 1e3

typedef struct dm_curvature_stats {
    int32_t welded_vertices;      /* vertices after welding */
    int32_t boundary_vertices;    /* on a boundary or non-manifold edge */
    int32_t degenerate_triangles; /* skipped by the Laplacian */
    int32_t mirrored_triangles;   /* UV winding opposite to the geometry's (counted only) */
    int64_t covered_texels, gutter_texels;
    double coverage;
    double percentile[5]; /* texel curvature over covered texels at 1, 5, 50, 95, 99 % (mm⁻¹) */
    double min, max;
    double vertex_ms, smooth_ms, raster_ms, fill_ms;
} dm_curvature_stats;

/* Per-vertex smoothed mean curvature, mm⁻¹, for the mesh's vertex_count vertices (welded
 * duplicates get the same value). m valid (dm_mesh_validate), mm_per_unit > 0, smooth_mm in
 * [0, DM_CURVATURE_SMOOTH_MAX_MM] (0 = no smoothing). h: caller-owned vertex_count doubles.
 * stats may be NULL (only the vertex fields are filled). DM_ERR_RANGE for bad options,
 * DM_ERR_OUT_OF_MEMORY. */
dm_result dm_curvature_vertices(const dm_mesh *m, double mm_per_unit, double smooth_mm, int thread_count, double *h,
                                dm_curvature_stats *stats, dm_error *err);

typedef struct dm_curvature_options {
    int width, height;  /* 1..DM_CURVATURE_SIZE_MAX; 0 = DM_CURVATURE_SIZE_DEFAULT */
    double mm_per_unit; /* > 0; 0 = 50 (the Lee Perry-Smith head) */
    double smooth_mm;   /* σ, see above; 0 = none (use dm_curvature_profile_scale_mm) */
    int thread_count;   /* 0 = all cores */
} dm_curvature_options;

typedef struct dm_curvature_map {
    int width, height;
    float *curvature; /* width*height, mm⁻¹, rows bottom-up */
    float *mask;      /* width*height, 1 covered, 0 gutter */
    dm_curvature_stats stats;
} dm_curvature_map;

/* Bakes the map. DM_ERR_EMPTY when no triangle covers a texel; others as above. Free with
 * dm_curvature_map_free, also after a failure. */
dm_result dm_curvature_bake(const dm_mesh *m, const dm_curvature_options *opt, dm_curvature_map *out,
                            dm_error *err);
void dm_curvature_map_free(dm_curvature_map *map);

/* The profile's scale for the smoothing: its RMS radius per axis,
 * √(Σ_c Σ_k w_kc v_k / Σ_c Σ_k w_kc) mm (gems3-skin: 0.70 mm). */
double dm_curvature_profile_scale_mm(const dm_profile *p);

#ifdef __cplusplus
}
#endif
#endif
