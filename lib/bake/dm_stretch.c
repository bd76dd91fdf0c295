#define _DEFAULT_SOURCE /* madvise, MADV_HUGEPAGE (Linux) */
#include "bake/dm_stretch.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "mesh/dm_gutter.h"
#include "mesh/dm_uv_raster.h"
#include "core/dm_cli.h"
#include "core/dm_math.h"
#include "pack/dm_pack_semantic.h"
#include "core/dm_parallel.h"

void dm_triangle_stretch_of(const dm_mesh *m, int32_t t, double mm_per_unit, dm_triangle_stretch *out)
{
    memset(out, 0, sizeof *out);
    dm_uv_jacobian j;
    dm_mesh_uv_jacobian(m, t, mm_per_unit, &j);
    out->kind = j.kind;
    if (j.kind != DM_TRIANGLE_OK) return;
    out->mirrored = j.det < 0.0;
    out->s_u = fabs(j.det) / j.la;
    out->s_v = fabs(j.det) / j.lb;
    if (!(out->s_u <= DM_PACK_STRETCH_MAX_PER_MM && out->s_v <= DM_PACK_STRETCH_MAX_PER_MM)) {
        /* a sliver: the atlas would span less than a nanometre along it (the pack's bound) */
        out->kind = DM_TRIANGLE_ZERO_AREA;
        out->s_u = out->s_v = 0.0;
        out->mirrored = false;
    }
}

/* Allocates a texture-sized buffer (freed with free()). Large buffers are 2 MiB aligned
 * and offered to transparent huge pages: first-touch page faults were a third of the
 * bake time at 2048² in a VM with 4 KiB pages. */
static void *big_alloc(size_t size)
{
    enum { HUGE = 2u << 20 };
    if (size < HUGE) return malloc(size);
    void *p = NULL;
    if (posix_memalign(&p, HUGE, size) != 0) return NULL;
#ifdef MADV_HUGEPAGE
    madvise(p, (size + HUGE - 1) / HUGE * HUGE, MADV_HUGEPAGE); /* a hint: failure is harmless */
#endif
    return p;
}

void dm_stretch_blur_weights(double w[DM_STRETCH_TAPS])
{
    /* the bin masses of the unit Gaussian at 1σ spacing (dm_blur_taps, lib/core), the tails
     * left out and the rest renormalised to sum to 1 */
    dm_result rc = dm_blur_taps(DM_STRETCH_TAPS, 1.0, 0, w, NULL, NULL);
    assert(rc == DM_OK);
    (void)rc;
    double sum = 0.0;
    for (int k = 0; k < DM_STRETCH_TAPS; ++k) sum += w[k];
    for (int k = 0; k < DM_STRETCH_TAPS; ++k) w[k] /= sum;
}

void dm_stretch_map_free(dm_stretch_map *map)
{
    if (!map) return;
    for (int k = 0; k < DM_PROFILE_MAX_GAUSSIANS; ++k) {
        free(map->s_u[k]);
        free(map->s_v[k]);
    }
    free(map->mask);
    memset(map, 0, sizeof *map);
}

/* ---- base map --------------------------------------------------------------------- */

typedef struct base_job {
    const int32_t *triangle_of;
    const float *tri_su, *tri_sv;
    float *su, *sv, *mask;
    uint8_t *covered;
} base_job;

static void base_texels(void *ctx, size_t begin, size_t end)
{
    base_job *job = ctx;
    for (size_t i = begin; i < end; ++i) {
        int32_t t = job->triangle_of[i];
        int c = t >= 0;
        job->covered[i] = (uint8_t)c;
        job->mask[i] = c ? 1.0f : 0.0f;
        job->su[i] = c ? job->tri_su[t] : 0.0f;
        job->sv[i] = c ? job->tri_sv[t] : 0.0f;
    }
}

/* ---- blur ------------------------------------------------------------------------- */

typedef struct blur_job {
    int width, height;
    float sigma_mm;
    float w[DM_STRETCH_TAPS];
    const float *src_u, *src_v; /* level k−1: the values blurred and the stretch used */
    float *tmp;                 /* after the U pass, (u, v) interleaved: one cache line per tap */
    float *dst_u, *dst_v;       /* level k */
} blur_job;

/* A linear tap at texel position t along a row or column of n texels (t clamped to
 * [0, tmax], tmax = n − 1): the texels i0 and i1 it reads, and the weight of i1. */
static inline float tap(float t, float tmax, int n, int *i0, int *i1)
{
    float ts = dm_clampf(t, 0.0f, tmax);
    *i0 = (int)ts;
    *i1 = *i0 < n - 1 ? *i0 + 1 : *i0;
    return ts - (float)*i0;
}

/* Float arithmetic: the values are float, 7 taps add at most a few ulp. */
static void blur_u_rows(void *ctx, size_t begin, size_t end)
{
    blur_job *job = ctx;
    const int w = job->width, half = DM_STRETCH_TAPS / 2;
    const float xmax = (float)(w - 1), scale = job->sigma_mm * (float)w;
    for (size_t y = begin; y < end; ++y) {
        const float *su = job->src_u + y * (size_t)w, *sv = job->src_v + y * (size_t)w;
        float *o = job->tmp + y * (size_t)w * 2;
        for (int x = 0; x < w; ++x) {
            float step = scale * su[x]; /* texels per σ along u */
            float au = 0.0f, av = 0.0f;
            for (int i = -half; i <= half; ++i) {
                int x0, x1;
                float f = tap((float)x + (float)i * step, xmax, w, &x0, &x1), wt = job->w[i + half];
                au += wt * (su[x0] + f * (su[x1] - su[x0]));
                av += wt * (sv[x0] + f * (sv[x1] - sv[x0]));
            }
            o[2 * x] = au;
            o[2 * x + 1] = av;
        }
    }
}

/* The V pass walks strips of columns top to bottom: the taps of neighbouring rows then
 * fall in the same few cache lines of each strip (row by row they scattered over up to
 * 14 rows of the whole width and missed the cache). */
enum { V_STRIP = 64 };

static void blur_v_strips(void *ctx, size_t begin, size_t end)
{
    blur_job *job = ctx;
    const int w = job->width, h = job->height, half = DM_STRETCH_TAPS / 2;
    const float ymax = (float)(h - 1), scale = job->sigma_mm * (float)h;
    const float *tmp = job->tmp;
    for (size_t strip = begin; strip < end; ++strip) {
        const int x0 = (int)strip * V_STRIP, x1 = x0 + V_STRIP < w ? x0 + V_STRIP : w;
        for (int y = 0; y < h; ++y) {
            const float *stretch_v = job->src_v + (size_t)y * w;
            float *ou = job->dst_u + (size_t)y * w, *ov = job->dst_v + (size_t)y * w;
            for (int x = x0; x < x1; ++x) {
                float step = scale * stretch_v[x]; /* texels per σ along v */
                float au = 0.0f, av = 0.0f;
                for (int i = -half; i <= half; ++i) {
                    int y0, y1;
                    float f = tap((float)y + (float)i * step, ymax, h, &y0, &y1), wt = job->w[i + half];
                    const float *a = tmp + ((size_t)y0 * w + x) * 2, *b = tmp + ((size_t)y1 * w + x) * 2;
                    au += wt * (a[0] + f * (b[0] - a[0]));
                    av += wt * (a[1] + f * (b[1] - a[1]));
                }
                ou[x] = au;
                ov[x] = av;
            }
        }
    }
}

/* ---- statistics ------------------------------------------------------------------- */

typedef struct weighted {
    float value;
    int64_t count;
} weighted;

static int cmp_weighted(const void *a, const void *b)
{
    float x = ((const weighted *)a)->value, y = ((const weighted *)b)->value;
    return x < y ? -1 : x > y;
}

/* Texel-weighted percentiles (1, 5, 50, 95, 99 %) and maximum of per-triangle values. */
static void percentiles(weighted *v, int32_t n, int64_t total, double out[5], double *max)
{
    static const double q[5] = {0.01, 0.05, 0.50, 0.95, 0.99};
    qsort(v, (size_t)n, sizeof *v, cmp_weighted);
    int64_t run = 0;
    int k = 0;
    for (int32_t i = 0; i < n && k < 5; ++i) {
        run += v[i].count;
        while (k < 5 && (double)run >= q[k] * (double)total) out[k++] = v[i].value;
    }
    *max = n > 0 ? v[n - 1].value : 0.0;
}

static void progress(const dm_stretch_options *o, double f)
{
    if (o->progress) o->progress(o->progress_ctx, f);
}

dm_result dm_stretch_bake(const dm_mesh *m, const dm_stretch_options *opt, dm_stretch_map *out, dm_error *err)
{
    assert(m && out);
    memset(out, 0, sizeof *out);
    dm_stretch_options o = {0};
    if (opt) o = *opt;
    dm_profile gems3;
    dm_profile_gems3_skin(&gems3);
    if (!o.profile) o.profile = &gems3;
    if (o.width == 0) o.width = DM_STRETCH_SIZE_DEFAULT;
    if (o.height == 0) o.height = DM_STRETCH_SIZE_DEFAULT;
    if (o.mm_per_unit == 0.0) o.mm_per_unit = DM_STRETCH_MM_PER_UNIT_DEFAULT;
    if (o.level_count == 0) o.level_count = o.profile->count;
    if (o.width < 1 || o.height < 1 || o.width > DM_STRETCH_SIZE_MAX || o.height > DM_STRETCH_SIZE_MAX)
        return dm_fail(err, DM_ERR_RANGE, "stretch map size %dx%d: expected 1..%d on each side", o.width, o.height,
                       (int)DM_STRETCH_SIZE_MAX);
    if (!(o.mm_per_unit > 0.0) || !isfinite(o.mm_per_unit))
        return dm_fail(err, DM_ERR_RANGE, "mm_per_unit = %g: expected a finite value > 0", o.mm_per_unit);
    dm_result r = dm_profile_validate(o.profile, o.profile->name[0] ? o.profile->name : "profile", err);
    if (r != DM_OK) return r;
    if (o.level_count < 1 || o.level_count > o.profile->count)
        return dm_fail(err, DM_ERR_RANGE, "levels = %d: expected 1..%d (the Gaussians of profile '%s')", o.level_count,
                       o.profile->count, o.profile->name);

    const int w = o.width, h = o.height, tris = m->triangle_count;
    const size_t n = (size_t)w * (size_t)h;
    dm_stretch_stats *st = &out->stats;
    out->width = w;
    out->height = h;
    out->level_count = o.level_count;
    for (int k = 0; k < o.level_count; ++k) {
        out->variance_mm2[k] = o.profile->variance_mm2[k];
        out->s_u[k] = big_alloc(n * sizeof(float));
        out->s_v[k] = big_alloc(n * sizeof(float));
        if (!out->s_u[k] || !out->s_v[k]) goto oom;
    }
    out->mask = big_alloc(n * sizeof(float));
    if (!out->mask) goto oom;

    /* 1. Per-triangle stretch and the raster. */
    double t0 = dm_now_ms();
    st->triangle_count = tris;
    float *tri_su = malloc((size_t)tris * sizeof *tri_su), *tri_sv = malloc((size_t)tris * sizeof *tri_sv);
    uint8_t *skip = malloc((size_t)tris);
    int32_t *triangle_of = big_alloc(n * sizeof *triangle_of);
    uint8_t *covered = big_alloc(n);
    if (!tri_su || !tri_sv || !skip || !triangle_of || !covered) {
        free(tri_su), free(tri_sv), free(skip), free(triangle_of), free(covered);
        goto oom;
    }
    for (int32_t t = 0; t < tris; ++t) {
        dm_triangle_stretch ts;
        dm_triangle_stretch_of(m, t, o.mm_per_unit, &ts);
        skip[t] = ts.kind != DM_TRIANGLE_OK;
        st->zero_uv_area_triangles += ts.kind == DM_TRIANGLE_ZERO_UV_AREA;
        st->zero_area_triangles += ts.kind == DM_TRIANGLE_ZERO_AREA;
        st->mirrored_triangles += ts.mirrored;
        tri_su[t] = (float)ts.s_u;
        tri_sv[t] = (float)ts.s_v;
    }
    dm_uv_raster_stats rs;
    r = dm_uv_raster(m, skip, w, h, o.thread_count, triangle_of, &rs, err);
    free(skip);
    if (r == DM_OK && rs.covered_texels == 0)
        r = dm_fail(err, DM_ERR_EMPTY,
                    "%dx%d stretch map: no texel is covered (%d triangles, %d of zero UV area, %d of zero area, "
                    "%lld with UVs out of range)",
                    w, h, tris, st->zero_uv_area_triangles, st->zero_area_triangles, (long long)rs.out_of_range_triangles);
    if (r != DM_OK) {
        free(tri_su), free(tri_sv), free(triangle_of), free(covered);
        dm_stretch_map_free(out);
        return r;
    }
    st->out_of_range_triangles = (int32_t)rs.out_of_range_triangles;
    st->covered_texels = rs.covered_texels;
    st->overlap_texels = rs.overlap_texels;
    st->gutter_texels = (int64_t)n - rs.covered_texels;
    st->coverage = (double)rs.covered_texels / (double)n;
    base_job bj = {triangle_of, tri_su, tri_sv, out->s_u[0], out->s_v[0], out->mask, covered};
    dm_parallel_for(n, 0, o.thread_count, base_texels, &bj);
    st->raster_ms = dm_now_ms() - t0;
    progress(&o, 0.2);

    /* Statistics over covered texels, from per-triangle texel counts. */
    t0 = dm_now_ms();
    int32_t islands = 0;
    weighted *ws = malloc((size_t)tris * sizeof *ws);
    int64_t *texels_of = calloc((size_t)tris, sizeof *texels_of);
    r = ws && texels_of ? dm_mesh_uv_islands(m, NULL, &islands, err) : DM_ERR_OUT_OF_MEMORY;
    if (r == DM_OK) {
        st->uv_islands = islands;
        for (size_t i = 0; i < n; ++i)
            if (triangle_of[i] >= 0) ++texels_of[triangle_of[i]];
        int32_t used = 0;
        for (int32_t t = 0; t < tris; ++t)
            if (texels_of[t]) ws[used++] = (weighted){tri_su[t], texels_of[t]};
        percentiles(ws, used, st->covered_texels, st->s_u_percentile, &st->s_u_max);
        used = 0;
        for (int32_t t = 0; t < tris; ++t)
            if (texels_of[t]) ws[used++] = (weighted){tri_sv[t], texels_of[t]};
        percentiles(ws, used, st->covered_texels, st->s_v_percentile, &st->s_v_max);
    }
    free(ws), free(texels_of), free(tri_su), free(tri_sv), free(triangle_of);
    if (r != DM_OK) {
        free(covered);
        dm_stretch_map_free(out);
        return r == DM_ERR_OUT_OF_MEMORY ? dm_fail(err, r, "stretch statistics: out of memory") : r;
    }
    st->stats_ms = dm_now_ms() - t0;

    /* 2. Gutters. */
    t0 = dm_now_ms();
    float *planes[2] = {out->s_u[0], out->s_v[0]};
    dm_gutter_stats gs;
    r = dm_gutter_fill(covered, w, h, planes, 2, o.thread_count, &gs, err);
    free(covered);
    if (r != DM_OK) {
        dm_stretch_map_free(out);
        return r;
    }
    st->fill_distance_max_texels = gs.max_distance_texels;
    st->fill_ms = dm_now_ms() - t0;
    progress(&o, 0.3);

    /* 3. The chain. */
    t0 = dm_now_ms();
    if (o.level_count > 1) {
        blur_job bj2 = {.width = w, .height = h};
        double wd[DM_STRETCH_TAPS];
        dm_stretch_blur_weights(wd);
        for (int i = 0; i < DM_STRETCH_TAPS; ++i) bj2.w[i] = (float)wd[i];
        bj2.tmp = big_alloc(n * 2 * sizeof(float));
        if (!bj2.tmp) goto oom;
        double widest = 0.0;
        for (int k = 1; k < o.level_count; ++k) {
            double sigma = sqrt(o.profile->variance_mm2[k] - o.profile->variance_mm2[k - 1]);
            bj2.sigma_mm = (float)sigma;
            if (sigma > widest) widest = sigma;
            bj2.src_u = out->s_u[k - 1];
            bj2.src_v = out->s_v[k - 1];
            bj2.dst_u = out->s_u[k];
            bj2.dst_v = out->s_v[k];
            dm_parallel_for((size_t)h, 0, o.thread_count, blur_u_rows, &bj2);
            dm_parallel_for(((size_t)w + V_STRIP - 1) / V_STRIP, 1, o.thread_count, blur_v_strips, &bj2);
            progress(&o, 0.3 + 0.7 * k / (o.level_count - 1));
        }
        free(bj2.tmp);
        double s_max = fmax(st->s_u_max * w, st->s_v_max * h);
        st->blur_reach_texels = (DM_STRETCH_TAPS / 2) * widest * s_max;
    }
    st->blur_ms = dm_now_ms() - t0;
    progress(&o, 1.0);
    return DM_OK;

oom:
    dm_stretch_map_free(out);
    return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "stretch map %dx%d with %d levels: out of memory", w, h, o.level_count);
}
