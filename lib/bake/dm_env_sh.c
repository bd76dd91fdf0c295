#include "bake/dm_env_sh.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_math.h"
#include "core/dm_parallel.h"

/* Column integrals over φ in [φ0, φ1] of: 1, sin, cos, sin·cos, sin², cos². */
enum { H_ONE, H_SIN, H_COS, H_SINCOS, H_SIN2, H_COS2, H_COUNT };
/* Row integrals over θ in [θ0, θ1], the Jacobian sin θ included, of:
 * 1, cos, sin, sin·cos, sin², cos²  (i.e. ∫ f(θ) sin θ dθ). */
enum { G_ONE, G_COS, G_SIN, G_SINCOS, G_SIN2, G_COS2, G_COUNT };

typedef struct sh_job {
    const dm_envmap *map;
    const double *col;  /* width × H_COUNT */
    double *row_coeffs; /* height × 27 */
} sh_job;

static void column_integrals(double p0, double p1, double h[H_COUNT])
{
    double s0 = sin(p0), s1 = sin(p1), c0 = cos(p0), c1 = cos(p1);
    double dp = p1 - p0;
    double s2 = sin(2.0 * p1) - sin(2.0 * p0);
    h[H_ONE] = dp;
    h[H_SIN] = c0 - c1;
    h[H_COS] = s1 - s0;
    h[H_SINCOS] = 0.5 * (s1 * s1 - s0 * s0);
    h[H_SIN2] = 0.5 * dp - 0.25 * s2;
    h[H_COS2] = 0.5 * dp + 0.25 * s2;
}

static void row_integrals(double t0, double t1, double g[G_COUNT])
{
    /* θ0 < θ1; with t = cos θ: ∫ f sin θ dθ = ∫_{cos θ1}^{cos θ0} f dt. */
    double a = cos(t0), b = cos(t1);
    double sa = sin(t0), sb = sin(t1);
    g[G_ONE] = a - b;
    g[G_COS] = 0.5 * (a * a - b * b);
    g[G_SIN] = 0.5 * (t1 - t0) - 0.25 * (sin(2.0 * t1) - sin(2.0 * t0)); /* ∫ sin² θ dθ */
    g[G_SINCOS] = (sb * sb * sb - sa * sa * sa) / 3.0;                   /* ∫ sin² θ cos θ dθ */
    g[G_SIN2] = (a - b) - (a * a * a - b * b * b) / 3.0;                 /* ∫ sin³ θ dθ */
    g[G_COS2] = (a * a * a - b * b * b) / 3.0;                           /* ∫ cos² θ sin θ dθ */
}

static void sh_rows(void *ctx, size_t begin, size_t end)
{
    sh_job *job = ctx;
    const int w = job->map->width, h = job->map->height;
    const float *px = job->map->level[0];
    /* Sloan's constants: 1/(2√π), √(3/4π), √(15/4π), √(5/16π), √(15/16π). */
    const double k0 = 0.28209479177387814, k1 = 0.48860251190291992, k2 = 1.0925484305920792,
                 k3 = 0.31539156525252005, k4 = 0.54627421529603959;
    for (size_t j = begin; j < end; ++j) {
        double m[3][H_COUNT] = {{0}};
        const float *row = px + j * (size_t)w * 3;
        for (int i = 0; i < w; ++i) {
            const double *hc = job->col + (size_t)i * H_COUNT;
            for (int c = 0; c < 3; ++c) {
                double v = row[(size_t)i * 3 + c];
                if (v == 0.0) continue;
                for (int q = 0; q < H_COUNT; ++q) m[c][q] += v * hc[q];
            }
        }
        double t0 = DM_PI * (1.0 - (double)(j + 1) / h), t1 = DM_PI * (1.0 - (double)j / h);
        double g[G_COUNT];
        row_integrals(t0, t1, g);
        double *out = job->row_coeffs + j * 27;
        /* Direction: x = sin θ sin φ, y = cos θ, z = −sin θ cos φ (core/dm_equirect.h). */
        for (int c = 0; c < 3; ++c) {
            const double *mc = m[c];
            out[0 * 3 + c] = k0 * g[G_ONE] * mc[H_ONE];
            out[1 * 3 + c] = k1 * g[G_COS] * mc[H_ONE];                               /* y */
            out[2 * 3 + c] = -k1 * g[G_SIN] * mc[H_COS];                              /* z */
            out[3 * 3 + c] = k1 * g[G_SIN] * mc[H_SIN];                               /* x */
            out[4 * 3 + c] = k2 * g[G_SINCOS] * mc[H_SIN];                            /* xy */
            out[5 * 3 + c] = -k2 * g[G_SINCOS] * mc[H_COS];                           /* yz */
            out[6 * 3 + c] = k3 * (3.0 * g[G_SIN2] * mc[H_COS2] - g[G_ONE] * mc[H_ONE]); /* 3z² − 1 */
            out[7 * 3 + c] = -k2 * g[G_SIN2] * mc[H_SINCOS];                          /* xz */
            out[8 * 3 + c] = k4 * (g[G_SIN2] * mc[H_SIN2] - g[G_COS2] * mc[H_ONE]);   /* x² − y² */
        }
    }
}

dm_result dm_env_project_sh9(const dm_envmap *map, double rotate_deg, int threads, double sh[DM_SH9_COUNT][3],
                             dm_error *err)
{
    assert(map && map->level[0] && sh);
    const int w = map->width, h = map->height;
    double *col = malloc((size_t)w * H_COUNT * sizeof *col);
    double *rows = malloc((size_t)h * 27 * sizeof *rows);
    if (!col || !rows) {
        free(col);
        free(rows);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "SH projection of a %dx%d map: out of memory", w, h);
    }
    /* Rotated map L'(φ) = L(φ + α): its coefficient is ∫ L(φ) Y(φ − α), so source column i
     * integrates the basis over [φ0 − α, φ1 − α]. */
    double alpha = rotate_deg * DM_PI / 180.0;
    for (int i = 0; i < w; ++i) {
        double p0 = DM_2PI * ((double)i / w - 0.5) - alpha, p1 = DM_2PI * ((double)(i + 1) / w - 0.5) - alpha;
        column_integrals(p0, p1, col + (size_t)i * H_COUNT);
    }
    sh_job job = {map, col, rows};
    dm_parallel_for((size_t)h, 0, threads, sh_rows, &job);
    for (int k = 0; k < 27; ++k) {
        double s = 0.0, comp = 0.0; /* Kahan over rows, in row order */
        for (int j = 0; j < h; ++j) {
            double y = rows[(size_t)j * 27 + k] - comp;
            double t = s + y;
            comp = (t - s) - y;
            s = t;
        }
        sh[k / 3][k % 3] = s;
    }
    free(col);
    free(rows);
    return DM_OK;
}
