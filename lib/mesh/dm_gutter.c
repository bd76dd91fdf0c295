#include "mesh/dm_gutter.h"

#include <assert.h>
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_parallel.h"

enum { COLUMN_BLOCK = 64 };

typedef struct gutter_job {
    const uint8_t *covered;
    int width, height;
    float *const *planes;
    int plane_count;
    int32_t *near_row;  /* per texel: row of the nearest covered texel in its column, −1 none */
    double *row_max_d2; /* per row: largest squared fill distance */
    int64_t *row_filled;
    atomic_int out_of_memory;
} gutter_job;

/* Pass 1, per block of columns: the nearest covered row in each column, by one sweep
 * up and one down (row-major order keeps the memory access sequential). */
static void columns(void *ctx, size_t begin, size_t end)
{
    gutter_job *job = ctx;
    const int w = job->width, h = job->height;
    for (size_t blk = begin; blk < end; ++blk) {
        int x0 = (int)blk * COLUMN_BLOCK, x1 = x0 + COLUMN_BLOCK < w ? x0 + COLUMN_BLOCK : w;
        int32_t last[COLUMN_BLOCK];
        for (int x = x0; x < x1; ++x) last[x - x0] = -1;
        for (int y = 0; y < h; ++y) {
            const uint8_t *cov = job->covered + (size_t)y * w;
            int32_t *nr = job->near_row + (size_t)y * w;
            for (int x = x0; x < x1; ++x) {
                if (cov[x]) last[x - x0] = y;
                nr[x] = last[x - x0];
            }
        }
        for (int x = x0; x < x1; ++x) last[x - x0] = -1;
        for (int y = h - 1; y >= 0; --y) {
            const uint8_t *cov = job->covered + (size_t)y * w;
            int32_t *nr = job->near_row + (size_t)y * w;
            for (int x = x0; x < x1; ++x) {
                if (cov[x]) last[x - x0] = y;
                int32_t up = last[x - x0]; /* nearest covered row above (≥ y) */
                if (up >= 0 && (nr[x] < 0 || up - y < y - nr[x])) nr[x] = up;
            }
        }
    }
}

/* Pass 2, per row: the lower envelope of the parabolas (x − q)² + (y − near_row(q))²
 * over the columns q that have a covered texel, then a copy from each minimum. */
static void rows(void *ctx, size_t begin, size_t end)
{
    gutter_job *job = ctx;
    const int w = job->width;
    int32_t *site = malloc((size_t)w * sizeof *site);
    double *bound = malloc(((size_t)w + 1) * sizeof *bound);
    double *f = malloc((size_t)w * sizeof *f);
    if (!site || !bound || !f) {
        atomic_store(&job->out_of_memory, 1);
        begin = end;
    }
    for (size_t y = begin; y < end; ++y) {
        const int32_t *nr = job->near_row + y * (size_t)w;
        const uint8_t *cov = job->covered + y * (size_t)w;
        int k = -1;
        for (int q = 0; q < w; ++q) {
            if (nr[q] < 0) continue;
            double dy = (double)nr[q] - (double)y;
            f[q] = dy * dy;
            double s = 0.0;
            while (k >= 0) {
                int p = site[k];
                s = ((f[q] + (double)q * q) - (f[p] + (double)p * p)) / (2.0 * (q - p));
                if (s > bound[k]) break;
                --k;
            }
            ++k;
            site[k] = q;
            bound[k] = k == 0 ? -INFINITY : s;
            bound[k + 1] = INFINITY;
        }
        double max_d2 = 0.0;
        int64_t filled = 0;
        if (k >= 0) {
            int j = 0;
            for (int x = 0; x < w; ++x) {
                while (bound[j + 1] < x) ++j;
                if (cov[x]) continue;
                int q = site[j];
                double d2 = (double)(x - q) * (x - q) + f[q];
                if (d2 > max_d2) max_d2 = d2;
                size_t src = (size_t)nr[q] * (size_t)w + (size_t)q, dst = y * (size_t)w + (size_t)x;
                for (int c = 0; c < job->plane_count; ++c) job->planes[c][dst] = job->planes[c][src];
                ++filled;
            }
        }
        job->row_max_d2[y] = max_d2;
        job->row_filled[y] = filled;
    }
    free(site);
    free(bound);
    free(f);
}

dm_result dm_gutter_fill(const uint8_t *covered, int width, int height, float *const *planes, int plane_count,
                         int thread_count, dm_gutter_stats *stats, dm_error *err)
{
    assert(covered && width > 0 && height > 0 && (planes || plane_count == 0));
    const size_t n = (size_t)width * (size_t)height;
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) count += covered[i] != 0;
    if (count == 0) return dm_fail(err, DM_ERR_EMPTY, "gutter fill %dx%d: no covered texel to fill from", width, height);
    gutter_job job = {covered, width, height, planes, plane_count, malloc(n * sizeof(int32_t)),
                      calloc((size_t)height, sizeof(double)), calloc((size_t)height, sizeof(int64_t)), 0};
    if (!job.near_row || !job.row_max_d2 || !job.row_filled) {
        free(job.near_row);
        free(job.row_max_d2);
        free(job.row_filled);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "gutter fill %dx%d: out of memory", width, height);
    }
    dm_parallel_for(((size_t)width + COLUMN_BLOCK - 1) / COLUMN_BLOCK, 1, thread_count, columns, &job);
    dm_parallel_for((size_t)height, 0, thread_count, rows, &job);
    if (atomic_load(&job.out_of_memory)) {
        free(job.near_row);
        free(job.row_max_d2);
        free(job.row_filled);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "gutter fill %dx%d: out of memory", width, height);
    }
    dm_gutter_stats st = {0};
    double max_d2 = 0.0;
    for (int y = 0; y < height; ++y) {
        if (job.row_max_d2[y] > max_d2) max_d2 = job.row_max_d2[y];
        st.filled_texels += job.row_filled[y];
    }
    st.max_distance_texels = sqrt(max_d2);
    free(job.near_row);
    free(job.row_max_d2);
    free(job.row_filled);
    if (stats) *stats = st;
    return DM_OK;
}
