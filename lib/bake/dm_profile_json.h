/* dm_profile_json.h — writing a fitted profile as the JSON that dm_profile_read loads:
 * the full document around core's gaussians writer (dm_profile_put_gaussians).
 *
 * The document (keys in this order, doubles with 17 significant digits so they read back
 * exactly, no time stamps: the same inputs give byte-identical files):
 *   { "format": "dermis-profile", "version": 1, "name": "...",
 *     "normalized": true|false,              weights normalised to white per channel
 *     "gaussians": [ {"variance_mm2": v, "incremental_variance_mm2": v_k − v_(k−1),
 *                     "weights": [r, g, b]}, ... ],
 *     "blur_passes": 2(N − 1),               separable passes the runtime spends
 *     "total_reflectance_rgb": [...],        Σ_k w_kc before normalisation (∫ 2πr ΣG dr)
 *     "error": {"measure": "...", "relative_rgb": [...], "relative_max": e},
 *     "source": {"model": "gaussians"|"dipole"|"multipole"|"burley"|"skin", "preset": "...",
 *                the parameters: gaussians, or sigma_a_per_mm, sigma_s_prime_per_mm, eta,
 *                thickness_mm, pairs, or albedo, mfp_mm, or the skin's melanin_fraction,
 *                eumelanin_blend, blood_fraction, oxygenation, epidermis_mm, dermis_mm, eta;
 *                and its closed-form "total_reflectance_rgb" (the skin's: colorimetric,
 *                the total diffuse reflectance per channel)},
 *     "provenance": {...} }                  dm_prov_to_json
 * Non-finite numbers are written as null.
 */
#ifndef DM_PROFILE_JSON_H
#define DM_PROFILE_JSON_H

#include "bake/dm_profile_fit.h"
#include "core/dm_profile.h"
#include "core/dm_prov.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_profile_doc {
    const dm_profile *profile;          /* written as "gaussians"; required */
    int normalized;                     /* 1 when profile's weights were normalised to white */
    double total_reflectance[3];        /* per channel, before normalisation */
    int has_error;                      /* 0: "error" is omitted */
    double error_relative[3];
    double error_relative_max;
    const dm_profile_source *source;    /* may be NULL: "source" omitted */
    const char *source_preset;          /* preset name, or NULL / "" when given by numbers */
    const dm_provenance *provenance;    /* may be NULL: "provenance" omitted */
} dm_profile_doc;

/* Serialises doc into a malloc'd NUL-terminated string (*json; free with free()). */
dm_result dm_profile_doc_to_json(const dm_profile_doc *doc, char **json, dm_error *err);
/* The same, written to path through a temporary file and rename (core/dm_file.h). */
dm_result dm_profile_write(const char *path, const dm_profile_doc *doc, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
