/* thin_sheet.h — a thin sheet: two parallel square plates s mm apart, back to back (the top at
 * z = 0 facing +z, the bottom at z = −s facing −z), each its own UV chart at the same texel
 * density, so the point straight across from every texel is known exactly: the sheet's
 * thin-part map (bake/dm_thin_map.h) in closed form. The renderer tests put it in the assets
 * by hand; the bake's tests hold the baked map to it. */
#ifndef TEST_THIN_SHEET_H
#define TEST_THIN_SHEET_H

#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>

#include "mesh/dm_mesh.h"

enum { THIN_SHEET_CELLS = 8 };
#define THIN_SHEET_L 40.0   /* mm (mm_per_unit 1) */

/* UV of sheet point (x, y) mm on side `bottom`: the top chart u in [0.05, 0.45], the bottom
 * one u in [0.55, 0.95], v in [0.1, 0.5] on both (0.01 UV per mm). */
static inline void thin_sheet_uv(int bottom, double x, double y, double uv[2])
{
    uv[0] = (bottom ? 0.55 : 0.05) + 0.01 * x, uv[1] = 0.1 + 0.01 * y;
}

/* The sheet as a mesh (corners per triangle, one position per grid vertex and side). */
static inline void thin_sheet_mesh(double s_mm, dm_mesh *m)
{
    enum { N = THIN_SHEET_CELLS, V = (N + 1) * (N + 1) };
    dm_error err = {0};
    cr_assert_eq(dm_mesh_alloc(2 * V, 4 * N * N, m, &err), DM_OK);
    double step = THIN_SHEET_L / N;
    for (int side = 0; side < 2; ++side)
        for (int j = 0; j <= N; ++j)
            for (int i = 0; i <= N; ++i) {
                float *q = m->positions + (side * V + j * (N + 1) + i) * 3;
                q[0] = (float)(i * step), q[1] = (float)(j * step), q[2] = side ? (float)-s_mm : 0.0f;
            }
    int t = 0;
    for (int side = 0; side < 2; ++side)
        for (int j = 0; j < N; ++j)
            for (int i = 0; i < N; ++i) {
                /* counter-clockwise seen from +z on top, from −z on the bottom */
                const int up[2][3][2] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
                const int down[2][3][2] = {{{0, 0}, {1, 1}, {1, 0}}, {{0, 0}, {0, 1}, {1, 1}}};
                for (int h = 0; h < 2; ++h, ++t)
                    for (int k = 0; k < 3; ++k) {
                        const int *c = side ? down[h][k] : up[h][k];
                        int ii = i + c[0], jj = j + c[1];
                        m->indices[t * 3 + k] = (uint32_t)(side * V + jj * (N + 1) + ii);
                        double uv[2];
                        thin_sheet_uv(side, ii * step, jj * step, uv);
                        m->uvs[(t * 3 + k) * 2] = (float)uv[0], m->uvs[(t * 3 + k) * 2 + 1] = (float)uv[1];
                    }
            }
    dm_mesh_compute_normals(m);
}

/* The sheet's thin-part map at n × n texels (RGBA, n × 2n: layer 0 the candidate straight
 * across, layer 1 empty): every texel centre on a chart gets (u', v', s, 1). malloc'd. */
static inline float *thin_sheet_map(double s_mm, int n)
{
    float *map = calloc((size_t)4 * n * 2 * n, sizeof(float));
    cr_assert_not_null(map);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double u = (i + 0.5) / n, v = (j + 0.5) / n, y = (v - 0.1) / 0.01;
            int bottom = u > 0.5;
            double x = (u - (bottom ? 0.55 : 0.05)) / 0.01, uv[2];
            if (!(x >= 0 && x <= THIN_SHEET_L && y >= 0 && y <= THIN_SHEET_L)) continue;
            thin_sheet_uv(!bottom, x, y, uv);
            float *c = map + 4 * ((size_t)j * n + i);
            c[0] = (float)uv[0], c[1] = (float)uv[1], c[2] = (float)s_mm, c[3] = 1.0f;
        }
    return map;
}

#endif
