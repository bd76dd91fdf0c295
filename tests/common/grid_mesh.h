/* grid_mesh.h — analytic test meshes: a parametric grid with per-triangle corners. */
#ifndef TEST_GRID_MESH_H
#define TEST_GRID_MESH_H

#include <criterion/criterion.h>

#include "mesh/dm_mesh.h"

/* A (nu × nv)-cell grid: P = pos(s, t), UV = uv(s, t) for s, t in [0, 1], two
 * triangles per cell (counter-clockwise in (s, t)); corners are per triangle, so
 * seams need no shared vertices. */
typedef void (*grid_fn)(double s, double t, double out[3]);

static inline void grid_mesh(int nu, int nv, grid_fn pos, grid_fn uv, dm_mesh *m)
{
    dm_error err = {0};
    cr_assert_eq(dm_mesh_alloc((nu + 1) * (nv + 1), 2 * nu * nv, m, &err), DM_OK);
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            double p[3];
            pos((double)i / nu, (double)j / nv, p);
            for (int d = 0; d < 3; ++d) m->positions[(j * (nu + 1) + i) * 3 + d] = (float)p[d];
        }
    int t = 0;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const int c[2][3][2] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
            for (int h = 0; h < 2; ++h, ++t)
                for (int k = 0; k < 3; ++k) {
                    int ii = i + c[h][k][0], jj = j + c[h][k][1];
                    m->indices[t * 3 + k] = (uint32_t)(jj * (nu + 1) + ii);
                    double q[3];
                    uv((double)ii / nu, (double)jj / nv, q);
                    m->uvs[(t * 3 + k) * 2] = (float)q[0];
                    m->uvs[(t * 3 + k) * 2 + 1] = (float)q[1];
                }
        }
    dm_mesh_compute_normals(m);
    cr_assert_eq(dm_mesh_validate(m, "grid", &err), DM_OK, "%s", err.detail);
}

#endif
