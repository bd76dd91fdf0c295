/* dm_skin_weights.h — live weights: the physical skin's Gaussian weights refitted for new
 * parameters with the Gaussians' variances held fixed (issue #30, point 3).
 *
 * With the variances fixed (a pack's profile, GPU Gems 3's six, any ascending set), only
 * the weights depend on the skin: the blur chain and the stretch maps, which depend on the
 * variances alone, stay valid, so a renderer keeps them and takes the new weights
 * (render/dm_render.h: dm_renderer_set_profile_weights). The fit is dm_skin_profile_fit's —
 * weights ≥ 0 per channel by NNLS (dm_lsq_nnls_shared) against the signed channel transform
 * R̃_c(s), on the frequency-domain quadrature of dm_skin_freq.h — on fewer nodes:
 *
 *   - the top node is where the narrowest Gaussian's transform exp(−v₁ s²/2) has fallen to
 *     DM_SKIN_WEIGHTS_CUT (s = √(2 ln(1/CUT)/v₁), at most dm_skin_profile's 3e3 mm⁻¹): above
 *     it every design row is below CUT, so those nodes change neither AᵀA nor Aᵀy (the NNLS
 *     solution) by more than CUT relative, while R̃ there still costs as much to evaluate;
 *   - node_count nodes (default DM_SKIN_WEIGHTS_NODES_DEFAULT, 81) ln-spaced from 1e-3 mm⁻¹
 *     up to it, Simpson in ln s, instead of 401 over the whole range;
 *   - DM_SKIN_WEIGHTS_PAIRS_DEFAULT (8) multipole image pairs instead of 20: the pairs past
 *     the eighth are below e^(−8·2d·σtr) of the first.
 * Together they put the weights within 1e-6 of dm_skin_profile_fit's (measured: 5.7e-7 over
 * four presets at 0.25 and 0.05 mm of epidermis; test_skin_weights.c holds 1e-5) at about
 * a twelfth of its time.
 *
 * What depends only on the variances (the nodes, the design, the colour weights) is made
 * once by dm_skin_weights_plan_init; each dm_skin_weights_fit evaluates R̃_λ(s) at the nodes
 * for the 31 wavelength rows (the expensive part: the spectrum is sampled as offline, not
 * reduced) and solves. docs/skin-model.md gives its time and its difference from the
 * offline fit; bench/bench_skin_weights.c measures both.
 */
#ifndef DM_SKIN_WEIGHTS_H
#define DM_SKIN_WEIGHTS_H

#include "bake/dm_skin_data.h"
#include "bake/dm_skin_optics.h"
#include "core/dm_profile.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    DM_SKIN_WEIGHTS_NODES_DEFAULT = 81,
    DM_SKIN_WEIGHTS_NODES_MAX = 401,
    DM_SKIN_WEIGHTS_PAIRS_DEFAULT = 8,
    DM_SKIN_WEIGHTS_STREAMS_DEFAULT = 8
};
#define DM_SKIN_WEIGHTS_CUT 1e-9

/* Zero-initialised = defaults. */
typedef struct dm_skin_weights_options {
    int node_count; /* odd, 3..DM_SKIN_WEIGHTS_NODES_MAX; 0 = DM_SKIN_WEIGHTS_NODES_DEFAULT */
    int pair_count; /* multipole image pairs, 1..DM_MULTIPOLE_PAIRS_MAX; 0 = DM_SKIN_WEIGHTS_PAIRS_DEFAULT
                     * (offline: DM_MULTIPOLE_PAIRS_DEFAULT, 20) */
    int stream_count; /* adding-doubling streams (dm_skin_ad.h), even 2..DM_SKIN_AD_STREAMS_MAX;
                       * 0 = DM_SKIN_WEIGHTS_STREAMS_DEFAULT (offline: DM_SKIN_AD_STREAMS_DEFAULT, 16) */
} dm_skin_weights_options;

/* What the fit keeps between calls (caller-owned, about 40 KB; no allocation). */
typedef struct dm_skin_weights_plan {
    int gaussian_count;
    double variance_mm2[DM_PROFILE_MAX_GAUSSIANS];
    int node_count, pair_count, stream_count;
    double s_hi_per_mm;                       /* the top node */
    double s[DM_SKIN_WEIGHTS_NODES_MAX];      /* nodes, mm⁻¹ */
    double sq[DM_SKIN_WEIGHTS_NODES_MAX];     /* √ of their quadrature weights */
    double design[DM_SKIN_WEIGHTS_NODES_MAX * DM_PROFILE_MAX_GAUSSIANS]; /* column-major */
    double rgb[DM_SKIN_LAMBDA_COUNT][3];      /* dm_skin_rgb_weights */
} dm_skin_weights_plan;

/* Makes the plan for gaussian_count (1..DM_PROFILE_MAX_GAUSSIANS) variances, strictly
 * ascending, in (0, DM_PROFILE_VARIANCE_MAX_MM2] (dm_profile_validate's rule and message);
 * opt may be NULL. DM_ERR_RANGE for a bad variance or option, naming it. */
dm_result dm_skin_weights_plan_init(dm_skin_weights_plan *plan, const double *variance_mm2, int gaussian_count,
                                    const dm_skin_weights_options *opt, dm_error *err);

/* The weights of the skin p (validated here: dm_skin_params_validate's errors) for the
 * plan's variances: out receives the name (may be NULL: ""), the count, the variances and
 * weights ≥ 0, not normalised (their sums are the fitted totals, ≤ 1); a channel whose
 * transform is nowhere above zero gets zero weights. No allocation (about 40 KB of stack);
 * deterministic. */
dm_result dm_skin_weights_fit(const dm_skin_weights_plan *plan, const dm_skin_params *p, const char *name,
                              dm_profile *out, dm_error *err);
/* The same, and the skin's colorimetric total diffuse reflectance per linear-sRGB channel,
 * total_rgb[c] = Σ_λ w_c(λ) T_λ with T_λ adding-doubling's total at the plan's stream count
 * (what the fit normalises to; within 5e-3 of the offline 16 streams): exact where the
 * weights' sums are not — a peak the variances cannot hold (the closed-form epidermis, dark
 * skins) leaves the sums up to twice the total. A colour follows total_rgb, never the sums
 * (dermis-view's sliders: docs/dermis-view.md). total_rgb may be NULL. */
dm_result dm_skin_weights_fit_colour(const dm_skin_weights_plan *plan, const dm_skin_params *p, const char *name,
                                     dm_profile *out, double total_rgb[3], dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
