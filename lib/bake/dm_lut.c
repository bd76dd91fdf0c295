#include "bake/dm_lut.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_brdf.h"
#include "core/dm_cli.h"
#include "core/dm_parallel.h"

static dm_result check_size(int w, int h, const char *what, dm_error *err)
{
    if (w < 1 || h < 1 || w > DM_LUT_SIZE_MAX || h > DM_LUT_SIZE_MAX)
        return dm_fail(err, DM_ERR_RANGE, "%s table size %dx%d: expected 1..%d on each side", what, w, h,
                       DM_LUT_SIZE_MAX);
    return DM_OK;
}

/* ---- Beckmann ------------------------------------------------------------------- */

typedef struct beckmann_job {
    dm_beckmann_lut *lut;
    int64_t *row_saturated;
} beckmann_job;

static void beckmann_rows(void *ctx, size_t begin, size_t end)
{
    beckmann_job *job = ctx;
    dm_beckmann_lut *lut = job->lut;
    for (size_t j = begin; j < end; ++j) {
        double m = (j + 0.5) / lut->height;
        int64_t sat = 0;
        for (int i = 0; i < lut->width; ++i) {
            double d = dm_beckmann((i + 0.5) / lut->width, m);
            size_t k = j * (size_t)lut->width + i;
            lut->texels[k] = dm_beckmann_encode8(d);
            if (d >= DM_BECKMANN_LUT_D_MAX) ++sat;
            if (lut->exact) lut->exact[k] = (float)d;
        }
        job->row_saturated[j] = sat;
    }
}

dm_result dm_lut_bake_beckmann(int width, int height, int want_exact, int threads, dm_beckmann_lut *out,
                               dm_error *err)
{
    assert(out);
    memset(out, 0, sizeof *out);
    dm_result r = check_size(width, height, "Beckmann", err);
    if (r != DM_OK) return r;
    double t0 = dm_now_ms();
    size_t n = (size_t)width * height;
    out->width = width;
    out->height = height;
    out->texels = malloc(n);
    out->exact = want_exact ? malloc(n * sizeof(float)) : NULL;
    int64_t *row_sat = calloc((size_t)height, sizeof *row_sat);
    if (!out->texels || (want_exact && !out->exact) || !row_sat) {
        free(row_sat);
        dm_beckmann_lut_free(out);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "Beckmann table %dx%d: out of memory", width, height);
    }
    beckmann_job job = {out, row_sat};
    dm_parallel_for((size_t)height, 0, threads, beckmann_rows, &job);
    for (int j = 0; j < height; ++j) {
        out->saturated_texels += row_sat[j];
        if (row_sat[j]) {
            ++out->clipped_rows;
            out->max_clipped_m = (j + 0.5) / height;
        }
    }
    free(row_sat);
    out->bake_ms = dm_now_ms() - t0;
    return DM_OK;
}

void dm_beckmann_lut_free(dm_beckmann_lut *lut)
{
    if (!lut) return;
    free(lut->texels);
    free(lut->exact);
    memset(lut, 0, sizeof *lut);
}

/* ---- directional albedo (rho_dt) and split sum ------------------------------------ */

static void directional_rows(void *ctx, size_t begin, size_t end)
{
    dm_directional_lut *lut = ctx;
    for (size_t j = begin; j < end; ++j) {
        double m = (j + 0.5) / lut->height;
        for (int i = 0; i < lut->width; ++i) {
            double s, b;
            dm_ks_directional((i + 0.5) / lut->width, m, lut->nodes, &s, &b);
            size_t k = j * (size_t)lut->width + i;
            lut->scale[k] = (float)s;
            lut->bias[k] = (float)b;
            lut->rho_dt[k] = (float)(lut->f0 * s + b);
        }
    }
}

dm_result dm_lut_bake_directional(int width, int height, double f0, int nodes, int threads, dm_directional_lut *out,
                                  dm_error *err)
{
    assert(out);
    memset(out, 0, sizeof *out);
    dm_result r = check_size(width, height, "rho_dt", err);
    if (r != DM_OK) return r;
    if (!(f0 >= 0.0 && f0 <= 1.0)) return dm_fail(err, DM_ERR_RANGE, "F0 %g: expected 0..1", f0);
    if (nodes < 8 || nodes > 128) return dm_fail(err, DM_ERR_RANGE, "node count %d: expected 8..128", nodes);
    double t0 = dm_now_ms();
    size_t n = (size_t)width * height;
    out->width = width;
    out->height = height;
    out->f0 = f0;
    out->nodes = nodes;
    out->rho_dt = malloc(n * sizeof(float));
    out->scale = malloc(n * sizeof(float));
    out->bias = malloc(n * sizeof(float));
    if (!out->rho_dt || !out->scale || !out->bias) {
        dm_directional_lut_free(out);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "rho_dt table %dx%d: out of memory", width, height);
    }
    dm_parallel_for((size_t)height, 1, threads, directional_rows, out);
    out->bake_ms = dm_now_ms() - t0;
    return DM_OK;
}

void dm_directional_lut_free(dm_directional_lut *lut)
{
    if (!lut) return;
    free(lut->rho_dt);
    free(lut->scale);
    free(lut->bias);
    memset(lut, 0, sizeof *lut);
}

/* ---- sampling as the GPU does ----------------------------------------------------- */

static void bilinear_setup(int n, double s, int *i0, int *i1, double *f)
{
    double x = s * n - 0.5;
    if (!(x > 0.0)) x = 0.0; /* NaN too */
    if (x > n - 1) x = n - 1;
    int i = (int)x;
    if (i > n - 2) i = n - 2 < 0 ? 0 : n - 2;
    *i0 = i;
    *i1 = n > 1 ? i + 1 : i;
    *f = n > 1 ? x - i : 0.0;
}

double dm_lut_bilinear_f32(const float *t, int w, int h, double s, double tt)
{
    int i0, i1, j0, j1;
    double fx, fy;
    bilinear_setup(w, s, &i0, &i1, &fx);
    bilinear_setup(h, tt, &j0, &j1, &fy);
    double a = t[(size_t)j0 * w + i0] * (1 - fx) + t[(size_t)j0 * w + i1] * fx;
    double b = t[(size_t)j1 * w + i0] * (1 - fx) + t[(size_t)j1 * w + i1] * fx;
    return a * (1 - fy) + b * fy;
}

double dm_lut_bilinear_u8(const uint8_t *t, int w, int h, double s, double tt)
{
    int i0, i1, j0, j1;
    double fx, fy;
    bilinear_setup(w, s, &i0, &i1, &fx);
    bilinear_setup(h, tt, &j0, &j1, &fy);
    double a = t[(size_t)j0 * w + i0] * (1 - fx) + t[(size_t)j0 * w + i1] * fx;
    double b = t[(size_t)j1 * w + i0] * (1 - fx) + t[(size_t)j1 * w + i1] * fx;
    return (a * (1 - fy) + b * fy) / 255.0;
}

/* ---- error reports ----------------------------------------------------------------- */

typedef struct row_stats {
    int64_t n;
    double max_rel, sum_sq, max_abs, max_abs_c, max_w, ws, wt;
} row_stats;

typedef struct beckmann_err_job {
    const dm_beckmann_lut *lut;
    int nx;
    row_stats *rows;
} beckmann_err_job;

static void beckmann_err_rows(void *ctx, size_t begin, size_t end)
{
    beckmann_err_job *job = ctx;
    const dm_beckmann_lut *lut = job->lut;
    int nx = job->nx;
    for (size_t r = begin; r < end; ++r) {
        double t = (r + 0.5) / (double)job->nx; /* same density on both axes (square grid) */
        row_stats st = {0};
        double peak = 0.0;
        for (int k = 0; k < nx; ++k) {
            double d = dm_beckmann((k + 0.5) / nx, t);
            if (d > peak) peak = d;
        }
        for (int k = 0; k < nx; ++k) {
            double s = (k + 0.5) / nx;
            double d = dm_beckmann(s, t);
            if (!(d > 0.01 * peak) || d >= DM_BECKMANN_LUT_D_MAX) continue;
            double got = dm_beckmann_decode8(dm_lut_bilinear_u8(lut->texels, lut->width, lut->height, s, t));
            double rel = fabs(got - d) / d;
            ++st.n;
            st.sum_sq += rel * rel;
            if (rel > st.max_rel) {
                st.max_rel = rel;
                st.ws = s;
                st.wt = t;
            }
        }
        job->rows[r] = st;
    }
}

void dm_lut_beckmann_error(const dm_beckmann_lut *lut, int supersample, int threads, dm_lut_error *out)
{
    assert(lut && out && lut->texels);
    memset(out, 0, sizeof *out);
    double t0 = dm_now_ms();
    if (supersample < 1) supersample = 1;
    int nx = (lut->width > lut->height ? lut->width : lut->height) * supersample;
    row_stats *rows = calloc((size_t)nx, sizeof *rows);
    if (!rows) return;
    beckmann_err_job job = {lut, nx, rows};
    dm_parallel_for((size_t)nx, 0, threads, beckmann_err_rows, &job);
    double sum_sq = 0.0;
    for (int r = 0; r < nx; ++r) {
        out->samples += rows[r].n;
        sum_sq += rows[r].sum_sq;
        if (rows[r].max_rel > out->max_rel) {
            out->max_rel = rows[r].max_rel;
            out->worst_s = rows[r].ws;
            out->worst_t = rows[r].wt;
        }
    }
    out->rms_rel = out->samples ? sqrt(sum_sq / out->samples) : 0.0;
    free(rows);
    out->ms = dm_now_ms() - t0;
}

typedef struct dir_err_job {
    const dm_directional_lut *lut;
    int channel;
    row_stats *rows;
} dir_err_job;

static void directional_err_rows(void *ctx, size_t begin, size_t end)
{
    dir_err_job *job = ctx;
    const dm_directional_lut *lut = job->lut;
    const float *table = job->channel == 0 ? lut->rho_dt : job->channel == 1 ? lut->scale : lut->bias;
    int nx = 2 * lut->width, ny = 2 * lut->height;
    for (size_t r = begin; r < end; ++r) {
        double t = (double)r / ny; /* odd r: texel centres; even r: midpoints and borders */
        row_stats st = {0};
        for (int k = 0; k <= nx; ++k) {
            double s = (double)k / nx;
            double sc, b;
            dm_ks_directional(s, t, DM_LUT_REFERENCE_NODES, &sc, &b);
            double exact = job->channel == 0 ? lut->f0 * sc + b : job->channel == 1 ? sc : b;
            double got = dm_lut_bilinear_f32(table, lut->width, lut->height, s, t);
            double e = fabs(got - exact);
            ++st.n;
            if (e > st.max_abs) {
                st.max_abs = e;
                st.ws = s;
                st.wt = t;
            }
            if ((k & 1) && (r & 1) && e > st.max_abs_c) st.max_abs_c = e;
            if (s * e > st.max_w) st.max_w = s * e;
        }
        job->rows[r] = st;
    }
}

void dm_lut_directional_error(const dm_directional_lut *lut, int channel, int threads, dm_lut_error *out)
{
    assert(lut && out && channel >= 0 && channel <= 2);
    memset(out, 0, sizeof *out);
    double t0 = dm_now_ms();
    int ny = 2 * lut->height + 1;
    row_stats *rows = calloc((size_t)ny, sizeof *rows);
    if (!rows) return;
    dir_err_job job = {lut, channel, rows};
    dm_parallel_for((size_t)ny, 1, threads, directional_err_rows, &job);
    for (int r = 0; r < ny; ++r) {
        out->samples += rows[r].n;
        if (rows[r].max_abs > out->max_abs) {
            out->max_abs = rows[r].max_abs;
            out->worst_s = rows[r].ws;
            out->worst_t = rows[r].wt;
        }
        if (rows[r].max_abs_c > out->max_abs_centres) out->max_abs_centres = rows[r].max_abs_c;
        if (rows[r].max_w > out->max_abs_weighted) out->max_abs_weighted = rows[r].max_w;
    }
    free(rows);
    out->ms = dm_now_ms() - t0;
}
