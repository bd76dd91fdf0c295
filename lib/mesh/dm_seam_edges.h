/* dm_seam_edges.h — the mesh's UV seams as edges: where the surface goes on but the atlas
 * does not.
 *
 * Positions are welded by exact value first (a GPU mesh split at seams has one vertex per
 * (position, uv, normal)); an edge is a pair of welded positions, and the triangles that
 * have it are its sides. An edge is a seam when
 *   - two triangles have it and give its ends different UVs (a cut of the atlas: the
 *     surface continues in another place of the atlas, or of the same chart), or
 *   - one triangle has it (a mesh boundary: the surface and the atlas both end), or
 *   - three or more triangles have it (non-manifold: no single continuation).
 * Edges whose two ends weld to one position are left out (no length, no side).
 *
 * Each seam edge lists its welded ends and, for a cut, both sides (tri[s], and the corner
 * of tri[s] at which the edge starts: it runs from corner c to corner (c + 1) % 3). For a
 * boundary or a non-manifold edge tri[1] is −1 (tri[0] is the lowest-indexed triangle).
 * Order: by welded ends (a < b), so the list does not depend on the triangle order's
 * accidents beyond the welding; deterministic, no threads.
 *
 * Beside the seams, the welded adjacency of every triangle: adj[3t + c] is the triangle across
 * t's edge from corner c to (c + 1) % 3 when exactly two triangles have that edge (a seam's
 * cut or not), else −1 (a boundary, a non-manifold edge, or an edge of no length): what a walk
 * along the surface crosses (dm_seam_map.h).
 */
#ifndef DM_SEAM_EDGES_H
#define DM_SEAM_EDGES_H

#include <stddef.h>
#include <stdint.h>

#include "core/dm_result.h"
#include "mesh/dm_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_seam_edge {
    uint32_t a, b;     /* welded position indices (each the lowest original index of its weld), a < b */
    int32_t tri[2];    /* its sides; tri[1] = −1 at a boundary or a non-manifold edge */
    int8_t corner[2];  /* the edge runs from corner[s] to (corner[s] + 1) % 3 of tri[s] */
    int32_t sides;     /* triangles that have the edge: 1 boundary, 2 cut, ≥ 3 non-manifold */
} dm_seam_edge;

typedef struct dm_seam_edges {
    dm_seam_edge *edges;
    size_t count;
    int64_t boundary_edges;     /* of them with one side */
    int64_t nonmanifold_edges;  /* of them with three or more */
    uint32_t *weld;             /* vertex_count entries: each vertex's welded index */
    int32_t *adj;               /* 3·triangle_count entries: the triangle across each edge, or −1 */
} dm_seam_edges;

/* Finds the seam edges of a valid mesh. DM_ERR_OUT_OF_MEMORY. Free with dm_seam_edges_free
 * (also after a failure; safe on a zeroed struct). */
dm_result dm_seam_edges_find(const dm_mesh *m, dm_seam_edges *out, dm_error *err);
void dm_seam_edges_free(dm_seam_edges *s);

#ifdef __cplusplus
}
#endif
#endif
