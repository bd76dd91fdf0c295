/* dm_preintegrated.h — Penner's pre-integrated skin diffuse table (GPU Pro 2, 2011, "Pre-
 * Integrated Skin Shading"): diffuse light on a ring of radius r, blurred by the profile.
 *
 *   D(θ, r) = ∫_{−π}^{π} max(0, cos(θ + x)) R(2r sin(x/2)) dx / ∫_{−π}^{π} R(2r sin(x/2)) dx
 *
 * per channel, R the profile's radial Gaussian sum (mm⁻²; any overall scale cancels), 2r
 * |sin(x/2)| the chord between two points of the ring x radians apart, θ the angle between
 * the normal and the light (cos θ = N·L) and 1/r the curvature κ (mm⁻¹). The whole circle
 * and the normalisation are integrated (not −π/2..π/2); κ = 0 is the limit max(0, cos θ).
 *
 * Quadrature (deterministic, no randomness): per Gaussian, the integrand over x ∈ [0, π]
 * (R is even in x) is cut at the kinks of max(0, cos(θ ± x)) and at the angles where the
 * chord is {1/4, 1/2, 1, 3/2, 2, 3, 4, 6, 8, 12, 16, 24} σ, and stops at 40σ (the Gaussian
 * is below e^(−800) beyond); each piece is smooth and at most a few σ wide, and takes
 * DM_PREINT_NODES Gauss–Legendre nodes. Measured against a 2^17-point brute force:
 * ≤ 1e-12 absolute (tests/unit/test_preintegrated.c).
 *
 * Table layout (dm_preint_lut): texel (i, j), rows bottom-up like every dermis LUT:
 *   s: N·L = 2 (i + 0.5)/width − 1 at texel centres (so ±1 lies half a texel outside);
 *   t: κ = κ_max · j/(height − 1): row 0 is exactly flat (κ = 0) and the last row κ_max,
 *      so the runtime looks up t = (0.5 + (height − 1) κ/κ_max)/height.
 * A Burley profile (R ∝ 1/r) makes ∫ R dx diverge like ln(1/x) at x → 0, so the formula
 * would give max(0, N·L) for every r: bake Burley through its Gaussian fit
 * (dermis-fit-profile --burley), which is what this module takes.
 */
#ifndef DM_PREINTEGRATED_H
#define DM_PREINTEGRATED_H

#include "core/dm_profile.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    DM_PREINT_WIDTH_DEFAULT = 256,  /* N·L texels */
    DM_PREINT_HEIGHT_DEFAULT = 128, /* curvature texels */
    DM_PREINT_SIZE_MAX = 4096,
    DM_PREINT_NODES = 24 /* Gauss–Legendre nodes per piece */
};
/* Default κ_max: 1 mm⁻¹ covers the head (an ear rim or nostril is ~1–3 mm in radius, the
 * forehead ~50–100 mm). */
#define DM_PREINT_CURVATURE_MAX_DEFAULT 1.0
#define DM_PREINT_CURVATURE_MAX_LIMIT 100.0

/* D per channel for one (N·L, κ): cos_theta in [−1, 1], curvature_per_mm ≥ 0 (0 = flat).
 * p must pass dm_profile_validate; a channel with no weight gives max(0, N·L). */
void dm_preint_eval(const dm_profile *p, double cos_theta, double curvature_per_mm, double rgb[3]);

/* The same integral by brute force: the midpoint rule with sample_count points over
 * [−π, π] of R evaluated through dm_profile_eval (no splitting), for reports and tests. */
void dm_preint_brute(const dm_profile *p, double cos_theta, double curvature_per_mm, int sample_count,
                     double rgb[3]);

typedef struct dm_preint_lut {
    int width, height;
    double curvature_max_per_mm;
    float *rgb;     /* 3 planes R, G, B of width*height each (plane c at rgb + c*width*height),
                     * rows bottom-up: what an EXR channel or a GL upload per channel takes */
    double bake_ms;
} dm_preint_lut;

/* N·L and κ of texel centre (i, j) of a width × height table. */
double dm_preint_texel_cos(int i, int width);
double dm_preint_texel_curvature(int j, int height, double curvature_max_per_mm);

/* Bakes the table on `threads` threads (0 = all cores; byte-identical for any count).
 * width in [2, DM_PREINT_SIZE_MAX], height in [2, DM_PREINT_SIZE_MAX], curvature_max in
 * (0, DM_PREINT_CURVATURE_MAX_LIMIT]; DM_ERR_RANGE otherwise, DM_ERR_OUT_OF_MEMORY. Free
 * with dm_preint_lut_free. */
dm_result dm_preint_bake(const dm_profile *p, int width, int height, double curvature_max_per_mm, int threads,
                         dm_preint_lut *out, dm_error *err);
void dm_preint_lut_free(dm_preint_lut *lut);

/* Error of the table against dm_preint_brute (sample_count points): at texel centres
 * (the integral's own error) and at the midpoints between centres as a bilinear lookup
 * samples them (GL_LINEAR, clamp to edge), over every `stride`-th row and column. */
typedef struct dm_preint_error {
    double max_abs_centres; /* max over channels */
    double max_abs_bilinear;
    double worst_cos, worst_curvature; /* where max_abs_bilinear was found */
    long samples;
    double ms;
} dm_preint_error;
void dm_preint_lut_error(const dm_profile *p, const dm_preint_lut *lut, int stride, int sample_count, int threads,
                         dm_preint_error *out);

#ifdef __cplusplus
}
#endif
#endif
