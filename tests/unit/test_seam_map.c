/* The seam map (bake/dm_seam_map.h): on a flat plate cut into two charts the walked
 * continuation is exact, so every continued gutter texel must land on the other chart's point
 * for it to float precision — also where that chart's texel density changes from triangle to
 * triangle, which extending the first triangle's map across the seam got wrong; and the hard cases of issue #29 point 6 — charts
 * of very different texel density, a mirrored chart, a seam meeting the mesh's boundary,
 * zero-UV-area triangles, a mesh with no seam at all — and the head itself. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_seam_map.h"
#include "mesh/dm_mesh.h"
#include "mesh/dm_seam_edges.h"
#include "mesh/dm_uv_raster.h"
#include "../common/seam_plate.h"

#define HEAD DERMIS_ASSETS "/lps/LeePerrySmith.obj"
enum { N = 256 };
#define REACH 6.0

static void bake_plate(const seam_plate *p, dm_mesh *m, dm_seam_map *map, dm_seam_map_stats *st)
{
    dm_error err = {0};
    seam_plate_mesh(p, m);
    cr_assert_eq(dm_seam_map_bake(m, &(dm_seam_map_options){N, 1.0, REACH}, map, st, &err), DM_OK, "%s", err.detail);
}

/* Every gutter texel beyond the left chart's seam edge and within reach (clear of the plate's
 * top and bottom boundary by a texel) is continued onto the right chart's point for it; every
 * texel beyond the left chart's outer edge (the mesh boundary) is left empty. */
static int check_left_chart(const seam_plate *p, const dm_seam_map *map)
{
    double texel_mm = 1.0 / (N * p->a);
    int checked = 0, beyond_one_cell = 0;
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            double x = ((i + 0.5) / N - 0.05) / p->a, y = ((j + 0.5) / N - 0.1) / p->a;
            const float *px = map->texels + 4 * ((size_t)j * N + i);
            cr_assert(isfinite(px[0]) && isfinite(px[1]) && isfinite(px[2]) && isfinite(px[3]));
            if (!(y > texel_mm && y < SEAM_PLATE_L - texel_mm)) continue;
            if (x < 0 && x > -REACH) cr_assert_eq(px[2], 0.0f, "texel (%d, %d) beyond the boundary is continued", i, j);
            double beyond = x - SEAM_PLATE_L / 2;
            if (!(beyond > 0 && beyond < REACH - texel_mm)) continue;
            cr_assert_eq(px[2], 1.0f, "texel (%d, %d), %.2f mm beyond the seam, not continued", i, j, beyond);
            double uv[2];
            seam_plate_uv_surface(p, 1, x, y, uv);
            cr_assert(fabs(px[0] - uv[0]) < 2e-6 && fabs(px[1] - uv[1]) < 2e-6,
                      "texel (%d, %d): (%.7f, %.7f), the surface is at (%.7f, %.7f)", i, j, px[0], px[1], uv[0], uv[1]);
            cr_assert(fabs(px[3] - beyond) < 1e-4, "distance %.5f mm, expected %.5f", px[3], beyond);
            ++checked;
            beyond_one_cell += beyond > SEAM_PLATE_L / SEAM_PLATE_CELLS;
        }
    cr_assert_gt(checked, 200, "only %d texels checked", checked);
    return beyond_one_cell;
}

/* The same from the right chart back into the left: for a texel beyond the right chart's
 * seam edge, the left chart's point. */
static void check_right_chart(const seam_plate *p, const dm_seam_map *map)
{
    int checked = 0;
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            double u = (i + 0.5) / N, v = (j + 0.5) / N;
            double y = (v - 0.1) / p->b, x = p->mirrored ? SEAM_PLATE_L - (u - 0.55) / p->b : (u - 0.55) / p->b + 20;
            double beyond = SEAM_PLATE_L / 2 - x, texel_mm = 1.0 / (N * p->b);
            if (!(beyond > 0 && beyond < REACH - texel_mm && y > texel_mm && y < SEAM_PLATE_L - texel_mm)) continue;
            const float *px = map->texels + 4 * ((size_t)j * N + i);
            cr_assert_eq(px[2], 1.0f, "right chart: texel (%d, %d) %.2f mm beyond, not continued", i, j, beyond);
            double uv[2];
            seam_plate_uv(p, 0, x, y, uv);
            cr_assert(fabs(px[0] - uv[0]) < 2e-6 && fabs(px[1] - uv[1]) < 2e-6, "right chart: texel (%d, %d)", i, j);
            ++checked;
        }
    cr_assert_gt(checked, 100, "only %d texels checked", checked);
}

Test(seam_map, a_cut_plate_continues_onto_the_other_chart_exactly)
{
    seam_plate p = {.a = 0.01, .b = 0.01};
    dm_mesh m;
    dm_seam_map map;
    dm_seam_map_stats st;
    bake_plate(&p, &m, &map, &st);
    cr_assert_eq(st.cut_edges, SEAM_PLATE_CELLS, "%lld cut edges", (long long)st.cut_edges);
    cr_assert_eq(st.boundary_edges, 4 * SEAM_PLATE_CELLS);
    /* lost: only beyond the seam's ends, where the unfolded point is off the plate */
    cr_assert_lt(st.lost_texels, st.continued_texels / 10);
    cr_assert(st.max_distance_mm <= REACH);
    check_left_chart(&p, &map), check_right_chart(&p, &map);
    dm_seam_map_free(&map), dm_mesh_free(&m);
}

Test(seam_map, charts_of_very_different_texel_density)
{
    seam_plate p = {.a = 0.01, .b = 0.02}; /* the right chart at twice the texels per mm */
    dm_mesh m;
    dm_seam_map map;
    bake_plate(&p, &m, &map, NULL);
    check_left_chart(&p, &map), check_right_chart(&p, &map);
    dm_seam_map_free(&map), dm_mesh_free(&m);
    p.b = 0.004; /* and at 0.4 of them */
    bake_plate(&p, &m, &map, NULL);
    check_left_chart(&p, &map), check_right_chart(&p, &map);
    dm_seam_map_free(&map), dm_mesh_free(&m);
}

/* The right chart's texel density grows along x, triangle column by column (u at the grid's
 * vertices b·(ξ + ξ²/L): 1.125 b per mm over the first column, 1.375 b over the second). A
 * texel more than a column (5 mm) beyond the seam must land where the surface is, in the
 * second column's map: extending the first column's triangle across the seam would put it
 * 0.25 b per mm beyond (2e-3 at 6 mm, half a texel) off. */
Test(seam_map, a_chart_whose_texel_density_varies_is_walked_triangle_by_triangle)
{
    seam_plate p = {.a = 0.01, .b = 0.01, .warp = 1.0};
    dm_mesh m;
    dm_seam_map map;
    dm_seam_map_stats st;
    bake_plate(&p, &m, &map, &st);
    int far = check_left_chart(&p, &map);
    cr_assert_gt(far, 60, "%d texels beyond the first column", far);
    cr_assert_lt(st.lost_texels, st.continued_texels / 10);
    dm_seam_map_free(&map), dm_mesh_free(&m);
}

Test(seam_map, a_mirrored_chart)
{
    seam_plate p = {.a = 0.01, .b = 0.015, .mirrored = 1};
    dm_mesh m;
    dm_seam_map map;
    bake_plate(&p, &m, &map, NULL);
    check_left_chart(&p, &map), check_right_chart(&p, &map);
    dm_seam_map_free(&map), dm_mesh_free(&m);
}

/* The seam's ends meet the plate's boundary: beyond the corner the nearest edge decides,
 * and a texel whose nearest edge is the boundary is left empty (the surface ends). */
Test(seam_map, a_seam_at_the_mesh_boundary)
{
    seam_plate p = {.a = 0.01, .b = 0.01};
    dm_mesh m;
    dm_seam_map map;
    dm_seam_map_stats st;
    bake_plate(&p, &m, &map, &st);
    cr_assert_gt(st.ended_texels, 0);
    /* straight above the seam's top end, beyond the boundary: y > L, x just right of L/2 */
    for (int k = 1; k < 10; ++k) {
        double x = 20.2, y = SEAM_PLATE_L + 0.5 * k, uv[2];
        seam_plate_uv(&p, 0, x, y, uv);
        int i = (int)floor(uv[0] * N), j = (int)floor(uv[1] * N);
        const float *px = map.texels + 4 * ((size_t)j * N + i);
        cr_assert_eq(px[2], 0.0f, "texel %.1f mm beyond the boundary continued", 0.5 * k);
    }
    dm_seam_map_free(&map), dm_mesh_free(&m);
}

Test(seam_map, zero_uv_area_triangles_give_no_continuation_and_no_nan)
{
    seam_plate p = {.a = 0.01, .b = 0.01};
    dm_mesh m;
    seam_plate_mesh(&p, &m);
    /* collapse the right chart's triangles along the seam (column N/2) to a point in UV */
    for (int t = 0; t < m.triangle_count; ++t) {
        int cell = t / 2, i = cell % SEAM_PLATE_CELLS;
        if (i != SEAM_PLATE_CELLS / 2) continue;
        for (int k = 0; k < 3; ++k) m.uvs[(t * 3 + k) * 2] = 0.55f, m.uvs[(t * 3 + k) * 2 + 1] = 0.3f;
    }
    dm_seam_map map;
    dm_seam_map_stats st;
    dm_error err = {0};
    cr_assert_eq(dm_seam_map_bake(&m, &(dm_seam_map_options){N, 1.0, REACH}, &map, &st, &err), DM_OK, "%s", err.detail);
    cr_assert_gt(st.degenerate_sides, 0);
    for (size_t x = 0; x < 4 * (size_t)N * N; ++x) cr_assert(isfinite(map.texels[x]));
    /* every continuation lands on a covered texel */
    int32_t *tri = malloc(sizeof *tri * N * N);
    cr_assert_eq(dm_uv_raster(&m, NULL, N, N, 1, tri, NULL, &err), DM_OK);
    for (size_t x = 0; x < (size_t)N * N; ++x) {
        const float *px = map.texels + 4 * x;
        if (px[2] == 0) continue;
        int i = (int)floor(px[0] * N), j = (int)floor(px[1] * N);
        cr_assert(tri[x] < 0 && tri[(size_t)j * N + i] >= 0);
    }
    free(tri), dm_seam_map_free(&map), dm_mesh_free(&m);
}

/* A triangle of no 3-D area (one corner moved onto the line of the other two; its UVs
 * unchanged) on the walks' way, one column into the right chart: a walk that meets it stops
 * there (no direction to go on in it), counted lost; nothing is NaN and every continuation
 * still lands on a covered texel. */
Test(seam_map, a_walk_meeting_a_triangle_of_no_area_stops)
{
    seam_plate p = {.a = 0.01, .b = 0.01};
    dm_mesh m, plain;
    seam_plate_mesh(&p, &m), seam_plate_mesh(&p, &plain);
    const int c = SEAM_PLATE_CELLS / 2, row = SEAM_PLATE_CELLS + 1; /* cell (c, c): corners (c,c) (c+1,c) (c+1,c+1) */
    float *v = m.positions + 3 * (size_t)(c * row + c + 1), *a = m.positions + 3 * (size_t)(c * row + c),
          *b = m.positions + 3 * (size_t)((c + 1) * row + c + 1);
    for (int k = 0; k < 3; ++k) v[k] = 0.5f * (a[k] + b[k]);
    dm_mesh_compute_normals(&m);
    dm_seam_map map, map0;
    dm_seam_map_stats st, st0;
    dm_error err = {0};
    cr_assert_eq(dm_seam_map_bake(&m, &(dm_seam_map_options){N, 1.0, REACH}, &map, &st, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_seam_map_bake(&plain, &(dm_seam_map_options){N, 1.0, REACH}, &map0, &st0, &err), DM_OK, "%s",
                 err.detail);
    for (size_t x = 0; x < 4 * (size_t)N * N; ++x) cr_assert(isfinite(map.texels[x]));
    cr_assert_gt(st.lost_texels, st0.lost_texels, "%lld lost, %lld without the flat triangle", (long long)st.lost_texels,
                 (long long)st0.lost_texels);
    int32_t *tri = malloc(sizeof *tri * N * N);
    cr_assert_eq(dm_uv_raster(&m, NULL, N, N, 1, tri, NULL, &err), DM_OK);
    for (size_t x = 0; x < (size_t)N * N; ++x) {
        const float *px = map.texels + 4 * x;
        if (px[2] == 0) continue;
        int i = (int)floor(px[0] * N), j = (int)floor(px[1] * N);
        cr_assert(tri[x] < 0 && tri[(size_t)j * N + i] >= 0);
    }
    free(tri), dm_seam_map_free(&map), dm_seam_map_free(&map0), dm_mesh_free(&m), dm_mesh_free(&plain);
}

Test(seam_map, a_mesh_without_seams_gives_an_empty_map)
{
    seam_plate p = {.a = 0.01, .b = 0.01, .uncut = 1};
    dm_mesh m;
    dm_seam_map map;
    dm_seam_map_stats st;
    bake_plate(&p, &m, &map, &st);
    cr_assert_eq(st.cut_edges, 0);
    cr_assert_eq(st.continued_texels, 0);
    float *zero = calloc(4 * (size_t)N * N, sizeof *zero);
    cr_assert_eq(memcmp(zero, map.texels, 4 * sizeof *zero * N * N), 0);
    free(zero), dm_seam_map_free(&map), dm_mesh_free(&m);
}

Test(seam_map, bad_options_are_refused)
{
    seam_plate p = {.a = 0.01, .b = 0.01};
    dm_mesh m;
    seam_plate_mesh(&p, &m);
    dm_seam_map map;
    dm_error err = {0};
    cr_assert_eq(dm_seam_map_bake(&m, &(dm_seam_map_options){0, 1.0, REACH}, &map, NULL, &err), DM_ERR_RANGE);
    cr_assert_eq(dm_seam_map_bake(&m, &(dm_seam_map_options){N, 0, REACH}, &map, NULL, &err), DM_ERR_RANGE);
    cr_assert_eq(dm_seam_map_bake(&m, &(dm_seam_map_options){N, 1.0, NAN}, &map, NULL, &err), DM_ERR_RANGE);
    cr_assert_null(map.texels);
    dm_mesh_free(&m);
}

/* The head: the seams dm_ref_regions counts (375), every continuation on a covered texel of
 * another place of the atlas, the same bytes twice; and its counts pinned (11720 continued,
 * 1025 lost at 512²: extending the first triangle across the seam instead of the walk gave
 * 11341 and 1404). */
Test(seam_map, the_head)
{
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(HEAD, NULL, &m, &err), DM_OK, "%s", err.detail);
    enum { H = 512 };
    dm_seam_map a, b;
    dm_seam_map_stats st;
    dm_seam_map_options o = {H, 50.0, dm_seam_map_reach_mm(7.41)};
    cr_assert_eq(dm_seam_map_bake(&m, &o, &a, &st, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_seam_map_bake(&m, &o, &b, NULL, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(memcmp(a.texels, b.texels, sizeof *a.texels * 4 * H * H), 0);
    cr_assert_eq(st.seam_edges, 375);
    cr_assert_eq(st.boundary_edges, 0);
    cr_assert_eq(st.continued_texels, 11720);
    cr_assert_eq(st.lost_texels, 1025);
    int32_t *tri = malloc(sizeof *tri * H * H);
    cr_assert_eq(dm_uv_raster(&m, NULL, H, H, 1, tri, NULL, &err), DM_OK);
    for (size_t x = 0; x < (size_t)H * H; ++x) {
        const float *px = a.texels + 4 * x;
        cr_assert(isfinite(px[0]) && isfinite(px[1]) && isfinite(px[3]));
        if (px[2] == 0) continue;
        int i = (int)floor(px[0] * H), j = (int)floor(px[1] * H);
        cr_assert(tri[x] < 0 && tri[(size_t)j * H + i] >= 0 && px[3] > 0 && px[3] <= o.reach_mm);
    }
    cr_log_info("head at %d: %lld continued, %lld lost, %lld ended, max %.2f mm", H, (long long)st.continued_texels,
                (long long)st.lost_texels, (long long)st.ended_texels, st.max_distance_mm);
    free(tri), dm_seam_map_free(&a), dm_seam_map_free(&b), dm_mesh_free(&m);
}
