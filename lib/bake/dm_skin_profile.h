/* dm_skin_profile.h — the physical skin (dm_skin_optics.h) as a dm_profile: a sum of
 * Gaussians per RGB channel, fitted straight in the radial frequency domain.
 *
 * Per wavelength of dm_skin_data.h the two-layer reflectance transform R̃_λ(s) is diffusion's
 * (dm_skin_layers.h: closed-form poles, no numerical transform), normalised to the total
 * diffuse reflectance of adding-doubling (dm_skin_ad.h, Henyey–Greenstein g 0.8; the
 * factor of dm_skin_freq_totals): the shape is diffusion's, the total exact for g. Every
 * output below — the fit's targets, the report's totals and radii, the dense profile — uses
 * that one normalisation. A channel is R̃_c(s) = Σ_λ w_c(λ) R̃_λ(s) (dm_skin_rgb.h). Gaussians transform to exp(−v s²/2), so
 *   R̃_c(s) ≈ Σ_k w_kc exp(−v_k s²/2)
 * with fixed variances v_k and weights w_kc ≥ 0 by non-negative least squares
 * (dm_lsq_nnls_shared) on DM_SKIN_FREQ_NODES nodes in ln s over [1e-3, 3e3] mm⁻¹, each
 * weighted by s² Δ(ln s) (Simpson). By Parseval for this transform,
 * ∫ s (F − G)² ds = 4π² ∫ r (f − g)² dr: the r-weighted L2 error of dm_profile_fit.h, so
 * the reported sqrt(e_c/E_c) is the same measure, found without an inverse transform and so
 * without its ringing.
 *
 * Negative lobes: a channel's R_c(r) may be negative at some radii (dm_skin_rgb.h). The
 * fit does not clamp it first: NNLS against the signed R̃_c is the L2-closest sum of
 * non-negative Gaussians to the signed profile (clamping first would add light that the
 * spectrum does not have); the dense profile below shows the lobes as they are. A channel
 * whose colorimetric total is ≤ 0 (a dark skin's blue) gets all-zero weights.
 */
#ifndef DM_SKIN_PROFILE_H
#define DM_SKIN_PROFILE_H

#include "bake/dm_skin_data.h"
#include "bake/dm_skin_optics.h"
#include "core/dm_profile.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_SKIN_FREQ_NODES = 401, DM_SKIN_DENSE_GAUSSIANS = 32 };

/* GPU Gems 3's six variances (d'Eon & Luebke, ch. 14), mm². */
extern const double DM_SKIN_GEMS3_VARIANCES_MM2[6];

/* Zero-initialised = defaults. */
typedef struct dm_skin_profile_options {
    int gaussian_count;                            /* 0: the six of DM_SKIN_GEMS3_VARIANCES_MM2 */
    double variance_mm2[DM_PROFILE_MAX_GAUSSIANS]; /* when gaussian_count > 0: strictly ascending, > 0 */
    int pair_count;                                /* multipole image pairs; 0: DM_MULTIPOLE_PAIRS_DEFAULT */
    int stream_count;                              /* adding-doubling streams (dm_skin_ad.h); 0: DM_SKIN_AD_STREAMS_DEFAULT */
} dm_skin_profile_options;

/* What the fit found, and what the physics said on the way. */
typedef struct dm_skin_report {
    double total_rgb[3];            /* colorimetric total diffuse reflectance Σ_λ w_c R̃_λ(0) */
    double fit_total_rgb[3];        /* Σ_k w_kc of the fitted profile */
    double fit_error_relative[3];   /* sqrt(e_c/E_c) as in dm_profile_fit.h; 0 for a zero channel */
    double fit_error_relative_max;
    double rms_radius_mm[3];        /* √(∫ r² R_c 2πr dr / ∫ R_c 2πr dr) of the physical profile, exact
                                     * (from ∂R̃/∂s² at 0); 0 where the channel's total or its
                                     * second moment is ≤ 0 (negative lobes) */
    double total_spectral[DM_SKIN_LAMBDA_COUNT]; /* R̃_λ(0) per wavelength row: adding-doubling's total */
    double diffusion_total_spectral[DM_SKIN_LAMBDA_COUNT]; /* diffusion's own R̃_λ(0), before the normalisation */
    unsigned invalid[DM_SKIN_LAMBDA_COUNT];      /* DM_SKIN_INVALID_* per wavelength row */
    int epidermis_invalid_count, dermis_invalid_count;      /* rows where that layer fell back */
} dm_skin_report;

/* Fits the profile of validated-here parameters p (dm_skin_params_validate's errors, naming
 * the parameter) with opt (may be NULL: defaults); names it `name` (may be NULL: "").
 * rep may be NULL. DM_ERR_RANGE for bad options, DM_ERR_OUT_OF_MEMORY. Allocates scratch
 * (about 0.3 MB) and frees it before returning. Deterministic. */
dm_result dm_skin_profile_fit(const dm_skin_params *p, const dm_skin_profile_options *opt, const char *name,
                              dm_profile *out, dm_skin_report *rep, dm_error *err);

/* The report's physics alone, without a fit: total_rgb, rms_radius_mm, total_spectral, invalid
 * and the counts, exact (closed form at s = 0); the fit fields are 0. p validated here;
 * pair_count 0 = the default. Cheap: 31 wavelengths at one frequency. */
dm_result dm_skin_physics_report(const dm_skin_params *p, int pair_count, dm_skin_report *rep, dm_error *err);
/* The dense physical profile, for comparison: each wavelength's R_λ(r) represented by
 * DM_SKIN_DENSE_GAUSSIANS Gaussians (standard deviations log-spaced 0.004..16 mm, NNLS in
 * the frequency domain as above, weights ≥ 0 per wavelength), combined per channel with the
 * signed w_c(λ): channel weights may be negative, which is how the lobes show. Normalised
 * as the fit is, with the default adding-doubling streams. */
typedef struct dm_skin_dense {
    double variance_mm2[DM_SKIN_DENSE_GAUSSIANS];
    double weight[DM_SKIN_DENSE_GAUSSIANS][3];
    double error_relative_max; /* the worst wavelength's representation error, sqrt(e/E) */
} dm_skin_dense;

dm_result dm_skin_dense_profile(const dm_skin_params *p, int pair_count, dm_skin_dense *out, dm_error *err);
/* R_c(r) of the dense profile, mm⁻², per channel (may be negative). */
void dm_skin_dense_eval(const dm_skin_dense *d, double r_mm, double rgb[3]);
/* Its weight sums per channel: the colorimetric totals to ~1e-6 where every layer diffuses.
 * Where the epidermis takes the closed form (dark skins at short wavelengths) its light has no
 * lateral spread, a flat transform no Gaussian sum follows, and the sums overshoot the total
 * (Fitzpatrick 6: twice it): dm_skin_physics_report has the exact totals. */
void dm_skin_dense_total(const dm_skin_dense *d, double rgb[3]);

#ifdef __cplusplus
}
#endif
#endif
