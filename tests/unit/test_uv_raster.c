/* The UV rasterizer's fill rule (shared edges through texel centres covered once, the
 * same on any thread count) and the gutter fill (mesh/dm_uv_raster.h, mesh/dm_gutter.h),
 * which the stretch baker stands on. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/dm_gutter.h"
#include "mesh/dm_mesh.h"
#include "mesh/dm_uv_raster.h"

#define HEAD DERMIS_ASSETS "/lps/LeePerrySmith.obj"

/* ---- the rasterizer --------------------------------------------------------------- */

Test(stretch, raster_shared_edges_through_texel_centres_cover_once)
{
    /* A 6×6-cell grid whose vertices sit exactly on texel centres of a 13×13 texture
     * (every other centre), some cells mirrored: diagonals, cell edges and vertices all
     * pass through centres. Every centre strictly inside the union is covered once;
     * on the outer border, left and bottom edges are in, right and top out. */
    enum { W = 13, CELLS = 6 };
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_alloc(1, 2 * CELLS * CELLS, &m, &err), DM_OK);
    int t = 0;
    for (int j = 0; j < CELLS; ++j)
        for (int i = 0; i < CELLS; ++i) {
            int x0 = 2 * i, y0 = 2 * j; /* texel indices of the cell's corner centres */
            int flip = (i + j) % 3 == 0; /* other diagonal: also a mirrored-order triangle */
            int c[2][3][2] = {{{0, 0}, {2, 0}, {2, 2}}, {{0, 0}, {2, 2}, {0, 2}}};
            int cf[2][3][2] = {{{0, 0}, {0, 2}, {2, 0}}, {{2, 0}, {0, 2}, {2, 2}}}; /* clockwise */
            for (int h = 0; h < 2; ++h, ++t)
                for (int k = 0; k < 3; ++k) {
                    const int *q = flip ? cf[h][k] : c[h][k];
                    m.uvs[(t * 3 + k) * 2] = (float)((x0 + q[0] + 0.5) / W);
                    m.uvs[(t * 3 + k) * 2 + 1] = (float)((y0 + q[1] + 0.5) / W);
                }
        }
    int32_t ids[W * W];
    dm_uv_raster_stats st;
    cr_assert_eq(dm_uv_raster(&m, NULL, W, W, 2, ids, &st, &err), DM_OK);
    cr_assert_eq(st.overlap_texels, 0, "an edge covered twice");
    for (int y = 0; y < W; ++y)
        for (int x = 0; x < W; ++x) {
            int inside = x <= 11 && y <= 11 && x >= 0 && y >= 0; /* [0, 12) × [0, 12) */
            cr_assert_eq(ids[y * W + x] >= 0, inside, "texel (%d, %d)", x, y);
        }
    cr_assert_eq(st.covered_texels, 12 * 12);
    dm_mesh_free(&m);
}

Test(stretch, raster_is_the_same_on_any_thread_count)
{
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(HEAD, NULL, &m, &err), DM_OK, "%s", err.detail);
    enum { W = 256 };
    int32_t *a = malloc(W * W * sizeof *a), *b = malloc(W * W * sizeof *b);
    dm_uv_raster_stats sa, sb;
    cr_assert_eq(dm_uv_raster(&m, NULL, W, W, 1, a, &sa, &err), DM_OK);
    cr_assert_eq(dm_uv_raster(&m, NULL, W, W, 3, b, &sb, &err), DM_OK);
    cr_assert_eq(memcmp(a, b, W * W * sizeof *a), 0);
    cr_assert_eq(sa.overlap_texels, sb.overlap_texels);
    free(a);
    free(b);
    dm_mesh_free(&m);
}

/* ---- gutters ---------------------------------------------------------------------- */

Test(stretch, gutter_fill_takes_the_nearest_covered_texel)
{
    /* Brute force: for every uncovered texel, the squared distance to the nearest
     * covered one; the filled value names its source texel, which must be at exactly
     * that distance (integer arithmetic: exact). */
    enum { W = 41, H = 29 };
    uint8_t cov[W * H] = {0};
    float val[W * H];
    uint32_t x = 5;
    for (int i = 0; i < W * H; ++i) {
        x = x * 1664525u + 1013904223u;
        cov[i] = (x >> 24) < 6; /* ~2 % covered */
        val[i] = cov[i] ? (float)i : -1.0f;
    }
    cov[0] = 1, val[0] = 0.0f;
    float *planes[1] = {val};
    dm_gutter_stats st;
    dm_error err = {0};
    cr_assert_eq(dm_gutter_fill(cov, W, H, planes, 1, 2, &st, &err), DM_OK);
    long long max_d2 = 0;
    for (int i = 0; i < W * H; ++i) {
        if (cov[i]) {
            cr_assert_eq(val[i], (float)i);
            continue;
        }
        long long best = -1;
        for (int k = 0; k < W * H; ++k)
            if (cov[k]) {
                long long dx = i % W - k % W, dy = i / W - k / W, d2 = dx * dx + dy * dy;
                if (best < 0 || d2 < best) best = d2;
            }
        int src = (int)val[i];
        cr_assert(src >= 0 && cov[src], "texel %d filled with %g, not a covered texel", i, val[i]);
        long long dx = i % W - src % W, dy = i / W - src / W;
        cr_assert_eq(dx * dx + dy * dy, best, "texel %d: source at d2 %lld, nearest at %lld", i, dx * dx + dy * dy,
                     best);
        if (best > max_d2) max_d2 = best;
    }
    cr_assert_float_eq(st.max_distance_texels, sqrt((double)max_d2), 1e-12);
}

Test(stretch, gutter_fill_refuses_an_empty_mask)
{
    uint8_t cov[16] = {0};
    float v[16];
    float *planes[1] = {v};
    dm_error err = {0};
    cr_assert_eq(dm_gutter_fill(cov, 4, 4, planes, 1, 1, NULL, &err), DM_ERR_EMPTY);
}
