/* dm_lut.h — the specular lookup tables and their accuracy against the exact functions.
 *
 * Layout of every table: texel (i, j) samples s = (i + 0.5)/width, t = (j + 0.5)/height
 * (texel centres), rows bottom-up in memory (row 0 is t ≈ 0), so an OpenGL upload of the
 * memory as-is gives texture(tex, vec2(s, t)) = table(s, t).
 *   Beckmann:    s = N·H, t = m; 8-bit value round(255 · 0.5 · D^0.1), decoded (2·v)^10;
 *                D ≥ 1024 saturates at 255 (m < 1/32 near N·H = 1).
 *   Directional: s = N·L (or N·V), t = m; float rho_dt (F0 given) and the split-sum
 *                scale and bias of F0 (rho_dt = F0 · scale + bias). True values, not
 *                clamped: rho_dt exceeds 1 towards grazing (up to ~π·F as m → 0).
 */
#ifndef DM_LUT_H
#define DM_LUT_H

#include <stdint.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    DM_LUT_BECKMANN_SIZE_DEFAULT = 512,
    DM_LUT_DIRECTIONAL_SIZE_DEFAULT = 64,
    DM_LUT_NODES_DEFAULT = 32,   /* Gauss–Legendre nodes per dimension for rho_dt */
    DM_LUT_REFERENCE_NODES = 96, /* the "much finer" reference */
    DM_LUT_SIZE_MAX = 8192
};

typedef struct dm_beckmann_lut {
    int width, height;
    uint8_t *texels;           /* width*height, bottom-up */
    float *exact;              /* width*height exact D (float), or NULL when not asked for */
    int64_t saturated_texels;  /* texels whose D ≥ 1024 (stored as 255) */
    int clipped_rows;          /* rows with at least one saturated texel */
    double max_clipped_m;      /* largest m (t) of a clipped row, 0 when none */
    double bake_ms;
} dm_beckmann_lut;

/* Bakes the 8-bit table (and the float one when want_exact) on `threads` threads
 * (0 = all cores). Sizes in [1, DM_LUT_SIZE_MAX]. Free with dm_beckmann_lut_free. */
dm_result dm_lut_bake_beckmann(int width, int height, int want_exact, int threads, dm_beckmann_lut *out,
                               dm_error *err);
void dm_beckmann_lut_free(dm_beckmann_lut *lut);

typedef struct dm_directional_lut {
    int width, height;
    double f0;
    int nodes;
    float *rho_dt; /* width*height each, bottom-up */
    float *scale;
    float *bias;
    double bake_ms;
} dm_directional_lut;

/* Bakes rho_dt and the split-sum scale/bias in one pass. f0 in [0, 1]; nodes in
 * [8, 128]. Free with dm_directional_lut_free. */
dm_result dm_lut_bake_directional(int width, int height, double f0, int nodes, int threads, dm_directional_lut *out,
                                  dm_error *err);
void dm_directional_lut_free(dm_directional_lut *lut);

/* Error of a table as the runtime samples it (bilinear between texel centres, clamp to
 * edge; for Beckmann the 8-bit values are filtered, then decoded). */
typedef struct dm_lut_error {
    int64_t samples;         /* points compared */
    double max_rel, rms_rel; /* Beckmann: relative, over the lobe (D > 1 % of its row's peak,
                              * D < 1024 so clipped samples are excluded) */
    double max_abs;          /* directional: max |table − exact| over [0, 1]² */
    double max_abs_centres;  /* directional: the same at texel centres (the integral's own error) */
    double max_abs_weighted; /* directional: max N·L · |Δ|, its effect on lit irradiance */
    double worst_s, worst_t; /* where the largest error was found */
    double ms;               /* time taken by the comparison */
} dm_lut_error;

/* Errors per roughness band: out[b] counts only samples with m ≥ m_min[b] (band_count
 * bands, m_min[b] = 0 for all). supersample: sample points per texel per axis (≥ 1). */
void dm_lut_beckmann_error(const dm_beckmann_lut *lut, int supersample, const double *m_min, int band_count,
                           int threads, dm_lut_error *out);
/* Compares the three channels at every texel centre, every midpoint between centres and
 * the borders, against dm_ks_directional with DM_LUT_REFERENCE_NODES nodes (one reference
 * evaluation for all channels and bands): out[3*b + 0] rho_dt, out[3*b + 1] scale,
 * out[3*b + 2] bias, for band b. */
void dm_lut_directional_error(const dm_directional_lut *lut, const double *m_min, int band_count, int threads,
                              dm_lut_error *out);

/* Bilinear lookup as the GPU does it with GL_LINEAR + CLAMP_TO_EDGE; exposed for tests. */
double dm_lut_bilinear_f32(const float *table, int width, int height, double s, double t);
double dm_lut_bilinear_u8(const uint8_t *table, int width, int height, double s, double t); /* in [0, 1] */

#ifdef __cplusplus
}
#endif
#endif
