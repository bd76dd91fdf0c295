/* dm_seam_map.h — where the surface continues beyond a UV chart's edge: the seam map that
 * lets texture-space diffusion blur across UV seams (issue #29, point 1).
 *
 * The irradiance atlas ends at each chart's edge; the surface does not. A blur tap that
 * leaves a chart reads the gutter, which today drops out (coverage 0, the kernel
 * renormalised over the chart): light never crosses a seam. The seam map gives each gutter
 * texel that a blur can reach from a chart the point of the surface it stands for: the
 * chart's own parametrisation extended across its edge, unfolded onto the neighbouring
 * triangle on the other side of the seam, and looked up in that triangle's UVs (which may be
 * another chart, a mirrored one, one of another texel density, or the same chart elsewhere).
 * The runtime lights that point there (irradiance.glsl, DM_SEAM) with coverage 1, so every
 * blur level, on the GL and the CPU path alike, reads the continued surface.
 *
 * Per gutter texel g (centre ((i+½)/N, (j+½)/N), rows bottom-up as dm_uv_raster.h):
 *  1. For every side of every cut seam edge (dm_seam_edges.h, two sides each), triangle A
 *     of that side with the edge P0→P1 and third corner P2: A's affine map UV → 3-D (mm)
 *     extended to g gives P_g in A's plane. g is beyond the edge when its barycentric of
 *     P2 is < 0. Its distance to the edge segment, in mm, is the candidate's rank.
 *  2. Continuing: t = (P_g − P0)·E/|E|², d = |P_g − P0 − tE| (E = P1 − P0). From the edge
 *     point at t (clamped a hair inside the edge) the offset (t − t_c)E + d·n_B, n_B the unit
 *     vector in the other side's triangle B, normal to E, pointing into B, is walked on the
 *     surface: a straight line in B, and across each edge it meets into the triangle on the
 *     other side (dm_seam_edges.adj, whatever its chart), turned about that edge into its
 *     plane — the straightest geodesic, exact for a developable surface, however many
 *     triangles the reach spans and however their texel density varies. UV' is the end
 *     triangle's UVs at the end point. A walk that meets a boundary or non-manifold edge, or
 *     ends on a triangle with no UV area, leaves g empty and is counted as lost.
 *  3. The nearest candidate (mm) within reach_mm wins (ties: the edge listed first); a
 *     boundary or non-manifold edge's side competes too and, when nearest or tied (1e-9
 *     relative: beyond a seam's end where it meets the boundary), leaves g empty (the
 *     surface ends there). A winning continuation whose UV' lands on an uncovered texel
 *     (or outside [0, 1)²) leaves g empty and is counted.
 * Covered texels are never written. A zero-UV-area triangle on the chart's side, or a B
 * with no height over the edge, gives no continuation and is counted; the walk crosses
 * zero-UV-area triangles (3-D alone). Each texel: (u', v', 1, d mm) when continued, else
 * (0, 0, 0, 0). Deterministic, no threads (tens of ms for the head at 1024²).
 */
#ifndef DM_SEAM_MAP_H
#define DM_SEAM_MAP_H

#include <stdint.h>

#include "core/dm_prov.h"
#include "core/dm_result.h"
#include "mesh/dm_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_SEAM_MAP_SIZE_DEFAULT = 1024, DM_SEAM_MAP_SIZE_MAX = 16384 };

typedef struct dm_seam_map_options {
    int size;            /* texels along u and v, 1..DM_SEAM_MAP_SIZE_MAX */
    double mm_per_unit;  /* > 0 */
    double reach_mm;     /* > 0: how far beyond an edge a blur reads (3 σ of the profile's widest Gaussian) */
} dm_seam_map_options;

typedef struct dm_seam_map_stats {
    int64_t seam_edges;         /* dm_seam_edges.h */
    int64_t cut_edges;          /* with two sides: a continuation exists */
    int64_t boundary_edges;     /* one side: the surface ends */
    int64_t nonmanifold_edges;
    int64_t degenerate_sides;   /* a side whose triangle has no UV area, or whose B has no height */
    int64_t continued_texels;   /* gutter texels given a continuation */
    int64_t lost_texels;        /* nearest continuation left the mesh or landed outside every chart */
    int64_t ended_texels;       /* nearest edge is a boundary / non-manifold: left empty */
    double max_distance_mm;     /* farthest continued texel beyond its edge */
} dm_seam_map_stats;

typedef struct dm_seam_map {
    int size;
    float *texels; /* size·size·4: u', v', continued (0/1), distance beyond the edge (mm) */
} dm_seam_map;

/* Bakes the seam map of a valid mesh. DM_ERR_RANGE for bad options, DM_ERR_OUT_OF_MEMORY.
 * stats may be NULL. Free with dm_seam_map_free (safe on a zeroed map). */
dm_result dm_seam_map_bake(const dm_mesh *m, const dm_seam_map_options *opt, dm_seam_map *out,
                           dm_seam_map_stats *stats, dm_error *err);
void dm_seam_map_free(dm_seam_map *map);
/* The stats as provenance keys (seam_edges, cut_edges, …, max_distance_mm): what the pack
 * entry and dermis-bake-seams's EXR both record. */
void dm_seam_map_stats_prov(const dm_seam_map_stats *s, dm_provenance *p);

/* 3·√(largest variance) in mm: where a Gaussian's weight beyond is < 0.3 %. */
double dm_seam_map_reach_mm(double largest_variance_mm2);

#ifdef __cplusplus
}
#endif
#endif
