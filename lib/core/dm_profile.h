/* dm_profile.h — diffusion profiles as sums of Gaussians (DESIGN.md "Six Gaussians").
 *
 * G(v, r) = exp(−r²/2v) / (2πv), v in mm². A profile is R(r) = Σ_k w_k G(v_k, r) per
 * RGB channel, variances ascending and shared by the channels (the runtime's incremental
 * blur needs that: level k is level k−1 blurred by v_k − v_{k−1}).
 *
 * JSON form (written by dermis-fit-profile and dm_profile_to_json, read here):
 *   { "format": "dermis-profile", "version": 1, "name": "gems3-skin",
 *     "gaussians": [ {"variance_mm2": 0.0064, "weights": [0.233, 0.455, 0.649]}, ... ],
 *     "error": {...}, "source": {...}, "provenance": {...} }
 * Only "gaussians" is needed to use a profile; the rest is information. The writer
 * (bake/dm_profile_json.h) adds, per Gaussian, "incremental_variance_mm2", and at the top
 * "normalized", "total_reflectance_rgb", "blur_passes"; readers ignore what they do not know.
 *
 * Runtime cost: N Gaussians need N − 1 incremental blur levels (level 0 is the irradiance
 * itself, standing in for the narrowest Gaussian as in the chapter), each a U and a V
 * pass: 2(N − 1) separable passes (dm_profile_blur_passes).
 */
#ifndef DM_PROFILE_H
#define DM_PROFILE_H

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_PROFILE_MAX_GAUSSIANS = 8, DM_PROFILE_NAME_SIZE = 64 };

/* What makes physical sense (dm_profile_validate; so every reader of a profile, a scene or a
 * pack takes the same ones):
 *   variance ≤ 1e8 mm² (σ ≤ 10 m, the largest scene a pack holds, pack/dm_pack_semantic.h:
 *   skin's widest is 7.41 mm²; no measured translucent material spreads light metres);
 *   weights in [0, 1] and each channel's sum in [0, 1.001]: a profile returns at most the
 *   light it receives (1e-3 allows weights printed with three decimals, as the GPU Gems
 *   table is); a channel of no weight at all is a medium that scatters none of it back. */
#define DM_PROFILE_VARIANCE_MAX_MM2 1e8
#define DM_PROFILE_WEIGHT_SUM_MAX 1.001

typedef struct dm_profile {
    char name[DM_PROFILE_NAME_SIZE];
    int count;                                      /* 1..DM_PROFILE_MAX_GAUSSIANS */
    double variance_mm2[DM_PROFILE_MAX_GAUSSIANS];  /* strictly ascending, (0, DM_PROFILE_VARIANCE_MAX_MM2] */
    double weight[DM_PROFILE_MAX_GAUSSIANS][3];     /* [0, 1] per RGB channel, sums [0, WEIGHT_SUM_MAX] */
} dm_profile;

/* G(v, r) = exp(−r²/2v) / (2πv): the unit-integral (∫ 2πr G dr = 1) radial Gaussian of
 * variance v mm² (v > 0), in mm⁻². Finite for every r ≥ 0 including +inf (gives 0); very
 * large r underflows to 0, never NaN. */
double dm_gaussian(double variance_mm2, double r_mm);

/* R(r) per RGB channel: Σ_k w_k G(v_k, r), in mm⁻². */
void dm_profile_eval(const dm_profile *p, double r_mm, double rgb[3]);
/* Σ_k w_k per channel: the total diffuse reflectance ∫ 2πr R dr (each G integrates to 1). */
void dm_profile_channel_sums(const dm_profile *p, double sums[3]);
/* Divides each channel's weights by that channel's sum, so each sums to 1 (the colour then
 * comes from the albedo map alone). The sums before are written to sums_before (may be
 * NULL). DM_ERR_RANGE, p unchanged, when a channel sums to 0 (nothing to normalise). */
dm_result dm_profile_normalize_white(dm_profile *p, double sums_before[3], dm_error *err);
/* The blur variance that makes level k from level k−1: v_0 for k = 0 (the irradiance
 * itself stands in for it, no pass), v_k − v_{k−1} after; out holds p->count values. */
void dm_profile_incremental_variances(const dm_profile *p, double *out_mm2);
/* Separable passes the runtime spends on a profile of gaussian_count Gaussians:
 * 2(gaussian_count − 1) (a U and a V pass per incremental level). */
int dm_profile_blur_passes(int gaussian_count);

/* ---- blur kernels ------------------------------------------------------------------
 * One separable 1-D pass of a Gaussian of standard deviation σ with tap_count taps (odd,
 * 1..DM_BLUR_TAPS_MAX) at offsets (i − (tap_count−1)/2)·spacing·σ, i = 0..tap_count−1.
 * The exact weight of a tap is the normal density integrated over its bin, the interval of
 * width spacing·σ centred on the tap: Φ((o + s/2)) − Φ((o − s/2)) in σ units. The mass
 * beyond the outermost bins, 2·Φ(−tap_count·spacing/2), is not in any tap: it is returned
 * as tail (so the weights sum to 1 − tail); fold_tails adds half of it to each end tap
 * instead, so the kernel keeps energy (sums to 1 to rounding).
 * The chapter's kernel (GPU Gems 3 ch. 14, 7 taps at 1σ spacing, ±3σ) is this function
 * with tap_count 7, spacing 1, rounded to 3 decimals: DM_BLUR_TAPS_GEMS3. */
enum { DM_BLUR_TAPS_MAX = 63, DM_BLUR_TAPS_GEMS3_COUNT = 7 };
extern const double DM_BLUR_TAPS_GEMS3[DM_BLUR_TAPS_GEMS3_COUNT]; /* {0.006, 0.061, 0.242, 0.383, ...} */

/* Fills weight[tap_count]; tail may be NULL. DM_ERR_RANGE for an even or out-of-range
 * tap_count or a spacing that is not a finite value > 0. */
dm_result dm_blur_taps(int tap_count, double spacing_sigma, int fold_tails, double *weight, double *tail,
                       dm_error *err);

/* The d'Eon/Luebke six-Gaussian skin profile of DESIGN.md ("gems3-skin"). */
void dm_profile_gems3_skin(dm_profile *p);

/* Checks the invariants above (DM_ERR_RANGE); names `what`, the offending index and the
 * value in the message. */
dm_result dm_profile_validate(const dm_profile *p, const char *what, dm_error *err);

/* Parses the JSON form; `what` (usually the file name) prefixes error messages, which
 * name the JSON path, the value and what was expected. */
dm_result dm_profile_from_json(const char *json, const char *what, dm_profile *p, dm_error *err);
/* The same from a parsed JSON node (a scene's inline profile): the numbers as parsed, no
 * printing and parsing again (cJSON prints 15 digits when they come within an ulp). */
struct cJSON;
dm_result dm_profile_from_cjson(const struct cJSON *node, const char *what, dm_profile *p, dm_error *err);
/* Reads a profile JSON file. */
dm_result dm_profile_read(const char *path, dm_profile *p, dm_error *err);

/* The one writer of profile JSON. dm_profile_put_gaussians appends the "gaussians" array
 * (entries one per line after `indent` and two spaces; with_increments adds each
 * "incremental_variance_mm2"); bake/dm_profile_json.h builds the full document around it.
 * dm_profile_to_json writes the smallest document dm_profile_from_json reads back
 * exactly: {"format", "version", "name", "gaussians"} (the scene's inline profile, the
 * pack's profile entry). Fails on a profile dm_profile_validate refuses, or out of
 * memory; *json is malloc'd, free with free(). */
struct dm_sbuf;
void dm_profile_put_gaussians(struct dm_sbuf *b, const dm_profile *p, const char *indent, int with_increments);
dm_result dm_profile_to_json(const dm_profile *p, char **json, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
