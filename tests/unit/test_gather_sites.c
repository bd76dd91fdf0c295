/* The thin gather's quadrature sites (bake/dm_gather_sites.h): their areas add up to the
 * surface's exactly (also with zero-UV-area and mirrored triangles, and on the head), each lies
 * on its plate where its UV says, within the radius of its first piece, and their coarse groups
 * partition them. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_gather_sites.h"
#include "mesh/dm_uv_raster.h"
#include "../common/thin_sheet.h"

enum { N = 256 };
#define S_MM 1.0

static int32_t *coverage(const dm_mesh *m, int n)
{
    int32_t *tri = malloc(sizeof *tri * (size_t)n * n);
    dm_error err = {0};
    cr_assert_eq(dm_uv_raster(m, NULL, n, n, 0, tri, NULL, &err), DM_OK, "%s", err.detail);
    return tri;
}

static double total_area(const dm_mesh *m, double mm)
{
    double a = 0;
    for (int32_t t = 0; t < m->triangle_count; ++t) a += dm_mesh_triangle_area(m, t) * mm * mm;
    return a;
}

static double site_sum(const dm_gather_sites *s)
{
    double a = 0;
    for (int64_t i = 0; i < s->count; ++i) a += s->area[i];
    return a + s->dropped_mm2;
}

/* On the sheet each site's point is where its UV puts it on its plate (the charts are affine:
 * the area-weighted mean UV maps to the mean point), its normal the plate's. */
Test(gather_sites, on_the_sheet_areas_are_exact_and_points_match_their_uv)
{
    dm_mesh m;
    thin_sheet_mesh(S_MM, &m);
    int32_t *tri = coverage(&m, N);
    dm_gather_sites s;
    dm_error err = {0};
    cr_assert_eq(dm_gather_sites_build(&m, tri, N, 1.0, 2, 0.85, &s, &err), DM_OK, "%s", err.detail);
    cr_assert_float_eq(site_sum(&s), 2 * THIN_SHEET_L * THIN_SHEET_L, 1e-9 * 3200);
    cr_assert(s.dropped_mm2 < 1e-9 * 3200, "dropped %g mm²", s.dropped_mm2);
    /* cells of 2 texels (0.78 mm), 52² on a plate, and a radius of 0.85 mm (less than a cell's
     * diagonal: some cells hold two) */
    cr_assert(s.count > 2 * 2704 && s.count < 2 * 2 * 2704, "%lld sites", (long long)s.count);
    for (int64_t i = 0; i < s.count; ++i) {
        const double *p = s.p + 3 * i, *n = s.nrm + 3 * i;
        int bottom = s.uv[2 * i] > 0.5f;
        double x = (s.uv[2 * i] - (bottom ? 0.55 : 0.05)) / 0.01, y = (s.uv[2 * i + 1] - 0.1) / 0.01;
        cr_assert(fabs(p[0] - x) < 1e-4 && fabs(p[1] - y) < 1e-4 && fabs(p[2] - (bottom ? -S_MM : 0.0)) < 1e-9,
                  "site %lld at (%g, %g, %g), its uv says (%g, %g) on the %s", (long long)i, p[0], p[1], p[2], x, y,
                  bottom ? "bottom" : "top");
        cr_assert(fabs(n[2] - (bottom ? -1.0 : 1.0)) < 1e-9);
        cr_assert(s.area[i] > 0 && s.area[i] <= 4 * 0.85 * 0.85 + 1e-9, "a site no larger than its cluster");
        cr_assert_eq(s.island[i], bottom ? 1 : 0);
    }
    dm_gather_sites_free(&s), free(tri), dm_mesh_free(&m);
}

/* Zero-UV-area triangles keep their 3-D area, read at a covered texel near their UV; a mirrored
 * chart (the bottom's u flipped) gives the same areas. */
Test(gather_sites, zero_uv_area_and_mirrored_triangles_keep_their_area)
{
    dm_mesh m;
    thin_sheet_mesh(S_MM, &m);
    for (int t = 52; t < 60; t += 2) /* collapse a few triangles' UVs onto their first corner: inside the */
        for (int c = 1; c < 3; ++c)  /* plate, where the other triangle of their cell stays covered */ m.uvs[(3 * t + c) * 2] = m.uvs[6 * t], m.uvs[(3 * t + c) * 2 + 1] = m.uvs[6 * t + 1];
    for (int t = m.triangle_count / 2; t < m.triangle_count; ++t) /* the bottom plate mirrored in u */
        for (int c = 0; c < 3; ++c) m.uvs[(3 * t + c) * 2] = 1.5f - m.uvs[(3 * t + c) * 2];
    int32_t *tri = coverage(&m, N);
    dm_gather_sites s;
    dm_error err = {0};
    cr_assert_eq(dm_gather_sites_build(&m, tri, N, 1.0, 4, 1.6, &s, &err), DM_OK, "%s", err.detail);
    cr_assert_float_eq(site_sum(&s), total_area(&m, 1.0), 1e-9 * 3200);
    cr_assert(s.dropped_mm2 < 1e-9 * 3200, "every collapsed triangle has covered texels near its UV");
    for (int64_t i = 0; i < s.count; ++i) { /* every site reads a covered texel among the 2 × 2 around its UV */
        double x = s.uv[2 * i] * N - 0.5, y = s.uv[2 * i + 1] * N - 0.5;
        int x0 = (int)floor(x), y0 = (int)floor(y), any = 0;
        for (int j = 0; j < 2; ++j)
            for (int k = 0; k < 2; ++k) {
                int xx = x0 + k, yy = y0 + j;
                any |= xx >= 0 && yy >= 0 && xx < N && yy < N && tri[yy * N + xx] >= 0;
            }
        cr_assert(any, "site %lld reads nothing at (%g, %g)", (long long)i, s.uv[2 * i], s.uv[2 * i + 1]);
    }
    dm_gather_sites_free(&s), free(tri), dm_mesh_free(&m);
}

/* Sliver triangles, their UV images a hair (1e-9 UV) off a line: no site strays off the sheet
 * (the centroid's barycentrics of a clipped sliver are rounding), and the areas still add up; a
 * triangle of zero 3-D area (its corners one vertex) gives no site and no NaN. */
Test(gather_sites, slivers_stay_on_the_surface)
{
    dm_mesh m;
    thin_sheet_mesh(S_MM, &m);
    for (int t = 40; t < 48; ++t) { /* corner 2 onto the line through corners 0 and 1, a hair off it */
        float *uv = m.uvs + 6 * t;
        uv[4] = 0.5f * (uv[0] + uv[2]) + 1e-9f, uv[5] = 0.5f * (uv[1] + uv[3]) - 1e-9f;
    }
    m.indices[3 * 70 + 1] = m.indices[3 * 70 + 2] = m.indices[3 * 70]; /* zero 3-D area */
    int32_t *tri = coverage(&m, N);
    dm_gather_sites s;
    dm_error err = {0};
    cr_assert_eq(dm_gather_sites_build(&m, tri, N, 1.0, 2, 0.85, &s, &err), DM_OK, "%s", err.detail);
    for (int64_t i = 0; i < s.count; ++i) {
        const double *p = s.p + 3 * i;
        cr_assert(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]) && s.area[i] > 0);
        cr_assert(p[0] >= -1e-9 && p[0] <= THIN_SHEET_L + 1e-9 && p[1] >= -1e-9 && p[1] <= THIN_SHEET_L + 1e-9 &&
                      p[2] >= -S_MM - 1e-9 && p[2] <= 1e-9,
                  "site %lld at (%g, %g, %g), off the sheet", (long long)i, p[0], p[1], p[2]);
    }
    cr_assert_float_eq(site_sum(&s), total_area(&m, 1.0), 1e-9 * 3200);
    dm_gather_sites_free(&s), free(tri), dm_mesh_free(&m);
}

/* A chart far from any covered texel (its triangles left out of the coverage): its sites are
 * dropped and their area counted. */
Test(gather_sites, sites_with_nothing_to_read_are_dropped_and_counted)
{
    dm_mesh m;
    thin_sheet_mesh(S_MM, &m);
    int32_t *tri = coverage(&m, N);
    for (size_t i = 0; i < (size_t)N * N; ++i)
        if (tri[i] >= m.triangle_count / 2) tri[i] = -1; /* the bottom plate unlit */
    dm_gather_sites s;
    dm_error err = {0};
    cr_assert_eq(dm_gather_sites_build(&m, tri, N, 1.0, 2, 0.85, &s, &err), DM_OK, "%s", err.detail);
    cr_assert_float_eq(s.dropped_mm2, THIN_SHEET_L * THIN_SHEET_L, 1e-6);
    cr_assert_float_eq(site_sum(&s), 2 * THIN_SHEET_L * THIN_SHEET_L, 1e-6);
    for (int64_t i = 0; i < s.count; ++i) cr_assert(s.uv[2 * i] < 0.5f);
    dm_gather_sites_free(&s), free(tri), dm_mesh_free(&m);
}

/* Coarse sites: each fine site in exactly one, the coarse area their sum, the coarse point their
 * area-weighted mean; fewer of them; bad options refused. */
Test(gather_sites, coarse_sites_partition_the_fine_ones)
{
    dm_mesh m;
    thin_sheet_mesh(S_MM, &m);
    int32_t *tri = coverage(&m, N), *first = NULL, *children = NULL;
    dm_gather_sites f, c;
    dm_error err = {0};
    cr_assert_eq(dm_gather_sites_build(&m, tri, N, 1.0, 2, 0.85, &f, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_gather_sites_coarsen(&f, tri, N, 4, 1.3, &c, &first, &children, &err), DM_OK, "%s", err.detail);
    cr_assert(c.count > 0 && c.count < f.count / 2, "%lld coarse of %lld", (long long)c.count, (long long)f.count);
    char *seen = calloc((size_t)f.count, 1);
    cr_assert_eq(first[0], 0);
    cr_assert_eq(first[c.count], f.count);
    for (int64_t k = 0; k < c.count; ++k) {
        double a = 0, p[3] = {0, 0, 0};
        for (int32_t q = first[k]; q < first[k + 1]; ++q) {
            int32_t i = children[q];
            cr_assert(i >= 0 && i < f.count && !seen[i]);
            seen[i] = 1, a += f.area[i];
            for (int d = 0; d < 3; ++d) p[d] += f.area[i] * f.p[3 * i + d];
            cr_assert_eq(f.island[i], c.island[k]);
            double d2 = 0;
            for (int d = 0; d < 3; ++d) d2 += (f.p[3 * i + d] - f.p[3 * children[first[k]] + d]) * (f.p[3 * i + d] - f.p[3 * children[first[k]] + d]);
            cr_assert(d2 <= 1.3 * 1.3 + 1e-12, "a fine site farther than the radius from its group's first");
        }
        cr_assert_float_eq(c.area[k], a, 1e-12 * a);
        for (int d = 0; d < 3; ++d) cr_assert(fabs(c.p[3 * k + d] - p[d] / a) < 1e-9);
    }
    for (int64_t i = 0; i < f.count; ++i) cr_assert(seen[i]);
    free(seen), free(first), free(children), dm_gather_sites_free(&c);
    cr_expect_eq(dm_gather_sites_coarsen(&f, tri, N, 0, 1.3, &c, &first, &children, &err), DM_ERR_RANGE);
    cr_expect_eq(dm_gather_sites_build(&m, tri, N, 1.0, 2, 0.0, &c, &err), DM_ERR_RANGE);
    cr_expect_eq(dm_gather_sites_build(&m, tri, N, NAN, 2, 0.85, &c, &err), DM_ERR_RANGE);
    cr_expect(c.p == NULL && c.count == 0);
    dm_gather_sites_free(&f), free(tri), dm_mesh_free(&m);
}

/* The head at 512²: the sites' areas are the mesh's (the eyes' zero-UV-area triangles among them)
 * to 1e-9, none dropped, the same sites built twice. */
Test(gather_sites, the_head_keeps_its_area, .timeout = 60)
{
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(DERMIS_ASSETS "/lps/LeePerrySmith.obj", NULL, &m, &err), DM_OK, "%s", err.detail);
    int32_t *tri = coverage(&m, 512);
    dm_gather_sites a, b;
    cr_assert_eq(dm_gather_sites_build(&m, tri, 512, 50.0, 2, 1.6, &a, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_gather_sites_build(&m, tri, 512, 50.0, 2, 1.6, &b, &err), DM_OK, "%s", err.detail);
    double whole = total_area(&m, 50.0);
    cr_log_info("head at 512: %lld sites, %.1f of %.1f mm², %.3g dropped", (long long)a.count, site_sum(&a), whole, a.dropped_mm2);
    cr_assert(fabs(site_sum(&a) / whole - 1) < 1e-9, "sites %.6f mm², mesh %.6f mm²", site_sum(&a), whole);
    cr_assert(a.dropped_mm2 < 1e-6 * whole);
    cr_assert(a.count == b.count && !memcmp(a.p, b.p, sizeof(double) * 3 * (size_t)a.count) &&
              !memcmp(a.uv, b.uv, sizeof(float) * 2 * (size_t)a.count));
    dm_gather_sites_free(&a), dm_gather_sites_free(&b), free(tri), dm_mesh_free(&m);
}
