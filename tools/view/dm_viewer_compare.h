/* dm_viewer_compare.h — dermis-view --reference: the comparison with a ground truth
 * (dm_viewer_compare.c; the state is dm_viewer.cmp). */
#ifndef DM_VIEWER_COMPARE_H
#define DM_VIEWER_COMPARE_H

#include <stdbool.h>

#include "dm_viewer_session.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Load after dm_viewer_load and before
 * dm_viewer_start: a texture-space reference sets the irradiance size to its N, a frame
 * reference the picture size to its own; the comparison starts side by side. */
dm_result dm_viewer_compare_load(dm_viewer *v, const char *path, dm_error *err);
/* "off", "side", "split" or "error" (refused without a reference). */
bool dm_viewer_set_compare(dm_viewer *v, const char *mode);
/* Key C: off → side → split → error → off. */
void dm_viewer_cycle_compare(dm_viewer *v);
/* The frame's comparison picture into v->rgba (called by dm_viewer_update). */
bool dm_viewer_compare_frame(dm_viewer *v);
void dm_viewer_compare_free(dm_viewer *v);

#ifdef __cplusplus
}
#endif
#endif
