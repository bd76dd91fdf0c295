/* dm_reference_impl.h — internals shared by the ground truth's files (dm_reference*.c):
 * the reference object over its grids (dm_ref_grid.h) and its irradiance lookup
 * (dm_ref_lookup.h). Not a public API. */
#ifndef DM_REFERENCE_IMPL_H
#define DM_REFERENCE_IMPL_H

#include <stddef.h>
#include <stdint.h>

#include "reference/dm_ref_grid.h"
#include "reference/dm_ref_lookup.h"
#include "reference/dm_reference.h"

/* Wide-Gaussian sources: pieces of triangles clipped to texel cells. */
typedef struct dm_ref_element {
    float pos[3];  /* centroid, mm */
    float flux[3]; /* I at the centroid × area (mm²) */
} dm_ref_element;

/* A group of Gaussians evaluated on one point set. */
typedef struct dm_ref_group {
    int first, count;  /* kernel indices */
    double spacing_mm; /* narrow: sub-triangle edge; wide: 0 (texel elements) */
    double radius_mm;  /* cut · σ of the widest in the group */
} dm_ref_group;

struct dm_reference {
    const dm_mesh *mesh;
    dm_reference_atlas atlas;
    dm_ref_lookup lookup;
    dm_reference_kernel kernel;
    dm_reference_options opt;
    double cut_sigma, spacing_sigma, wide_texels, tail_fraction; /* resolved options */
    double *pos_mm;     /* vertex_count * 3 */
    double lo_mm[3], hi_mm[3]; /* the bounds of pos_mm */
    double *tri_area;   /* triangle_count, mm² */
    double *tri_edge;   /* triangle_count: longest edge, mm */
    dm_ref_grid tri_grid;
    int group_count;
    dm_ref_group group[DM_REFERENCE_GAUSSIANS_MAX];
    int wide_group; /* index into group[] or −1 */
    dm_ref_element *element;
    int64_t element_count;
    dm_ref_grid element_grid;
    dm_reference_stats stats;
};

/* Texel elements and their grid (dm_reference_elements.c). */
dm_result dm_ref_build_elements(dm_reference *ref, dm_error *err);

#endif
