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

/* Per sampled row: its m and its statistics; bands are sums over rows with m ≥ m_min. */
typedef struct row_stats {
    double t;
    int64_t n;
    double max_rel, sum_sq, max_abs, max_abs_c, max_w, ws, wt;
} row_stats;

static void merge_rows(const row_stats *rows, int row_count, int stride, int offset, double m_min, dm_lut_error *o)
{
    double sum_sq = 0.0;
    memset(o, 0, sizeof *o);
    for (int r = 0; r < row_count; ++r) {
        const row_stats *q = &rows[r * stride + offset];
        if (q->t < m_min) continue;
        o->samples += q->n;
        sum_sq += q->sum_sq;
        if (q->max_rel > o->max_rel) {
            o->max_rel = q->max_rel;
            o->worst_s = q->ws;
            o->worst_t = q->wt;
        }
        if (q->max_abs > o->max_abs) {
            o->max_abs = q->max_abs;
            o->worst_s = q->ws;
            o->worst_t = q->wt;
        }
        if (q->max_abs_c > o->max_abs_centres) o->max_abs_centres = q->max_abs_c;
        if (q->max_w > o->max_abs_weighted) o->max_abs_weighted = q->max_w;
    }
    o->rms_rel = o->samples ? sqrt(sum_sq / (double)o->samples) : 0.0;
}

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
        double t = (r + 0.5) / (double)nx; /* same density on both axes */
        row_stats st = {.t = t};
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

void dm_lut_beckmann_error(const dm_beckmann_lut *lut, int supersample, const double *m_min, int band_count,
                           int threads, dm_lut_error *out)
{
    assert(lut && lut->texels && m_min && out && band_count > 0);
    double t0 = dm_now_ms();
    if (supersample < 1) supersample = 1;
    int nx = (lut->width > lut->height ? lut->width : lut->height) * supersample;
    row_stats *rows = calloc((size_t)nx, sizeof *rows);
    if (!rows) {
        memset(out, 0, sizeof *out * band_count);
        return;
    }
    beckmann_err_job job = {lut, nx, rows};
    dm_parallel_for((size_t)nx, 0, threads, beckmann_err_rows, &job);
    double ms = dm_now_ms() - t0;
    for (int b = 0; b < band_count; ++b) {
        merge_rows(rows, nx, 1, 0, m_min[b], &out[b]);
        out[b].max_abs = 0.0; /* relative figures only for this table */
        out[b].ms = ms;
    }
    free(rows);
}

typedef struct dir_err_job {
    const dm_directional_lut *lut;
    row_stats *rows; /* 3 per row: rho_dt, scale, bias */
} dir_err_job;

static void directional_err_rows(void *ctx, size_t begin, size_t end)
{
    dir_err_job *job = ctx;
    const dm_directional_lut *lut = job->lut;
    const float *tables[3] = {lut->rho_dt, lut->scale, lut->bias};
    int nx = 2 * lut->width, ny = 2 * lut->height;
    for (size_t r = begin; r < end; ++r) {
        double t = (double)r / ny; /* odd r: texel centres; even r: midpoints and borders */
        row_stats st[3] = {{.t = t}, {.t = t}, {.t = t}};
        for (int k = 0; k <= nx; ++k) {
            double s = (double)k / nx;
            double sc, b;
            dm_ks_directional(s, t, DM_LUT_REFERENCE_NODES, &sc, &b);
            double exact[3] = {lut->f0 * sc + b, sc, b};
            for (int c = 0; c < 3; ++c) {
                double e = fabs(dm_lut_bilinear_f32(tables[c], lut->width, lut->height, s, t) - exact[c]);
                ++st[c].n;
                if (e > st[c].max_abs) {
                    st[c].max_abs = e;
                    st[c].ws = s;
                    st[c].wt = t;
                }
                if ((k & 1) && (r & 1) && e > st[c].max_abs_c) st[c].max_abs_c = e;
                if (s * e > st[c].max_w) st[c].max_w = s * e;
            }
        }
        for (int c = 0; c < 3; ++c) job->rows[3 * r + c] = st[c];
    }
}

void dm_lut_directional_error(const dm_directional_lut *lut, const double *m_min, int band_count, int threads,
                              dm_lut_error *out)
{
    assert(lut && m_min && out && band_count > 0);
    double t0 = dm_now_ms();
    int ny = 2 * lut->height + 1;
    row_stats *rows = calloc((size_t)ny * 3, sizeof *rows);
    if (!rows) {
        memset(out, 0, sizeof *out * 3 * band_count);
        return;
    }
    dir_err_job job = {lut, rows};
    dm_parallel_for((size_t)ny, 1, threads, directional_err_rows, &job);
    double ms = dm_now_ms() - t0;
    for (int b = 0; b < band_count; ++b)
        for (int c = 0; c < 3; ++c) {
            merge_rows(rows, ny, 3, c, m_min[b], &out[3 * b + c]);
            out[3 * b + c].ms = ms;
        }
    free(rows);
}
