/* dm_profile_tsv.h — a profile's numbers as tab-separated text for plotting (dermis-fit-profile
 * --radial, --spectrum; `make gallery` plots them with gnuplot). Each file starts with '#' lines:
 * the provenance (tool, version, every parameter, as JSON) and what the columns hold; then a
 * header line of column names and one row per sample, numbers at 9 significant digits. Written
 * through a temporary name (core/dm_file.h). */
#ifndef DM_PROFILE_TSV_H
#define DM_PROFILE_TSV_H

#include "bake/dm_profile_fit.h"
#include "bake/dm_skin_optics.h"
#include "core/dm_profile.h"
#include "core/dm_prov.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Radial samples per file: r log-spaced from DM_PROFILE_TSV_R_MIN_MM to _MAX_MM, both included. */
enum { DM_PROFILE_TSV_RADIAL_ROWS = 121 };
#define DM_PROFILE_TSV_R_MIN_MM 0.01
#define DM_PROFILE_TSV_R_MAX_MM 20.0

/* Columns r_mm, src_r, src_g, src_b (the source's R(r), mm⁻², as dm_profile_source_eval gives
 * it: a skin's channel may be negative), fit_r, fit_g, fit_b (the Gaussians of `fit` at r, in the
 * source's units: pass the fit before normalising to white). */
dm_result dm_profile_tsv_radial(const char *path, const dm_profile_source *s, const dm_profile *fit,
                                const dm_provenance *prov, dm_error *err);

/* Columns lambda_nm, total (the skin's total diffuse reflectance R̃_λ(0) at each row of
 * bake/dm_skin_data.h), flags (DM_SKIN_INVALID_* where diffusion was invalid, 0 elsewhere);
 * then '#' lines with the colorimetric totals in linear sRGB. p is validated here. */
dm_result dm_profile_tsv_spectrum(const char *path, const dm_skin_params *p, const dm_provenance *prov, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
