#include "mesh/dm_uv_raster.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_parallel.h"

enum { BAND_ROWS = 16 };
#define COORD_LIMIT (1048576.0 * DM_UV_RASTER_SUBTEXEL) /* ±2^20 texels, in subtexels */

typedef struct snapped {
    int32_t x[3], y[3]; /* subtexel coordinates, texel centres at multiples of SUBTEXEL,
                         * counter-clockwise (y up) */
    int32_t row0, row1; /* covered row range, clipped; row0 > row1 when none */
} snapped;

typedef struct raster_job {
    const snapped *tri;
    const int32_t *band_start; /* band b's triangles: band_tris[band_start[b] .. band_start[b+1]) */
    const int32_t *band_tris;
    int width, height;
    int32_t *triangle_of;
    int64_t *band_overlaps;
} raster_job;

static int64_t floor_div(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
static int64_t ceil_div(int64_t a, int64_t b) { return -floor_div(-a, b); }

/* Snaps triangle t; returns 0 (ok), 1 (zero area) or 2 (out of range). */
static int snap(const dm_mesh *m, int32_t t, int width, int height, snapped *s)
{
    double x[3], y[3];
    for (int c = 0; c < 3; ++c) {
        const float *uv = m->uvs + ((size_t)t * 3 + (size_t)c) * 2;
        x[c] = ((double)uv[0] * width - 0.5) * DM_UV_RASTER_SUBTEXEL;
        y[c] = ((double)uv[1] * height - 0.5) * DM_UV_RASTER_SUBTEXEL;
        if (!(fabs(x[c]) <= COORD_LIMIT) || !(fabs(y[c]) <= COORD_LIMIT)) return 2;
    }
    int64_t X[3], Y[3];
    for (int c = 0; c < 3; ++c) {
        X[c] = llround(x[c]);
        Y[c] = llround(y[c]);
    }
    int64_t area2 = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    if (area2 == 0) return 1;
    int order[3] = {0, 1, 2};
    if (area2 < 0) order[1] = 2, order[2] = 1; /* mirrored in UV: turn it counter-clockwise */
    int64_t ymin = Y[0], ymax = Y[0];
    for (int c = 0; c < 3; ++c) {
        s->x[c] = (int32_t)X[order[c]];
        s->y[c] = (int32_t)Y[order[c]];
        if (Y[c] < ymin) ymin = Y[c];
        if (Y[c] > ymax) ymax = Y[c];
    }
    int64_t r0 = ceil_div(ymin, DM_UV_RASTER_SUBTEXEL), r1 = floor_div(ymax, DM_UV_RASTER_SUBTEXEL);
    if (r0 < 0) r0 = 0;
    if (r1 > height - 1) r1 = height - 1;
    s->row0 = (int32_t)r0;
    s->row1 = (int32_t)(r1 < r0 ? r0 - 1 : r1);
    return 0;
}

static void raster_triangle(const raster_job *job, const snapped *s, int32_t t, int row_lo, int row_hi,
                            int64_t *overlaps)
{
    const int64_t S = DM_UV_RASTER_SUBTEXEL;
    int64_t xmin = s->x[0], xmax = s->x[0];
    for (int c = 1; c < 3; ++c) {
        if (s->x[c] < xmin) xmin = s->x[c];
        if (s->x[c] > xmax) xmax = s->x[c];
    }
    int64_t c0 = ceil_div(xmin, S), c1 = floor_div(xmax, S);
    if (c0 < 0) c0 = 0;
    if (c1 > job->width - 1) c1 = job->width - 1;
    if (c0 > c1) return;
    int y0 = s->row0 > row_lo ? s->row0 : row_lo;
    int y1 = s->row1 < row_hi ? s->row1 : row_hi;
    /* Edge e runs from corner e to corner e+1; E ≥ 0 on its left (inside). A centre on
     * the edge counts when the edge goes down (a left edge) or is horizontal going right
     * (a bottom edge); the neighbour runs the edge the other way and leaves it out. */
    int64_t ex[3], ey[3], bias[3];
    for (int e = 0; e < 3; ++e) {
        int n = (e + 1) % 3;
        ex[e] = (int64_t)s->x[n] - s->x[e];
        ey[e] = (int64_t)s->y[n] - s->y[e];
        bias[e] = (ey[e] < 0 || (ey[e] == 0 && ex[e] > 0)) ? 0 : -1;
    }
    for (int y = y0; y <= y1; ++y) {
        int64_t py = (int64_t)y * S, px0 = c0 * S;
        int64_t E[3];
        for (int e = 0; e < 3; ++e) E[e] = ex[e] * (py - s->y[e]) - ey[e] * (px0 - s->x[e]) + bias[e];
        int32_t *row = job->triangle_of + (size_t)y * (size_t)job->width;
        for (int64_t x = c0; x <= c1; ++x) {
            if ((E[0] | E[1] | E[2]) >= 0) {
                if (row[x] < 0) row[x] = t;
                else ++*overlaps;
            }
            for (int e = 0; e < 3; ++e) E[e] -= ey[e] * S;
        }
    }
}

static void raster_bands(void *ctx, size_t begin, size_t end)
{
    raster_job *job = ctx;
    for (size_t b = begin; b < end; ++b) {
        int row_lo = (int)b * BAND_ROWS;
        int row_hi = row_lo + BAND_ROWS - 1;
        if (row_hi > job->height - 1) row_hi = job->height - 1;
        int64_t overlaps = 0;
        for (int32_t k = job->band_start[b]; k < job->band_start[b + 1]; ++k) {
            int32_t t = job->band_tris[k];
            raster_triangle(job, &job->tri[t], t, row_lo, row_hi, &overlaps);
        }
        job->band_overlaps[b] = overlaps;
    }
}

dm_result dm_uv_raster(const dm_mesh *m, const uint8_t *skip, int width, int height, int thread_count,
                       int32_t *triangle_of, dm_uv_raster_stats *stats, dm_error *err)
{
    assert(m && triangle_of);
    if (width < 1 || height < 1 || width > DM_UV_RASTER_SIZE_MAX || height > DM_UV_RASTER_SIZE_MAX)
        return dm_fail(err, DM_ERR_RANGE, "UV raster %dx%d: expected 1..%d on each side", width, height,
                       (int)DM_UV_RASTER_SIZE_MAX);
    dm_uv_raster_stats st = {0};
    const int32_t tris = m->triangle_count;
    const int bands = (height + BAND_ROWS - 1) / BAND_ROWS;
    snapped *tri = malloc((size_t)tris * sizeof *tri);
    int32_t *band_start = calloc((size_t)bands + 1, sizeof *band_start);
    int64_t *band_overlaps = calloc((size_t)bands, sizeof *band_overlaps);
    if (!tri || !band_start || !band_overlaps) {
        free(tri);
        free(band_start);
        free(band_overlaps);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "UV raster of %d triangles: out of memory", tris);
    }
    /* Bin triangles by bands of rows (counting sort, triangle order kept inside a band:
     * the lowest index claims an overlapped texel whatever the thread count). */
    int64_t entries = 0;
    for (int32_t t = 0; t < tris; ++t) {
        if (skip && skip[t]) {
            tri[t].row0 = 1, tri[t].row1 = 0;
            continue;
        }
        int rc = snap(m, t, width, height, &tri[t]);
        if (rc != 0) {
            tri[t].row0 = 1, tri[t].row1 = 0;
            if (rc == 1) ++st.zero_area_triangles;
            else ++st.out_of_range_triangles;
            continue;
        }
        if (tri[t].row0 > tri[t].row1) continue;
        for (int b = tri[t].row0 / BAND_ROWS; b <= tri[t].row1 / BAND_ROWS; ++b) ++band_start[b + 1];
        entries += tri[t].row1 / BAND_ROWS - tri[t].row0 / BAND_ROWS + 1;
    }
    if (entries > INT32_MAX) {
        free(tri);
        free(band_start);
        free(band_overlaps);
        return dm_fail(err, DM_ERR_RANGE, "UV raster: %lld band entries, too many", (long long)entries);
    }
    for (int b = 0; b < bands; ++b) band_start[b + 1] += band_start[b];
    int32_t *band_tris = malloc((size_t)(entries ? entries : 1) * sizeof *band_tris);
    int32_t *cursor = malloc((size_t)bands * sizeof *cursor);
    if (!band_tris || !cursor) {
        free(tri);
        free(band_start);
        free(band_overlaps);
        free(band_tris);
        free(cursor);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "UV raster of %d triangles: out of memory", tris);
    }
    memcpy(cursor, band_start, (size_t)bands * sizeof *cursor);
    for (int32_t t = 0; t < tris; ++t) {
        if (tri[t].row0 > tri[t].row1) continue;
        for (int b = tri[t].row0 / BAND_ROWS; b <= tri[t].row1 / BAND_ROWS; ++b) band_tris[cursor[b]++] = t;
    }
    free(cursor);

    memset(triangle_of, 0xff, (size_t)width * (size_t)height * sizeof *triangle_of);
    raster_job job = {tri, band_start, band_tris, width, height, triangle_of, band_overlaps};
    dm_parallel_for((size_t)bands, 1, thread_count, raster_bands, &job);

    for (int b = 0; b < bands; ++b) st.overlap_texels += band_overlaps[b];
    const size_t n = (size_t)width * (size_t)height;
    for (size_t i = 0; i < n; ++i) st.covered_texels += triangle_of[i] >= 0;
    free(tri);
    free(band_start);
    free(band_overlaps);
    free(band_tris);
    if (stats) *stats = st;
    return DM_OK;
}

void dm_uv_raster_barycentrics(const dm_mesh *m, int32_t t, double u, double v, double *b1, double *b2)
{
    const float *uv = m->uvs + 6 * (size_t)t;
    double ax = uv[0], ay = uv[1], bx = uv[2], by = uv[3], cx = uv[4], cy = uv[5];
    double d = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay);
    double l1 = ((u - ax) * (cy - ay) - (cx - ax) * (v - ay)) / d;
    double l2 = ((bx - ax) * (v - ay) - (u - ax) * (by - ay)) / d;
    *b1 = fmin(1.0, fmax(0.0, l1));
    *b2 = fmin(1.0 - *b1, fmax(0.0, l2));
}
