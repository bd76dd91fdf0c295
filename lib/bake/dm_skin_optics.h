/* dm_skin_optics.h — the parameters of the physical three-layer skin and, per wavelength,
 * the absorption σa and reduced scattering σs′ of its epidermis and dermis.
 *
 * Units: λ in nm, σa and σs′ in mm⁻¹, thicknesses in mm, fractions dimensionless.
 * The laws (all from /work/shared/SKIN-MODEL.md; docs/skin-model.md says more):
 *   eumelanin    σa = 6.6·10¹⁰ λ^−3.33      (Jacques 1998, cm⁻¹ law ÷ 10)
 *   pheomelanin  σa = 2.9·10¹⁴ λ^−4.75      (Jacques 1998)
 *   baseline     σa = 0.0244 + 8.53 exp(−(λ − 154)/66.2)   (bloodless tissue, Jacques)
 *   whole blood  σa = ln 10 · ε · 150 g/L / 64 500 g/mol / 10   (ε from Prahl, cm⁻¹/M)
 *   epidermis    σa = Cm [βm σa_eu + (1 − βm) σa_pheo] + (1 − Cm) σa_base
 *   dermis       σa = Ch [γ σa_HbO2 + (1 − γ) σa_Hb] + (1 − Ch) σa_base
 *   scattering   S(λ) = 14.74 λ^−0.22 + 2.2·10¹¹ λ^−4   (Donner & Jensen 2006, mm⁻¹)
 *                epidermis σs′ = S(λ); dermis σs′ = S(λ)/2 (DJ2006's dermis takes half).
 *
 * Oil (the specular layer) is not part of this: it is white and belongs to the BRDF.
 */
#ifndef DM_SKIN_OPTICS_H
#define DM_SKIN_OPTICS_H

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Accepted ranges (dm_skin_params_validate). Cm, βm and Ch are DJ2006's ranges; Ch may be 0
 * (bloodless, blanched tissue: the baseline still absorbs, so diffusion stays finite), the
 * physiological floor DJ2006 quote is 0.001. Thicknesses: epidermis 1 µm (far below a mean
 * free path, a hard case the model must survive) to 2 mm (palms, soles); a finite dermis
 * 0.1–10 mm, 0 meaning semi-infinite (DJ2006). */
#define DM_SKIN_MELANIN_MAX 0.5
#define DM_SKIN_BLOOD_MAX 0.1
#define DM_SKIN_EPIDERMIS_MIN_MM 0.001
#define DM_SKIN_EPIDERMIS_MAX_MM 2.0
#define DM_SKIN_DERMIS_MIN_MM 0.1
#define DM_SKIN_DERMIS_MAX_MM 10.0
#define DM_SKIN_ETA_MIN 1.0
#define DM_SKIN_ETA_MAX 2.0

/* The skin. The physical zeros are valid values here (no melanin, no blood), so zero does
 * not mean "default": start from dm_skin_params_default() or dm_skin_preset(). */
typedef struct dm_skin_params {
    double melanin_fraction;   /* Cm, epidermal melanin volume fraction, [0, 0.5] */
    double eumelanin_blend;    /* βm, eumelanin share of the melanin, [0, 1] (rest pheomelanin) */
    double blood_fraction;     /* Ch, dermal blood volume fraction, [0, 0.1] */
    double oxygenation;        /* γ, HbO2 share of the hemoglobin, [0, 1]; DJ2006 0.75 */
    double epidermis_mm;       /* [DM_SKIN_EPIDERMIS_MIN_MM, MAX]; DJ2006 0.25 */
    double dermis_mm;          /* 0: semi-infinite (DJ2006), else [DM_SKIN_DERMIS_MIN_MM, MAX] */
    double eta;                /* refractive index of both layers over air, [1, 2]; 1.4 */
} dm_skin_params;

/* DJ2006's defaults with the Caucasian exemplar's chromophores: Cm 0.005, βm 0.7, Ch 0.005,
 * γ 0.75, epidermis 0.25 mm, semi-infinite dermis, η 1.4. */
dm_skin_params dm_skin_params_default(void);

/* The DJ2006 exemplars (SKIN-MODEL.md): "caucasian" (Cm 0.005, βm 0.7, Ch 0.005), "asian"
 * (0.15, 0, 0.01), "african" (0.5, 0.7, 0.05), epidermis 0.25 mm; and a Fitzpatrick gallery,
 * our own mapping (no paper tabulates one) spread over the NIST forearm cohort, I near its
 * top and VI near its bottom: "fitzpatrick-1" … "-6" with Cm 0.006, 0.009, 0.013, 0.019,
 * 0.028, 0.042 in the forearm's measured 0.075 mm epidermis, βm 0.7, Ch 0.005
 * (docs/skin-model.md). The rest as the default.
 * DM_ERR_INVALID_ARGUMENT, naming the known ones, for another name. */
dm_result dm_skin_preset(const char *name, dm_skin_params *p, dm_error *err);
/* The preset names in order, index 0..; NULL past the last. */
const char *dm_skin_preset_name(int index);

/* Refuses a NaN, infinite or out-of-range parameter: the message names `what`, the
 * parameter (field, and its key in dm_skin_spec.h), its value and its accepted range
 * (DM_ERR_RANGE or DM_ERR_NON_FINITE). */
dm_result dm_skin_params_validate(const dm_skin_params *p, const char *what, dm_error *err);

/* The laws above, one each, mm⁻¹ at λ nm (any λ > 0; the ε of blood from the caller). */
double dm_skin_eumelanin_sigma_a(double lambda_nm);
double dm_skin_pheomelanin_sigma_a(double lambda_nm);
double dm_skin_baseline_sigma_a(double lambda_nm);
double dm_skin_blood_sigma_a(double molar_ext_per_cm_per_molar);
double dm_skin_scattering(double lambda_nm);

/* Bulk optics of the two layers at one wavelength. */
typedef struct dm_skin_optics {
    double lambda_nm;
    double epidermis_sigma_a, epidermis_sigma_s_prime; /* mm⁻¹ */
    double dermis_sigma_a, dermis_sigma_s_prime;       /* mm⁻¹ */
} dm_skin_optics;

/* The optics at row lambda_index (0..DM_SKIN_LAMBDA_COUNT−1) of dm_skin_data.h, for
 * validated parameters. */
void dm_skin_optics_at(const dm_skin_params *p, int lambda_index, dm_skin_optics *out);

#ifdef __cplusplus
}
#endif
#endif
