/* dm_viewer_camera.c — dermis-view's orbit camera (yaw, pitch, distance about a target, from
 * and into the scene's camera) and the mouse actions on it and on the chosen light. */
#include "dm_viewer_camera.h"

#include <math.h>
#include <string.h>

#include "core/dm_math.h"

/* The orbit parameters from the loaded scene's camera. */
void dm_viewer_camera_from_scene(dm_viewer *v)
{
    const dm_scene *s = &v->loaded;
    float d[3];
    for (int k = 0; k < 3; ++k) d[k] = s->camera_eye[k] - s->camera_target[k], v->target[k] = s->camera_target[k];
    v->distance = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (v->distance <= 0) v->distance = 1;
    v->yaw_deg = (float)(atan2(d[0], d[2]) * 180.0 / DM_PI);
    v->pitch_deg = (float)(asin(d[1] / v->distance) * 180.0 / DM_PI);
    v->camera_moved = false;
}

/* The orbit into the scene's camera, when it moved. */
void dm_viewer_apply_camera(dm_viewer *v)
{
    if (!v->camera_moved) return;
    float y = (float)(v->yaw_deg * DM_PI / 180.0), p = (float)(v->pitch_deg * DM_PI / 180.0);
    float dir[3] = {cosf(p) * sinf(y), sinf(p), cosf(p) * cosf(y)};
    for (int k = 0; k < 3; ++k) {
        v->scene.camera_target[k] = v->target[k];
        v->scene.camera_eye[k] = v->target[k] + v->distance * dir[k];
    }
    v->scene.camera_up[0] = 0, v->scene.camera_up[1] = 1, v->scene.camera_up[2] = 0;
}

void dm_viewer_orbit(dm_viewer *v, float dx, float dy)
{
    v->yaw_deg = fmodf(v->yaw_deg - 0.4f * dx, 360.0f);
    v->pitch_deg += 0.4f * dy;
    if (v->pitch_deg > 89) v->pitch_deg = 89;
    if (v->pitch_deg < -89) v->pitch_deg = -89;
    v->camera_moved = v->dirty = true;
}

void dm_viewer_pan(dm_viewer *v, float dx, float dy)
{
    /* one pixel moves the target by one pixel's size at the target's distance */
    float px = 2.0f * v->distance * tanf((float)(v->scene.fov_y_deg * DM_PI / 360.0)) / (float)v->opt.height;
    float y = (float)(v->yaw_deg * DM_PI / 180.0), p = (float)(v->pitch_deg * DM_PI / 180.0);
    float right[3] = {cosf(y), 0, -sinf(y)};
    float up[3] = {-sinf(p) * sinf(y), cosf(p), -sinf(p) * cosf(y)};
    for (int k = 0; k < 3; ++k) v->target[k] += px * (-dx * right[k] + dy * up[k]);
    v->camera_moved = v->dirty = true;
}

void dm_viewer_zoom(dm_viewer *v, float steps)
{
    v->distance *= powf(0.9f, steps);
    float r = v->distance;
    if (r < 0.05f) v->distance = 0.05f;
    if (r > 1e4f) v->distance = 1e4f;
    v->camera_moved = v->dirty = true;
}

void dm_viewer_reset_camera(dm_viewer *v)
{
    dm_viewer_camera_from_scene(v);
    memcpy(v->scene.camera_eye, v->loaded.camera_eye, sizeof v->scene.camera_eye);
    memcpy(v->scene.camera_target, v->loaded.camera_target, sizeof v->scene.camera_target);
    memcpy(v->scene.camera_up, v->loaded.camera_up, sizeof v->scene.camera_up);
    v->dirty = true;
}

void dm_viewer_drag_light(dm_viewer *v, float dx, float dy)
{
    if (v->scene.light_count == 0) return;
    dm_light *l = &v->scene.lights[v->light];
    float d[3];
    for (int k = 0; k < 3; ++k)
        d[k] = l->type == DM_LIGHT_DIRECTIONAL ? l->direction[k] : l->position[k] - v->target[k];
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len <= 0) return;
    double az = atan2(d[0], d[2]) + 0.5 * dx * DM_PI / 180.0;
    double el = asin(d[1] / len) - 0.5 * dy * DM_PI / 180.0;
    if (el > 1.5) el = 1.5;
    if (el < -1.5) el = -1.5;
    float n[3] = {(float)(cos(el) * sin(az)), (float)sin(el), (float)(cos(el) * cos(az))};
    for (int k = 0; k < 3; ++k) {
        if (l->type == DM_LIGHT_DIRECTIONAL) l->direction[k] = n[k];
        else l->position[k] = v->target[k] + len * n[k];
    }
    v->dirty = true;
}

