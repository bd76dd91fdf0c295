/* dm_viewer_skin.h — the live physical skin of dermis-view (issue #30, point 3): melanin,
 * blood and epidermis sliders that refit the profile's weights with its variances fixed
 * (bake/dm_skin_weights.h) and hand them to the renderer (dm_renderer_set_profile_weights):
 * no re-bake, no re-pack, no new renderer.
 *
 * The sliders start from the pack's skin when its profile was fitted to one (the profile
 * entry's provenance "skin", dermis-pack of a scene with "profile": {"skin": …}), else from
 * dm_skin_params_default() (DJ2006's Caucasian); the variances are always the loaded
 * profile's. The albedo map shows the starting skin, so each channel's diffuse light is
 * scaled by the new skin's fitted total over the starting one's: more melanin darkens it,
 * more blood reddens it. A pack not fitted to a skin changes shape on the first change
 * (its weights become the physical skin's), not colour. Texture-space only (the other
 * techniques made their kernel or table from the profile: the change is refused there).
 * A feature over the session (dm_viewer_session.h) only.
 */
#ifndef DM_VIEWER_SKIN_H
#define DM_VIEWER_SKIN_H

#include <stdbool.h>

#include "dm_viewer_session.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Reads the starting skin and makes the plan for the loaded profile's variances (no GL).
 * On failure the sliders are off (v->skin.available false) and the status says why. */
void dm_viewer_skin_init(dm_viewer *v);
/* "melanin" [0, 0.5], "blood" [0, 0.1], "epidermis" [0.001, 2] mm (dm_skin_optics.h's
 * ranges): refits and hands the weights to the renderer; false, with the status set, when
 * refused. Times the refit and the hand-over (v->skin.ms). */
bool dm_viewer_skin_set(dm_viewer *v, const char *name, double value);
/* Median of the changes' latencies so far, ms (0 before the first). */
double dm_viewer_skin_median_ms(const dm_viewer *v);

#ifdef __cplusplus
}
#endif
#endif
