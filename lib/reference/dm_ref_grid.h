/* dm_ref_grid.h — the uniform 3-D grids the ground truth finds triangles and texel
 * elements in (dm_reference.c fills the triangle grid, dm_reference_elements.c the element
 * grid, dm_reference_eval.c walks both). Depends on nothing else in lib/reference. */
#ifndef DM_REF_GRID_H
#define DM_REF_GRID_H

#include <stdint.h>

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
/* The range of cells the box [lo, hi] overlaps, clamped to the grid. */
void dm_ref_grid_box(const dm_ref_grid *g, const double lo[3], const double hi[3], int cell_lo[3], int cell_hi[3]);
/* The index (x fastest, then y, then z) of the cell holding p, clamped to the grid. */
int64_t dm_ref_grid_cell(const dm_ref_grid *g, const double p[3]);
void dm_ref_grid_free(dm_ref_grid *g);

#endif
