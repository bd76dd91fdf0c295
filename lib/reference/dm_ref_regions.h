/* dm_ref_regions.h — where on the skin an error is measured, from the geometry alone, and
 * the area-weighted error statistics the accuracy report gives per region.
 *
 * REGIONS. Every surface point gets one label (the first that applies, in this order):
 *   seam   — within seam_mm (default 3 mm, 3-D distance) of a seam edge: an edge whose two
 *            triangles give its ends different UVs, an edge only one triangle has (a mesh
 *            boundary is the edge of a UV chart too: the atlas ends there), or an edge of
 *            three or more triangles. Positions are welded by exact value first (a GPU
 *            mesh split at seams has one vertex per (position, uv, normal)).
 *   thin   — thin parts and folds: some triangle whose geometric normal faces the opposite
 *            way (n_x · n_y < 0, n_x the geometric normal of the point's own triangle) lies
 *            within thin_mm (default 5 mm, 3-D distance to the closest point of the
 *            triangle; a point of a zero-area triangle takes its interpolated corner
 *            normals). This catches both what texture-space diffusion cannot reach: the
 *            far side of a thin part (ear, nostril wall, eyelid rim: the back face is a
 *            few mm behind) and the other side of a fold (the other lip, the eyelid over
 *            the eyeball, the crease behind the ear), whose surfaces face each other. A ray
 *            along −n would find the first kind only (the other lip is not behind the
 *            lip's own normal). 5 mm is ~1.8 σ of the widest skin Gaussian (7.41 mm²):
 *            light from a surface farther away carries < 20 % of that Gaussian's weight.
 *            A convex bump is thin when its radius is < thin_mm / √2 (3.5 mm): ear rims
 *            and nostril rims are, cheeks and the nose's bridge are not.
 *   smooth — the rest.
 *
 * AREA. A texel of an N×M atlas stands for the surface area its UV cell maps to:
 * area_mm2 = (3-D area of its triangle in mm²) / (UV area of the triangle) / (N·M).
 *
 * ERROR STATISTICS (dm_ref_error_stats_compute). Per channel c over the texels (or
 * pixels) compared — both alphas ≥ 0.5, weight > 0, the label asked for —
 *   rel = |render − ref| / max(ref, floor_c),  floor_c = DM_REF_ERROR_FLOOR × the weighted
 *   mean of ref_c over them (as dm_render_refcmp, so near-black texels do not dominate);
 * mean = Σ w rel / Σ w, p95 = the smallest rel such that the texels at or below it carry
 * ≥ 95 % of Σ w (weighted nearest rank), max. With weight = area_mm2 these are
 * area-weighted; with weight NULL every texel counts once (frame pixels: screen area).
 *
 * Units: mesh positions in mesh units × mm_per_unit = mm. Determinism: no threads, no
 * order-dependent sums beyond a fixed loop order.
 */
#ifndef DM_REF_REGIONS_H
#define DM_REF_REGIONS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "mesh/dm_mesh.h"
#include "reference/dm_reference.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum dm_ref_region {
    DM_REF_REGION_SMOOTH = 0,
    DM_REF_REGION_SEAM = 1,
    DM_REF_REGION_THIN = 2,
    DM_REF_REGION_COUNT
} dm_ref_region;

#define DM_REF_ERROR_FLOOR 0.01 /* the floor's fraction of the reference's mean */

const char *dm_ref_region_name(dm_ref_region r); /* "smooth", "seam", "thin" */

typedef struct dm_ref_regions_options {
    double seam_mm; /* 0 = 3; > 0 */
    double thin_mm; /* 0 = 5; > 0 */
} dm_ref_regions_options;

typedef struct dm_ref_regions dm_ref_regions;

typedef struct dm_ref_regions_info {
    int64_t seam_edges;     /* UV-discontinuous, boundary and non-manifold edges */
    int64_t boundary_edges; /* of which edges of one triangle */
    double surface_area_mm2;
} dm_ref_regions_info;

/* Builds the seam segments and the triangle grid of a valid mesh (borrowed for the
 * lifetime of the result). mm_per_unit > 0 and finite; opt may be NULL. DM_ERR_RANGE for
 * a bad mm_per_unit or option, DM_ERR_OUT_OF_MEMORY. Free with dm_ref_regions_destroy. */
dm_result dm_ref_regions_create(const dm_mesh *mesh, double mm_per_unit, const dm_ref_regions_options *opt,
                                dm_ref_regions **out, dm_error *err);
void dm_ref_regions_destroy(dm_ref_regions *r);
void dm_ref_regions_get_info(const dm_ref_regions *r, dm_ref_regions_info *info);

/* The label of the point at barycentrics (b1, b2) of triangle tri (corner 0 gets
 * 1 − b1 − b2), as described above. */
dm_ref_region dm_ref_regions_classify(const dm_ref_regions *r, int32_t tri, double b1, double b2);

/* Per texel of a width×height atlas: label[texel] and area_mm2[texel] for each target
 * (dm_reference_atlas_targets: targets and texel_of, count of each); texels without a
 * target are left as they are (callers clear both arrays first). Triangles of zero UV
 * area give area 0. */
void dm_ref_regions_atlas(const dm_ref_regions *r, int width, int height, const dm_reference_target *targets,
                          const int64_t *texel_of, size_t count, uint8_t *label, float *area_mm2);

typedef struct dm_ref_error_stats {
    long count;           /* texels/pixels compared */
    double weight_sum;    /* Σ w (mm² with area weights) */
    double floor[3], mean[3], p95[3], max[3];
} dm_ref_error_stats;

/* Error of render against ref (both texel_count RGBA floats, the same layout) over the
 * texels whose label equals region (label NULL or region < 0: every texel), weighted by
 * weight (NULL: 1 each). DM_ERR_EMPTY when nothing is compared, DM_ERR_OUT_OF_MEMORY. */
dm_result dm_ref_error_stats_compute(const float *ref, const float *render, const float *weight,
                                     const uint8_t *label, int region, size_t texel_count, dm_ref_error_stats *st,
                                     dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
