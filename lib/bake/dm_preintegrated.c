#include "bake/dm_preintegrated.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_cli.h"
#include "core/dm_math.h"
#include "core/dm_parallel.h"
#include "core/dm_sort.h"

enum { GL = DM_PREINT_NODES, CUTS_MAX = 32 };

/* Gauss–Legendre nodes and weights on [−1, 1] by Newton on P_n (converged to ~1e-16). */
static void gauss_legendre(double *x, double *w)
{
    for (int i = 0; i < GL; ++i) {
        double z = cos(DM_PI * (i + 0.75) / (GL + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= GL; ++k) {
                double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = GL * (z * p1 - p0) / (z * z - 1.0);
            double dz = p1 / dp;
            z -= dz;
            if (fabs(dz) < 1e-16) break;
        }
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
}

/* The angle x ∈ [0, π] at which the chord 2r sin(x/2) equals c. */
static double chord_angle(double c, double r)
{
    double h = c / (2.0 * r);
    return h >= 1.0 ? DM_PI : 2.0 * asin(h);
}

/* ∫₀^π G(v, 2r sin(x/2)) [max(0, cos(θ+x)) + max(0, cos(θ−x))] dx into *num and
 * ∫₀^π 2 G(v, 2r sin(x/2)) dx into *den (so both cover the full circle). */
static void ring_gaussian(double v, double r, double theta, const double *gx, const double *gw, double *num,
                          double *den)
{
    static const double chords[] = {0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0};
    double sigma = sqrt(v), x_max = chord_angle(40.0 * sigma, r);
    double cut[CUTS_MAX];
    int n = 0;
    cut[n++] = 0.0;
    cut[n++] = x_max;
    const double kinks[4] = {DM_PI / 2 - theta, 3 * DM_PI / 2 - theta, theta - DM_PI / 2, theta + DM_PI / 2};
    for (int i = 0; i < 4; ++i)
        if (kinks[i] > 0.0 && kinks[i] < x_max) cut[n++] = kinks[i];
    for (size_t i = 0; i < sizeof chords / sizeof chords[0]; ++i) {
        double x = chord_angle(chords[i] * sigma, r);
        if (x < x_max) cut[n++] = x;
    }
    dm_sort_doubles(cut, (size_t)n);
    double sn = 0.0, sd = 0.0;
    for (int p = 0; p + 1 < n; ++p) {
        double a = cut[p], b = cut[p + 1];
        if (!(b > a)) continue;
        double mid = 0.5 * (a + b), half = 0.5 * (b - a), pn = 0.0, pd = 0.0;
        for (int q = 0; q < GL; ++q) {
            double x = mid + half * gx[q];
            double s = sin(0.5 * x), g = dm_gaussian(v, 2.0 * r * s);
            pn += gw[q] * g * (fmax(0.0, cos(theta + x)) + fmax(0.0, cos(theta - x)));
            pd += gw[q] * g;
        }
        sn += half * pn;
        sd += half * pd;
    }
    *num = sn;
    *den = 2.0 * sd;
}

static void eval_with(const dm_profile *p, double cos_theta, double curvature, const double *gx, const double *gw,
                      double rgb[3])
{
    double c = fmin(1.0, fmax(-1.0, cos_theta)), lambert = fmax(0.0, c);
    if (!(curvature > 0.0)) {
        rgb[0] = rgb[1] = rgb[2] = lambert;
        return;
    }
    double theta = acos(c), r = 1.0 / curvature, num[3] = {0, 0, 0}, den[3] = {0, 0, 0};
    for (int k = 0; k < p->count; ++k) {
        double n, d;
        ring_gaussian(p->variance_mm2[k], r, theta, gx, gw, &n, &d);
        for (int ch = 0; ch < 3; ++ch) {
            num[ch] += p->weight[k][ch] * n;
            den[ch] += p->weight[k][ch] * d;
        }
    }
    for (int ch = 0; ch < 3; ++ch) rgb[ch] = den[ch] > 0.0 ? fmin(1.0, fmax(0.0, num[ch] / den[ch])) : lambert;
}

void dm_preint_eval(const dm_profile *p, double cos_theta, double curvature_per_mm, double rgb[3])
{
    double gx[GL], gw[GL];
    gauss_legendre(gx, gw);
    eval_with(p, cos_theta, curvature_per_mm, gx, gw, rgb);
}

void dm_preint_brute(const dm_profile *p, double cos_theta, double curvature_per_mm, int sample_count,
                     double rgb[3])
{
    double c = fmin(1.0, fmax(-1.0, cos_theta));
    if (!(curvature_per_mm > 0.0)) {
        rgb[0] = rgb[1] = rgb[2] = fmax(0.0, c);
        return;
    }
    double theta = acos(c), r = 1.0 / curvature_per_mm, h = DM_2PI / sample_count;
    double num[3] = {0, 0, 0}, den[3] = {0, 0, 0};
    for (int i = 0; i < sample_count; ++i) {
        double x = -DM_PI + (i + 0.5) * h, R[3];
        dm_profile_eval(p, fabs(2.0 * r * sin(0.5 * x)), R);
        double l = fmax(0.0, cos(theta + x));
        for (int ch = 0; ch < 3; ++ch) {
            num[ch] += l * R[ch];
            den[ch] += R[ch];
        }
    }
    for (int ch = 0; ch < 3; ++ch) rgb[ch] = den[ch] > 0.0 ? num[ch] / den[ch] : fmax(0.0, c);
}

double dm_preint_texel_cos(int i, int width)
{
    return 2.0 * (i + 0.5) / width - 1.0;
}

double dm_preint_texel_curvature(int j, int height, double curvature_max_per_mm)
{
    return curvature_max_per_mm * j / (height - 1);
}

typedef struct bake_ctx {
    const dm_profile *p;
    dm_preint_lut *lut;
    double gx[GL], gw[GL];
} bake_ctx;

static void bake_rows(void *vctx, size_t begin, size_t end)
{
    bake_ctx *b = vctx;
    dm_preint_lut *l = b->lut;
    for (size_t j = begin; j < end; ++j) {
        double kappa = dm_preint_texel_curvature((int)j, l->height, l->curvature_max_per_mm);
        for (int i = 0; i < l->width; ++i) {
            double rgb[3];
            eval_with(b->p, dm_preint_texel_cos(i, l->width), kappa, b->gx, b->gw, rgb);
            size_t plane = (size_t)l->width * l->height, at = j * l->width + i;
            for (int ch = 0; ch < 3; ++ch) l->rgb[ch * plane + at] = (float)rgb[ch];
        }
    }
}

dm_result dm_preint_bake(const dm_profile *p, int width, int height, double curvature_max_per_mm, int threads,
                         dm_preint_lut *out, dm_error *err)
{
    memset(out, 0, sizeof *out);
    dm_result r = dm_profile_validate(p, "pre-integrated table: profile", err);
    if (r != DM_OK) return r;
    if (width < 2 || width > DM_PREINT_SIZE_MAX || height < 2 || height > DM_PREINT_SIZE_MAX)
        return dm_fail(err, DM_ERR_RANGE, "pre-integrated table: size %dx%d, expected 2..%d each", width, height,
                       DM_PREINT_SIZE_MAX);
    if (!(curvature_max_per_mm > 0.0 && curvature_max_per_mm <= DM_PREINT_CURVATURE_MAX_LIMIT))
        return dm_fail(err, isfinite(curvature_max_per_mm) ? DM_ERR_RANGE : DM_ERR_NON_FINITE,
                       "pre-integrated table: curvature_max = %g /mm, expected (0, %g]", curvature_max_per_mm,
                       DM_PREINT_CURVATURE_MAX_LIMIT);
    double t0 = dm_now_ms();
    out->rgb = malloc(sizeof(float) * 3 * (size_t)width * (size_t)height);
    if (!out->rgb) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "pre-integrated table: %dx%d texels", width, height);
    out->width = width;
    out->height = height;
    out->curvature_max_per_mm = curvature_max_per_mm;
    bake_ctx b = {.p = p, .lut = out};
    gauss_legendre(b.gx, b.gw);
    dm_parallel_for((size_t)height, 1, threads, bake_rows, &b);
    out->bake_ms = dm_now_ms() - t0;
    return DM_OK;
}

void dm_preint_lut_free(dm_preint_lut *lut)
{
    free(lut->rgb);
    memset(lut, 0, sizeof *lut);
}

typedef struct err_row {
    double centres, bilinear, worst_cos, worst_kappa;
    long samples;
} err_row;

typedef struct err_ctx {
    const dm_profile *p;
    const dm_preint_lut *lut;
    int stride, sample_count;
    err_row *rows;
} err_ctx;

static void error_rows(void *vctx, size_t begin, size_t end)
{
    err_ctx *e = vctx;
    const dm_preint_lut *l = e->lut;
    for (size_t jr = begin; jr < end; ++jr) {
        int j = (int)jr * e->stride;
        err_row *o = &e->rows[jr];
        memset(o, 0, sizeof *o);
        for (int i = 0; i < l->width; i += e->stride) {
            double ref[3];
            size_t plane = (size_t)l->width * l->height, at = (size_t)j * l->width + i, up = at + l->width;
            const float *t = l->rgb;
            dm_preint_brute(e->p, dm_preint_texel_cos(i, l->width),
                            dm_preint_texel_curvature(j, l->height, l->curvature_max_per_mm), e->sample_count, ref);
            for (int ch = 0; ch < 3; ++ch) o->centres = fmax(o->centres, fabs(t[ch * plane + at] - ref[ch]));
            ++o->samples;
            if (i + 1 >= l->width || j + 1 >= l->height) continue;
            /* halfway between four centres, GL_LINEAR is their mean */
            double c = 2.0 * (i + 1.0) / l->width - 1.0;
            double kappa = l->curvature_max_per_mm * (j + 0.5) / (l->height - 1);
            dm_preint_brute(e->p, c, kappa, e->sample_count, ref);
            for (int ch = 0; ch < 3; ++ch) {
                const float *q = t + ch * plane;
                double m = 0.25 * ((double)q[at] + q[at + 1] + q[up] + q[up + 1]), d = fabs(m - ref[ch]);
                if (d > o->bilinear) {
                    o->bilinear = d;
                    o->worst_cos = c;
                    o->worst_kappa = kappa;
                }
            }
            ++o->samples;
        }
    }
}

void dm_preint_lut_error(const dm_profile *p, const dm_preint_lut *lut, int stride, int sample_count, int threads,
                         dm_preint_error *out)
{
    memset(out, 0, sizeof *out);
    double t0 = dm_now_ms();
    if (stride < 1) stride = 1;
    int rows = (lut->height + stride - 1) / stride;
    err_ctx e = {.p = p, .lut = lut, .stride = stride, .sample_count = sample_count};
    e.rows = calloc((size_t)rows, sizeof *e.rows);
    if (!e.rows) return;
    dm_parallel_for((size_t)rows, 1, threads, error_rows, &e);
    for (int j = 0; j < rows; ++j) { /* in row order: deterministic worst-case location */
        out->max_abs_centres = fmax(out->max_abs_centres, e.rows[j].centres);
        if (e.rows[j].bilinear > out->max_abs_bilinear) {
            out->max_abs_bilinear = e.rows[j].bilinear;
            out->worst_cos = e.rows[j].worst_cos;
            out->worst_curvature = e.rows[j].worst_kappa;
        }
        out->samples += e.rows[j].samples;
    }
    free(e.rows);
    out->ms = dm_now_ms() - t0;
}
