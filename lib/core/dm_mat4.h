/* dm_mat4.h — small 3-vector and 4x4 matrix helpers for cameras and lights: column-major
 * float[16], as OpenGL takes them (m[column * 4 + row]). No allocation; outputs may alias
 * inputs. */
#ifndef DM_MAT4_H
#define DM_MAT4_H

/* o = a · b (4x4). */
void dm_mat4_mul(float *o, const float *a, const float *b);
/* View matrix looking from eye at target, up_hint roughly up (another axis is taken when
 * it is parallel to the view). right, up, fwd (each NULL or 3 floats) receive the camera
 * basis: unit vectors, fwd = normalised target − eye. */
void dm_mat4_look_at(float *m, const float *eye, const float *target, const float *up_hint, float *right, float *up,
                     float *fwd);
/* Perspective projection: vertical field of view in radians, aspect = width / height,
 * near and far distances > 0. */
void dm_mat4_perspective(float *m, float fovy_rad, float aspect, float n, float f);
/* Orthographic projection of the square [−half, half]² between depths n and f. */
void dm_mat4_ortho(float *m, float half, float n, float f);

void dm_v3_sub(float *o, const float *a, const float *b);
float dm_v3_dot(const float *a, const float *b);
void dm_v3_cross(float *o, const float *a, const float *b);
/* Normalises v in place (left as it is when zero); returns its length before. */
float dm_v3_norm(float *v);

#endif
