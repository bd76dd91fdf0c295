/* dm_lut_check.h — re-evaluates a sample of LUT texels against the analytic functions of
 * core/dm_brdf.h: the validator's proof that a table holds what its name says.
 *
 * Samples: the four corners, an 8×8 grid of texels and 32 pseudo-random ones (fixed seed),
 * so results are reproducible. Tables use the layout of bake/dm_lut.h (texel centres,
 * rows bottom-up).
 *   Beckmann (8-bit): expected dm_beckmann_encode8(dm_beckmann(s, t)); a texel passes
 *     within ±1 code (a 1-ulp difference of libm can move a value across a rounding edge).
 *   Directional (float): expected dm_ks_directional with the table's own f0 and node
 *     count, so only storage rounding separates them; a texel passes within
 *     1e-3·max(1, |expected|) — half-float storage rounds by up to 4.9e-4 relative,
 *     float by 6e-8; real damage (a wrong table, a wrong F0, swapped axes) is ≥ 1e-2.
 */
#ifndef DM_LUT_CHECK_H
#define DM_LUT_CHECK_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_lut_check {
    int samples;                   /* texels compared */
    int failures;                  /* texels outside the tolerance */
    double max_error;              /* largest |table − expected| (Beckmann: in codes) */
    int worst_i, worst_j;          /* the texel of max_error */
    double worst_value, worst_expected;
} dm_lut_check;

void dm_lut_check_beckmann(const uint8_t *texels, int width, int height, dm_lut_check *out);
/* table: width*height texels of `stride` floats; channels 1 = rho_dt (value[0]) or
 * 2 = env-BRDF split sum (value[0] scale, value[1] bias). */
void dm_lut_check_directional(const float *table, int stride, int channels, int width, int height, double f0,
                              int nodes, dm_lut_check *out);

#ifdef __cplusplus
}
#endif
#endif
