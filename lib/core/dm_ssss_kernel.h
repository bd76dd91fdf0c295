/* dm_ssss_kernel.h — the 1-D kernel of screen-space separable subsurface scattering
 * (Jimenez, Zsolnai, Jarabo, Freude, Auzinger, Wu, von der Pahlen, Wimmer, Gutierrez,
 * "Separable Subsurface Scattering", Computer Graphics Forum 34(6), 2015), fitted offline
 * from a sum-of-Gaussians diffusion profile (dermis-pack stores it in the pack).
 *
 * A separable blur applies k(x)·k(y); the profile R(r) = Σ_j w_j G(v_j, r) is radial. What a
 * straight edge sees of a separable blur is k alone (the other pass sums to 1 along the edge),
 * and what it sees of R is R's marginal, the line-spread function L(x) = ∫ R dy = Σ_j w_j
 * G₁(v_j, x): a 2-D Gaussian of variance v integrates to the 1-D Gaussian of variance v. So k is
 * L integrated exactly over the taps' bins, k[a] = Σ_j w_j p_j[a] / Σ_j w_j, with p_j[a] the 1-D
 * Gaussian's mass in bin a (tails folded into the end bins): per channel, summing to 1 (the blur
 * keeps energy, as the texture-space weights do), and an edge, an albedo step or a shadow's
 * border, spreads as the profile spreads it (issue #29; the edge-spread ∫L is exact at the bin
 * boundaries). The 2-D product k kᵀ is then the product of the marginals, which is R only for
 * one Gaussian: fit_error is ‖M/ΣM − k kᵀ‖_F / ‖M/ΣM‖_F per channel with M[a][b] = ∫∫ R over
 * bin_a × bin_b = Σ_j w_j p_j p_jᵀ, what a point of light's spot loses. (The best rank-1 factor
 * of M, fitted here before, loses less of the spot, 36 / 14 / 8 % against 48 / 18 / 10 % R/G/B
 * for gems3-skin at 17 taps, but its 1-D kernel is too narrow: an albedo edge came out half as
 * wide in red as the profile's, 8 % of the step off at 0.1 mm per pixel.)
 *
 * Taps: odd count, offsets o_a = range·t·|t| for t uniform in [−1, 1] (denser near the
 * centre, Jimenez's exponent 2), range = 3σ of the widest Gaussian, in mm. Units: mm, mm².
 */
#ifndef DM_SSSS_KERNEL_H
#define DM_SSSS_KERNEL_H

#include "core/dm_profile.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_SSSS_MAX_TAPS = 25 };
/* The end taps sit at 3σ of the widest Gaussian: 3·√DM_PROFILE_VARIANCE_MAX_MM2, + 1e-3. */
#define DM_SSSS_OFFSET_MAX_MM (3e4 * 1.001)

typedef struct dm_ssss_kernel {
    int taps;                              /* odd, 3..DM_SSSS_MAX_TAPS */
    float offset_mm[DM_SSSS_MAX_TAPS];     /* ascending, centre tap 0 at index taps/2 */
    float weight[DM_SSSS_MAX_TAPS][3];     /* per channel, each channel sums to 1 */
    double range_mm;                       /* |offset| of the end taps */
    double fit_error[3];                   /* relative Frobenius error of k kᵀ against M/ΣM */
} dm_ssss_kernel;

/* Fits the kernel of `taps` taps to the profile (dm_profile_validate'd). Fails with
 * DM_ERR_RANGE naming the value when taps is not odd in [3, DM_SSSS_MAX_TAPS]. */
dm_result dm_ssss_kernel_fit(const dm_profile *p, int taps, dm_ssss_kernel *k, dm_error *err);

/* The kernel as taps RGBA float32 texels (rgb = weights, a = offset mm): the pack's
 * "sss.kernel" entry layout. out holds 4·taps floats. */
void dm_ssss_kernel_texels(const dm_ssss_kernel *k, float *out);
/* Reads that layout back, checking finiteness, odd taps, ascending offsets within
 * ±DM_SSSS_OFFSET_MAX_MM and weights ≥ 0 that sum to 1 per channel within 1e-4 (so each is
 * at most 1). The one reading of the layout: the pack reader and the renderer both call it. */
dm_result dm_ssss_kernel_from_texels(const float *texels, int taps, dm_ssss_kernel *k, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
