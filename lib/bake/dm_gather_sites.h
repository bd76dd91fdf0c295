/* dm_gather_sites.h — the surface as the points of a quadrature, for the thin gather
 * (bake/dm_thin_gather.h): small patches of exact area, each with a 3-D point, a normal and the
 * atlas position its light is read at.
 *
 * Every triangle of 3-D area > 0 is cut into s² congruent sub-triangles of 3-D edge ≤ radius_mm
 * (s ≤ 64), and each is clipped against the atlas's C × C texel cells in UV: exact areas, mapped to
 * mm² by the triangle's Jacobian, each piece a point at its centroid. A triangle of zero UV area
 * (below 1e-6 texel²: clipping anything thinner is rounding) gives its sub-triangles whole, at
 * their UV. The pieces of a cell are grouped in
 * triangle order: a piece joins the first site of its cell and UV island whose first piece lies
 * within radius_mm in 3-D, else it starts one. A site is then the area-weighted mean point, unit
 * normal and UV of its pieces, and their summed area.
 *
 * Why not the texels: a texel's centre stands for its whole square, but where a chart is squashed
 * (a lid's or a lip's inner side pressed into a one-texel band, the neck's coarse charts) a texel
 * is many mm long and its centre may miss the sliver triangles it holds; the texture-space truth
 * (dm_reference.h) integrates the exact surface. On the head at 1024² the texel sum of the widest
 * level's mass is off by 10–14 % within 3 mm of a seam; these sites are within 0.3 %.
 *
 * The light of a site is read at its UV as the renderer's sampler reads level 0 (bilinear,
 * coverage-normalised), as the truth reads it. Where none of the 2 × 2 texels around that UV is
 * covered (a sliver's, a zero-UV-area triangle's) the UV moves to the nearest covered texel's
 * centre within 2 texels, the truth's rule; a site with none is dropped (the truth reads no light
 * there) and its area counted in dropped_mm2, as are clipping's slivers of rounding (pieces below
 * 1e-9 of their sub-triangle, whose centroids mean nothing).
 *
 * Deterministic: one thread, triangles in order. */
#ifndef DM_GATHER_SITES_H
#define DM_GATHER_SITES_H

#include <stdint.h>

#include "core/dm_result.h"
#include "mesh/dm_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_gather_sites {
    int64_t count;
    double *p;          /* 3 a site: the mean point, mm */
    double *nrm;        /* 3 a site: the mean unit normal, normalised (0 where they cancel) */
    double *area;       /* mm² */
    float *uv;          /* 2 a site: where its light is read, in [0, 1] */
    int32_t *island;    /* its UV island (dm_mesh_uv_islands) */
    double dropped_mm2; /* the area of sites with no covered texel near */
} dm_gather_sites;

/* Sites over the n × n atlas, cells of `cell` texels (1..n), grouped within radius_mm (> 0).
 * covered: the n × n triangle per texel of dm_uv_raster (−1: none), rows bottom-up.
 * DM_ERR_OUT_OF_MEMORY; m must be valid. Free with dm_gather_sites_free (safe on a zeroed one). */
dm_result dm_gather_sites_build(const dm_mesh *m, const int32_t *covered, int n, double mm_per_unit, int cell,
                                double radius_mm, dm_gather_sites *out, dm_error *err);
void dm_gather_sites_free(dm_gather_sites *s);

/* Coarser sites made of whole fine ones, for the far part of a Gaussian: the fine sites grouped
 * as above (cells of `cell` texels by their UV, island, radius_mm from the group's first, in the
 * fine sites' order). parent (fine->count) receives each fine site's coarse one; children and
 * child_first (coarse count + 1, malloc'd) list each coarse site's fine ones in order. */
dm_result dm_gather_sites_coarsen(const dm_gather_sites *fine, const int32_t *covered, int n, int cell,
                                  double radius_mm, dm_gather_sites *coarse, int32_t **child_first,
                                  int32_t **children, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
