/* dm_skin_rgb.h — a reflectance spectrum on dm_skin_data.h's grid to linear sRGB, as seen
 * under CIE D65 by the CIE 1931 2° observer.
 *
 *   XYZ = Σ_λ R(λ) S(λ) (x̄, ȳ, z̄)(λ) Δλ / Σ_λ S(λ) ȳ(λ) Δλ,   S = D65,
 *   RGB = M · XYZ, M the IEC 61966-2-1 (sRGB) matrix, linear (no transfer curve).
 * Linear in R, so it is one weight per channel and wavelength, w_c(λ) (dm_skin_rgb_weights):
 * RGB_c = Σ_λ w_c(λ) R(λ). The 10 nm sums leave a perfect white reflector (R ≡ 1) within
 * about 1 % of (1, 1, 1); each channel's weights are scaled so it maps to (1, 1, 1) exactly
 * (what a renderer's albedo expects; the factors are dm_skin_rgb_white_scale).
 *
 * The weights have negative lobes (R below 550 nm, G at both ends, B around 580 nm), so a
 * channel's radial profile Σ_λ w_c(λ) R_λ(r) may dip below zero at some radii although every
 * R_λ(r) is positive. dm_skin_profile.h says what the fit does with that.
 */
#ifndef DM_SKIN_RGB_H
#define DM_SKIN_RGB_H

#include "bake/dm_skin_data.h"

#ifdef __cplusplus
extern "C" {
#endif

/* w[λ index][channel], DM_SKIN_LAMBDA_COUNT rows: RGB_c = Σ w[i][c] R(λ_i). */
void dm_skin_rgb_weights(double w[DM_SKIN_LAMBDA_COUNT][3]);
/* The per-channel factors applied to make white (1, 1, 1): 1 / (M · XYZ_white) before scaling. */
void dm_skin_rgb_white_scale(double scale[3]);
/* CIE XYZ (Y = 1 for a perfect white) of a spectrum R[DM_SKIN_LAMBDA_COUNT] under D65. */
void dm_skin_spectrum_to_xyz(const double *reflectance, double xyz[3]);
/* Linear sRGB of a spectrum R[DM_SKIN_LAMBDA_COUNT] (white-balanced as above). */
void dm_skin_spectrum_to_rgb(const double *reflectance, double rgb[3]);

#ifdef __cplusplus
}
#endif
#endif
