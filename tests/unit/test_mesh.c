/* Mesh loading (every bad input its own test), the GPU split, tangent frames,
 * subdivision and UV islands. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mesh/dm_mesh.h"
#include "bake/dm_stretch.h"

static char tmpdir[256];

static void make_tmpdir(void)
{
    snprintf(tmpdir, sizeof tmpdir, "/tmp/dm_test_mesh_XXXXXX");
    cr_assert_not_null(mkdtemp(tmpdir));
}

static char made[64][512]; /* fixtures written, removed by the suite's fini */
static int made_count;

static void remove_tmpdir(void)
{
    for (int i = 0; i < made_count; ++i) unlink(made[i]);
    rmdir(tmpdir);
}

/* A reader stuck in a loop is a failure, not a hang. */
TestSuite(mesh, .init = make_tmpdir, .fini = remove_tmpdir, .timeout = 20);

/* Writes text (size bytes; -1 = strlen) under the suite's folder; returns the path. */
static const char *fixture(const char *name, const char *text, long size)
{
    static char path[512];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "wb");
    cr_assert_not_null(f);
    size_t n = size < 0 ? strlen(text) : (size_t)size;
    cr_assert_eq(fwrite(text, 1, n, f), n);
    fclose(f);
    if (made_count < 64) snprintf(made[made_count++], sizeof made[0], "%s", path);
    return path;
}

/* The unit cube as 6 quads with a cross unwrap: a 4×3 grid of UV cells, the cross
 * made of the middle row (4 faces) and two cells above and below the second column.
 * 14 distinct UVs: the seams of the cross keep separate UVs for one position. */
static const char cube_obj[] =
    "# unit cube, cross unwrap\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    /* row 1 (v in [1/3, 2/3]): u = 0, 1/4, 2/4, 3/4, 1 at v = 1/3 (1..5) and 2/3 (6..10) */
    "vt 0 0.3333333333\nvt 0.25 0.3333333333\nvt 0.5 0.3333333333\nvt 0.75 0.3333333333\nvt 1 0.3333333333\n"
    "vt 0 0.6666666667\nvt 0.25 0.6666666667\nvt 0.5 0.6666666667\nvt 0.75 0.6666666667\nvt 1 0.6666666667\n"
    /* top cell above column 1 (v = 1): 11, 12; bottom cell below (v = 0): 13, 14 */
    "vt 0.25 1\nvt 0.5 1\nvt 0.25 0\nvt 0.5 0\n"
    /* middle row around the sides: -y, +x, +y, -x (counter-clockwise seen from outside) */
    "f 1/1 2/2 6/7 5/6\n"
    "f 2/2 3/3 7/8 6/7\n"
    "f 3/3 4/4 8/9 7/8\n"
    "f 4/4 1/5 5/10 8/9\n"
    /* +z above the +x cell, -z below it */
    "f 6/7 7/8 8/12 5/11\n"
    "f 1/13 4/14 3/3 2/2\n";

Test(mesh, cube_quads_keep_corner_uvs_at_seams)
{
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(fixture("cube.obj", cube_obj, -1), NULL, &m, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(m.vertex_count, 8);
    cr_assert_eq(m.triangle_count, 12);
    cr_assert_eq(m.polygon_count, 6);
    cr_assert_eq(m.normals_from_file, 0);
    /* Each triangle's corner UVs must be the ones its face gave those positions: check
     * that every corner's (position, uv) pair occurs in the file's face list. */
    static const int pairs[][2] = {{1, 1}, {2, 2}, {6, 7}, {5, 6}, {3, 3}, {7, 8}, {4, 4}, {8, 9}, {1, 5}, {5, 10},
                                   {8, 12}, {5, 11}, {1, 13}, {4, 14}};
    static const float vt[14][2] = {{0, 1 / 3.f}, {.25f, 1 / 3.f}, {.5f, 1 / 3.f}, {.75f, 1 / 3.f}, {1, 1 / 3.f},
                                    {0, 2 / 3.f}, {.25f, 2 / 3.f}, {.5f, 2 / 3.f}, {.75f, 2 / 3.f}, {1, 2 / 3.f},
                                    {.25f, 1}, {.5f, 1}, {.25f, 0}, {.5f, 0}};
    for (int c = 0; c < 36; ++c) {
        int found = 0;
        for (size_t p = 0; p < sizeof pairs / sizeof pairs[0]; ++p)
            if ((int)m.indices[c] == pairs[p][0] - 1 && fabsf(m.uvs[c * 2] - vt[pairs[p][1] - 1][0]) < 1e-6f &&
                fabsf(m.uvs[c * 2 + 1] - vt[pairs[p][1] - 1][1]) < 1e-6f)
                found = 1;
        cr_assert(found, "corner %d: position %u with uv (%g, %g) is not in the file", c, m.indices[c] + 1,
                  m.uvs[c * 2], m.uvs[c * 2 + 1]);
    }
    /* Seams: position 1 (index 0) appears with three different UVs. */
    int uv5 = 0, uv1 = 0, uv13 = 0;
    for (int c = 0; c < 36; ++c)
        if (m.indices[c] == 0) {
            uv1 += m.uvs[c * 2] == 0.0f;
            uv5 += m.uvs[c * 2] == 1.0f;
            uv13 += m.uvs[c * 2 + 1] == 0.0f;
        }
    cr_assert(uv1 > 0 && uv5 > 0 && uv13 > 0);
    /* Every triangle turns counter-clockwise in UV as in 3-D (outward normals). */
    for (int t = 0; t < 12; ++t) cr_assert_gt(dm_mesh_triangle_uv_area(&m, t), 0.0, "triangle %d", t);
    for (int t = 0; t < 12; ++t) cr_assert_float_eq(dm_mesh_triangle_area(&m, t), 0.5, 1e-12);
    int32_t islands = 0;
    cr_assert_eq(dm_mesh_uv_islands(&m, NULL, &islands, &err), DM_OK);
    cr_assert_eq(islands, 1);
    dm_mesh_free(&m);
}

Test(mesh, cube_gpu_split_and_tangents)
{
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(fixture("cube.obj", cube_obj, -1), NULL, &m, &err), DM_OK, "%s", err.detail);
    dm_gpu_mesh g;
    cr_assert_eq(dm_mesh_split_for_gpu(&m, &g, &err), DM_OK);
    /* Computed smooth normals are one per position, so the split is by UV: 14. */
    cr_assert_eq(g.vertex_count, 14);
    cr_assert_eq(g.index_count, 36);
    for (int i = 0; i < g.index_count; ++i) {
        uint32_t v = g.indices[i];
        cr_assert_lt(v, (uint32_t)g.vertex_count);
        /* The split vertex carries the corner's own position and UV. */
        for (int d = 0; d < 3; ++d) cr_assert_eq(g.positions[v * 3 + d], m.positions[m.indices[i] * 3 + d]);
        for (int d = 0; d < 2; ++d) cr_assert_eq(g.uvs[v * 2 + d], m.uvs[i * 2 + d]);
    }
    for (int v = 0; v < g.vertex_count; ++v) {
        const float *n = g.normals + v * 3, *t = g.tangents + v * 4;
        double nt = n[0] * t[0] + n[1] * t[1] + n[2] * t[2];
        double tl = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        /* float vectors from double math: 1e-6 covers their rounding. */
        cr_assert_float_eq(nt, 0.0, 1e-6);
        cr_assert_float_eq(tl, 1.0, 1e-6);
        cr_assert_eq(t[3], 1.0f, "vertex %d: no mirrored UVs on the cube, w = %g", v, t[3]);
    }
    dm_gpu_mesh_free(&g);
    dm_mesh_free(&m);
}

/* A flat quad in the z = 0 plane, normal +z, with UVs mirrored in u: both triangles
 * turn clockwise in UV. */
static void mirrored_quad(dm_mesh *m)
{
    dm_error err = {0};
    cr_assert_eq(dm_mesh_alloc(4, 2, m, &err), DM_OK);
    static const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    static const uint32_t ix[6] = {0, 1, 2, 0, 2, 3};
    memcpy(m->positions, p, sizeof p);
    memcpy(m->indices, ix, sizeof ix);
    for (int c = 0; c < 6; ++c) {
        const float *q = p[ix[c]];
        m->uvs[c * 2] = 1.0f - q[0]; /* mirrored */
        m->uvs[c * 2 + 1] = q[1];
    }
    dm_mesh_compute_normals(m);
}

Test(mesh, mirrored_uvs_give_negative_handedness)
{
    dm_mesh m;
    mirrored_quad(&m);
    dm_error err = {0};
    cr_assert_eq(dm_mesh_validate(&m, "quad", &err), DM_OK);
    for (int t = 0; t < 2; ++t) cr_assert_lt(dm_mesh_triangle_uv_area(&m, t), 0.0);
    dm_gpu_mesh g;
    cr_assert_eq(dm_mesh_split_for_gpu(&m, &g, &err), DM_OK);
    cr_assert_eq(g.vertex_count, 4);
    for (int v = 0; v < 4; ++v) {
        const float *t = g.tangents + v * 4;
        /* +u runs along −x; +v along +y = w · cross(+z, −x) = w · (−y): w = −1. */
        cr_assert_float_eq(t[0], -1.0f, 1e-6);
        cr_assert_float_eq(t[1], 0.0f, 1e-6);
        cr_assert_eq(t[3], -1.0f);
    }
    dm_gpu_mesh_free(&g);
    dm_mesh_free(&m);
}

Test(mesh, handedness_splits_a_vertex_shared_by_mirrored_and_plain_triangles)
{
    /* Two triangles sharing an edge whose UVs coincide, the second mirrored (a
     * symmetric unwrap folded on its axis): the shared corners must split. */
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_alloc(4, 2, &m, &err), DM_OK);
    static const float p[4][3] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {-1, 0, 0}};
    static const uint32_t ix[6] = {0, 2, 1, 0, 1, 3};
    static const float uv[6][2] = {{0, 0}, {1, 0}, {0, 1}, {0, 0}, {0, 1}, {1, 0}};
    memcpy(m.positions, p, sizeof p);
    memcpy(m.indices, ix, sizeof ix);
    memcpy(m.uvs, uv, sizeof uv);
    dm_mesh_compute_normals(&m);
    cr_assert_gt(dm_mesh_triangle_uv_area(&m, 0), 0.0);
    cr_assert_lt(dm_mesh_triangle_uv_area(&m, 1), 0.0);
    dm_gpu_mesh g;
    cr_assert_eq(dm_mesh_split_for_gpu(&m, &g, &err), DM_OK);
    cr_assert_eq(g.vertex_count, 6);
    cr_assert_eq(g.tangents[g.indices[0] * 4 + 3], 1.0f);
    cr_assert_eq(g.tangents[g.indices[3] * 4 + 3], -1.0f);
    dm_gpu_mesh_free(&g);
    dm_mesh_free(&m);
}

Test(mesh, zero_uv_area_vertex_gets_a_finite_tangent)
{
    dm_mesh m;
    mirrored_quad(&m);
    for (int c = 0; c < 12; ++c) m.uvs[c] = 0.5f; /* the whole island collapsed to a point */
    dm_gpu_mesh g;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_split_for_gpu(&m, &g, &err), DM_OK);
    for (int v = 0; v < g.vertex_count; ++v) {
        const float *t = g.tangents + v * 4, *n = g.normals + v * 3;
        for (int d = 0; d < 4; ++d) cr_assert(isfinite(t[d]));
        cr_assert_float_eq(t[0] * n[0] + t[1] * n[1] + t[2] * n[2], 0.0f, 1e-6);
        cr_assert_eq(t[3], 1.0f);
    }
    dm_gpu_mesh_free(&g);
    dm_mesh_free(&m);
}

/* One UV Jacobian (dm_mesh_uv_jacobian) for the stretch bake and the tangent frames: a
 * triangle whose UV area is zero relative to its UV edges (D = -1e-10 against edges of
 * length 1) is DM_TRIANGLE_ZERO_UV_AREA for the stretch and adds nothing to the tangents
 * (the tangent path used to test D == 0 only: this triangle's ∂P/∂u, 1e10 long and
 * pointing at (-2, -1, 0)/√5, pulled the shared corner's tangent off +x). */
Test(mesh, near_zero_uv_area_is_degenerate_for_stretch_and_tangents)
{
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_alloc(4, 2, &m, &err), DM_OK);
    static const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
    static const uint32_t ix[6] = {0, 1, 2, 0, 2, 3};
    static const float uv[12] = {0, 0, 1, 0, 0, 1, /* good: +u along +x */
                                 0, 0, 0, 1, 1e-10f, 0.5f};
    memcpy(m.positions, p, sizeof p);
    memcpy(m.indices, ix, sizeof ix);
    memcpy(m.uvs, uv, sizeof uv);
    dm_mesh_compute_normals(&m);
    dm_uv_jacobian j;
    dm_mesh_uv_jacobian(&m, 0, 1.0, &j);
    cr_assert_eq(j.kind, DM_TRIANGLE_OK);
    dm_mesh_uv_jacobian(&m, 1, 1.0, &j);
    cr_assert_eq(j.kind, DM_TRIANGLE_ZERO_UV_AREA);
    dm_triangle_stretch st;
    dm_triangle_stretch_of(&m, 1, 50.0, &st);
    cr_assert_eq(st.kind, DM_TRIANGLE_ZERO_UV_AREA);
    dm_gpu_mesh g;
    cr_assert_eq(dm_mesh_split_for_gpu(&m, &g, &err), DM_OK, "%s", err.detail);
    for (int c = 0; c < 2; ++c) { /* corners 0 and 2: shared by both triangles */
        const float *t = g.tangents + g.indices[c * 2] * 4;
        cr_assert_float_eq(t[0], 1.0f, 1e-6, "corner %d tangent (%g, %g, %g)", c * 2, t[0], t[1], t[2]);
        cr_assert_float_eq(t[1], 0.0f, 1e-6);
        cr_assert_float_eq(t[2], 0.0f, 1e-6);
    }
    dm_gpu_mesh_free(&g);
    dm_mesh_free(&m);
}

Test(mesh, subdivision_keeps_surface_and_uvs)
{
    dm_mesh m, s1, s2;
    mirrored_quad(&m);
    dm_error err = {0};
    cr_assert_eq(dm_mesh_subdivide(&m, &s1, &err), DM_OK);
    cr_assert_eq(s1.triangle_count, 8);
    cr_assert_eq(s1.vertex_count, 4 + 5); /* one new vertex per edge, the diagonal shared */
    cr_assert_eq(dm_mesh_subdivide(&s1, &s2, &err), DM_OK);
    cr_assert_eq(s2.triangle_count, 32);
    cr_assert_eq(dm_mesh_validate(&s2, "subdivided", &err), DM_OK);
    double area = 0.0, uv_area = 0.0;
    for (int t = 0; t < s2.triangle_count; ++t) {
        area += dm_mesh_triangle_area(&s2, t);
        uv_area += dm_mesh_triangle_uv_area(&s2, t);
    }
    cr_assert_float_eq(area, 1.0, 1e-12);
    cr_assert_float_eq(uv_area, -1.0, 1e-12); /* mirrored stays mirrored */
    dm_mesh_free(&s2);
    dm_mesh_free(&s1);
    dm_mesh_free(&m);
}

Test(mesh, head_counts)
{
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(DERMIS_ASSETS "/lps/LeePerrySmith.obj", NULL, &m, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(m.vertex_count, 8844);
    cr_assert_eq(m.triangle_count, 17684);
    cr_assert_eq(m.normals_from_file, 1);
    int mirrored = 0, zero_uv = 0;
    for (int t = 0; t < m.triangle_count; ++t) {
        double a = dm_mesh_triangle_uv_area(&m, t);
        mirrored += a < 0.0;
        zero_uv += a == 0.0;
    }
    cr_assert_eq(mirrored, 662);
    cr_assert_eq(zero_uv, 11);
    dm_gpu_mesh g;
    cr_assert_eq(dm_mesh_split_for_gpu(&m, &g, &err), DM_OK);
    cr_assert_geq(g.vertex_count, 9218); /* at least one per distinct UV */
    int negative = 0;
    for (int v = 0; v < g.vertex_count; ++v) {
        for (int d = 0; d < 4; ++d) cr_assert(isfinite(g.tangents[v * 4 + d]));
        negative += g.tangents[v * 4 + 3] < 0.0f;
    }
    cr_assert_gt(negative, 0, "mirrored triangles must give w = -1 vertices");
    dm_gpu_mesh_free(&g);
    dm_mesh_free(&m);
}

Test(mesh, ply_with_vertex_uvs_loads)
{
    const char *ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                      "property float z\nproperty float u\nproperty float v\nelement face 1\n"
                      "property list uchar int vertex_indices\nend_header\n"
                      "0 0 0 0 0\n2 0 0 1 0\n2 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n";
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(fixture("quad.ply", ply, -1), NULL, &m, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(m.triangle_count, 2);
    cr_assert_float_eq(dm_mesh_triangle_uv_area(&m, 0) + dm_mesh_triangle_uv_area(&m, 1), 1.0, 1e-7);
    dm_mesh_free(&m);
}

Test(mesh, off_without_uvs_loads_when_uvs_are_optional)
{
    const char *off = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    const char *path = fixture("tri.off", off, -1);
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(path, NULL, &m, &err), DM_ERR_FORMAT);
    cr_assert(strstr(err.detail, "no texture coordinates"), "%s", err.detail);
    dm_mesh_load_options opt = {.uvs_optional = 1};
    cr_assert_eq(dm_mesh_load(path, &opt, &m, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(m.triangle_count, 1);
    cr_assert_float_eq(m.normals[2], 1.0f, 1e-6); /* computed: +z */
    dm_mesh_free(&m);
}

/* ---- bad inputs: each its own test, each a clear error, none a crash ---------------- */

static void expect_failure(const char *path, dm_result code, const char *words)
{
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(path, NULL, &m, &err), code, "got %s: %s", dm_result_name(err.code), err.detail);
    cr_assert(strstr(err.detail, words), "message '%s' lacks '%s'", err.detail, words);
    cr_assert(strstr(err.detail, path) || strstr(err.detail, strrchr(path, '/') + 1), "message '%s' lacks the file",
              err.detail);
    cr_assert_eq(m.triangle_count, 0);
    cr_assert_null(m.positions);
    dm_mesh_free(&m);
}

Test(mesh, bad_missing_file) { expect_failure("/nonexistent/dir/head.obj", DM_ERR_FILE_OPEN, "cannot open"); }

Test(mesh, bad_unknown_format)
{
    expect_failure(fixture("mesh.xyz", "v 0 0 0\n", -1), DM_ERR_UNSUPPORTED, "unknown mesh format");
}

Test(mesh, bad_empty_file) { expect_failure(fixture("empty.obj", "", 0), DM_ERR_EMPTY, "empty"); }

Test(mesh, bad_no_faces)
{
    expect_failure(fixture("comments.obj", "# nothing here\ng group\n", -1), DM_ERR_EMPTY, "no faces");
}

Test(mesh, bad_points_only)
{
    expect_failure(fixture("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\np 1 2 3\n", -1), DM_ERR_EMPTY,
                   "points or lines only");
}

Test(mesh, bad_lines_only)
{
    expect_failure(fixture("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n", -1), DM_ERR_EMPTY,
                   "points or lines only");
}

Test(mesh, bad_no_uvs)
{
    expect_failure(fixture("nouv.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", -1), DM_ERR_FORMAT,
                   "no texture coordinates");
}

Test(mesh, bad_nan_position)
{
    expect_failure(fixture("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n", -1),
                   DM_ERR_NON_FINITE, "nan.obj:2: vertex 2");
}

Test(mesh, bad_inf_uv)
{
    expect_failure(fixture("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 inf\nvt 0 1\nf 1/1 2/2 3/3\n", -1),
                   DM_ERR_NON_FINITE, "texture coordinate 2");
}

Test(mesh, bad_float_overflow)
{
    /* Finite as a double, infinite as the float OpenMesh reads: its stream fails, the
     * vertex is dropped and the face's indices point past the end (found by fuzz_obj). */
    expect_failure(fixture("big.obj", "v 1e40 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n", -1),
                   DM_ERR_NON_FINITE, "big.obj:1: vertex 1");
}

Test(mesh, bad_control_characters)
{
    /* OpenMesh reads past a NUL and takes a vertical tab for text (found by fuzz_obj). */
    static const char nul[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/\0\0 4//2\n";
    expect_failure(fixture("nul.obj", nul, (long)sizeof nul - 1), DM_ERR_FORMAT, "nul.obj:7: control character 0x00");
    expect_failure(fixture("vt.obj", "\vv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n", -1), DM_ERR_FORMAT,
                   "vt.obj:1: control character 0x0B");
}

Test(mesh, bad_hex_float)
{
    /* strtod reads 0x1p0, OpenMesh's stream reads 0 and stops: not a number here either. */
    expect_failure(fixture("hex.obj", "v 0x1p0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n", -1),
                   DM_ERR_FORMAT, "hex.obj:1: vertex 1 has 0 numbers");
}

Test(mesh, bad_nan_in_binary_ply)
{
    /* Binary PLY: no text parser in the way, the NaN reaches our check as a float. */
    static const char header[] = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                                 "property float y\nproperty float z\nproperty float u\nproperty float v\n"
                                 "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    unsigned char buf[sizeof header - 1 + 15 * 4 + 1 + 3 * 4];
    float v[15] = {0, 0, 0, 0, 0, 1, NAN, 0, 1, 0, 0, 1, 0, 0, 1};
    int32_t f[3] = {0, 1, 2};
    unsigned char n3 = 3;
    size_t o = 0;
    memcpy(buf + o, header, sizeof header - 1), o += sizeof header - 1;
    memcpy(buf + o, v, sizeof v), o += sizeof v;
    memcpy(buf + o, &n3, 1), o += 1;
    memcpy(buf + o, f, sizeof f), o += sizeof f;
    expect_failure(fixture("nan.ply", (const char *)buf, (long)o), DM_ERR_NON_FINITE, "vertex 2");
}

Test(mesh, bad_nan_in_binary_stl)
{
    /* Binary STL: 80-byte header, count, then normal + 3 vertices + attribute per facet.
     * The STL reader merges vertices by position and loses the NaN facet: a clean
     * failure either way. */
    unsigned char buf[84 + 50] = {0};
    uint32_t one = 1;
    memcpy(buf + 80, &one, 4);
    float f[12] = {0, 0, 1, NAN, 0, 0, 1, 0, 0, 0, 1, 0};
    memcpy(buf + 84, f, sizeof f);
    const char *path = fixture("nan.stl", (const char *)buf, sizeof buf);
    dm_mesh m;
    dm_error err = {0};
    dm_mesh_load_options opt = {.uvs_optional = 1};
    dm_result r = dm_mesh_load(path, &opt, &m, &err);
    cr_assert(r == DM_ERR_NON_FINITE || r == DM_ERR_EMPTY, "%s", err.detail);
    dm_mesh_free(&m);
}

Test(mesh, bad_index_out_of_range)
{
    expect_failure(fixture("oob.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 9/3\n", -1),
                   DM_ERR_RANGE, "oob.obj:7: face corner 3 uses vertex 9, expected 1..3");
}

Test(mesh, bad_uv_index_out_of_range)
{
    expect_failure(fixture("vtoob.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/-7\n", -1),
                   DM_ERR_RANGE, "texture coordinate");
}

Test(mesh, bad_index_zero)
{
    expect_failure(fixture("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 0/1 1/1 2/1\n", -1), DM_ERR_FORMAT,
                   "face corner 1");
}

Test(mesh, bad_face_with_two_corners)
{
    expect_failure(fixture("two.obj", "v 0 0 0\nv 1 0 0\nvt 0 0\nf 1/1 2/1\n", -1), DM_ERR_FORMAT,
                   "face with 2 corners");
}

Test(mesh, bad_ply_index_out_of_range)
{
    const char *ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nproperty float u\nproperty float v\nelement face 1\n"
                      "property list uchar int vertex_indices\nend_header\n"
                      "0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 5\n";
    expect_failure(fixture("oob.ply", ply, -1), DM_ERR_EMPTY, "no faces");
}

Test(mesh, bad_truncated_obj)
{
    /* The head cut mid-file: vertices only, the faces gone. */
    FILE *f = fopen(DERMIS_ASSETS "/lps/LeePerrySmith.obj", "rb");
    cr_assert_not_null(f);
    static char buf[600000];
    size_t n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    while (n > 0 && buf[n - 1] != '\n') --n; /* cut at a line end: a cut line is another test */
    expect_failure(fixture("trunc.obj", buf, (long)n), DM_ERR_EMPTY, "no faces");
}

Test(mesh, bad_ply_without_end_header)
{
    /* OpenMesh's PLY probe loops forever on this; the pre-check refuses it. */
    expect_failure(fixture("noend.ply", "ply\nformat ascii 1.0\nelement vertex 3\n", -1), DM_ERR_FORMAT,
                   "end_header");
}

Test(mesh, bad_om_that_crashes_openmesh_is_an_error)
{
    /* An OM file (written by OpenMesh, one byte of a chunk header changed) on which
     * OpenMesh's reader trips its own assert: isolated in a child, it is an error. */
    static const unsigned char om[] = {
        0x4f, 0x4d, 0x50, 0x42, 0x08, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00,
        0x00, 0x16, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x80, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00,
        0x80, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x80, 0x3f, 0x40, 0x0e, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x72, 0x54, 0x49, 0x66, 0x4c, 0x69, 0x33, 0x45, 0x45, 0x45, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x04, 0x00,
        0x00, 0x00, 0x08, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x00, 0x20, 0x00, 0x00, 0x00, 0x40, 0x00,
        0x00, 0x00, 0x80, 0x00, 0xf8, 0x16, 0xda, 0x01, 0x00, 0x07, 0x00, 0xff, 0x04, 0x02, 0x00, 0x01,
        0x01, 0xff, 0x06, 0x03, 0x00, 0x03, 0x02, 0xff, 0x00, 0x00, 0x00, 0x05, 0x03, 0xff, 0x0a, 0x06,
        0x01, 0x0d, 0x05, 0xff, 0x0c, 0x07, 0x01, 0x09, 0x06, 0xff, 0x08, 0x05, 0x01, 0x0b, 0x07, 0xff,
        0xe0, 0x06, 0x07, 0x01, 0x03, 0x05, 0xff, 0x0d, 0x09, 0x0b, 0xe8, 0x06, 0x06, 0x0c, 0x1c, 0x00,
    };
    dm_mesh m;
    dm_error err = {0};
    dm_mesh_load_options opt = {.uvs_optional = 1};
    cr_assert_eq(dm_mesh_load(fixture("crash.om", (const char *)om, sizeof om), &opt, &m, &err), DM_ERR_FORMAT, "%s",
                 err.detail);
    cr_assert(strstr(err.detail, "the reader crashed on this file"), "%s", err.detail);
    dm_mesh_free(&m);
}

Test(mesh, bad_garbage_in_every_format)
{
    /* Deterministic pseudo-random bytes: whatever the reader makes of them, a clean
     * failure (or a mesh that validates), never a crash. */
    static const char *const ext[] = {"obj", "ply", "off", "stl", "om"};
    unsigned char buf[4096];
    uint32_t x = 12345;
    for (int round = 0; round < 8; ++round) {
        for (size_t i = 0; i < sizeof buf; ++i) {
            x = x * 1664525u + 1013904223u;
            buf[i] = (unsigned char)(x >> 24);
        }
        if (round == 1) memcpy(buf, "ply\nformat binary_little_endian 1.0\n", 36);
        if (round == 2) memcpy(buf, "OFF\n3 1 0\n", 10);
        for (size_t e = 0; e < sizeof ext / sizeof ext[0]; ++e) {
            char name[32];
            snprintf(name, sizeof name, "garbage%d.%s", round, ext[e]);
            dm_mesh m;
            dm_error err = {0};
            dm_result r = dm_mesh_load(fixture(name, (const char *)buf, sizeof buf), NULL, &m, &err);
            if (r == DM_OK) cr_assert_eq(dm_mesh_validate(&m, name, &err), DM_OK);
            else cr_assert(strlen(err.detail) > 0);
            dm_mesh_free(&m);
        }
    }
}
