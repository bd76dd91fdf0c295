/* seam_plate.h — a flat plate cut into two UV charts along x = L/2 (the seam), the
 * continuation exact: both charts are affine, the plate is flat, so the unfolded point
 * beyond one chart's edge is the other chart's point. Options: the right chart mirrored,
 * at another texel density, or not cut at all (one chart, no seam). */
#ifndef TEST_SEAM_PLATE_H
#define TEST_SEAM_PLATE_H

#include <criterion/criterion.h>

#include "mesh/dm_mesh.h"

enum { SEAM_PLATE_CELLS = 8 };
#define SEAM_PLATE_L 40.0 /* mm (mm_per_unit 1) */

typedef struct seam_plate {
    double a, b;   /* UV units per mm of the left and the right chart */
    int mirrored;  /* the right chart flipped along u */
    int uncut;     /* one chart: the right half continues the left's map */
} seam_plate;

/* UV of plate point (x, y) in mm on chart `right` (0: x ≤ L/2, 1: x ≥ L/2). */
static inline void seam_plate_uv(const seam_plate *p, int right, double x, double y, double uv[2])
{
    if (!right || p->uncut) {
        uv[0] = 0.05 + p->a * x, uv[1] = 0.1 + p->a * y;
        return;
    }
    double h = SEAM_PLATE_L / 2;
    uv[0] = p->mirrored ? 0.55 + p->b * (SEAM_PLATE_L - x) : 0.55 + p->b * (x - h);
    uv[1] = 0.1 + p->b * y;
}

/* The plate as a mesh: one position per grid vertex (the seam's welded by value), corners per
 * triangle. */
static inline void seam_plate_mesh(const seam_plate *p, dm_mesh *m)
{
    enum { N = SEAM_PLATE_CELLS };
    dm_error err = {0};
    cr_assert_eq(dm_mesh_alloc((N + 1) * (N + 1), 2 * N * N, m, &err), DM_OK);
    double step = SEAM_PLATE_L / N;
    for (int j = 0; j <= N; ++j)
        for (int i = 0; i <= N; ++i) {
            float *q = m->positions + (j * (N + 1) + i) * 3;
            q[0] = (float)(i * step), q[1] = (float)(j * step), q[2] = 0;
        }
    int t = 0;
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            const int c[2][3][2] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
            int right = i >= N / 2;
            for (int h = 0; h < 2; ++h, ++t)
                for (int k = 0; k < 3; ++k) {
                    int ii = i + c[h][k][0], jj = j + c[h][k][1];
                    m->indices[t * 3 + k] = (uint32_t)(jj * (N + 1) + ii);
                    double uv[2];
                    seam_plate_uv(p, right, ii * step, jj * step, uv);
                    m->uvs[(t * 3 + k) * 2] = (float)uv[0], m->uvs[(t * 3 + k) * 2 + 1] = (float)uv[1];
                }
        }
    dm_mesh_compute_normals(m);
    cr_assert_eq(dm_mesh_validate(m, "seam plate", &err), DM_OK, "%s", err.detail);
}

#endif
