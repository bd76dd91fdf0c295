/* dm_viewer_technique.h — dermis-view's subsurface technique at runtime (key T, the panel)
 * and two techniques side by side (shift+T) (dm_viewer_technique.c). */
#ifndef DM_VIEWER_TECHNIQUE_H
#define DM_VIEWER_TECHNIQUE_H

#include <stdbool.h>

#include "dm_viewer_session.h"

#ifdef __cplusplus
extern "C" {
#endif

/* "texture-space", "screen-space" or
 * "pre-integrated"; the renderer is recreated over the same assets (a screen-space kernel
 * missing from the pack is fitted from the profile; texture-space needs the pack's stretch
 * maps, pre-integrated its table and curvature map: refused without, naming them). */
/* What technique t needs that the pack lacks (a phrase), NULL when it can run. */
const char *dm_viewer_technique_missing(const dm_viewer *v, dm_sss_technique t);
bool dm_viewer_set_technique(dm_viewer *v, const char *name);
/* Key T: the next technique the pack supports (texture-space → screen-space →
 * pre-integrated → ...). */
void dm_viewer_cycle_technique(dm_viewer *v);
/* Key shift+T: the other technique beside this one (layout and divider of the comparison:
 * split at cmp.split by default; C cycles side/split/error), with their difference's
 * statistics; refused while a --reference comparison is on. */
bool dm_viewer_set_technique_split(dm_viewer *v, bool on);
/* The frame's technique comparison into v->rgba (called by dm_viewer_update). */
bool dm_viewer_technique_frame(dm_viewer *v, const dm_frame_options *fo);

#ifdef __cplusplus
}
#endif
#endif
