/* dm_brdf.h — the skin specular model of GPU Gems 3 ch. 14 (Kelemen/Szirmay-Kalos with a
 * Beckmann distribution and Schlick Fresnel), in double for bakes and references and in
 * float where the runtime needs the same numbers.
 *
 * Conventions (DESIGN.md):
 *   D(c, m) = exp((c² − 1)/(c² m²)) / (m² c⁴), c = N·H, m = Beckmann roughness.
 *   This D is normalised so that ∫ D(N·H) (N·H) dω_h = π (not 1).
 *   f_KS(L, V) = D(N·H) F(H·V) / |h|², h = L + V unnormalised, H = h/|h|.
 *   Specular radiance factor = (N·L) rho_s max(f_KS, 0).
 *   rho_dt(c = N·L, m) = ∫ f_KS(L, V) (N·V) dω_V with rho_s = 1 (upper hemisphere).
 *
 * Hard cases, all finite: c ≤ 0 gives D = 0; c > 1 is treated as 1; m ≤ 0 is the limit
 * m → 0 (D = 0 for c < 1, DM_BECKMANN_D_MAX at c = 1); every result is clamped to
 * DM_BECKMANN_D_MAX, which only bites for m < 1e-10.
 */
#ifndef DM_BRDF_H
#define DM_BRDF_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define DM_BECKMANN_D_MAX 1e20     /* finite stand-in for the m → 0 delta; float-safe */
#define DM_SKIN_F0 0.028           /* Schlick F0 of skin */
#define DM_BECKMANN_LUT_D_MAX 1024.0 /* largest D the 8-bit 0.5·D^0.1 encoding holds */

/* Beckmann D(c, m); see the header comment for every edge. */
double dm_beckmann(double c, double m);
float dm_beckmann_f(float c, float m);

/* Schlick: F0 + (1 − F0)(1 − cos)^5, cos clamped to [0, 1]. */
double dm_fresnel_schlick(double cos_theta, double f0);
float dm_fresnel_schlick_f(float cos_theta, float f0);

/* (N·L) rho_s max(D F / |h|², 0) for unit vectors n, l, v. Zero when N·L ≤ 0 or when
 * L and V are opposite (|h|² → 0). Finite for every unit input. */
double dm_ks_specular(const double n[3], const double l[3], const double v[3], double m, double rho_s,
                      double f0);
float dm_ks_specular_f(const float n[3], const float l[3], const float v[3], float m, float rho_s, float f0);

/* The directional integral of the KS lobe split by Schlick's F0 (split sum):
 *   ∫ f_KS (N·ω) dω = f0 * scale + bias,
 * with scale = ∫ D/|h|² (1 − (1 − L·H)^5) (N·ω) dω and bias = ∫ D/|h|² (1 − L·H)^5 (N·ω) dω,
 * where c is the cosine of the fixed direction (by reciprocity either L or V).
 * Integrated in half-vector space under u = tan²θ_h / m², cut exactly at the horizon;
 * `nodes` Gauss–Legendre points per dimension and piece (16 ≥ nodes ≥ 96; 48 gives
 * < 1e-6 absolute error for m ≥ 0.01, c ∈ [0, 1]). c is clamped to [0, 1], m ≤ 0 uses the
 * m → 0 limit (scale + bias·… = π F(c) times its parts). */
void dm_ks_directional(double c, double m, int nodes, double *scale, double *bias);
/* rho_dt(c, m) with Schlick F0 f0: f0 * scale + bias of dm_ks_directional. */
double dm_rho_dt(double c, double m, double f0, int nodes);

/* 8-bit Beckmann texel: round(255 · 0.5 · D^0.1), saturating at 255 (D ≥ 1024). */
uint8_t dm_beckmann_encode8(double d);
/* (2 · v / 255)^10: what the shader reads back from a texel (or a filtered value). */
double dm_beckmann_decode8(double v_over_255);

#ifdef __cplusplus
}
#endif
#endif
