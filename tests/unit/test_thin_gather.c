/* The thin gather's bake (bake/dm_thin_gather.h) on a thin sheet (tests/common/thin_sheet.h):
 * every tap's weight against the formula over the sites (fine: min(G·A, cap); coarse: the sum of
 * its fine sites'), each level's weights against the closed form for a plane across
 * (e^(−s²/2v) · (1 − e^(−(r² − s²)/2v)), r the reach) and for its own plane, which texels gather
 * (near a surface facing away, near a seam), the header, threads, bad options and zero-UV-area
 * triangles. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_gather_sites.h"
#include "bake/dm_thin_gather.h"
#include "mesh/dm_uv_raster.h"
#include "../common/thin_sheet.h"

enum { N = 256 };
#define S_MM 1.0
#define PI 3.14159265358979323846
static const double V[2] = {1.99, 7.41}; /* gems3-skin's two widest levels, mm² */

static dm_thin_gather_options options(int threads)
{
    dm_thin_gather_options o = {N, 1.0, 4, 2, {V[0], V[1]}, 2.0 * sqrt(V[1]), 1.1 * sqrt(V[1]), threads, 0, 0};
    return o;
}

static void bake(const dm_mesh *m, int threads, dm_thin_gather *g, dm_thin_gather_stats *st)
{
    dm_error err = {0};
    dm_thin_gather_options o = options(threads);
    cr_assert_eq(dm_thin_gather_bake(m, &o, g, st, &err), DM_OK, "%s", err.detail);
}

/* Sheet point (x, y) of side `bottom` from texel (i, j), or false off the charts. */
static bool texel_xy(int i, int j, int *bottom, double *x, double *y)
{
    double u = (i + 0.5) / N, v = (j + 0.5) / N;
    *bottom = u > 0.5;
    *x = (u - (*bottom ? 0.55 : 0.05)) / 0.01, *y = (v - 0.1) / 0.01;
    return *x > 0 && *x < THIN_SHEET_L && *y > 0 && *y < THIN_SHEET_L;
}

/* Texel (i, j)'s index entry and sheet point q, or NULL off the charts. */
static const float *sheet_texel(const dm_thin_gather *g, int i, int j, int *bottom, double q[3])
{
    if (!texel_xy(i, j, bottom, &q[0], &q[1])) return NULL;
    q[2] = *bottom ? -S_MM : 0.0;
    return g->index + 4 * ((size_t)j * N + i);
}

/* A level's weights across and on its own plate against the plane's closed forms, truncated at
 * the reach r = 3.5 σ: the quadrature over sites of 0.6 σ (coarse ones of 0.9 σ from 2 σ on)
 * within 0.5 %; the larger departure folded into *worst. */
static void plane_check(double v, double across, double own, int i, int j, int l, double *worst)
{
    double r = 3.5 * sqrt(v);
    double cf_across = exp(-S_MM * S_MM / (2 * v)) * (1 - exp(-(r * r - S_MM * S_MM) / (2 * v)));
    double cf_own = 1 - exp(-r * r / (2 * v)), e = fmax(fabs(across / cf_across - 1), fabs(own / cf_own - 1));
    *worst = fmax(*worst, e);
    cr_assert_lt(e, 5e-3, "(%d, %d) level %d: across %.5f (plane %.5f), own %.5f (plane %.5f)", i, j, l, across, cf_across,
                 own, cf_own);
}

/* A site's weight for a texel at q, as dm_thin_gather.h defines it. */
static double weight(double v, const double *q, const double *p, double a)
{
    double d2 = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]);
    return fmin(exp(-d2 / (2 * v)) / (2 * PI * v) * a, -expm1(-a / (2 * PI * v)));
}

Test(thin_gather, a_sheet_gathers_the_plane_across_by_its_closed_form)
{
    dm_mesh m;
    thin_sheet_mesh(S_MM, &m);
    dm_thin_gather g;
    dm_thin_gather_stats st;
    bake(&m, 0, &g, &st);
    cr_assert_eq(g.first_level, 4);
    cr_assert_eq(g.level_count, 2);
    cr_assert(g.taps[0] == 4.0f && g.taps[1] == 2.0f && g.taps[2] == -2.0f && g.taps[3] == (float)(g.sites[0] + g.sites[1]));
    /* a texel is 0.39 mm: cells of 2 (0.78 mm ≤ σ 1.41) and 4 texels (1.56 mm ≤ σ 2.72) */
    cr_assert(g.cell[0] == 2 && g.cell[1] == 4, "cells %d, %d", g.cell[0], g.cell[1]);
    /* the sites again, as the header describes them: level 0's fine and coarse, then level 1's */
    int32_t *tri = malloc(sizeof *tri * N * N), *first[2], *children[2];
    dm_error err = {0};
    cr_assert_eq(dm_uv_raster(&m, NULL, N, N, 0, tri, NULL, &err), DM_OK);
    dm_gather_sites fine[2], coarse[2];
    int64_t base[2] = {2, 0};
    for (int l = 0; l < 2; ++l) {
        double sigma = sqrt(V[l]);
        cr_assert_eq(dm_gather_sites_build(&m, tri, N, 1.0, g.cell[l], 0.6 * sigma, &fine[l], &err), DM_OK);
        cr_assert_eq(dm_gather_sites_coarsen(&fine[l], tri, N, 2 * g.cell[l], 0.9 * sigma, &coarse[l], &first[l], &children[l], &err), DM_OK);
        if (l) base[1] = base[0] + fine[0].count + coarse[0].count;
        cr_assert_eq(g.sites[l], fine[l].count + coarse[l].count);
        for (int64_t i = 0; i < fine[l].count; ++i) /* the sites' UVs in the taps texture */
            cr_assert(g.taps[2 * (base[l] + i)] == fine[l].uv[2 * i] && g.taps[2 * (base[l] + i) + 1] == fine[l].uv[2 * i + 1]);
    }
    int checked = 0, coarse_taps = 0;
    double worst = 0;
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            int bottom;
            double q[3];
            const float *ix = sheet_texel(&g, i, j, &bottom, q);
            if (!ix) continue;
            cr_assert(ix[1] > 0 && ix[2] > 0, "(%d, %d): a plate 1 mm across gathers everywhere", i, j);
            if (!(q[0] > 12 && q[0] < 28 && q[1] > 12 && q[1] < 28)) continue; /* the reach (9.5 mm) inside the plates */
            size_t t = (size_t)ix[0] * DM_THIN_GATHER_TAPS_WIDTH + (size_t)ix[3];
            for (int l = 0; l < 2; ++l) {
                double across = 0, own = 0;
                for (int k = 0; k < (int)ix[1 + l]; ++k, ++t) {
                    int64_t s = (int64_t)g.taps[2 * t] - base[l];
                    double w = 0;
                    const double *p;
                    if (s < fine[l].count) {
                        cr_assert(s >= 0, "a tap of level %d reads another level's site", l);
                        p = fine[l].p + 3 * s, w = weight(V[l], q, p, fine[l].area[s]);
                    } else {
                        int64_t c = s - fine[l].count;
                        cr_assert(c < coarse[l].count);
                        p = coarse[l].p + 3 * c, ++coarse_taps;
                        for (int32_t f = first[l][c]; f < first[l][c + 1]; ++f)
                            w += weight(V[l], q, fine[l].p + 3 * (size_t)children[l][f], fine[l].area[children[l][f]]);
                    }
                    /* float UVs and positions put the texel's point within ~5e-6 mm of (x, y): a
                     * weight moves by up to d·δ/v ≤ 9.5 · 5e-6 / 1.99 = 2.4e-5 of itself */
                    cr_assert(fabs(g.taps[2 * t + 1] - w) <= 5e-5 * w, "(%d, %d) level %d tap %d: %.8g, the formula %.8g", i,
                              j, l, k, g.taps[2 * t + 1], w);
                    ((p[2] < -0.5 * S_MM) == (bottom != 0) ? &own : &across)[0] += g.taps[2 * t + 1];
                }
                plane_check(V[l], across, own, i, j, l, &worst);
            }
            ++checked;
        }
    cr_log_info("sheet: %d texels, a level's sum off its plane's closed form by %.2e at most", checked, worst);
    cr_assert_gt(checked, 3000);
    cr_assert_gt(coarse_taps, checked);
    cr_assert_eq(st.gathering_texels, st.covered_texels);
    cr_assert_eq(st.thin_texels, st.covered_texels, "every texel faces the other plate");
    for (int l = 0; l < 2; ++l) {
        dm_gather_sites_free(&fine[l]), dm_gather_sites_free(&coarse[l]);
        free(first[l]), free(children[l]);
    }
    free(tri), dm_thin_gather_free(&g), dm_mesh_free(&m);
}

/* The top plate alone: no surface faces away, so only the texels near its rim (a boundary: a seam
 * of the atlas) gather, those within seam_mm; with seam_mm 0 nothing does. */
Test(thin_gather, a_lone_plate_gathers_only_near_its_rim)
{
    dm_mesh sheet, m;
    thin_sheet_mesh(S_MM, &sheet);
    /* the top plate alone: the sheet's first half of triangles and their vertices */
    dm_error err = {0};
    cr_assert_eq(dm_mesh_alloc(sheet.vertex_count / 2, sheet.triangle_count / 2, &m, &err), DM_OK);
    memcpy(m.positions, sheet.positions, sizeof(float) * 3 * (size_t)m.vertex_count);
    memcpy(m.indices, sheet.indices, sizeof(uint32_t) * 3 * (size_t)m.triangle_count);
    memcpy(m.uvs, sheet.uvs, sizeof(float) * 6 * (size_t)m.triangle_count);
    dm_mesh_compute_normals(&m);
    dm_thin_gather g;
    dm_thin_gather_stats st;
    bake(&m, 0, &g, &st);
    cr_assert_gt(st.covered_texels, 10000);
    cr_assert_eq(st.thin_texels, 0);
    cr_assert_eq(st.seam_texels, st.gathering_texels);
    const double seam = 1.1 * sqrt(V[1]);
    int near = 0;
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            int bottom;
            double x, y;
            if (!texel_xy(i, j, &bottom, &x, &y) || bottom) continue; /* the bottom chart is gone */
            double rim = fmin(fmin(x, THIN_SHEET_L - x), fmin(y, THIN_SHEET_L - y));
            const float *ix = g.index + 4 * ((size_t)j * N + i);
            bool gathers = ix[1] > 0 && ix[2] > 0;
            /* the rim as points 0.25 mm apart: a texel within seam_mm − 0.125 mm surely finds one */
            if (rim <= seam - 0.125) {
                cr_assert(gathers, "(%d, %d) %.3f mm from the rim does not gather", i, j, rim);
                ++near;
            }
            if (rim > seam) cr_assert(!gathers, "(%d, %d) %.3f mm from the rim gathers", i, j, rim);
        }
    cr_assert_gt(near, 2000);
    dm_thin_gather_free(&g);
    dm_thin_gather_options o = options(0);
    o.seam_mm = 0.0;
    cr_assert_eq(dm_thin_gather_bake(&m, &o, &g, &st, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(st.gathering_texels, 0);
    cr_assert_eq(st.taps, 0);
    for (size_t i = 0; i < (size_t)N * N; ++i) cr_assert(g.index[4 * i + 1] == 0 && g.index[4 * i + 2] == 0);
    dm_thin_gather_free(&g), dm_mesh_free(&m), dm_mesh_free(&sheet);
}

Test(thin_gather, the_same_bytes_for_any_thread_count)
{
    dm_mesh m;
    thin_sheet_mesh(S_MM, &m);
    dm_thin_gather a, b;
    dm_thin_gather_stats sa, sb;
    bake(&m, 1, &a, &sa);
    bake(&m, 2, &b, &sb);
    cr_assert_eq(a.tap_count, b.tap_count);
    cr_assert_eq(a.taps_rows, b.taps_rows);
    cr_assert(!memcmp(a.index, b.index, sizeof(float) * 4 * N * N));
    cr_assert(!memcmp(a.taps, b.taps, sizeof(float) * 2 * DM_THIN_GATHER_TAPS_WIDTH * (size_t)a.taps_rows));
    dm_thin_gather_free(&a), dm_thin_gather_free(&b), dm_mesh_free(&m);
}

Test(thin_gather, zero_uv_area_triangles_leave_nothing_nan)
{
    dm_mesh m;
    thin_sheet_mesh(S_MM, &m);
    for (int t = 0; t < 8; ++t) /* collapse a few triangles' UVs onto one point */
        for (int c = 0; c < 3; ++c) m.uvs[(3 * t + c) * 2] = m.uvs[6 * t], m.uvs[(3 * t + c) * 2 + 1] = m.uvs[6 * t + 1];
    dm_thin_gather g;
    dm_thin_gather_stats st;
    dm_thin_gather_options o = options(0);
    for (o.block = 1; o.block <= 2; ++o.block) { /* alone and in blocks: a group never takes a texel of no area */
        dm_error err = {0};
        cr_assert_eq(dm_thin_gather_bake(&m, &o, &g, &st, &err), DM_OK, "%s", err.detail);
        cr_assert_gt(st.gathering_texels, 10000);
        for (size_t i = 0; i < 4 * (size_t)N * N; ++i) cr_assert(isfinite(g.index[i]));
        for (int64_t t = 0; t < g.tap_count; ++t) cr_assert(isfinite(g.taps[2 * t + 1]) && g.taps[2 * t + 1] >= 0);
        dm_thin_gather_free(&g);
    }
    dm_mesh_free(&m);
}

Test(thin_gather, options_for_a_profile_and_bad_ones)
{
    const double gems3[6] = {0.0064, 0.0484, 0.187, 0.567, 1.99, 7.41};
    dm_thin_gather_options o;
    dm_thin_gather_options_for(gems3, 6, 1024, 50, &o);
    cr_assert(o.first_level == 4 && o.level_count == 2 && o.variance_mm2[0] == 1.99 && o.variance_mm2[1] == 7.41);
    cr_assert_float_eq(o.near_mm, 2 * sqrt(7.41), 1e-12);
    cr_assert_float_eq(o.seam_mm, 1.1 * sqrt(7.41), 1e-12);
    const double narrow[3] = {0.01, 0.1, 0.5};
    dm_thin_gather_options_for(narrow, 3, 1024, 50, &o);
    cr_assert_eq(o.level_count, 0, "no level as wide as 1 mm: nothing to gather");
    /* the dipole fitted by 8 Gaussians: every level of σ ≥ 1 mm, four of them */
    const double skin8[8] = {0.0547, 0.123, 0.278, 0.648, 1.617, 4.495, 13.22, 39.63};
    dm_thin_gather_options_for(skin8, 8, 1024, 50, &o);
    cr_assert(o.first_level == 4 && o.level_count == 4 && o.variance_mm2[0] == 1.617 && o.variance_mm2[3] == 39.63);
    cr_assert(o.block == 0 && o.taps_max == 0, "blocks as the taps need");
    /* six of σ ≥ 1 mm: the widest four */
    const double six[7] = {0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0};
    dm_thin_gather_options_for(six, 7, 1024, 50, &o);
    cr_assert(o.first_level == 3 && o.level_count == 4 && o.variance_mm2[0] == 3.0);
    dm_mesh m;
    thin_sheet_mesh(S_MM, &m);
    dm_thin_gather g;
    dm_error err = {0};
    dm_thin_gather_options bad[5] = {options(0), options(0), options(0), options(0), options(0)};
    bad[0].size = 0, bad[1].level_count = DM_THIN_GATHER_LEVELS + 1, bad[2].variance_mm2[1] = NAN, bad[3].near_mm = -1, bad[4].seam_mm = -1;
    for (int k = 0; k < 5; ++k) {
        cr_expect_eq(dm_thin_gather_bake(&m, &bad[k], &g, NULL, &err), DM_ERR_RANGE, "bad option %d", k);
        cr_expect(g.index == NULL && g.taps == NULL);
    }
    dm_mesh_free(&m);
}

/* The head at 256² with gems3-skin's widest levels: which texels gather and how many taps, held
 * to what the bake gives today within 1 % (a tenth more or less of near_mm, seam_mm, the reach or
 * the sites' size moves them further); every weight finite and ≥ 0, each texel's sum per level
 * (the light of a uniformly lit surface: 1 on a plane, about 2 between two close sheets, less at
 * the neck's open rim) within (0.8, 2.5), and the same bytes for 1 and 2 threads. */
Test(thin_gather, the_head, .timeout = 120)
{
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(DERMIS_ASSETS "/lps/LeePerrySmith.obj", NULL, &m, &err), DM_OK, "%s", err.detail);
    const double gems3[6] = {0.0064, 0.0484, 0.187, 0.567, 1.99, 7.41};
    dm_thin_gather_options o;
    dm_thin_gather_options_for(gems3, 6, 256, 50.0, &o);
    o.threads = 1;
    dm_thin_gather a, b;
    dm_thin_gather_stats st;
    cr_assert_eq(dm_thin_gather_bake(&m, &o, &a, &st, &err), DM_OK, "%s", err.detail);
    o.threads = 2;
    cr_assert_eq(dm_thin_gather_bake(&m, &o, &b, NULL, &err), DM_OK, "%s", err.detail);
    cr_assert(!memcmp(a.index, b.index, sizeof(float) * 4 * 256 * 256) &&
              !memcmp(a.taps, b.taps, sizeof(float) * 2 * DM_THIN_GATHER_TAPS_WIDTH * (size_t)a.taps_rows));
    cr_log_info("head at 256: %lld of %lld texels gather (%lld near a surface facing away, %lld near a seam), %lld taps, "
                "%lld + %lld sites, cells %d %d, texel %.4f mm", (long long)st.gathering_texels, (long long)st.covered_texels,
                (long long)st.thin_texels, (long long)st.seam_texels, (long long)st.taps, (long long)st.sites[0],
                (long long)st.sites[1], st.cell[0], st.cell[1], st.texel_mm);
    cr_expect_eq(st.covered_texels, 60007);
    cr_expect(fabs(st.gathering_texels / 3997.0 - 1) < 0.01, "gathering texels %lld", (long long)st.gathering_texels);
    cr_expect(fabs(st.taps / 837763.0 - 1) < 0.01, "taps %lld", (long long)st.taps);
    cr_expect(st.cell[0] == 1 && st.cell[1] == 1 && fabs(st.texel_mm - 1.941) < 0.001);
    double most = 0, least = 1e9;
    for (size_t i = 0; i < (size_t)256 * 256; ++i) {
        const float *ix = a.index + 4 * i;
        size_t t = (size_t)ix[0] * DM_THIN_GATHER_TAPS_WIDTH + (size_t)ix[3];
        for (int l = 0; l < 2 && ix[1] > 0; ++l) {
            double sum = 0;
            for (int k = 0; k < (int)ix[1 + l]; ++k, ++t) {
                cr_assert(isfinite(a.taps[2 * t + 1]) && a.taps[2 * t + 1] >= 0);
                sum += a.taps[2 * t + 1];
            }
            most = fmax(most, sum), least = fmin(least, sum);
        }
    }
    cr_log_info("a texel's weights per level sum to %.3f..%.3f", least, most);
    cr_expect(least > 0.8 && most < 2.5, "sums %.3f..%.3f (measured 0.863..2.385)", least, most);
    dm_thin_gather_free(&a), dm_thin_gather_free(&b), dm_mesh_free(&m);
}

/* The sheet with its bottom chart moved against the top one in UV (u from 0.4505): texel column
 * 115 is the bottom plate's first, 114 the top plate's last, in one 2 × 2 block but 40 mm apart. */
#define ABUT_U 0.4505
static void abutting_sheet(dm_mesh *m)
{
    thin_sheet_mesh(S_MM, m);
    for (int t = 0; t < m->triangle_count; ++t)
        for (int c = 0; c < 3; ++c)
            if (m->uvs[(3 * t + c) * 2] > 0.5f) m->uvs[(3 * t + c) * 2] -= (float)(0.55 - ABUT_U);
}

/* Texel (i, j)'s point on the abutting sheet, or false off the charts. */
static bool abut_point(int i, int j, double q[3])
{
    double u = (i + 0.5) / N, v = (j + 0.5) / N;
    int bottom = u > ABUT_U;
    q[0] = (u - (bottom ? ABUT_U : 0.05)) / 0.01, q[1] = (v - 0.1) / 0.01, q[2] = bottom ? -S_MM : 0.0;
    return q[0] > 0 && q[0] < THIN_SHEET_L && q[1] > 0 && q[1] < THIN_SHEET_L && (bottom || u < 0.45);
}

/* Texel i's sum of gathered level l under the light 1 + u + 0.5 v at each site's UV, in double. */
static double lit_sum(const dm_thin_gather *g, size_t i, int l)
{
    const float *ix = g->index + 4 * i;
    size_t t = (size_t)ix[0] * DM_THIN_GATHER_TAPS_WIDTH + (size_t)ix[3] + (l ? (size_t)ix[1] : 0);
    double sum = 0;
    for (int k = 0; k < (int)ix[1 + l]; ++k, ++t) {
        const float *uv = g->taps + 2 * (size_t)g->taps[2 * t];
        sum += g->taps[2 * t + 1] * (1.0 + uv[0] + 0.5 * uv[1]);
    }
    return sum;
}

/* Blocks of 2 × 2 texels sharing one run of taps: each texel's sums are the mean of its group's
 * own sums (texels alone), a group never spans the two plates where their charts touch in UV,
 * the taps are under 40 % of the texels' own, and the same bytes for 1 and 2 threads. */
Test(thin_gather, blocks_share_the_mean_of_their_texels_taps)
{
    dm_mesh m;
    abutting_sheet(&m);
    dm_thin_gather one, two, two_b;
    dm_thin_gather_stats s1, s2;
    dm_error err = {0};
    dm_thin_gather_options o = options(2);
    o.block = 1;
    cr_assert_eq(dm_thin_gather_bake(&m, &o, &one, &s1, &err), DM_OK, "%s", err.detail);
    o.block = 2;
    cr_assert_eq(dm_thin_gather_bake(&m, &o, &two, &s2, &err), DM_OK, "%s", err.detail);
    o.threads = 1;
    cr_assert_eq(dm_thin_gather_bake(&m, &o, &two_b, NULL, &err), DM_OK, "%s", err.detail);
    cr_assert(two.tap_count == two_b.tap_count && !memcmp(two.index, two_b.index, sizeof(float) * 4 * N * N) &&
              !memcmp(two.taps, two_b.taps, sizeof(float) * 2 * DM_THIN_GATHER_TAPS_WIDTH * (size_t)two.taps_rows));
    cr_assert(one.block == 1 && two.block == 2 && s2.block == 2);
    cr_assert_eq(s2.gathering_texels, s1.gathering_texels, "every covered texel of the sheet gathers");
    cr_log_info("blocks of 2: %lld taps against %lld alone", (long long)s2.taps, (long long)s1.taps);
    cr_assert_lt((double)s2.taps, 0.4 * (double)s1.taps);
    int groups = 0, straddling = 0;
    double worst = 0;
    for (int j = 0; j < N; j += 2)
        for (int i = 0; i < N; i += 2) {
            /* the block's texels by the run they read */
            size_t t[4];
            int count = 0;
            for (int k = 0; k < 4; ++k) {
                size_t x = (size_t)(i + (k & 1)), y = (size_t)(j + (k >> 1)), ix = y * N + x;
                if (two.index[4 * ix + 1] > 0) t[count++] = ix;
            }
            bool plates[2] = {false, false};
            for (int a = 0; a < count; ++a) {
                double qa[3];
                cr_assert(abut_point((int)(t[a] % N), (int)(t[a] / N), qa), "texel %zu gathers off the plates", t[a]);
                plates[qa[2] < 0] = true;
                for (int l = 0; l < 2; ++l) {
                    double mean = 0;
                    int members = 0;
                    for (int b = 0; b < count; ++b) {
                        if (two.index[4 * t[b]] != two.index[4 * t[a]] || two.index[4 * t[b] + 3] != two.index[4 * t[a] + 3])
                            continue;
                        double qb[3];
                        abut_point((int)(t[b] % N), (int)(t[b] / N), qb);
                        cr_assert(qa[2] == qb[2] && hypot(qa[0] - qb[0], qa[1] - qb[1]) < 2 * 1.5 * 0.3907,
                                  "texels %zu and %zu share a run %.1f mm apart", t[a], t[b], hypot(qa[0] - qb[0], qa[1] - qb[1]));
                        mean += lit_sum(&one, t[b], l), ++members;
                    }
                    mean /= members;
                    double e = fabs(lit_sum(&two, t[a], l) / mean - 1);
                    worst = fmax(worst, e);
                    /* float weights: each within 6e-8 of the members' mean, the sum of a few
                     * hundred positive terms within 1e-6 */
                    cr_assert_lt(e, 1e-5, "texel %zu level %d: %.8g, its group's mean %.8g", t[a], l, lit_sum(&two, t[a], l), mean);
                    if (l == 0 && a == 0) groups += members;
                }
            }
            straddling += plates[0] && plates[1];
            /* a whole block on one plate (texels 0.39 mm apart, its diagonal 0.55, within
             * DM_THIN_GATHER_JOIN · 2 · h = 0.59 mm of the first) is one group */
            if (count == 4 && !(plates[0] && plates[1]))
                for (int a = 1; a < 4; ++a)
                    cr_assert(two.index[4 * t[a]] == two.index[4 * t[0]] && two.index[4 * t[a] + 3] == two.index[4 * t[0] + 3],
                              "block (%d, %d) is not one group", i, j);
        }
    cr_log_info("%d texels in groups, %d blocks on both plates, worst %.2e", groups, straddling, worst);
    cr_assert_geq(straddling, 45, "the blocks across the charts' meeting (one per two rows along its 40 mm: 51) are there to test");
    dm_thin_gather_free(&one), dm_thin_gather_free(&two), dm_thin_gather_free(&two_b), dm_mesh_free(&m);
}

/* block 0 takes the smallest block whose taps fit taps_max (byte for byte that block's bake);
 * none fits: DM_ERR_RANGE, nothing left. */
Test(thin_gather, blocks_grow_until_the_taps_fit)
{
    dm_mesh m;
    thin_sheet_mesh(S_MM, &m);
    dm_thin_gather a, b;
    dm_thin_gather_stats sa, sb;
    dm_error err = {0};
    dm_thin_gather_options o = options(0);
    o.block = 2;
    cr_assert_eq(dm_thin_gather_bake(&m, &o, &a, &sa, &err), DM_OK, "%s", err.detail);
    o.block = 0, o.taps_max = sa.taps; /* block 1 has more: 2 is the smallest that fits */
    cr_assert_eq(dm_thin_gather_bake(&m, &o, &b, &sb, &err), DM_OK, "%s", err.detail);
    cr_assert(b.block == 2 && a.tap_count == b.tap_count && !memcmp(a.index, b.index, sizeof(float) * 4 * N * N) &&
              !memcmp(a.taps, b.taps, sizeof(float) * 2 * DM_THIN_GATHER_TAPS_WIDTH * (size_t)a.taps_rows));
    dm_thin_gather_free(&a), dm_thin_gather_free(&b);
    o.block = 4;
    cr_assert_eq(dm_thin_gather_bake(&m, &o, &a, &sa, &err), DM_OK, "%s", err.detail);
    cr_assert(a.block == 4 && sa.taps < sb.taps);
    dm_thin_gather_free(&a);
    o.block = 0, o.taps_max = sa.taps - 1;
    cr_assert_eq(dm_thin_gather_bake(&m, &o, &b, NULL, &err), DM_ERR_RANGE);
    cr_assert(b.index == NULL && b.taps == NULL && strstr(err.detail, "blocks of 4 x 4"), "%s", err.detail);
    o.block = 3;
    cr_assert_eq(dm_thin_gather_bake(&m, &o, &b, NULL, &err), DM_ERR_RANGE, "block 3 is no power of two");
    dm_mesh_free(&m);
}

/* Four gathered levels (σ 1.3 to 3.1 mm): each gathering texel's run starts with its count tap
 * (levels 2 and 3's taps), and every level's weights over the plates' middle are each plane's
 * truncated closed form within 0.5 %, as two levels' are above. The variances keep each level's
 * cell side at most 0.6 σ, as gems3-skin's two (0.55 and 0.57): the cell grows by powers of two up
 * to σ, and at 0.9–1 σ (σ 1 mm on cells of 0.78, 1.7 on 1.56) a level is 0.6–0.8 % off. */
Test(thin_gather, four_levels_run_behind_their_count_tap)
{
    dm_mesh m;
    thin_sheet_mesh(S_MM, &m);
    const double v[4] = {1.8, 2.3, 7.0, 9.5};
    dm_thin_gather_options o = {N, 1.0, 2, 4, {v[0], v[1], v[2], v[3]}, 2.0 * sqrt(v[3]), 1.1 * sqrt(v[3]), 0, 0, 0};
    dm_thin_gather g;
    dm_thin_gather_stats st;
    dm_error err = {0};
    cr_assert_eq(dm_thin_gather_bake(&m, &o, &g, &st, &err), DM_OK, "%s", err.detail);
    cr_assert(g.taps[0] == 2.0f && g.taps[1] == 4.0f && g.level_count == 4 && g.block == 1);
    int64_t sites = 0;
    for (int l = 0; l < 4; ++l) {
        cr_assert_gt(st.sites[l], 0);
        sites += st.sites[l];
    }
    cr_assert(g.taps[3] == (float)sites);
    int checked = 0;
    double worst = 0;
    for (int k = 0; k < N * N; ++k) {
        int bottom, i = k % N, j = k / N;
        double q[3];
        const float *ix = sheet_texel(&g, i, j, &bottom, q);
        if (!ix) continue;
        cr_assert(ix[1] > 0 && ix[2] > 0);
        size_t t = (size_t)ix[0] * DM_THIN_GATHER_TAPS_WIDTH + (size_t)ix[3];
        const float count[4] = {ix[1], ix[2], g.taps[2 * t], g.taps[2 * t + 1]};
        cr_assert(count[2] > 0 && count[3] > 0, "(%d, %d): the count tap %g %g", i, j, count[2], count[3]);
        ++t;
        if (!(q[0] > 12 && q[0] < 28 && q[1] > 12 && q[1] < 28)) continue;
        for (int l = 0; l < 4; ++l) {
            double across = 0, own = 0;
            for (int n = 0; n < (int)count[l]; ++n, ++t) {
                const float *uv = g.taps + 2 * (size_t)g.taps[2 * t];
                cr_assert(isfinite(g.taps[2 * t + 1]) && g.taps[2 * t + 1] >= 0);
                (uv[0] > 0.5f ? bottom ? &own : &across : bottom ? &across : &own)[0] += g.taps[2 * t + 1];
            }
            plane_check(v[l], across, own, i, j, l, &worst);
        }
        ++checked;
    }
    cr_log_info("four levels: %d texels, off the planes by %.2e at most", checked, worst);
    cr_assert_gt(checked, 3000);
    dm_thin_gather_free(&g), dm_mesh_free(&m);
}

/* The sheet with its charts squashed 3:1 along v: a texel is 0.39 mm along u and 1.17 mm along v
 * (h, the median side, 0.68 mm). In blocks of 2 × 2 only the texels of one row share a run: the
 * next row's lie 1.17 mm away, beyond DM_THIN_GATHER_JOIN · 2 · h = 1.01 mm — a squashed chart's
 * long texels keep their own sums (on the head at 2048² a join of 2 · B · h let them share, and the
 * thin parts' red error doubled: 2.51 → 4.17 %, dm_thin_gather.h). */
Test(thin_gather, blocks_keep_a_squashed_charts_rows_apart)
{
    dm_mesh m;
    thin_sheet_mesh(S_MM, &m);
    for (int k = 0; k < 3 * m.triangle_count; ++k) m.uvs[2 * k + 1] = 0.1f + (m.uvs[2 * k + 1] - 0.1f) / 3.0f;
    dm_thin_gather g;
    dm_thin_gather_stats st;
    dm_error err = {0};
    dm_thin_gather_options o = options(0);
    o.block = 2;
    cr_assert_eq(dm_thin_gather_bake(&m, &o, &g, &st, &err), DM_OK, "%s", err.detail);
    cr_assert(fabs(st.texel_mm - 0.6766) < 0.001, "h %.4f", st.texel_mm);
    int pairs = 0;
    for (int j = 0; j + 1 < N; j += 2)
        for (int i = 0; i + 1 < N; i += 2) {
            const float *a = g.index + 4 * ((size_t)j * N + i), *b = a + 4, *c = a + 4 * N;
            if (!(a[1] > 0 && b[1] > 0 && c[1] > 0)) continue;
            cr_assert(a[0] != c[0] || a[3] != c[3], "block (%d, %d): rows 1.17 mm apart share a run", i, j);
            pairs += a[0] == b[0] && a[3] == b[3];
        }
    cr_assert_gt(pairs, 1000, "a row's two texels, 0.39 mm apart, share theirs");
    dm_thin_gather_free(&g), dm_mesh_free(&m);
}
