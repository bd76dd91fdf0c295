/* dm_reference_impl.h — internals shared by the ground truth's files (dm_reference*.c):
 * the uniform grids, the irradiance lookup and the reference object. Not a public API. */
#ifndef DM_REFERENCE_IMPL_H
#define DM_REFERENCE_IMPL_H

#include <stddef.h>
#include <stdint.h>

#include "reference/dm_reference.h"

/* A uniform 3-D grid of items in CSR form: the items of cell c are
 * item[start[c] .. start[c + 1]). Cells are cubes of edge cell_mm from origin. */
typedef struct dm_ref_grid {
    double origin[3], cell_mm;
    int dim[3];
    int64_t *start; /* dim[0]*dim[1]*dim[2] + 1 */
    int32_t *item;
} dm_ref_grid;

/* Sets origin, cell size and dims for the box [lo, hi] and cells of about cell_mm (grown
 * until there are at most 2^21 cells); allocates nothing. */
void dm_ref_grid_init(dm_ref_grid *g, const double lo[3], const double hi[3], double cell_mm);
/* The range of cells a sphere (centre p, radius r) overlaps, clamped to the grid. */
void dm_ref_grid_range(const dm_ref_grid *g, const double p[3], double r, int lo[3], int hi[3]);
void dm_ref_grid_free(dm_ref_grid *g);

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

/* The atlas premultiplied by its coverage (r·α, g·α, b·α, α, α clamped to [0, 1],
 * non-finite values 0), so a lookup is one weighted sum and one division. */
typedef struct dm_ref_lookup {
    int width, height;
    float *texel; /* width*height*4 */
} dm_ref_lookup;

dm_result dm_ref_premultiply(const dm_reference_atlas *a, dm_ref_lookup *out, dm_error *err);

struct dm_reference {
    const dm_mesh *mesh;
    dm_reference_atlas atlas;
    dm_ref_lookup lookup;
    dm_reference_kernel kernel;
    dm_reference_options opt;
    double cut_sigma, spacing_sigma, wide_texels, tail_fraction; /* resolved options */
    double *pos_mm;     /* vertex_count * 3 */
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

/* The nearest covered texel within 2 texels of texel position (x, y) (rgb 0 and 0 returned
 * when there is none). */
int dm_ref_sample_nearest(const dm_ref_lookup *a, double x, double y, double rgb[3]);

/* I at (u, v): bilinear over covered texels, renormalised; nearest covered texel within
 * 2 texels when none of the 2×2 is covered. Returns 0 (and zero rgb) when none is near,
 * 1 otherwise. Inline: it is most of the evaluation's time. */
static inline __attribute__((always_inline)) int dm_ref_sample(const dm_ref_lookup *a, double u, double v, double rgb[3])
{
    double x = u * a->width - 0.5, y = v * a->height - 0.5;
    if (!(x > -1.0)) x = -1.0; /* also NaN */
    if (!(y > -1.0)) y = -1.0;
    if (x > a->width) x = a->width;
    if (y > a->height) y = a->height;
    int i0 = (int)(x + 1.0) - 1, j0 = (int)(y + 1.0) - 1; /* floor for x ≥ −1 */
    double fx = x - i0, fy = y - j0;
    int i1 = i0 + 1, j1 = j0 + 1;
    /* clamp to edge, as the renderer's textures */
    if (i0 < 0) i0 = 0;
    if (j0 < 0) j0 = 0;
    if (i1 >= a->width) i1 = a->width - 1;
    if (j1 >= a->height) j1 = a->height - 1;
    const float *t00 = a->texel + 4 * ((size_t)j0 * a->width + i0), *t10 = a->texel + 4 * ((size_t)j0 * a->width + i1);
    const float *t01 = a->texel + 4 * ((size_t)j1 * a->width + i0), *t11 = a->texel + 4 * ((size_t)j1 * a->width + i1);
    double w00 = (1.0 - fx) * (1.0 - fy), w10 = fx * (1.0 - fy), w01 = (1.0 - fx) * fy, w11 = fx * fy;
    double al = w00 * t00[3] + w10 * t10[3] + w01 * t01[3] + w11 * t11[3];
    if (al > 1e-12) {
        double inv = al == 1.0 ? 1.0 : 1.0 / al; /* inside a chart: no division */
        for (int c = 0; c < 3; ++c) rgb[c] = (w00 * t00[c] + w10 * t10[c] + w01 * t01[c] + w11 * t11[c]) * inv;
        return 1;
    }
    return dm_ref_sample_nearest(a, x, y, rgb);
}


/* Texel elements and their grid (dm_reference_elements.c). */
dm_result dm_ref_build_elements(dm_reference *ref, dm_error *err);

#endif
