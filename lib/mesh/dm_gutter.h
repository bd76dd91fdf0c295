/* dm_gutter.h — filling the texels outside every UV chart ("gutters") from the charts.
 *
 * A texel of a UV-space map that no triangle covers is read anyway by any filter that
 * reaches across a chart's border (bilinear taps, the diffusion blurs). dm_gutter_fill
 * gives every uncovered texel the values of its nearest covered texel (exact Euclidean
 * distance between texel centres, by a two-pass distance transform: Felzenszwalb &
 * Huttenlocher), over the whole texture, so no reach, however wide, reads an empty
 * texel. Ties are broken the same way on every run. Covered texels are not
 * changed. Results do not depend on the thread count.
 */
#ifndef DM_GUTTER_H
#define DM_GUTTER_H

#include <stdint.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_gutter_stats {
    int64_t filled_texels;       /* texels that were uncovered */
    double max_distance_texels;  /* the farthest any filled texel is from its source */
} dm_gutter_stats;

/* covered: width*height flags (non-zero = covered), rows bottom-up. planes: plane_count
 * planes of width*height floats, filled in place. Allocates 4·width·height bytes of
 * scratch for the call. Fails with DM_ERR_EMPTY when nothing is covered. stats may be
 * NULL; thread_count 0 = all cores. */
dm_result dm_gutter_fill(const uint8_t *covered, int width, int height, float *const *planes, int plane_count,
                         int thread_count, dm_gutter_stats *stats, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
