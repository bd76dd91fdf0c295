/* dm_ref_regions: the labels on meshes whose answer is known (a plane cut into two UV
 * charts: the seam band's width on both sides of the cut and along the border; a closed
 * slab: thin below 5 mm, smooth above; spheres: never thin at 50 mm, thin everywhere at
 * 2 mm), texel areas against the charts' analytic scale, and the weighted statistics on
 * hand-computed cases. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../common/grid_mesh.h"
#include "reference/dm_ref_regions.h"
#include "core/dm_math.h"

/* ---- the plane: x in [-30, 30] mm, y in [-20, 20] mm, cut at x = 0 into two charts ---- */

enum { PW = 30, PH = 20 };
static double chart_u0(int right) { return right ? 0.55 : 0.05; }
static void left_pos(double s, double t, double o[3]) { o[0] = -PW + PW * s, o[1] = -PH + 2 * PH * t, o[2] = 0; }
static void right_pos(double s, double t, double o[3]) { o[0] = PW * s, o[1] = -PH + 2 * PH * t, o[2] = 0; }
static void left_uv(double s, double t, double o[3]) { o[0] = chart_u0(0) + 0.4 * s, o[1] = 0.05 + 0.9 * t, o[2] = 0; }
static void right_uv(double s, double t, double o[3]) { o[0] = chart_u0(1) + 0.4 * s, o[1] = 0.05 + 0.9 * t, o[2] = 0; }

/* Two grids in one mesh; the column x = 0 has equal positions in both (welded) and
 * different UVs (the seam). */
static void plane_two_charts(dm_mesh *m)
{
    dm_mesh a, b;
    dm_error err = {0};
    grid_mesh(30, 40, left_pos, left_uv, &a);
    grid_mesh(30, 40, right_pos, right_uv, &b);
    cr_assert_eq(dm_mesh_alloc(a.vertex_count + b.vertex_count, a.triangle_count + b.triangle_count, m, &err), DM_OK);
    memcpy(m->positions, a.positions, sizeof(float) * 3 * (size_t)a.vertex_count);
    memcpy(m->positions + 3 * (size_t)a.vertex_count, b.positions, sizeof(float) * 3 * (size_t)b.vertex_count);
    for (int32_t i = 0; i < 3 * a.triangle_count; ++i) m->indices[i] = a.indices[i];
    for (int32_t i = 0; i < 3 * b.triangle_count; ++i) m->indices[3 * a.triangle_count + i] = b.indices[i] + (uint32_t)a.vertex_count;
    memcpy(m->uvs, a.uvs, sizeof(float) * 6 * (size_t)a.triangle_count);
    memcpy(m->uvs + 6 * (size_t)a.triangle_count, b.uvs, sizeof(float) * 6 * (size_t)b.triangle_count);
    dm_mesh_compute_normals(m);
    cr_assert_eq(dm_mesh_validate(m, "plane", &err), DM_OK, "%s", err.detail);
    dm_mesh_free(&a), dm_mesh_free(&b);
}

/* The triangle and barycentrics of plane point (x, y) (the grids' cells are 1 mm). */
static int32_t plane_locate(double x, double y, double *b1, double *b2)
{
    int right = x >= 0;
    double s = right ? x : x + PW, t = y + PH; /* cell coordinates, 1 mm cells */
    int i = (int)fmin(floor(s), PW - 1), j = (int)fmin(floor(t), 2 * PH - 1);
    double fs = s - i, ft = t - j;
    int32_t tri = (int32_t)(right * PW * 2 * PH * 2 + 2 * (j * PW + i));
    /* lower triangle (0,0) (1,0) (1,1) when fs >= ft: P = c0 + b1 (c1 - c0) + b2 (c2 - c0) */
    if (fs >= ft) { *b1 = fs - ft, *b2 = ft; return tri; }
    *b1 = fs, *b2 = ft - fs; /* upper: (0,0) (1,1) (0,1) */
    return tri + 1;
}

static double seam_distance(double x, double y)
{
    return fmin(fmin(fabs(x), PW - fabs(x)), PH - fabs(y));
}

Test(ref_regions, plane_seam_band_is_3mm_on_both_sides_and_along_the_border)
{
    dm_mesh m;
    plane_two_charts(&m);
    dm_ref_regions *r = NULL;
    dm_error err = {0};
    cr_assert_eq(dm_ref_regions_create(&m, 1.0, NULL, &r, &err), DM_OK, "%s", err.detail);
    dm_ref_regions_info info;
    dm_ref_regions_get_info(r, &info);
    /* seam: 40 cut edges; border: 2 * (60 + 40) boundary edges */
    cr_expect_eq(info.boundary_edges, 200);
    cr_expect_eq(info.seam_edges, 240);
    cr_expect(fabs(info.surface_area_mm2 - 2400) < 1e-6, "area %g", info.surface_area_mm2);
    int checked = 0;
    for (double y = -19.9; y < 20; y += 0.37)
        for (double x = -29.9; x < 30; x += 0.23) {
            double d = seam_distance(x, y), b1, b2;
            if (fabs(d - 3) < 1e-3) continue; /* on the band's edge */
            int32_t t = plane_locate(x, y, &b1, &b2);
            dm_ref_region want = d <= 3 ? DM_REF_REGION_SEAM : DM_REF_REGION_SMOOTH;
            cr_assert_eq(dm_ref_regions_classify(r, t, b1, b2), want, "(%g, %g): %s, want %s", x, y,
                         dm_ref_region_name(dm_ref_regions_classify(r, t, b1, b2)), dm_ref_region_name(want));
            ++checked;
        }
    cr_expect_gt(checked, 25000);
    /* mm_per_unit scales the band: at 10 mm per unit the same mesh is 600 x 400 mm, and
     * 3 mm is 0.3 units */
    dm_ref_regions *r10 = NULL;
    cr_assert_eq(dm_ref_regions_create(&m, 10.0, NULL, &r10, &err), DM_OK);
    double b1, b2;
    int32_t t = plane_locate(0.29, 0, &b1, &b2);
    cr_expect_eq(dm_ref_regions_classify(r10, t, b1, b2), DM_REF_REGION_SEAM);
    t = plane_locate(0.31, 0, &b1, &b2);
    cr_expect_eq(dm_ref_regions_classify(r10, t, b1, b2), DM_REF_REGION_SMOOTH);
    dm_ref_regions_destroy(r10), dm_ref_regions_destroy(r), dm_mesh_free(&m);
}

Test(ref_regions, plane_texel_areas_and_band_in_an_atlas)
{
    dm_mesh m;
    plane_two_charts(&m);
    enum { N = 200 };
    float *atlas = calloc(4 * (size_t)N * N, sizeof *atlas);
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            double u = (i + 0.5) / N, v = (j + 0.5) / N;
            bool in = v > 0.05 && v < 0.95 && ((u > 0.05 && u < 0.45) || (u > 0.55 && u < 0.95));
            atlas[4 * ((size_t)j * N + i) + 3] = in ? 1.0f : 0.0f;
        }
    dm_reference_atlas ra = {N, N, atlas};
    dm_reference_target *tg = NULL;
    int64_t *texel_of = NULL;
    size_t count = 0;
    dm_error err = {0};
    cr_assert_eq(dm_reference_atlas_targets(&m, &ra, 1, &tg, &texel_of, &count, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(count, (size_t)2 * 80 * 180);
    dm_ref_regions *r = NULL;
    cr_assert_eq(dm_ref_regions_create(&m, 1.0, NULL, &r, &err), DM_OK);
    uint8_t *label = calloc((size_t)N * N, 1);
    float *area = calloc((size_t)N * N, sizeof *area);
    dm_ref_regions_atlas(r, N, N, tg, texel_of, count, label, area);
    /* each chart: 30 x 40 mm over 0.4 x 0.9 of the UV square */
    double want = 30.0 * 40.0 / (0.4 * 0.9) / ((double)N * N), sum = 0;
    long seam = 0;
    for (size_t k = 0; k < count; ++k) {
        int64_t i = texel_of[k];
        cr_assert(fabs(area[i] - want) < 1e-5 * want, "texel %lld: %g mm², want %g", (long long)i, area[i], want);
        sum += area[i];
        int right = (i % N) >= N / 2;
        double u = ((i % N) + 0.5) / N, v = ((i / N) + 0.5) / N;
        double x = (u - chart_u0(right)) / 0.4 * PW - (right ? 0 : PW), y = (v - 0.05) / 0.9 * 2 * PH - PH;
        double d = seam_distance(x, y);
        if (fabs(d - 3) > 1e-3) cr_assert_eq(label[i] == DM_REF_REGION_SEAM, d < 3, "texel (%g, %g) mm", x, y);
        seam += label[i] == DM_REF_REGION_SEAM;
    }
    /* the texels tile the charts exactly: 2 x 80 x 180 texels of 1/6 mm x 2/9 mm */
    cr_expect(fabs(sum - 2400) < 1e-3 * 2400, "covered area %g mm²", sum);
    /* band: 3 mm along the cut (both sides) and along the border, of 60 x 40 mm */
    double band = 2400 - (60 - 12) * (40 - 6.0);
    cr_expect(fabs(seam * want - band) < 0.03 * band, "seam area %g, want %g", seam * want, band);
    free(label), free(area), free(tg), free(texel_of), free(atlas);
    dm_ref_regions_destroy(r), dm_mesh_free(&m);
}

/* ---- a closed slab 40 x 40 x h mm, one chart per face (every edge a seam) ---- */

static void slab(double h, dm_mesh *m)
{
    static const int quads[6][4] = {{0, 1, 2, 3}, {7, 6, 5, 4}, {0, 4, 5, 1}, {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 4, 0}};
    dm_error err = {0};
    cr_assert_eq(dm_mesh_alloc(8, 12, m, &err), DM_OK);
    for (int v = 0; v < 8; ++v) {
        m->positions[3 * v] = (float)((v & 1) ^ ((v >> 1) & 1) ? 20 : -20);
        m->positions[3 * v + 1] = (float)((v & 3) >= 2 ? 20 : -20);
        m->positions[3 * v + 2] = (float)(v >= 4 ? -h / 2 : h / 2);
    }
    /* 0 (-20,-20,+) 1 (20,-20,+) 2 (20,20,+) 3 (-20,20,+), 4..7 the same at -h/2: top
     * counter-clockwise seen from +z */
    for (int f = 0; f < 6; ++f) {
        const int *q = quads[f];
        const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
        const float uvq[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        for (int h2 = 0; h2 < 2; ++h2)
            for (int k = 0; k < 3; ++k) {
                int t = 2 * f + h2, c = tri[h2][k];
                m->indices[3 * t + k] = (uint32_t)q[c];
                m->uvs[(3 * t + k) * 2] = (f % 3) / 3.0f + uvq[c][0] * 0.3f;
                m->uvs[(3 * t + k) * 2 + 1] = (f / 3) / 2.0f + uvq[c][1] * 0.45f;
            }
    }
    dm_mesh_compute_normals(m);
    cr_assert_eq(dm_mesh_validate(m, "slab", &err), DM_OK, "%s", err.detail);
}

static dm_ref_region slab_top_label(double h, double x, double y)
{
    dm_mesh m;
    slab(h, &m);
    dm_ref_regions *r = NULL;
    dm_error err = {0};
    cr_assert_eq(dm_ref_regions_create(&m, 1.0, NULL, &r, &err), DM_OK);
    /* top triangle 0: corners 0 (-20,-20) 1 (20,-20) 2 (20,20), P = c0 + b1 (c1 - c0) + b2 (c2 - c0) */
    double b2 = (y + 20) / 40, b1 = (x + 20) / 40 - b2;
    cr_assert(b1 >= 0 && b2 >= 0 && b1 + b2 <= 1);
    dm_ref_region l = dm_ref_regions_classify(r, 0, b1, b2);
    dm_ref_regions_destroy(r), dm_mesh_free(&m);
    return l;
}

Test(ref_regions, slab_is_thin_below_5mm_and_smooth_above)
{
    cr_expect_eq(slab_top_label(2, 5, -5), DM_REF_REGION_THIN);
    cr_expect_eq(slab_top_label(4.9, 5, -5), DM_REF_REGION_THIN);
    cr_expect_eq(slab_top_label(5.1, 5, -5), DM_REF_REGION_SMOOTH);
    cr_expect_eq(slab_top_label(12, 5, -5), DM_REF_REGION_SMOOTH);
    /* near an edge the seam label comes first (every face is its own chart) */
    cr_expect_eq(slab_top_label(2, 18, -5), DM_REF_REGION_SEAM);
    cr_expect_eq(slab_top_label(12, 16.5, -5), DM_REF_REGION_SMOOTH); /* 3.5 mm from the edge */
}

/* ---- spheres ---- */

static double sphere_r;
static void sphere_pos(double s, double t, double o[3])
{
    double phi = DM_2PI * s, theta = DM_PI * t;
    o[0] = sphere_r * sin(theta) * cos(phi), o[1] = sphere_r * sin(theta) * sin(phi), o[2] = -sphere_r * cos(theta);
}
static void sphere_uv(double s, double t, double o[3]) { o[0] = s, o[1] = t, o[2] = 0; }

static void sphere_counts(double radius, double seam_mm, long counts[DM_REF_REGION_COUNT])
{
    dm_mesh m;
    sphere_r = radius;
    grid_mesh(64, 32, sphere_pos, sphere_uv, &m);
    dm_ref_regions *r = NULL;
    dm_error err = {0};
    dm_ref_regions_options o = {.seam_mm = seam_mm};
    cr_assert_eq(dm_ref_regions_create(&m, 1.0, &o, &r, &err), DM_OK);
    memset(counts, 0, sizeof(long) * DM_REF_REGION_COUNT);
    for (int32_t t = 0; t < m.triangle_count; ++t) ++counts[dm_ref_regions_classify(r, t, 1 / 3.0, 1 / 3.0)];
    dm_ref_regions_destroy(r), dm_mesh_free(&m);
}

Test(ref_regions, sphere_of_50mm_is_smooth_away_from_its_seam)
{
    long n[DM_REF_REGION_COUNT];
    sphere_counts(50, 0, n);
    cr_expect_eq(n[DM_REF_REGION_THIN], 0);
    /* the seam meridian (and the poles' fans) take a few columns; the rest is smooth */
    cr_expect_gt(n[DM_REF_REGION_SMOOTH], 64 * 32 * 2 * 3 / 4, "smooth %ld seam %ld", n[0], n[1]);
}

Test(ref_regions, sphere_of_2mm_is_thin_everywhere)
{
    long n[DM_REF_REGION_COUNT];
    sphere_counts(2, 0.01, n);
    cr_expect_eq(n[DM_REF_REGION_SMOOTH], 0, "smooth %ld seam %ld thin %ld", n[0], n[1], n[2]);
    cr_expect_gt(n[DM_REF_REGION_THIN], 64 * 32 * 2 * 9 / 10);
}

Test(ref_regions, bad_arguments)
{
    dm_mesh m;
    plane_two_charts(&m);
    dm_ref_regions *r = (dm_ref_regions *)&m;
    dm_error err = {0};
    cr_expect_eq(dm_ref_regions_create(&m, 0, NULL, &r, &err), DM_ERR_RANGE);
    cr_expect_null(r);
    cr_expect_eq(dm_ref_regions_create(&m, NAN, NULL, &r, &err), DM_ERR_RANGE);
    cr_expect_eq(dm_ref_regions_create(&m, 1, &(dm_ref_regions_options){.seam_mm = -1}, &r, &err), DM_ERR_RANGE);
    cr_expect_eq(dm_ref_regions_create(&m, 1, &(dm_ref_regions_options){.thin_mm = INFINITY}, &r, &err), DM_ERR_RANGE);
    dm_mesh_free(&m);
}

/* ---- weighted statistics ---- */

Test(ref_regions, weighted_mean_and_p95)
{
    /* two texels: errors 10 % (weight 3) and 50 % (weight 1) */
    float ref[8] = {1, 1, 1, 1, 1, 1, 1, 1}, ren[8] = {1.1f, 1.1f, 1.1f, 1, 1.5f, 1.5f, 1.5f, 1};
    float w[2] = {3, 1};
    dm_ref_error_stats st;
    dm_error err = {0};
    cr_assert_eq(dm_ref_error_stats_compute(ref, ren, w, NULL, -1, 2, &st, &err), DM_OK);
    cr_expect_eq(st.count, 2);
    cr_expect(fabs(st.mean[0] - 0.2) < 1e-6, "mean %g", st.mean[0]);
    cr_expect(fabs(st.p95[0] - 0.5) < 1e-6, "p95 %g", st.p95[0]); /* 10 % carries only 75 % */
    w[0] = 19;
    cr_assert_eq(dm_ref_error_stats_compute(ref, ren, w, NULL, -1, 2, &st, &err), DM_OK);
    cr_expect(fabs(st.p95[1] - 0.1) < 1e-6, "p95 %g", st.p95[1]); /* 10 % carries 95 % */
    cr_expect(fabs(st.max[2] - 0.5) < 1e-6);
    /* unweighted, a region, coverage */
    uint8_t label[2] = {DM_REF_REGION_SEAM, DM_REF_REGION_THIN};
    cr_assert_eq(dm_ref_error_stats_compute(ref, ren, NULL, label, DM_REF_REGION_THIN, 2, &st, &err), DM_OK);
    cr_expect_eq(st.count, 1);
    cr_expect(fabs(st.mean[0] - 0.5) < 1e-6);
    cr_expect_eq(dm_ref_error_stats_compute(ref, ren, NULL, label, DM_REF_REGION_SMOOTH, 2, &st, &err), DM_ERR_EMPTY);
    ren[3] = 0; /* not covered in the render */
    cr_assert_eq(dm_ref_error_stats_compute(ref, ren, NULL, NULL, -1, 2, &st, &err), DM_OK);
    cr_expect_eq(st.count, 1);
    /* a black reference texel uses the floor: 1 % of the weighted mean (here 0.5) */
    float ref2[8] = {0, 0, 0, 1, 1, 1, 1, 1}, ren2[8] = {0.005f, 0, 0, 1, 1, 1, 1, 1};
    cr_assert_eq(dm_ref_error_stats_compute(ref2, ren2, NULL, NULL, -1, 2, &st, &err), DM_OK);
    cr_expect(fabs(st.floor[0] - 0.005) < 1e-9);
    cr_expect(fabs(st.max[0] - 1.0) < 1e-5, "max %g", st.max[0]);
}
