/* dm_skin_layers.h — layered slabs by the multipole, in the radial frequency domain
 * (Donner & Jensen 2005), and the two-layer skin built from them.
 *
 * Transform: F(s) = ∫₀^∞ 2πr J0(s r) f(r) dr (s in rad/mm), so F(0) is the total
 * ∫ 2πr f dr and a Gaussian G(v, r) of dm_profile.h has F = exp(−v s²/2). The inverse is
 * f(r) = (1/2π) ∫ s J0(s r) F(s) ds. Every function here also returns ∂F/∂(s²), exact, so
 * ⟨r²⟩ = −4 F′/F at s = 0 (the second moment, hence the RMS radius) needs no quadrature.
 *
 * One slab (σa, σs′ mm⁻¹, thickness d mm): σt′ = σa + σs′, α′ = σs′/σt′, l = 1/σt′,
 * σtr = √(3σa σt′), D = 1/(3σt′); each face has its own z_b = 2AD, A = (1 + Fdr)/(1 − Fdr)
 * with Fdr = dm_fresnel_diffuse_reflectance(η) of the index ratio η ≥ 1 across that face
 * (η = 1 between two layers of one index: z_b ≈ 2D). Poles i = −n..n:
 *   z_r,i = 2i(d + z_b,top + z_b,bottom) + l,   z_v,i = 2i(d + z_b,top + z_b,bottom) − l − 2 z_b,top,
 *   R̃(s) = α′/2 Σ_i [sgn(z_r,i) e^(−|z_r,i| q) − sgn(z_v,i) e^(−|z_v,i| q)],
 *   T̃(s) = α′/2 Σ_i [sgn(d − z_r,i) e^(−|d − z_r,i| q) − sgn(d − z_v,i) e^(−|d − z_v,i| q)],
 * q = √(σtr² + s²): each pole's closed-form transform (the 2-D transform of the radial flux
 * of a point source). At s = 0, R̃ is dm_multipole_total; a semi-infinite slab keeps only
 * the dipole i = 0 (dm_dipole_total). Seen from below, a slab is the same with its faces
 * swapped (the up-going reflectance and transmittance).
 *
 * Readout (dm_skin_exit): those sums are the net flux E leaving a face (Jensen 2001,
 * DM_SKIN_EXIT_FLUX). DM_SKIN_EXIT_PARTIAL_CURRENT reads a face as the Fresnel-weighted
 * partial current C_φ φ + C_E E (Kienle & Patterson 1997; d'Eon 2012), the fluence φ of a
 * real pole at depth a and its image at b being (e^(−a q) − e^(−b q))/(2Dq) per pair; at a
 * matched (η = 1) face that is φ/4 + E/2, the plain partial current. The boundary condition
 * (z_b) is the same in both.
 *
 * Stacking, top layer 1 over the rest 2 (pointwise in s; Kubelka–Munk-like series of
 * inter-reflections; Donner & Jensen 2005 eq. 12–13, with the up-going R and T of layer 1
 * where the light travels up):
 *   R12 = R1 + T1 R2 T1↑ / (1 − R1↑ R2),   T12 = T1 T2 / (1 − R1↑ R2).
 *
 * Where diffusion is invalid — σa > σs′ (α′ < 1/2: a dark epidermis at short wavelengths,
 * a blood-rich dermis in the Soret band), or a slab thinner than one transport mean free
 * path l = 1/σt′ (its real source would lie below it: the multipole's R and T then turn
 * negative; from d ≥ l on they are positive and tend smoothly to the thick limit) — the
 * layer is a strongly absorbing or thin slab in closed form instead, with no lateral spread
 * (∂/∂s² = 0):
 *   R = α′/2 ∫₀¹ μ/(1 + μ) (1 − e^(−τ(1 + 1/μ))) (1 − F_η(μ)) dμ,   τ = σt′ d
 * (single scattering, isotropic in the reduced coefficients, of light entering at normal
 * incidence, leaving at μ through the face's Fresnel transmittance 1 − F_η (unpolarised,
 * dm_skin_mc_fresnel from index η to 1; η = 1: none lost, α′(1 − ln 2)/2 when semi-
 * infinite); R↑ the same through the bottom face's η),
 *   T = e^(−σa d) − R going down (collimated light at normal incidence),
 *   T↑ = e^(−2σa d) − R going up (diffuse light: the mean 1/μ of a Lambertian flux is 2),
 * both ≥ 0: Beer–Lambert on the light that did not scatter back, so R + T ≤ 1.
 * The switch is continuous: the slab's responses are w·(multipole) + (1 − w)·(closed form),
 * w = dm_skin_layer_diffusion_weight, a C¹ ramp in α′ over [DM_SKIN_ALBEDO_FALLBACK,
 * DM_SKIN_ALBEDO_DIFFUSIVE] times one in d/l over [DM_SKIN_DEPTH_FALLBACK,
 * DM_SKIN_DEPTH_DIFFUSIVE]. The ramps lie where the multipole is still positive (α′ ≥ 0.4,
 * d ≥ l), so w·(multipole) never adds a negative response; above them the multipole is
 * used alone, as before. The layer reports it (dm_skin_layer_diffusive: w = 1), callers
 * count it.
 */
#ifndef DM_SKIN_LAYERS_H
#define DM_SKIN_LAYERS_H

#include "bake/dm_skin_optics.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_SKIN_LAYERS_MAX = 4 };

/* A transform value and its derivative with respect to s² (mm²). */
typedef struct dm_skin_dual {
    double v, d;
} dm_skin_dual;

/* What a diffusive slab's face lets out (see the top of this file). */
typedef enum dm_skin_exit {
    DM_SKIN_EXIT_FLUX = 0,       /* the net flux E = −D ∂φ/∂n (Jensen 2001, Donner & Jensen 2005) */
    DM_SKIN_EXIT_PARTIAL_CURRENT /* the Fresnel-weighted partial current C_φ φ + C_E E (Kienle & Patterson 1997) */
} dm_skin_exit;

/* One slab of a stack. */
typedef struct dm_skin_layer {
    double sigma_a, sigma_s_prime; /* mm⁻¹: σa ≥ 0, σs′ > 0 */
    double thickness_mm;           /* > 0; INFINITY for a semi-infinite last layer */
    double eta_top, eta_bottom;    /* index ratio (this layer over its neighbour) at each face, ≥ 1 */
    dm_skin_exit exit;             /* 0: the flux, the plain dipole / multipole */
} dm_skin_layer;

/* Its four responses at one frequency. */
typedef struct dm_skin_slab {
    dm_skin_dual r, r_up; /* reflectance lit from above, from below */
    dm_skin_dual t, t_up; /* transmittance going down, going up (0 for a semi-infinite slab) */
} dm_skin_slab;

/* The ramps of the switch (above): albedo α′ = σs′/σt′ and depth d/l = d σt′. */
#define DM_SKIN_ALBEDO_FALLBACK 0.4
#define DM_SKIN_ALBEDO_DIFFUSIVE 0.5
#define DM_SKIN_DEPTH_FALLBACK 1.0
#define DM_SKIN_DEPTH_DIFFUSIVE 1.1

/* The multipole's share w ∈ [0, 1] of the layer's responses: 1 where diffusion holds
 * (α′ ≥ 0.5, d σt′ ≥ 1.1), 0 where only the closed form applies, C¹ between. */
double dm_skin_layer_diffusion_weight(const dm_skin_layer *l);
/* 1 when the weight is 1 (the multipole alone), else 0 (the closed form takes part). */
int dm_skin_layer_diffusive(const dm_skin_layer *l);
/* The single-scattering reflectance above: albedo α′ ∈ [0, 1], optical depth τ ≥ 0
 * (INFINITY: semi-infinite), the face's index ratio eta ≥ 1; 16-point Gauss–Legendre in μ over
 * [μc, 1], μc = √(1 − 1/η²) the critical cosine (no light leaves below it). */
double dm_skin_single_scatter_reflectance(double albedo, double optical_depth, double eta);

/* The coefficients of DM_SKIN_EXIT_PARTIAL_CURRENT for a face of index ratio eta ≥ 1:
 * C_φ = (1 − 2C₁)/4, C_E = (1 − 3C₂)/2, C_n = ∫₀¹ F_η(μ) μⁿ dμ the Fresnel moments
 * (dm_skin_mc_fresnel from η to 1; 1 beyond the critical angle). η = 1: 1/4 and 1/2. */
void dm_skin_exit_coefficients(double eta, double *c_phi, double *c_e);

/* The slab's responses at frequency s_per_mm ≥ 0 with pairs image pairs (0: the default of
 * dm_diffusion.h, DM_MULTIPOLE_PAIRS_DEFAULT); the fallback above where not diffusive. */
void dm_skin_layer_transform(const dm_skin_layer *l, int pairs, double s_per_mm, dm_skin_slab *out);

/* Reflectance (and transmittance, t may be NULL) of layer_count (1..DM_SKIN_LAYERS_MAX)
 * layers, top first, at s_per_mm. */
void dm_skin_stack_transform(const dm_skin_layer *layers, int layer_count, int pairs, double s_per_mm, dm_skin_dual *r,
                             dm_skin_dual *t);

/* Flags of dm_skin_reflectance_at: which layers fell back to Beer–Lambert. */
enum { DM_SKIN_INVALID_EPIDERMIS = 1, DM_SKIN_INVALID_DERMIS = 2 };

/* The skin's two layers at wavelength row lambda_index (dm_skin_data.h): epidermis (faces:
 * η over air, 1 over the dermis) over the dermis (1 over the epidermis; η over air below a
 * finite dermis, semi-infinite when p->dermis_mm is 0), both read out as the partial current
 * (DM_SKIN_EXIT_PARTIAL_CURRENT: against the Monte Carlo the Caucasian R(r) at 650 nm is
 * within 0.91–1.14 over 0.25–4.5 mm where the flux's is 0.75–1.37, both normalised to
 * adding-doubling's total; docs/skin-model.md has the other cases). p must be validated. */
void dm_skin_layers_at(const dm_skin_params *p, int lambda_index, dm_skin_layer layers[2]);

/* The skin's reflectance transform R̃(s) at lambda_index by diffusion; *invalid (may be NULL)
 * receives the DM_SKIN_INVALID_* flags. R̃(0).v is diffusion's total at that λ: the profile
 * normalises it to adding-doubling's (dm_skin_freq_totals, dm_skin_ad.h). */
void dm_skin_reflectance_at(const dm_skin_params *p, int lambda_index, int pairs, double s_per_mm, dm_skin_dual *r,
                            unsigned *invalid);

#ifdef __cplusplus
}
#endif
#endif
