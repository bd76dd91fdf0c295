/* seam_plate.h — a flat plate cut into two UV charts along x = L/2 (the seam), the
 * continuation exact: the plate is flat, so the point beyond one chart's edge, walked across
 * the seam, is the other chart's point. Options: the right chart mirrored, at another texel
 * density, warped (its texel density varying along x from triangle to triangle), or not cut
 * at all (one chart, no seam). */
#ifndef TEST_SEAM_PLATE_H
#define TEST_SEAM_PLATE_H

#include <criterion/criterion.h>
#include <math.h>

#include "mesh/dm_mesh.h"

enum { SEAM_PLATE_CELLS = 8 };
#define SEAM_PLATE_L 40.0 /* mm (mm_per_unit 1) */

typedef struct seam_plate {
    double a, b;   /* UV units per mm of the left and the right chart */
    int mirrored;  /* the right chart flipped along u */
    int uncut;     /* one chart: the right half continues the left's map */
    double warp;   /* the right chart's u at the grid's vertices: b·(ξ + warp·ξ²/L), ξ = x − L/2 */
} seam_plate;

/* UV of plate point (x, y) in mm on chart `right` (0: x ≤ L/2, 1: x ≥ L/2). */
static inline void seam_plate_uv(const seam_plate *p, int right, double x, double y, double uv[2])
{
    if (!right || p->uncut) {
        uv[0] = 0.05 + p->a * x, uv[1] = 0.1 + p->a * y;
        return;
    }
    double h = SEAM_PLATE_L / 2, xi = x - h;
    uv[0] = p->mirrored ? 0.55 + p->b * (SEAM_PLATE_L - x) : 0.55 + p->b * (xi + p->warp * xi * xi / SEAM_PLATE_L);
    uv[1] = 0.1 + p->b * y;
}

/* The UV the mesh gives plate point (x, y) on chart `right`: seam_plate_uv at the corners of
 * the triangle holding the point, interpolated (the same as seam_plate_uv unless warped). */
static inline void seam_plate_uv_surface(const seam_plate *p, int right, double x, double y, double uv[2])
{
    double step = SEAM_PLATE_L / SEAM_PLATE_CELLS;
    int i = (int)floor(x / step), j = (int)floor(y / step);
    i = i < 0 ? 0 : i >= SEAM_PLATE_CELLS ? SEAM_PLATE_CELLS - 1 : i;
    j = j < 0 ? 0 : j >= SEAM_PLATE_CELLS ? SEAM_PLATE_CELLS - 1 : j;
    double fx = x / step - i, fy = y / step - j, c[3][2], w[3];
    if (fx >= fy) /* (0,0), (1,0), (1,1) */
        c[0][0] = i, c[0][1] = j, c[1][0] = i + 1, c[1][1] = j, c[2][0] = i + 1, c[2][1] = j + 1, w[0] = 1 - fx,
        w[1] = fx - fy, w[2] = fy;
    else /* (0,0), (1,1), (0,1) */
        c[0][0] = i, c[0][1] = j, c[1][0] = i + 1, c[1][1] = j + 1, c[2][0] = i, c[2][1] = j + 1, w[0] = 1 - fy,
        w[1] = fx, w[2] = fy - fx;
    uv[0] = uv[1] = 0;
    for (int k = 0; k < 3; ++k) {
        double q[2];
        seam_plate_uv(p, right, c[k][0] * step, c[k][1] * step, q);
        uv[0] += w[k] * q[0], uv[1] += w[k] * q[1];
    }
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
