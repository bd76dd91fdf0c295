/* dm_ssss_kernel.h — the 1-D kernels of screen-space separable subsurface scattering
 * (Jimenez, Zsolnai, Jarabo, Freude, Auzinger, Wu, von der Pahlen, Wimmer, Gutierrez,
 * "Separable Subsurface Scattering", Computer Graphics Forum 34(6), 2015), fitted offline
 * from a sum-of-Gaussians diffusion profile (dermis-pack stores them in the pack), one per
 * size of pixel on the surface.
 *
 * A separable blur applies k(x)·k(y); the profile R(r) = Σ_j w_j G(v_j, r) is radial. What a
 * straight edge sees of a separable blur is k alone (the other pass sums to 1 along the edge),
 * and what it sees of R is R's marginal, the line-spread function L(x) = ∫ R dy = Σ_j w_j
 * G₁(v_j, x): a 2-D Gaussian of variance v integrates to the 1-D Gaussian of variance v
 * (issue #29). The blur reads a picture sampled at pixel centres, so what it can get right is
 * the edge at pixel centres: a kernel whose taps sit on whole pixels with weights L's mass over
 * each pixel, [n − ½, n + ½] pixels, convolves a step sampled at pixel centres into the exact
 * edge-spread ∫L at every pixel centre. That needs a tap per pixel; with fewer taps than the
 * profile has pixels, a tap spans a bin of whole pixels [s − ½, e + ½], weighs L's mass over
 * it (so the edge is exact again at every bin's ends) and sits where its bilinear fetch, split
 * between two neighbouring pixels, best matches L's cumulative mass inside the bin. The error
 * of the blurred edge at a pixel centre is then the cumulative difference inside its bin.
 *
 * The fit, per size of pixel P mm (a row): the centre tap at 0 weighs L's mass over
 * [−½, ½] pixels; each side gets taps/2 bins of whole pixels, outward from pixel 1, the last
 * reaching to infinity (the tail folded in); the bins are the greedy partition that reaches
 * infinity in taps/2 bins with the smallest largest error τ (bisection on τ; each bin grows as
 * far as its error stays within τ). In a bin of pixels s..e the tap sits at pixel j + f
 * (j in s..e, f in [0, 1), f = 0 when j = e): the effective kernel puts (1 − f)·W on pixel j
 * and f·W on j + 1 (W the bin's mass), and the bin's error is the largest |effective − L|
 * cumulative mass at its inner pixel boundaries over the three channels; j and f minimise it.
 * A bin of one pixel has its tap on the pixel and no error. Rows: DM_SSSS_ROWS sizes of pixel,
 * DM_SSSS_ROW0_MM_PER_PX·2^r mm (one octave apart, 0.02 to 2.56 mm per pixel); the shader
 * interpolates the offsets and weights of the two rows around its pixel's size (in log₂ of
 * mm per pixel) and, off the table's ends, stretches the end row's offsets (a kernel in mm).
 *
 * fit_error per row and channel: what the product k kᵀ loses of the profile in 2-D,
 * ‖M/ΣM − k kᵀ‖_F / ‖M/ΣM‖_F with M[a][b] = ∫∫ R over bin_a × bin_b (what a point of light's
 * spot loses; the product of the marginals is R only for one Gaussian).
 *
 * Before the table (packs made before 2026-11-27) the kernel was one row with offsets in mm at
 * Jimenez's taps (range·t·|t|): it reads as a table of one row at 1 mm per pixel (offsets in
 * pixels = mm), stretched to every size. Units: mm, pixels at the row's size. */
#ifndef DM_SSSS_KERNEL_H
#define DM_SSSS_KERNEL_H

#include "core/dm_profile.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_SSSS_MAX_TAPS = 25, DM_SSSS_ROWS = 8, DM_SSSS_MAX_ROWS = 8 };
#define DM_SSSS_ROW0_MM_PER_PX 0.02 /* row r is fitted for 0.02·2^r mm per pixel */
/* An offset's reach on the surface, |offset px · row mm per px|, at most 12σ of the widest
 * Gaussian allowed, 12·√DM_PROFILE_VARIANCE_MAX_MM2 mm (+ 1e-3); a row's size within
 * [DM_SSSS_MM_PER_PX_MIN, DM_SSSS_MM_PER_PX_MAX]. */
#define DM_SSSS_OFFSET_MAX_MM (1.2e5 * 1.001)
#define DM_SSSS_MM_PER_PX_MIN 1e-4
#define DM_SSSS_MM_PER_PX_MAX 1e4

typedef struct dm_ssss_kernel {
    int taps;                                            /* odd, 3..DM_SSSS_MAX_TAPS */
    int rows;                                            /* 1..DM_SSSS_MAX_ROWS */
    double mm_per_px[2];                                 /* first and last row's size; rows log-spaced */
    float offset_px[DM_SSSS_MAX_ROWS][DM_SSSS_MAX_TAPS]; /* ascending, centre tap 0 at index taps/2 */
    float weight[DM_SSSS_MAX_ROWS][DM_SSSS_MAX_TAPS][3]; /* per channel, each row's channel sums to 1 */
    double edge_error[DM_SSSS_MAX_ROWS];                 /* the fit's τ: largest blurred-edge error, of the step */
    double fit_error[DM_SSSS_MAX_ROWS][3];               /* relative Frobenius error of k kᵀ against M/ΣM */
} dm_ssss_kernel;

/* The row r's size of pixel, mm: mm_per_px[0]·(mm_per_px[1]/mm_per_px[0])^(r/(rows − 1)). */
double dm_ssss_kernel_row_mm_per_px(const dm_ssss_kernel *k, int r);

/* Fits the DM_SSSS_ROWS rows of `taps` taps to the profile (dm_profile_validate'd). Fails
 * with DM_ERR_RANGE naming the value when taps is not odd in [3, DM_SSSS_MAX_TAPS]. */
dm_result dm_ssss_kernel_fit(const dm_profile *p, int taps, dm_ssss_kernel *k, dm_error *err);

/* The kernel as taps × rows RGBA float32 texels, row after row (rgb = weights, a = offset in
 * pixels at the row's size): the pack's "sss.kernel" entry layout, its "t_range" the first and
 * last row's mm per pixel. out holds 4·taps·rows floats. */
void dm_ssss_kernel_texels(const dm_ssss_kernel *k, float *out);
/* Reads that layout back; mm_per_px NULL: the layout before the table, one row, offsets in mm.
 * Checks finiteness, odd taps, rows in [1, DM_SSSS_MAX_ROWS] (1 without mm_per_px), the sizes
 * within [DM_SSSS_MM_PER_PX_MIN, DM_SSSS_MM_PER_PX_MAX] and ascending (equal for one row),
 * ascending offsets within ±DM_SSSS_OFFSET_MAX_MM on the surface and weights ≥ 0 that sum to 1
 * per row and channel within 1e-4. The one reading of the layout: the pack reader and the
 * renderer both call it. */
dm_result dm_ssss_kernel_from_texels(const float *texels, int taps, int rows, const float *mm_per_px,
                                     dm_ssss_kernel *k, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
