/* dm_mat4.c — 3-vector and 4x4 matrix helpers (dm_mat4.h). */
#include "core/dm_mat4.h"

#include <math.h>
#include <string.h>

void dm_mat4_mul(float *o, const float *a, const float *b)
{
    float r[16];
    for (int c = 0; c < 4; ++c)
        for (int rr = 0; rr < 4; ++rr) {
            float s = 0;
            for (int k = 0; k < 4; ++k) s += a[k * 4 + rr] * b[c * 4 + k];
            r[c * 4 + rr] = s;
        }
    memcpy(o, r, sizeof r);
}

void dm_v3_sub(float *o, const float *a, const float *b)
{
    for (int i = 0; i < 3; ++i) o[i] = a[i] - b[i];
}

float dm_v3_dot(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

void dm_v3_cross(float *o, const float *a, const float *b)
{
    float r[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(o, r, sizeof r);
}

float dm_v3_norm(float *v)
{
    float l = sqrtf(dm_v3_dot(v, v));
    if (l > 0)
        for (int i = 0; i < 3; ++i) v[i] /= l;
    return l;
}

void dm_mat4_look_at(float *m, const float *eye, const float *target, const float *up_hint, float *right, float *up,
                     float *fwd)
{
    float f[3], s[3], u[3];
    dm_v3_sub(f, target, eye);
    dm_v3_norm(f);
    dm_v3_cross(s, f, up_hint);
    if (dm_v3_norm(s) < 1e-6f) { /* up parallel to the view: pick another */
        float alt[3] = {fabsf(f[0]) < 0.9f ? 1.0f : 0.0f, 0.0f, fabsf(f[0]) < 0.9f ? 0.0f : 1.0f};
        dm_v3_cross(s, f, alt);
        dm_v3_norm(s);
    }
    dm_v3_cross(u, s, f);
    float r[16] = {s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
                   -dm_v3_dot(s, eye), -dm_v3_dot(u, eye), dm_v3_dot(f, eye), 1};
    memcpy(m, r, sizeof r);
    if (right) memcpy(right, s, sizeof s);
    if (up) memcpy(up, u, sizeof u);
    if (fwd) memcpy(fwd, f, sizeof f);
}

void dm_mat4_perspective(float *m, float fovy_rad, float aspect, float n, float f)
{
    float t = 1.0f / tanf(0.5f * fovy_rad);
    float r[16] = {t / aspect, 0, 0, 0, 0, t, 0, 0, 0, 0, (f + n) / (n - f), -1, 0, 0, 2 * f * n / (n - f), 0};
    memcpy(m, r, sizeof r);
}

void dm_mat4_ortho(float *m, float half, float n, float f)
{
    float r[16] = {1 / half, 0, 0, 0, 0, 1 / half, 0, 0, 0, 0, -2 / (f - n), 0, 0, 0, -(f + n) / (f - n), 1};
    memcpy(m, r, sizeof r);
}
