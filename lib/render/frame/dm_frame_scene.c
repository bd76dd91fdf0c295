/* dm_frame_scene.c — what a frame's settings make before its passes: the lights turned by the
 * light rotation with a matrix per shadow map (orthographic for directional lights around the
 * mesh's bounding sphere, perspective for point lights), the camera, the levels' blur kernel. */
#include <math.h>
#include <string.h>

#include "core/dm_mat4.h"
#include "core/dm_math.h"
#include "render/frame/dm_frame.h"

void dmr_frame_lights(dmr_frame *f, float rotation_deg)
{
    const dm_scene *s = &f->scene;
    float a = (float)(rotation_deg * DM_PI / 180.0), c = cosf(a), sn = sinf(a);
    for (int i = 0; i < s->light_count; ++i) {
        const dm_light *l = &s->lights[i];
        const float *v = l->type == DM_LIGHT_DIRECTIONAL ? l->direction : l->position;
        float x = c * v[0] + sn * v[2], z = -sn * v[0] + c * v[2];
        f->light_pos[i][0] = x;
        f->light_pos[i][1] = v[1];
        f->light_pos[i][2] = z;
        f->light_pos[i][3] = l->type == DM_LIGHT_DIRECTIONAL ? 0.0f : 1.0f;
        if (l->type == DM_LIGHT_DIRECTIONAL) dm_v3_norm(f->light_pos[i]);
        for (int k = 0; k < 3; ++k) f->light_color[i][k] = l->color[k] * l->intensity;
    }
    for (int j = 0; j < f->plan.shadow_count; ++j) {
        int i = f->plan.shadow_light[j];
        float view[16], proj[16], eye[3], up[3] = {0, 1, 0};
        float rad = f->radius;
        if (f->light_pos[i][3] == 0.0f) {
            for (int k = 0; k < 3; ++k) eye[k] = f->center[k] + f->light_pos[i][k] * 2.0f * rad;
            dm_mat4_look_at(view, eye, f->center, up, NULL, NULL, NULL);
            dm_mat4_ortho(proj, rad * 1.02f, 0.5f * rad, 3.5f * rad);
            f->light_depth[i][0] = 0.5f * rad, f->light_depth[i][1] = 3.5f * rad, f->light_depth[i][2] = 1.0f;
        } else {
            float d3[3];
            memcpy(eye, f->light_pos[i], sizeof eye);
            dm_v3_sub(d3, f->center, eye);
            float d = sqrtf(dm_v3_dot(d3, d3));
            float n = d > rad * 1.01f ? fmaxf(d - rad, 0.01f * rad) * 0.9f : 0.01f * rad, fr = d + rad * 1.1f;
            if (d > rad * 1.01f)
                dm_mat4_perspective(proj, 2.0f * asinf(rad / d) * 1.05f, 1.0f, n, fr);
            else
                dm_mat4_perspective(proj, (float)(150.0 * DM_PI / 180.0), 1.0f, n, fr);
            f->light_depth[i][0] = n, f->light_depth[i][1] = fr, f->light_depth[i][2] = 0.0f;
            dm_mat4_look_at(view, eye, f->center, up, NULL, NULL, NULL);
        }
        dm_mat4_mul(f->light_matrix[i], proj, view);
    }
}

void dmr_frame_camera(dmr_frame *f)
{
    const dm_scene *s = &f->scene;
    float view[16], proj[16], d3[3];
    memcpy(f->eye, s->camera_eye, sizeof f->eye);
    dm_mat4_look_at(view, s->camera_eye, s->camera_target, s->camera_up, f->cam_right, f->cam_up, f->cam_fwd);
    dm_v3_sub(d3, f->center, f->eye);
    float d = sqrtf(dm_v3_dot(d3, d3)), rad = f->radius;
    float n = fmaxf(d - 2.0f * rad, 0.01f * rad), fr = d + 2.0f * rad;
    float aspect = (float)f->width / (float)f->height;
    float fov = (float)(s->fov_y_deg * DM_PI / 180.0);
    dm_mat4_perspective(proj, fov, aspect, n, fr);
    dm_mat4_mul(f->view_proj, proj, view);
    float t = tanf(0.5f * fov);
    for (int k = 0; k < 3; ++k) {
        f->cam_right[k] *= t * aspect;
        f->cam_up[k] *= t;
    }
}

void dmr_frame_blur(dmr_frame *f, float scale)
{
    dmr_blur_kernel_make(&f->profile, f->taps, scale, &f->kernel);
    dmr_level_weights(&f->profile, f->level_scale, f->level_weight);
}
