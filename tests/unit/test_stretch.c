/* Stretch maps: the per-triangle Jacobian, the blurred chain, analytic meshes with known
 * answers, degenerate triangles and the Lee Perry-Smith head. The rasterizer and gutters
 * they stand on: test_uv_raster; the tool: test_stretch_tool. */
#define _DEFAULT_SOURCE /* mkstemps */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../common/grid_mesh.h"
#include "mesh/dm_mesh.h"
#include "bake/dm_stretch.h"
#include "core/dm_math.h"

#define HEAD DERMIS_ASSETS "/lps/LeePerrySmith.obj"

/* ---- mesh builders ---------------------------------------------------------------- */

static void uv_identity(double s, double t, double o[3]) { o[0] = s, o[1] = t, o[2] = 0; }
static void uv_mirrored(double s, double t, double o[3]) { o[0] = 1 - s, o[1] = t, o[2] = 0; }
static void quad_2x4(double s, double t, double o[3]) { o[0] = 2 * s, o[1] = 4 * t, o[2] = 0; }

enum { CYL_N = 32 };
#define CYL_R 1.5
#define CYL_H 3.0
static void cylinder(double s, double t, double o[3])
{
    double a = DM_2PI * s;
    o[0] = CYL_R * cos(a), o[1] = CYL_R * sin(a), o[2] = CYL_H * t;
}

#define SPH_R 2.0
static void sphere(double s, double t, double o[3])
{
    double phi = DM_2PI * s, theta = DM_PI * t; /* theta from the south pole */
    o[0] = SPH_R * sin(theta) * cos(phi), o[1] = SPH_R * sin(theta) * sin(phi), o[2] = -SPH_R * cos(theta);
}

static dm_stretch_map bake(const dm_mesh *m, int w, int h, double mm, int levels, int threads)
{
    dm_stretch_options o = {.width = w, .height = h, .mm_per_unit = mm, .level_count = levels, .thread_count = threads};
    dm_stretch_map map;
    dm_error err = {0};
    cr_assert_eq(dm_stretch_bake(m, &o, &map, &err), DM_OK, "%s", err.detail);
    return map;
}

/* ---- the Jacobian ----------------------------------------------------------------- */

Test(stretch, triangle_jacobian_matches_barycentric_difference)
{
    /* Reference: P(uv) through barycentric coordinates (double), differenced over a
     * unit step in u and in v: exact for an affine map, a route independent of the
     * closed form. Tolerance 1e-9 relative: double rounding of ill-conditioned solves. */
    uint32_t x = 99;
    for (int trial = 0; trial < 200; ++trial) {
        dm_mesh m;
        dm_error err = {0};
        cr_assert_eq(dm_mesh_alloc(3, 1, &m, &err), DM_OK);
        for (int k = 0; k < 9; ++k) {
            x = x * 1664525u + 1013904223u;
            m.positions[k] = (float)((x >> 8) / 16777216.0 * 2 - 1);
        }
        for (int k = 0; k < 3; ++k) m.indices[k] = (uint32_t)k;
        for (int k = 0; k < 6; ++k) {
            x = x * 1664525u + 1013904223u;
            m.uvs[k] = (float)((x >> 8) / 16777216.0);
        }
        dm_mesh_compute_normals(&m);
        dm_triangle_stretch ts;
        dm_triangle_stretch_of(&m, 0, 7.0, &ts);
        if (ts.kind != DM_TRIANGLE_OK) {
            dm_mesh_free(&m);
            continue;
        }
        const float *u = m.uvs;
        double T[2][2] = {{(double)u[2] - u[0], (double)u[4] - u[0]}, {(double)u[3] - u[1], (double)u[5] - u[1]}};
        double det = T[0][0] * T[1][1] - T[0][1] * T[1][0];
        cr_assert_eq(ts.mirrored, det < 0);
        double len[2];
        for (int axis = 0; axis < 2; ++axis) {
            /* Barycentric (b1, b2) of uv0 + e_axis: solve T b = e_axis. */
            double e0 = axis == 0, e1 = axis == 1;
            double b1 = (T[1][1] * e0 - T[0][1] * e1) / det, b2 = (-T[1][0] * e0 + T[0][0] * e1) / det;
            double l2 = 0.0;
            for (int d = 0; d < 3; ++d) {
                double p0 = m.positions[d], p1 = m.positions[3 + d], p2 = m.positions[6 + d];
                double step = (b1 * (p1 - p0) + b2 * (p2 - p0)) * 7.0;
                l2 += step * step;
            }
            len[axis] = sqrt(l2);
        }
        cr_assert(fabs(ts.s_u * len[0] - 1.0) < 1e-9, "trial %d: s_u %.17g vs %.17g", trial, ts.s_u, 1 / len[0]);
        cr_assert(fabs(ts.s_v * len[1] - 1.0) < 1e-9, "trial %d: s_v %.17g vs %.17g", trial, ts.s_v, 1 / len[1]);
        dm_mesh_free(&m);
    }
}

Test(stretch, degenerate_triangles_are_classified)
{
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_alloc(3, 1, &m, &err), DM_OK);
    float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    memcpy(m.positions, p, sizeof p);
    for (int k = 0; k < 3; ++k) m.indices[k] = (uint32_t)k;
    float point[6] = {.5f, .5f, .5f, .5f, .5f, .5f}; /* UV island collapsed to a point */
    memcpy(m.uvs, point, sizeof point);
    dm_triangle_stretch ts;
    dm_triangle_stretch_of(&m, 0, 50.0, &ts);
    cr_assert_eq(ts.kind, DM_TRIANGLE_ZERO_UV_AREA);
    float line[6] = {0, 0, .5f, .5f, 1, 1}; /* UVs on a line */
    memcpy(m.uvs, line, sizeof line);
    dm_triangle_stretch_of(&m, 0, 50.0, &ts);
    cr_assert_eq(ts.kind, DM_TRIANGLE_ZERO_UV_AREA);
    float good[6] = {0, 0, 1, 0, 0, 1};
    memcpy(m.uvs, good, sizeof good);
    float collinear[9] = {0, 0, 0, 1, 1, 1, 2, 2, 2}; /* zero surface area */
    memcpy(m.positions, collinear, sizeof collinear);
    dm_triangle_stretch_of(&m, 0, 50.0, &ts);
    cr_assert_eq(ts.kind, DM_TRIANGLE_ZERO_AREA);
    cr_assert_eq(ts.s_u, 0.0);
    memset(m.positions, 0, 9 * sizeof(float)); /* all corners at one point */
    dm_triangle_stretch_of(&m, 0, 50.0, &ts);
    cr_assert_eq(ts.kind, DM_TRIANGLE_ZERO_AREA);
    dm_mesh_free(&m);
}

/* ---- analytic meshes -------------------------------------------------------------- */

Test(stretch, flat_quad_known_scale_is_exact)
{
    /* 2 × 4 units at 10 mm per unit over the whole square: s_u = 1/20, s_v = 1/40 per
     * mm, every texel, every level (a constant blurs to itself: weights sum to 1, so
     * only float rounding of 7 taps × 10 passes, < 1e-6 relative). */
    dm_mesh m;
    grid_mesh(3, 5, quad_2x4, uv_identity, &m);
    dm_stretch_map map = bake(&m, 64, 48, 10.0, 6, 2);
    cr_assert_eq(map.stats.coverage, 1.0);
    cr_assert_eq(map.stats.mirrored_triangles, 0);
    for (int i = 0; i < 64 * 48; ++i) {
        cr_assert_eq(map.mask[i], 1.0f);
        cr_assert_eq(map.s_u[0][i], (float)(1.0 / 20.0));
        cr_assert_eq(map.s_v[0][i], (float)(1.0 / 40.0));
        for (int k = 1; k < 6; ++k) {
            cr_assert(fabs(map.s_u[k][i] * 20.0 - 1.0) < 1e-6);
            cr_assert(fabs(map.s_v[k][i] * 40.0 - 1.0) < 1e-6);
        }
    }
    dm_stretch_map_free(&map);
    dm_mesh_free(&m);
}

Test(stretch, mirrored_quad_has_the_same_stretch)
{
    dm_mesh m;
    grid_mesh(3, 5, quad_2x4, uv_mirrored, &m);
    dm_stretch_map map = bake(&m, 32, 32, 10.0, 1, 1);
    cr_assert_eq(map.stats.mirrored_triangles, 30);
    cr_assert_eq(map.stats.coverage, 1.0);
    cr_assert_eq(map.stats.overlap_texels, 0);
    for (int i = 0; i < 32 * 32; ++i) {
        /* 1e-6 relative: the mirrored UVs 1 − i/3 are rounded to float. */
        cr_assert(fabs(map.s_u[0][i] * 20.0 - 1.0) < 1e-6);
        cr_assert(fabs(map.s_v[0][i] * 40.0 - 1.0) < 1e-6);
    }
    dm_stretch_map_free(&map);
    dm_mesh_free(&m);
}

Test(stretch, cylinder_matches_facets_and_the_smooth_surface)
{
    /* Around: a facet spans Δu = 1/N for a chord 2R·sin(π/N), so exactly
     * s_u = 1/(2NR·sin(π/N)·mm); the smooth cylinder's 1/(2πR·mm) differs by the
     * tessellation, 1 − sin(π/N)/(π/N) ≤ (π/N)²/6 relative. Along: s_v = 1/(H·mm). */
    const double mm = 10.0;
    dm_mesh m;
    grid_mesh(CYL_N, 4, cylinder, uv_identity, &m);
    dm_stretch_map map = bake(&m, 128, 64, mm, 1, 2);
    cr_assert_eq(map.stats.coverage, 1.0);
    double facet = 1.0 / (2.0 * CYL_N * CYL_R * sin(DM_PI / CYL_N) * mm), smooth = 1.0 / (DM_2PI * CYL_R * mm);
    const double a = DM_PI / CYL_N;
    double tess = a * a / 6.0 + a * a * a * a / 20.0; /* a/sin(a) − 1 = a²/6 + 7a⁴/360 + … */
    for (int i = 0; i < 128 * 64; ++i) {
        cr_assert(fabs(map.s_u[0][i] / facet - 1.0) < 1e-6, "texel %d: %.9g vs %.9g", i, map.s_u[0][i], facet);
        cr_assert(fabs(map.s_u[0][i] / smooth - 1.0) <= tess + 1e-6);
        cr_assert(fabs(map.s_v[0][i] * CYL_H * mm - 1.0) < 1e-6);
    }
    dm_stretch_map_free(&map);
    dm_mesh_free(&m);
}

Test(stretch, sphere_matches_the_closed_form_at_texel_centres)
{
    /* Lat-long sphere: s_u = 1/(2πR·sinθ·mm), s_v = 1/(πR·mm). A triangle's u-edge lies
     * on a parallel at most Δθ from the texel centre's θ and its chord is short of the
     * arc by sinc(Δφ/2): the relative error of s_u is at most
     * max(sin θ / sin θ_edge) / sinc(Δφ/2) − 1 over the band's two parallels. Its
     * v-derivative runs along a meridian chord: ≤ Δθ²/24 for s_v. Poles (sin θ < 0.2)
     * are left out of the comparison, not of the finiteness check. The pole rows
     * hold 2·N zero-area triangles (two corners at the pole). */
    enum { NU = 48, NV = 32, W = 192, H = 128 };
    const double mm = 5.0, dth = DM_PI / NV, dph = DM_2PI / NU;
    dm_mesh m;
    grid_mesh(NU, NV, sphere, uv_identity, &m);
    dm_stretch_map map = bake(&m, W, H, mm, 2, 2);
    cr_assert_eq(map.stats.zero_area_triangles, NU * 1 + NU * 1, "got %d", map.stats.zero_area_triangles);
    int compared = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int i = y * W + x;
            for (int k = 0; k < 2; ++k)
                cr_assert(isfinite(map.s_u[k][i]) && map.s_u[k][i] > 0 && isfinite(map.s_v[k][i]) && map.s_v[k][i] > 0);
            double theta = DM_PI * (y + 0.5) / H;
            if (sin(theta) < 0.2 || map.mask[i] == 0.0f) continue;
            double su = 1.0 / (DM_2PI * SPH_R * sin(theta) * mm), sv = 1.0 / (DM_PI * SPH_R * mm);
            double band = floor(theta / dth) * dth, sinc = sin(dph / 2) / (dph / 2);
            double tol_u = fmax(fabs(sin(theta) / (sin(band) * sinc) - 1.0),
                                fabs(sin(theta) / (sin(band + dth) * sinc) - 1.0)) +
                           1e-4; /* float positions: 6e-8·R on chords ≥ 0.02·R, ≤ 1e-5 relative */
            cr_assert(fabs(map.s_u[0][i] / su - 1.0) <= tol_u, "texel (%d, %d): s_u %.6g vs %.6g, tol %.3g", x, y,
                      map.s_u[0][i], su, tol_u);
            cr_assert(fabs(map.s_v[0][i] / sv - 1.0) <= dth * dth / 24 + 1e-6, "texel (%d, %d): s_v %.6g vs %.6g", x,
                      y, map.s_v[0][i], sv);
            ++compared;
        }
    cr_assert_gt(compared, W * H / 2);
    dm_stretch_map_free(&map);
    dm_mesh_free(&m);
}

Test(stretch, cube_cross_unwrap)
{
    /* Unit faces on 1/4 × 1/3 UV cells, 50 mm per unit: s_u = 0.25/50, s_v = (1/3)/50.
     * At 96² the cells' borders fall between texel centres: coverage is exactly half. */
    static const char obj[] =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
        "vt 0 0.3333333333\nvt 0.25 0.3333333333\nvt 0.5 0.3333333333\nvt 0.75 0.3333333333\nvt 1 0.3333333333\n"
        "vt 0 0.6666666667\nvt 0.25 0.6666666667\nvt 0.5 0.6666666667\nvt 0.75 0.6666666667\nvt 1 0.6666666667\n"
        "vt 0.25 1\nvt 0.5 1\nvt 0.25 0\nvt 0.5 0\n"
        "f 1/1 2/2 6/7 5/6\nf 2/2 3/3 7/8 6/7\nf 3/3 4/4 8/9 7/8\nf 4/4 1/5 5/10 8/9\n"
        "f 6/7 7/8 8/12 5/11\nf 1/13 4/14 3/3 2/2\n";
    char path[] = "/tmp/dm_test_cube_XXXXXX.obj";
    int fd = mkstemps(path, 4);
    cr_assert_geq(fd, 0);
    cr_assert_eq(write(fd, obj, sizeof obj - 1), (ssize_t)(sizeof obj - 1));
    close(fd);
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(path, NULL, &m, &err), DM_OK, "%s", err.detail);
    unlink(path);
    dm_stretch_map map = bake(&m, 96, 96, 50.0, 3, 2);
    cr_assert_eq(map.stats.covered_texels, 96 * 96 / 2);
    cr_assert_eq(map.stats.overlap_texels, 0);
    cr_assert_eq(map.stats.uv_islands, 1);
    for (int i = 0; i < 96 * 96; ++i) {
        /* Gutters take the nearest chart texel, and every chart texel has the same value. */
        /* 1e-6 relative: the OBJ's thirds are floats (0.33333334). */
        cr_assert(fabs(map.s_u[0][i] / (0.25 / 50.0) - 1.0) < 1e-6);
        cr_assert(fabs(map.s_v[0][i] / ((1.0 / 3.0) / 50.0) - 1.0) < 1e-6);
    }
    dm_stretch_map_free(&map);
    dm_mesh_free(&m);
}

Test(stretch, zero_area_triangle_texels_are_filled_and_counted)
{
    /* A quad grid with one vertex moved onto its neighbour: the triangles that used
     * both collapse to zero area while keeping their UV area. */
    dm_mesh m;
    grid_mesh(4, 4, quad_2x4, uv_identity, &m);
    int a = 2 * 5 + 2, b = 2 * 5 + 3; /* vertex (2, 2) onto (3, 2) */
    memcpy(m.positions + a * 3, m.positions + b * 3, 3 * sizeof(float));
    int expected = 0;
    for (int t = 0; t < m.triangle_count; ++t) {
        int has_a = 0, has_b = 0;
        for (int c = 0; c < 3; ++c) has_a |= (int)m.indices[t * 3 + c] == a, has_b |= (int)m.indices[t * 3 + c] == b;
        expected += has_a && has_b;
    }
    cr_assert_gt(expected, 0);
    dm_stretch_map map = bake(&m, 64, 64, 10.0, 2, 2);
    cr_assert_eq(map.stats.zero_area_triangles, expected);
    cr_assert_lt(map.stats.coverage, 1.0);
    for (int i = 0; i < 64 * 64; ++i)
        for (int k = 0; k < 2; ++k) cr_assert(isfinite(map.s_u[k][i]) && map.s_u[k][i] > 0);
    dm_stretch_map_free(&map);
    dm_mesh_free(&m);
}

Test(stretch, only_zero_uv_area_triangles_is_an_error)
{
    dm_mesh m;
    grid_mesh(2, 2, quad_2x4, uv_identity, &m);
    for (int k = 0; k < m.triangle_count * 6; ++k) m.uvs[k] = 0.25f;
    dm_stretch_options o = {.width = 32, .height = 32};
    dm_stretch_map map;
    dm_error err = {0};
    cr_assert_eq(dm_stretch_bake(&m, &o, &map, &err), DM_ERR_EMPTY);
    cr_assert(strstr(err.detail, "8 of zero UV area"), "%s", err.detail);
    cr_assert_null(map.s_u[0]);
    dm_mesh_free(&m);
}

Test(stretch, bad_options_are_refused)
{
    dm_mesh m;
    grid_mesh(1, 1, quad_2x4, uv_identity, &m);
    dm_stretch_map map;
    dm_error err = {0};
    dm_stretch_options o = {.level_count = 7};
    cr_assert_eq(dm_stretch_bake(&m, &o, &map, &err), DM_ERR_RANGE);
    cr_assert(strstr(err.detail, "levels = 7"), "%s", err.detail);
    o = (dm_stretch_options){.mm_per_unit = -1};
    cr_assert_eq(dm_stretch_bake(&m, &o, &map, &err), DM_ERR_RANGE);
    o = (dm_stretch_options){.width = DM_STRETCH_SIZE_MAX + 1};
    cr_assert_eq(dm_stretch_bake(&m, &o, &map, &err), DM_ERR_RANGE);
    dm_mesh_free(&m);
}

/* ---- the chain -------------------------------------------------------------------- */

Test(stretch, blur_weights_are_the_chapters_kernel)
{
    double w[DM_STRETCH_TAPS], sum = 0.0;
    dm_stretch_blur_weights(w);
    /* GPU Gems 3 listing 14-5 prints 0.006, 0.061, 0.242, 0.383 (3 decimals). */
    static const double chapter[7] = {0.006, 0.061, 0.242, 0.383, 0.242, 0.061, 0.006};
    for (int i = 0; i < 7; ++i) {
        cr_assert(fabs(w[i] - chapter[i]) < 1e-3, "tap %d: %.4f", i, w[i]);
        cr_assert_eq(w[i], w[6 - i]);
        sum += w[i];
    }
    cr_assert_float_eq(sum, 1.0, 1e-15);
}

static double ref_lerp(const double *p, int n, int stride, double s)
{
    s = dm_clamp(s, 0.0, n - 1);
    int i0 = (int)s, i1 = i0 < n - 1 ? i0 + 1 : i0;
    return p[i0 * stride] + (s - i0) * (p[i1 * stride] - p[i0 * stride]);
}

Test(stretch, chain_level_matches_a_double_reference)
{
    /* One level of the chain recomputed in double from the tool's own base level, by
     * the formula of dm_stretch.h. The bake runs in float: a tap position x + i·step
     * carries ~6e-8 relative rounding, ~1e-5 texel at this size, and at a chart border
     * the base jumps by up to ~10× its value between neighbouring texels: 1e-4
     * relative bounds position rounding times slope, plus the sums' own rounding. */
    enum { W = 96, H = 80 };
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(HEAD, NULL, &m, &err), DM_OK, "%s", err.detail);
    dm_stretch_map map = bake(&m, W, H, 50.0, 3, 2);
    double w[7];
    dm_stretch_blur_weights(w);
    for (int k = 1; k < 3; ++k) {
        double sigma = sqrt(map.variance_mm2[k] - map.variance_mm2[k - 1]);
        double *su = malloc(W * H * sizeof *su), *sv = malloc(W * H * sizeof *sv);
        double *tu = malloc(W * H * sizeof *tu), *tv = malloc(W * H * sizeof *tv);
        for (int i = 0; i < W * H; ++i) su[i] = map.s_u[k - 1][i], sv[i] = map.s_v[k - 1][i];
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                double step = sigma * su[y * W + x] * W, au = 0, av = 0;
                for (int i = -3; i <= 3; ++i) {
                    au += w[i + 3] * ref_lerp(su + y * W, W, 1, x + i * step);
                    av += w[i + 3] * ref_lerp(sv + y * W, W, 1, x + i * step);
                }
                tu[y * W + x] = au, tv[y * W + x] = av;
            }
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                double step = sigma * sv[y * W + x] * H, au = 0, av = 0;
                for (int i = -3; i <= 3; ++i) {
                    au += w[i + 3] * ref_lerp(tu + x, H, W, y + i * step);
                    av += w[i + 3] * ref_lerp(tv + x, H, W, y + i * step);
                }
                int j = y * W + x;
                cr_assert(fabs(map.s_u[k][j] / au - 1.0) < 1e-4, "level %d texel (%d, %d): %.9g vs %.9g", k, x, y,
                          map.s_u[k][j], au);
                cr_assert(fabs(map.s_v[k][j] / av - 1.0) < 1e-4, "level %d texel (%d, %d): %.9g vs %.9g", k, x, y,
                          map.s_v[k][j], av);
            }
        free(su), free(sv), free(tu), free(tv);
    }
    dm_stretch_map_free(&map);
    dm_mesh_free(&m);
}

/* ---- the head --------------------------------------------------------------------- */

static double total_variation(const float *p, int w, int h)
{
    double tv = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (x + 1 < w) tv += fabs((double)p[y * w + x + 1] - p[y * w + x]);
            if (y + 1 < h) tv += fabs((double)p[(y + 1) * w + x] - p[y * w + x]);
        }
    return tv;
}

Test(stretch, lee_perry_smith_head)
{
    enum { S = 512 };
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(HEAD, NULL, &m, &err), DM_OK, "%s", err.detail);
    dm_stretch_map map = bake(&m, S, S, 50.0, 6, 2);
    const dm_stretch_stats *st = &map.stats;
    /* The layout covers 91.7 % of the square (measured at 4096²); 1 % either way. */
    cr_assert(fabs(st->coverage - 0.917) <= 0.01, "coverage %.4f", st->coverage);
    cr_assert_eq(st->zero_uv_area_triangles, 11);
    cr_assert_eq(st->zero_area_triangles, 0);
    cr_assert_eq(st->mirrored_triangles, 662);
    for (int k = 0; k < 6; ++k)
        for (int i = 0; i < S * S; ++i) {
            cr_assert(isfinite(map.s_u[k][i]) && map.s_u[k][i] > 0.0f, "level %d texel %d: s_u %g", k, i, map.s_u[k][i]);
            cr_assert(isfinite(map.s_v[k][i]) && map.s_v[k][i] > 0.0f, "level %d texel %d: s_v %g", k, i, map.s_v[k][i]);
        }
    /* Gutters filled: a sample of gutter texels holds the value of a nearest chart
     * texel (brute-force search). */
    int sampled = 0;
    for (int i = 0; i < S * S; i += 101) {
        if (map.mask[i] != 0.0f) continue;
        long long best = -1;
        for (int k = 0; k < S * S; ++k) {
            if (map.mask[k] == 0.0f) continue;
            long long dx = i % S - k % S, dy = i / S - k / S, d2 = dx * dx + dy * dy;
            if (best < 0 || d2 < best) best = d2;
        }
        int ok = 0;
        for (int k = 0; k < S * S && !ok; ++k) {
            if (map.mask[k] == 0.0f) continue;
            long long dx = i % S - k % S, dy = i / S - k / S;
            ok = dx * dx + dy * dy == best && map.s_u[0][k] == map.s_u[0][i] && map.s_v[0][k] == map.s_v[0][i];
        }
        cr_assert(ok, "gutter texel %d does not hold a nearest chart value", i);
        if (++sampled == 40) break;
    }
    cr_assert_eq(sampled, 40);
    /* The blurred levels are smoother than the base, and smoother down the chain. */
    double tv_u = total_variation(map.s_u[0], S, S), tv_v = total_variation(map.s_v[0], S, S);
    for (int k = 1; k < 6; ++k) {
        double u = total_variation(map.s_u[k], S, S), v = total_variation(map.s_v[k], S, S);
        cr_assert_lt(u, tv_u, "level %d: total variation %g not below %g", k, u, tv_u);
        cr_assert_lt(v, tv_v, "level %d: total variation %g not below %g", k, v, tv_v);
        tv_u = u, tv_v = v;
    }
    dm_stretch_map_free(&map);
    dm_mesh_free(&m);
}

Test(stretch, bakes_are_identical_on_any_thread_count)
{
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(HEAD, NULL, &m, &err), DM_OK, "%s", err.detail);
    dm_stretch_map a = bake(&m, 128, 128, 50.0, 6, 1), b = bake(&m, 128, 128, 50.0, 6, 2);
    for (int k = 0; k < 6; ++k) {
        cr_assert_eq(memcmp(a.s_u[k], b.s_u[k], 128 * 128 * sizeof(float)), 0);
        cr_assert_eq(memcmp(a.s_v[k], b.s_v[k], 128 * 128 * sizeof(float)), 0);
    }
    cr_assert_eq(memcmp(a.mask, b.mask, 128 * 128 * sizeof(float)), 0);
    dm_stretch_map_free(&a);
    dm_stretch_map_free(&b);
    dm_mesh_free(&m);
}
