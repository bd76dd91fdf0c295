/* dm_ref_frame_compare.h — the decomposed frame comparison (issue #27): how far a rendered
 * frame is from the ground-truth frame (dm_ref_frame.h) where subsurface transport shows,
 * measured against what leaving subsurface out would cost.
 *
 * A mean over every pixel cannot rank techniques: on the head's frame subsurface moves the
 * mean by ~1 %, and shadow-map edges and texture sampling differ by as much. So the
 * comparison is taken apart (bench/accuracy): a TRANSPORT run (white albedo, no normal map,
 * no shadows: dermis-reference --without albedo,normal-map,shadows, and the renderer with the
 * same maps left out) measured here, then what the surface terms and the shadows add (plain
 * dm_ref_error_stats over the interior pixels of the fuller runs).
 *
 * TRANSPORT STATISTICS (dm_ref_transport_compute). Given the reference frame ref, the same
 * frame without subsurface flat (dermis-reference --without subsurface: Lambert at the point,
 * everything else equal) and a render, per channel c over the weighted pixels (weight > 0,
 * the label asked for) where subsurface changes the reference by more than `threshold`
 * (|ref_c − flat_c| > threshold · max(ref_c, floor_c), the SIGNAL pixels; floor_c =
 * DM_REF_ERROR_FLOOR × the mean of ref_c over the pixels asked for, as dm_ref_error_stats:
 * on the dark side of a terminator, where the reference is a thousandth of its mean, a
 * relative change means nothing):
 *   mean       = mean of |render_c − ref_c| / max(ref_c, floor_c)  (relative error there)
 *   normalised = Σ |render_c − ref_c| / Σ |flat_c − ref_c|  (0: exact; 1: no better than
 *                leaving subsurface out; a ratio of sums, so the pixels whose signal is
 *                barely above the threshold do not blow it up)
 * both as fractions, and the signal pixel count.
 *
 * Frames are width·height RGBA floats, rows bottom-up, A ≥ 0.5 on skin (as dermis-reference
 * and the renderer's linear read-back give them). Deterministic: fixed loop order.
 */
#ifndef DM_REF_FRAME_COMPARE_H
#define DM_REF_FRAME_COMPARE_H

#include <stddef.h>
#include <stdint.h>

#include "reference/dm_ref_regions.h"
#include "reference/dm_ref_surface.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define DM_REF_TRANSPORT_THRESHOLD 0.02 /* the signal: subsurface changes the value by > 2 % */
#define DM_REF_LABEL_BACKGROUND 255     /* dm_ref_frame_labels: a pixel whose ray misses */

/* weight_out[i] = 1 where pixel i and its four neighbours are skin (A ≥ 0.5) in both frames,
 * else 0 (silhouette pixels, where the rasterizer's and the rays' coverage differ, and the
 * frame's border are left out). */
void dm_ref_frame_interior(const float *ref, const float *render, int width, int height, float *weight_out);

/* The region label (dm_ref_region) of each pixel's centre hit, DM_REF_LABEL_BACKGROUND
 * where it misses: the region masks projected into the frame through each pixel's triangle
 * (dm_ref_frame_hits, dm_ref_regions_classify). s and rg describe the same mesh. */
dm_result dm_ref_frame_labels(const dm_ref_surface *s, const dm_ref_regions *rg, int width, int height,
                              int thread_count, uint8_t *label_out, dm_error *err);

typedef struct dm_ref_transport_stats {
    long signal[3];       /* signal pixels per channel */
    double mean[3];       /* mean relative error over them */
    double normalised[3]; /* Σ |render − ref| / Σ |flat − ref| over them */
    double normalised_rgb; /* the same summed over the three channels' signal pixels: one
                            * number, weighted to where subsurface changes most (red) — a
                            * channel whose signal is small (blue, green on skin) does not
                            * swing it */
} dm_ref_transport_stats;

/* The transport statistics above over the n pixels with weight > 0 (NULL: all) whose label
 * equals region (label NULL or region < 0: all). threshold in (0, 1) (0: the default).
 * DM_ERR_EMPTY when no channel has a signal pixel, DM_ERR_RANGE for a bad threshold. */
dm_result dm_ref_transport_compute(const float *ref, const float *flat, const float *render, const float *weight,
                                   const uint8_t *label, int region, size_t n, double threshold,
                                   dm_ref_transport_stats *st, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
