/* dm_raycast.h — ray casting against a triangle mesh, in millimetres: a thin C wrapper over
 * Embree 3 (<embree3/rtcore.h>) for the ground truth (shadow rays, primary rays) and the
 * thin-part bake (bake/dm_thin_map.h: rays through the skin and across folds). It lives in
 * lib/mesh because it needs only the mesh and core, so the bakers below the reference may
 * use it.
 *
 * The mesh is copied into Embree as float positions in mm (mesh units × mm_per_unit); the
 * caller's mesh is not kept. The scene is built with RTC_SCENE_FLAG_ROBUST (watertight
 * edges: a ray through a shared edge or vertex hits one of its triangles, none is missed)
 * on a device limited to one build thread, so the same mesh always gives the same BVH.
 * Queries are independent and read-only: call them from any number of threads at once;
 * a query's answer does not depend on which thread asks or how many there are.
 *
 * Rays: origin in mm, direction any non-zero vector (not normalised by the wrapper: t is
 * in units of |dir|), the segment [t_near, t_far] is searched (t_far may be INFINITY).
 * Positions and directions are rounded to float by Embree: hits are accurate to a few
 * float ulps of the coordinates (about 3e-5 mm on a 250 mm head); callers offset secondary
 * rays by more than that (dm_raycast_epsilon_mm).
 *
 * Front faces are counter-clockwise seen from their front (dm_mesh.h). Closest-hit queries
 * may skip back faces (cull_back), as the renderer's final pass culls them; occlusion
 * queries see both sides, as shadow maps do.
 */
#ifndef DM_RAYCAST_H
#define DM_RAYCAST_H

#include <stdbool.h>
#include <stdint.h>

#include "mesh/dm_mesh.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_raycast dm_raycast;

typedef struct dm_ray_hit {
    int32_t triangle; /* index in the mesh, −1 when nothing was hit */
    float b1, b2;     /* barycentrics of corners 1 and 2 (corner 0 gets 1 − b1 − b2) */
    double t;         /* ray parameter of the hit: P = org + t·dir */
    double ng[3];     /* unit geometric normal of the triangle, front side (counter-clockwise) */
} dm_ray_hit;

/* Builds the scene: positions × mm_per_unit (> 0, finite). mesh must be valid
 * (dm_mesh_validate); triangles of zero area are kept (Embree never hits them).
 * DM_ERR_INTERNAL when Embree fails (its message is in err). Free with dm_raycast_destroy. */
dm_result dm_raycast_create(const dm_mesh *mesh, double mm_per_unit, dm_raycast **out, dm_error *err);
void dm_raycast_destroy(dm_raycast *rc);

/* The closest hit on [t_near, t_far] (t_near ≥ 0, t_far > t_near); cull_back: triangles
 * seen from behind (dir · front normal ≥ 0) are passed through. Returns true and fills hit
 * on a hit; false (hit->triangle = −1) otherwise. */
bool dm_raycast_closest(const dm_raycast *rc, const double org[3], const double dir[3], double t_near,
                        double t_far, bool cull_back, dm_ray_hit *hit);

/* Whether any triangle (either side) is hit on [t_near, t_far]. */
bool dm_raycast_occluded(const dm_raycast *rc, const double org[3], const double dir[3], double t_near,
                         double t_far);

/* A scale-aware offset for secondary rays, mm: 1e-5 × the mesh's bounding-box diagonal,
 * and never below 64 float ulps of its largest coordinate (2.5 mm of a 250 mm head would be
 * far too much; 1e-5 of it, 2.5 µm, is well above float rounding and well below any
 * feature the scene resolves). */
double dm_raycast_epsilon_mm(const dm_raycast *rc);

/* The mesh's bounding sphere in mm as the renderer computes it (centre of the box, radius
 * to the farthest vertex); for near/far planes. */
void dm_raycast_bounds(const dm_raycast *rc, double centre_mm[3], double *radius_mm);

#ifdef __cplusplus
}
#endif
#endif
