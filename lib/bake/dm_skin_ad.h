/* dm_skin_ad.h — the adding-doubling method for a plane-parallel stack of layers: the total
 * diffuse reflectance (and transmittance) of the layered skin, exact for the
 * Henyey–Greenstein anisotropy g, which diffusion (dm_skin_layers.h) does not see.
 *
 * The method of van de Hulst (1980) and Prahl ("The adding-doubling method", in Optical-
 * Thermal Response of Laser-Irradiated Tissue, 1995), written from their description:
 *  - streams: N cosines μ_i per hemisphere with weights w_i; where the stack's index n
 *    exceeds the air's, N/2 Gauss–Legendre on [0, μc] and N/2 Gauss–Radau on [μc, 1]
 *    (μc = √(1 − 1/n²), the critical cosine: the Fresnel reflectance has its kink there);
 *    else N Radau on [0, 1]. Radau fixes a node at μ = 1: the normally incident beam is
 *    that stream, so collimated light needs no stream of its own;
 *  - phase function: Henyey–Greenstein, δ-M truncated at N Legendre terms (f = g^N:
 *    χ_k = (g^k − f)/(1 − f), albedo a(1 − f)/(1 − af), optical depth τ(1 − af)), reduced
 *    to its azimuthal average h(μ, μ′) = Σ_{k<N} (2k + 1) χ_k P_k(μ) P_k(μ′); each column is
 *    renormalised so the quadrature conserves energy to rounding;
 *  - operators act on fluxes per stream (F_i = 2 μ_i w_i L_i: ordinary matrix products,
 *    the column sums are the totals), reflection R and transmission T of a homogeneous
 *    layer being the same from either side;
 *  - a thin layer of optical depth Δτ ≤ DM_SKIN_AD_START_DEPTH (τ/2^k) by the diamond
 *    initialisation (Wiscombe 1976: the discrete-ordinate equations with the mid-layer
 *    radiance the mean of the faces'), then doubled k times,
 *    R ← R + T R (I − R R)⁻¹ T, T ← T (I − R R)⁻¹ T;
 *    a semi-infinite layer doubled until every column of T sums below 1e-9 (at most 64
 *    times);
 *  - layers added from the bottom up, R = R_top + T_top R_below (I − R_top R_below)⁻¹ T_top;
 *  - faces against air (index 1, above and below): unpolarised Fresnel (dm_skin_mc_fresnel)
 *    per stream, inside the stack; what the face lets through leaves. Layers share one n,
 *    so inner interfaces do nothing.
 * Incidence: a normal beam, per unit of the power that ENTERED (the specular reflection
 * ((n − 1)/(n + 1))² of the top face is outside, as in dm_skin_layers.h's R̃(0) and the
 * renderer's shaders, which apply the entry Fresnel themselves). dm_skin_mc's Rd is per
 * unit incident: Rd/(1 − Rsp) is the same quantity.
 * Deterministic, double precision, no allocation (a few × N² doubles of stack).
 */
#ifndef DM_SKIN_AD_H
#define DM_SKIN_AD_H

#include "bake/dm_skin_data.h"
#include "bake/dm_skin_optics.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_SKIN_AD_LAYERS_MAX = 8, DM_SKIN_AD_STREAMS_MAX = 32, DM_SKIN_AD_STREAMS_DEFAULT = 16 };
#define DM_SKIN_AD_START_DEPTH 0.1
/* The Henyey–Greenstein anisotropy the skin's layers are given (μs = σs′/(1 − g)): 0.8,
 * as in the Monte Carlo comparisons (docs/skin-model.md); dermis 0.75–0.81 over 400–700 nm
 * in van Gemert et al. 1989's law g = 0.62 + 0.29·10⁻³ λ. */
#define DM_SKIN_ANISOTROPY 0.8

/* One homogeneous layer (as dm_skin_mc_layer, less the index, which the stack shares). */
typedef struct dm_skin_ad_layer {
    double mu_a_per_mm;  /* ≥ 0, finite */
    double mu_s_per_mm;  /* ≥ 0, finite (not reduced) */
    double g;            /* Henyey–Greenstein anisotropy, (−1, 1) */
    double thickness_mm; /* > 0; INFINITY for the last layer only (then μa > 0) */
} dm_skin_ad_layer;

/* Zero-initialised = defaults. */
typedef struct dm_skin_ad_options {
    int stream_count;   /* N per hemisphere, even, 2..DM_SKIN_AD_STREAMS_MAX; 0 = DEFAULT (16) */
    double start_depth; /* optical depth of the initial thin layer, (0, 1]; 0 = DM_SKIN_AD_START_DEPTH */
} dm_skin_ad_options;

typedef struct dm_skin_ad_result {
    double reflectance;   /* leaving the top, per unit entered, normal incidence */
    double transmittance; /* leaving the bottom (0 for a semi-infinite stack), per unit entered */
} dm_skin_ad_result;

/* The stack of layer_count (1..DM_SKIN_AD_LAYERS_MAX) layers, top first, of index n
 * ([1, 10]) in air; opt may be NULL. DM_ERR_RANGE / DM_ERR_NON_FINITE naming the layer, the
 * field, its value and the range. */
dm_result dm_skin_ad_run(const dm_skin_ad_layer *layers, int layer_count, double n, const dm_skin_ad_options *opt,
                         dm_skin_ad_result *out, dm_error *err);

/* The skin's two layers at row lambda_index (dm_skin_layers_at's σa, σs′ and thicknesses,
 * g = DM_SKIN_ANISOTROPY, n = p->eta; a semi-infinite dermis when p->dermis_mm is 0):
 * its total diffuse reflectance per unit entered. p validated; stream_count 0 = default. */
double dm_skin_ad_total_at(const dm_skin_params *p, int lambda_index, int stream_count);

#ifdef __cplusplus
}
#endif
#endif
