/* dm_ref_grid.c — the ground truth's uniform 3-D grids (dm_ref_grid.h): their size for a
 * box, and the cells a point, a sphere or a box falls in. */
#include "reference/dm_ref_grid.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { GRID_CELLS_MAX = 1 << 21 };

void dm_ref_grid_init(dm_ref_grid *g, const double lo[3], const double hi[3], double cell_mm)
{
    double ext = 0.0;
    for (int a = 0; a < 3; ++a) ext = fmax(ext, hi[a] - lo[a]);
    if (!(cell_mm > ext * 1e-6)) cell_mm = fmax(ext * 1e-6, DBL_MIN * 1e6);
    for (;;) {
        int64_t n = 1;
        for (int a = 0; a < 3; ++a) {
            double d = floor((hi[a] - lo[a]) / cell_mm) + 1.0;
            g->dim[a] = d > 4096.0 ? 4097 : (int)d;
            n *= g->dim[a];
        }
        if (n <= GRID_CELLS_MAX) break;
        cell_mm *= 1.26;
    }
    for (int a = 0; a < 3; ++a) g->origin[a] = lo[a];
    g->cell_mm = cell_mm;
}

static int cell_coord(const dm_ref_grid *g, int axis, double x)
{
    double c = floor((x - g->origin[axis]) / g->cell_mm);
    if (!(c >= 0.0)) return 0; /* also NaN */
    if (c >= g->dim[axis]) return g->dim[axis] - 1;
    return (int)c;
}

void dm_ref_grid_box(const dm_ref_grid *g, const double lo[3], const double hi[3], int cell_lo[3], int cell_hi[3])
{
    for (int a = 0; a < 3; ++a) {
        cell_lo[a] = cell_coord(g, a, lo[a]);
        cell_hi[a] = cell_coord(g, a, hi[a]);
    }
}

void dm_ref_grid_range(const dm_ref_grid *g, const double p[3], double r, int lo[3], int hi[3])
{
    for (int a = 0; a < 3; ++a) {
        lo[a] = cell_coord(g, a, p[a] - r);
        hi[a] = cell_coord(g, a, p[a] + r);
    }
}

int64_t dm_ref_grid_cell(const dm_ref_grid *g, const double p[3])
{
    int c[3];
    for (int a = 0; a < 3; ++a) c[a] = cell_coord(g, a, p[a]);
    return ((int64_t)c[2] * g->dim[1] + c[1]) * g->dim[0] + c[0];
}

void dm_ref_grid_free(dm_ref_grid *g)
{
    free(g->start);
    free(g->item);
    memset(g, 0, sizeof *g);
}
