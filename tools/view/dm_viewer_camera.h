/* dm_viewer_camera.h — dermis-view's orbit camera and the mouse actions on it and on the
 * chosen light (dm_viewer_camera.c). Each marks the frame dirty. */
#ifndef DM_VIEWER_CAMERA_H
#define DM_VIEWER_CAMERA_H

#include <stdbool.h>

#include "dm_viewer_session.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The orbit from the loaded scene's camera; into the scene's camera. */
void dm_viewer_camera_from_scene(dm_viewer *v);
void dm_viewer_apply_camera(dm_viewer *v);
void dm_viewer_orbit(dm_viewer *v, float dx_px, float dy_px);
void dm_viewer_pan(dm_viewer *v, float dx_px, float dy_px);
void dm_viewer_zoom(dm_viewer *v, float wheel_steps);
void dm_viewer_drag_light(dm_viewer *v, float dx_px, float dy_px);
void dm_viewer_reset_camera(dm_viewer *v);

#ifdef __cplusplus
}
#endif
#endif
