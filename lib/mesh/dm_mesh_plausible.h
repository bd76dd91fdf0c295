/* dm_mesh_plausible.h — checks that catch a silent wrong answer before a bake: a mesh whose
 * faces wind inward (normals pointing into the head), and a mm_per_unit that makes the
 * mesh implausibly small or large for a head (the diffusion widths are in mm). Warnings,
 * not errors: a test mesh may be anything.
 *
 *   char msg[512];
 *   if (dm_mesh_plausible(&mesh, mm_per_unit, path, msg, sizeof msg)) fprintf(stderr, "%s", msg);
 */
#ifndef DM_MESH_PLAUSIBLE_H
#define DM_MESH_PLAUSIBLE_H

#include <stddef.h>

#include "mesh/dm_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Head size the checks accept: the largest side of the mesh's bounding box in mm. A head
 * alone is about 200-250 mm, a bust with shoulders about 450 mm. */
#define DM_MESH_PLAUSIBLE_MIN_MM 50.0
#define DM_MESH_PLAUSIBLE_MAX_MM 1500.0

/* The signed volume enclosed by the triangles about the vertices' centroid, in mesh units³:
 * positive when the faces wind counter-clockwise seen from outside (normals outward), also
 * for a mesh open at the neck. */
double dm_mesh_signed_volume(const dm_mesh *m);
/* The largest side of the bounding box, in mesh units. */
double dm_mesh_extent(const dm_mesh *m);

/* Fills msg with one "warning: ..." line per problem (each naming the fix) and returns how
 * many: inward winding; an extent outside [MIN_MM, MAX_MM] at mm_per_unit. `what` names
 * the mesh in the messages. */
int dm_mesh_plausible(const dm_mesh *m, double mm_per_unit, const char *what, char *msg, size_t msg_size);

#ifdef __cplusplus
}
#endif
#endif
