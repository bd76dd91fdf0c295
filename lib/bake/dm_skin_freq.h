/* dm_skin_freq.h — the frequency-domain quadrature the physical skin's fits share: the
 * offline profile (dm_skin_profile.c: 401 nodes over [1e-3, 3e3] mm⁻¹) and the live weights
 * (dm_skin_weights.c: fewer nodes, cut where the narrowest Gaussian has vanished).
 *
 * Nodes s_i are ln-spaced over [s_lo, s_hi] (count odd, ≥ 3), each weighted by
 * q_i = s_i² · Simpson(Δ ln s), so Σ_i q_i F(s_i) G(s_i) ≈ ∫ s F G ds: by Parseval for the
 * transform of dm_skin_layers.h, 4π² ∫ r f g dr, the r-weighted L2 product of
 * dm_profile_fit.h. Rows carry √q_i, so a least-squares fit on them minimises that error.
 * Column-major arrays throughout: column k of a (count × n) matrix starts at a + k·count. */
#ifndef DM_SKIN_FREQ_H
#define DM_SKIN_FREQ_H

#include "bake/dm_skin_data.h"
#include "bake/dm_skin_optics.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The offline range (dm_skin_profile.h): [1e-3, 3e3] mm⁻¹. */
#define DM_SKIN_FREQ_S_LO_PER_MM 1e-3
#define DM_SKIN_FREQ_S_HI_PER_MM 3e3

/* s[count] (mm⁻¹) and sq[count] = √q_i. 0 < s_lo < s_hi, count odd ≥ 3. */
void dm_skin_freq_nodes(double s_lo, double s_hi, int count, double *s, double *sq);
/* The weighted design a (count × n): √q_i exp(−v_k s_i²/2) for the variances v[n] (mm²). */
void dm_skin_freq_design(const double *s, const double *sq, int count, const double *variance_mm2, int n, double *a);
/* The model's total diffuse reflectance per wavelength row, total[DM_SKIN_LAMBDA_COUNT]
 * (adding-doubling, dm_skin_ad_total_at with ad_stream_count streams, 0 = its default), and
 * scale[DM_SKIN_LAMBDA_COUNT] = total / R̃_λ(0), the factor that normalises diffusion's
 * transform (dm_skin_reflectance_at with pairs image pairs) to it: the profile keeps
 * diffusion's shape and takes adding-doubling's total, so scale·R̃_λ(0) is the total exactly
 * and the RMS radius (a ratio) is diffusion's. Either output may be NULL. p validated. */
void dm_skin_freq_totals(const dm_skin_params *p, int pairs, int ad_stream_count, double *total, double *scale);
/* y (count × DM_SKIN_LAMBDA_COUNT): √q_i scale_λ R̃_λ(s_i) for every wavelength row of
 * validated p (scale from dm_skin_freq_totals; NULL: 1, diffusion's own total). */
void dm_skin_freq_spectral(const dm_skin_params *p, int pairs, const double *scale, const double *s, const double *sq,
                           int count, double *y);
/* yc (count × 3): Σ_λ w_c(λ) √q_i scale_λ R̃_λ(s_i), the channel targets, with the weights w
 * of dm_skin_rgb_weights; the same numbers, bit for bit, as combining dm_skin_freq_spectral's
 * columns, without storing them. */
void dm_skin_freq_channels(const dm_skin_params *p, int pairs, const double *scale, const double *s, const double *sq,
                           int count, const double (*w)[3], double *yc);

#ifdef __cplusplus
}
#endif
#endif
