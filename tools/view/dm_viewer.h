/* dm_viewer.h — the state and actions of dermis-view, shared by the window callbacks,
 * the UI panel (dm_viewer_ui.h, C++) and the script player (dm_viewer_script.h): every
 * input path calls the same actions, so a script exercises what a person does.
 *
 * The viewer owns one renderer (lib/render) over assets that come either from an open
 * pack (pointers into its mapping) or from the synthetic scene. It keeps an edited copy
 * of the scene: values no pass depends on (camera, lights, exposure, mix, environment
 * intensity and rotation) reach the renderer through dm_renderer_set_scene; changes of
 * the pass list (effects, environment background, irradiance size) recreate the renderer
 * from the same assets. It renders on demand: only when something changed (`dirty`).
 *
 * The state and the rebuild are dm_viewer_session.h; the camera, the --reference
 * comparison and the technique switch are features over it (dm_viewer_camera.h,
 * dm_viewer_compare.h, dm_viewer_technique.h), included here; this file's actions
 * (dm_viewer.c) sit on top of them.
 */
#ifndef DM_VIEWER_H
#define DM_VIEWER_H

#include <stdbool.h>
#include <stdint.h>

#include "core/dm_prov.h"
#include "dm_viewer_camera.h"
#include "dm_viewer_compare.h"
#include "dm_viewer_session.h"
#include "dm_viewer_skin.h"
#include "dm_viewer_technique.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Loads the pack (dm_pack_open verifies all of it) or builds the synthetic scene.
 * Returns DM_ERR_FILE_OPEN when the pack is missing, the validator's error when it is
 * corrupt (err->detail is dermis-check's message). No GL needed. */
dm_result dm_viewer_load(dm_viewer *v, const dm_viewer_options *opt, dm_error *err);
/* Creates the renderer and the display texture; needs the current GL context. */
dm_result dm_viewer_start(dm_viewer *v, dm_error *err);
void dm_viewer_free(dm_viewer *v);

/* Renders a frame if dirty and uploads it to v->tex. Failures go to v->status and
 * stderr and count in v->failures; the viewer then falls back to the final view. */
void dm_viewer_update(dm_viewer *v, double dt_s);

/* actions (each marks the frame dirty and returns false, with v->status set, on failure) */
bool dm_viewer_set_effect(dm_viewer *v, dm_effect e, bool on);
bool dm_viewer_set_background(dm_viewer *v, bool on);
bool dm_viewer_set_irradiance(dm_viewer *v, int size);
/* Shows packed environment k in [0, env_count) (0 = the scene's main map, k = its k-th
 * alternative): the renderer is recreated over that environment's entries (no copies). */
bool dm_viewer_set_env(dm_viewer *v, int k);
/* The file name of packed environment k (from its provenance, else the scene). */
void dm_viewer_env_name(const dm_viewer *v, int k, char *out, int size);
bool dm_viewer_set_view(dm_viewer *v, const char *name);
bool dm_viewer_cycle_view(dm_viewer *v, int step);
/* "exposure", "mix", "blur_scale", "roughness_scale", "view_scale", "env_intensity",
 * "env_rotation", "light_intensity", "light_rotation", "rotate", "light", "split" [0, 1],
 * "error_scale" (0, 100], the skin's "melanin", "blood", "epidermis" (dm_viewer_skin.h): one value;
 * "light_color": three. Ranges as in the panel; out of range is refused. */
bool dm_viewer_set_param(dm_viewer *v, const char *name, const float *values, int count);
/* Screenshot of the rendered image with provenance (view, scene, every parameter). */
bool dm_viewer_screenshot(dm_viewer *v, const char *path);
/* A free name "dermis-view-NNN.png" in the current folder. */
void dm_viewer_next_shot_name(dm_viewer *v, char *out, int size);
/* The current view's name as dm_view_parse reads it ("blur3", "final"). */
void dm_viewer_view_text(const dm_viewer *v, char *out, int size);
/* Every parameter of the picture, as provenance (the same keys as dermis-render plus the
 * viewer's own). */
void dm_viewer_provenance(const dm_viewer *v, dm_provenance *p);
/* --watch: reloads the pack when its file changed (keeping camera and knobs). */
void dm_viewer_watch(dm_viewer *v, double now_ms);
/* Whether the scene is the Lee Perry-Smith head (its attribution must be shown). */
bool dm_viewer_shows_head(const dm_viewer *v);
extern const char dm_viewer_attribution[];
extern const char dm_viewer_help[];

#ifdef __cplusplus
}
#endif
#endif
