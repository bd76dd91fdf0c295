/* Mean curvature per vertex and per texel (bake/dm_curvature.h): a sphere (1/R, with its
 * UV seam's duplicated vertices and the poles' zero-area triangles), a cylinder (1/2R, two
 * boundaries), a plane (0), inverted winding, mirrored UVs, a degenerate triangle, smoothing,
 * thread invariance, and the tool's outputs and exit codes. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/grid_mesh.h"
#include "../common/tmpdir.h"
#include "bake/dm_curvature.h"
#include "image/dm_exr.h"
#include "core/dm_math.h"

static int g_flip; /* 1: mirror u */

static void sphere_pos(double s, double t, double p[3])
{
    double phi = DM_2PI * s, theta = DM_PI * (1.0 - t); /* CCW in (s, t) faces outwards */
    p[0] = cos(phi) * sin(theta);
    p[1] = sin(phi) * sin(theta);
    p[2] = cos(theta);
}
static void cylinder_pos(double s, double t, double p[3])
{
    double phi = DM_2PI * s;
    p[0] = cos(phi);
    p[1] = sin(phi);
    p[2] = 2.0 * t - 1.0;
}
static void plane_pos(double s, double t, double p[3])
{
    p[0] = 3.0 * s + 0.2 * t; /* sheared: obtuse triangles */
    p[1] = 2.0 * t;
    p[2] = 0.0;
}
static void uv_id(double s, double t, double q[3])
{
    q[0] = g_flip ? 1.0 - s : s;
    q[1] = t;
    q[2] = 0.0;
}

/* max |h − want| over vertices with |z| ≤ zmax (unit positions) */
static double max_error(const dm_mesh *m, const double *h, double want, double zmax)
{
    double e = 0.0;
    for (int v = 0; v < m->vertex_count; ++v)
        if (fabs(m->positions[3 * v + 2]) <= zmax) e = fmax(e, fabs(h[v] - want));
    return e;
}

Test(curvature, sphere_is_one_over_r)
{
    dm_mesh m;
    g_flip = 0;
    grid_mesh(128, 64, sphere_pos, uv_id, &m);
    double *h = malloc(sizeof(double) * m.vertex_count);
    dm_curvature_stats st;
    cr_assert_eq(dm_curvature_vertices(&m, 10.0, 0.0, 1, h, &st, NULL), DM_OK);
    /* 1/R = 0.1 /mm. The cotangent formula on a latitude-longitude grid is second order in
     * the edge length (0.049 R here): measured 2.7e-5 /mm (0.03 %), bound 0.1 %; the seam
     * (s = 0 and 1, duplicated, sin 2π ≠ 0 in the last bit) is welded: no boundary. */
    cr_log_info("sphere: max |H - 1/R| %.3g (|z| <= 0.95), %.3g (all) /mm", max_error(&m, h, 0.1, 0.95),
                max_error(&m, h, 0.1, 1.0));
    cr_assert(max_error(&m, h, 0.1, 0.95) < 1e-4, "%g", max_error(&m, h, 0.1, 0.95));
    cr_assert_eq(st.boundary_vertices, 0);
    cr_assert_eq(st.welded_vertices, 128 * 63 + 2);
    cr_assert_eq(st.degenerate_triangles, 2 * 128); /* a pole corner welded twice */
    /* everywhere including the poles (valence 128): measured 3.1e-5 */
    cr_assert(max_error(&m, h, 0.1, 1.0) < 1e-4, "%g", max_error(&m, h, 0.1, 1.0));
    /* smoothing keeps a constant constant */
    cr_assert_eq(dm_curvature_vertices(&m, 10.0, 2.0, 2, h, NULL, NULL), DM_OK);
    cr_assert(max_error(&m, h, 0.1, 0.95) < 1e-4);
    /* inverted winding: the inside of a sphere is concave */
    for (int t = 0; t < m.triangle_count; ++t) {
        uint32_t a = m.indices[3 * t + 1];
        m.indices[3 * t + 1] = m.indices[3 * t + 2];
        m.indices[3 * t + 2] = a;
    }
    cr_assert_eq(dm_curvature_vertices(&m, 10.0, 0.0, 1, h, NULL, NULL), DM_OK);
    cr_assert(max_error(&m, h, -0.1, 0.95) < 1e-4);
    free(h);
    dm_mesh_free(&m);
}

Test(curvature, sphere_map_mirrored_uvs_and_threads)
{
    dm_mesh m;
    dm_curvature_map a, b, c;
    dm_curvature_options o = {.width = 128, .height = 128, .mm_per_unit = 10.0, .smooth_mm = 1.0, .thread_count = 1};
    g_flip = 0;
    grid_mesh(128, 64, sphere_pos, uv_id, &m);
    cr_assert_eq(dm_curvature_bake(&m, &o, &a, NULL), DM_OK);
    o.thread_count = 3;
    cr_assert_eq(dm_curvature_bake(&m, &o, &b, NULL), DM_OK);
    cr_assert_eq(memcmp(a.curvature, b.curvature, sizeof(float) * 128 * 128), 0);
    cr_assert_eq(a.stats.mirrored_triangles, 0);
    /* every texel (the grid covers [0,1]²): the vertices' 1e-4 plus float rounding */
    for (int i = 0; i < 128 * 128; ++i) {
        cr_assert_eq(a.mask[i], 1.0f);
        cr_assert(fabs(a.curvature[i] - 0.1) < 1e-4, "texel %d: %g", i, a.curvature[i]);
    }
    dm_mesh_free(&m);
    g_flip = 1;
    grid_mesh(128, 64, sphere_pos, uv_id, &m);
    cr_assert_eq(dm_curvature_bake(&m, &o, &c, NULL), DM_OK);
    cr_assert_eq(c.stats.mirrored_triangles, m.triangle_count);
    for (int j = 0; j < 128; ++j) /* the same map, mirrored in u, to float rounding of the UVs */
        for (int i = 0; i < 128; ++i)
            cr_assert(fabs(c.curvature[j * 128 + i] - a.curvature[j * 128 + 127 - i]) < 1e-5);
    dm_curvature_map_free(&a);
    dm_curvature_map_free(&b);
    dm_curvature_map_free(&c);
    dm_mesh_free(&m);
}

Test(curvature, cylinder_with_boundaries)
{
    dm_mesh m;
    g_flip = 0;
    grid_mesh(128, 32, cylinder_pos, uv_id, &m);
    double *h = malloc(sizeof(double) * m.vertex_count);
    dm_curvature_stats st;
    cr_assert_eq(dm_curvature_vertices(&m, 1.0, 0.0, 1, h, &st, NULL), DM_OK);
    cr_assert_eq(st.boundary_vertices, 2 * 128);
    cr_assert_eq(st.degenerate_triangles, 0);
    /* H = 1/(2R) = 0.5; boundary rings take their interior neighbours' value; measured 1.4e-5 */
    cr_log_info("cylinder: max |H - 1/2R| %.3g /mm", max_error(&m, h, 0.5, 1.0));
    cr_assert(max_error(&m, h, 0.5, 1.0) < 1e-4, "%g", max_error(&m, h, 0.5, 1.0));
    free(h);
    dm_mesh_free(&m);
}

Test(curvature, plane_is_zero_with_a_degenerate_triangle)
{
    dm_mesh m;
    g_flip = 0;
    grid_mesh(16, 16, plane_pos, uv_id, &m);
    /* collapse one interior triangle to a sliver of zero area: its third corner onto an edge */
    m.positions[3 * 50 + 0] = 0.5f * (m.positions[3 * 49] + m.positions[3 * 51]);
    m.positions[3 * 50 + 1] = 0.5f * (m.positions[3 * 49 + 1] + m.positions[3 * 51 + 1]);
    dm_curvature_map map;
    dm_curvature_options o = {.width = 64, .height = 64, .mm_per_unit = 5.0, .smooth_mm = 0.5};
    cr_assert_eq(dm_curvature_bake(&m, &o, &map, NULL), DM_OK);
    cr_assert(map.stats.boundary_vertices == 4 * 16);
    for (int i = 0; i < 64 * 64; ++i) cr_assert(map.curvature[i] == 0.0f, "texel %d: %g", i, map.curvature[i]);
    dm_curvature_map_free(&map);
    dm_mesh_free(&m);
}

Test(curvature, options_and_gutters)
{
    dm_mesh m;
    g_flip = 0;
    grid_mesh(8, 8, plane_pos, uv_id, &m);
    for (int i = 0; i < m.triangle_count * 6; ++i) m.uvs[i] = 0.25f + 0.5f * m.uvs[i]; /* a chart in the middle */
    dm_curvature_map map;
    dm_error err = {0};
    dm_curvature_options o = {.width = 32, .height = 32, .mm_per_unit = 1.0};
    cr_assert_eq(dm_curvature_bake(&m, &o, &map, &err), DM_OK);
    cr_assert_eq(map.mask[0], 0.0f);
    cr_assert_eq(map.mask[16 * 32 + 16], 1.0f);
    cr_assert(map.stats.gutter_texels > 0 && map.stats.coverage < 0.5);
    dm_curvature_map_free(&map);
    o.smooth_mm = -1.0;
    cr_assert_eq(dm_curvature_bake(&m, &o, &map, &err), DM_ERR_RANGE);
    dm_curvature_map_free(&map);
    o.smooth_mm = NAN;
    cr_assert_eq(dm_curvature_bake(&m, &o, &map, &err), DM_ERR_NON_FINITE);
    dm_curvature_map_free(&map);
    o = (dm_curvature_options){.width = 20000};
    cr_assert_eq(dm_curvature_bake(&m, &o, &map, &err), DM_ERR_RANGE);
    dm_curvature_map_free(&map);
    dm_profile p;
    dm_profile_gems3_skin(&p);
    cr_assert(fabs(dm_curvature_profile_scale_mm(&p) - 0.70) < 0.01, "%g", dm_curvature_profile_scale_mm(&p));
    dm_mesh_free(&m);
}

#define TOOL DERMIS_BIN "/dermis-bake-curvature"

Test(curvature, tool)
{
    char dir[64], cmd[1024], path[256], obj[256];
    cr_assert(test_tmpdir(dir, sizeof dir));
    /* an octahedron-free closed mesh: a cube's 12 triangles with a UV per corner */
    snprintf(obj, sizeof obj, "%s/cube.obj", dir);
    FILE *f = fopen(obj, "w");
    cr_assert(f);
    fputs("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
          "vt 0.1 0.1\nvt 0.9 0.1\nvt 0.9 0.9\nvt 0.1 0.9\n"
          "f 1/1 4/2 3/3 2/4\nf 5/1 6/2 7/3 8/4\nf 1/1 2/2 6/3 5/4\nf 2/1 3/2 7/3 6/4\nf 3/1 4/2 8/3 7/4\n"
          "f 4/1 1/2 5/3 8/4\n",
          f);
    fclose(f);
    snprintf(path, sizeof path, "%s/c.exr", dir);
    snprintf(cmd, sizeof cmd, TOOL " %s -o %s --size 32 --mm-per-unit 10 --smooth 0 --quiet", obj, path);
    cr_assert_eq(test_run(cmd, NULL), 0);
    dm_exr_image img;
    dm_error err = {0};
    cr_assert_eq(dm_exr_read(path, &img, &err), DM_OK, "%s", err.detail);
    cr_assert(dm_exr_find(&img, "curvature") && dm_exr_find(&img, "mask"));
    cr_assert(img.has_provenance);
    cr_expect_eq(dm_prov_find(&img.prov, "mm_per_unit")->d, 10.0);
    cr_expect_eq(dm_prov_find(&img.prov, "smooth_mm")->d, 0.0);
    /* a cube is convex: every texel of the chart ≥ 0 */
    const float *c = dm_exr_find(&img, "curvature");
    for (int i = 0; i < 32 * 32; ++i) cr_assert(c[i] >= 0.0f && isfinite(c[i]));
    dm_exr_free(&img);
    cr_assert_eq(test_count_files(dir, ".tmp."), 0);
    static const char *const bad[] = {"", "--size 8", "--smooth -1", "--smooth 1 --profile p.json", "--bogus",
                                      "-v --quiet", "--mm-per-unit 0"};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; ++k) {
        snprintf(cmd, sizeof cmd, TOOL " %s %s %s 2>/dev/null", obj, k ? "-o /nonexistent-dir/y.exr" : "", bad[k]);
        cr_expect_eq(test_run(cmd, NULL), 1, "'%s'", bad[k]);
    }
    snprintf(cmd, sizeof cmd, TOOL " -o %s/y.exr 2>/dev/null", dir); /* no mesh */
    cr_expect_eq(test_run(cmd, NULL), 1);
    snprintf(cmd, sizeof cmd, TOOL " %s/none.obj -o %s/y.exr 2>/dev/null", dir, dir);
    cr_expect_eq(test_run(cmd, NULL), 2);
    snprintf(cmd, sizeof cmd, TOOL " %s -o /dev/null/y.exr --quiet 2>/dev/null", obj);
    cr_expect_eq(test_run(cmd, NULL), 4);
    cr_expect_eq(test_run(TOOL " --help >/dev/null", NULL), 0);
}
