/* ref_synth.h — synthetic surfaces for the ground-truth tests: planes and spheres in the
 * dermis vertex layout, with exact normals and tangents, and a scene with every effect off. */
#ifndef TEST_REF_SYNTH_H
#define TEST_REF_SYNTH_H

#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reference/dm_ref_surface.h"

#define SYNTH_PI 3.14159265358979323846

typedef struct synth {
    dm_scene scene;
    float *v;
    uint32_t *ix;
    int nv, ni, cap_v, cap_i;
} synth;

/* Mesh units are mm; no effect, no light; a camera at +Z looking at the origin. */
static inline void synth_init(synth *s)
{
    memset(s, 0, sizeof *s);
    dm_scene_defaults(&s->scene);
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) s->scene.effects[e] = false;
    s->scene.mm_per_unit = 1.0;
    s->scene.env_background = false;
    s->scene.camera_eye[2] = 100.0f;
}

static inline void synth_free(synth *s)
{
    free(s->v);
    free(s->ix);
}

static inline uint32_t synth_vertex(synth *s, const double p[3], const double n[3], const double uv[2],
                                    const double t[4])
{
    if (s->nv == s->cap_v) {
        s->cap_v = s->cap_v ? 2 * s->cap_v : 256;
        s->v = realloc(s->v, (size_t)s->cap_v * DM_REF_VERTEX_FLOATS * sizeof *s->v);
        cr_assert(s->v);
    }
    float *o = s->v + (size_t)s->nv * DM_REF_VERTEX_FLOATS;
    for (int c = 0; c < 3; ++c) {
        o[DM_PACK_VERTEX_POSITION / 4 + c] = (float)p[c];
        o[DM_PACK_VERTEX_NORMAL / 4 + c] = (float)n[c];
    }
    o[DM_PACK_VERTEX_UV / 4] = (float)uv[0];
    o[DM_PACK_VERTEX_UV / 4 + 1] = (float)uv[1];
    for (int c = 0; c < 4; ++c) o[DM_PACK_VERTEX_TANGENT / 4 + c] = (float)t[c];
    return (uint32_t)s->nv++;
}

static inline void synth_tri(synth *s, uint32_t a, uint32_t b, uint32_t c)
{
    if (s->ni + 3 > s->cap_i) {
        s->cap_i = s->cap_i ? 2 * s->cap_i : 768;
        s->ix = realloc(s->ix, (size_t)s->cap_i * sizeof *s->ix);
        cr_assert(s->ix);
    }
    s->ix[s->ni++] = a;
    s->ix[s->ni++] = b;
    s->ix[s->ni++] = c;
}

/* A flat parallelogram o + a·ex + b·ey (a, b in [0, 1]), n × n cells, front side ex × ey,
 * UV linear over the rectangle uv = {u0, v0, u1, v1} (u along ex, v along ey). */
static inline void synth_quad(synth *s, const double o[3], const double ex[3], const double ey[3], int n,
                              const double uv[4])
{
    double nrm[3] = {ex[1] * ey[2] - ex[2] * ey[1], ex[2] * ey[0] - ex[0] * ey[2], ex[0] * ey[1] - ex[1] * ey[0]};
    double ln = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    double lt = sqrt(ex[0] * ex[0] + ex[1] * ex[1] + ex[2] * ex[2]);
    double t[4] = {ex[0] / lt, ex[1] / lt, ex[2] / lt, 1.0};
    for (int c = 0; c < 3; ++c) nrm[c] /= ln;
    uint32_t base = (uint32_t)s->nv;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            double a = (double)i / n, b = (double)j / n, p[3], q[2] = {uv[0] + a * (uv[2] - uv[0]),
                                                                        uv[1] + b * (uv[3] - uv[1])};
            for (int c = 0; c < 3; ++c) p[c] = o[c] + a * ex[c] + b * ey[c];
            synth_vertex(s, p, nrm, q, t);
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            uint32_t a = base + (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)n + 1, d = c + 1;
            synth_tri(s, a, b, d);
            synth_tri(s, a, d, c);
        }
}

/* A UV sphere (nu × nv cells, θ from +Y, φ about Y), radial normals, tangent along +φ
 * (= +u), UV u = φ/2π, v = 1 − θ/π mapped into the rectangle uv. */
static inline void synth_sphere(synth *s, const double ctr[3], double r, int nu, int nv, const double uv[4])
{
    uint32_t base = (uint32_t)s->nv;
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            double th = SYNTH_PI * j / nv, ph = 2 * SYNTH_PI * i / nu;
            double n[3] = {sin(th) * cos(ph), cos(th), -sin(th) * sin(ph)}, p[3];
            double t[4] = {-sin(ph), 0.0, -cos(ph), 1.0};
            double q[2] = {uv[0] + (uv[2] - uv[0]) * i / nu, uv[1] + (uv[3] - uv[1]) * (1.0 - (double)j / nv)};
            for (int c = 0; c < 3; ++c) p[c] = ctr[c] + r * n[c];
            synth_vertex(s, p, n, q, t);
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            uint32_t a = base + (uint32_t)(j * (nu + 1) + i), b = a + 1, c = a + (uint32_t)nu + 1, d = c + 1;
            if (j < nv - 1) synth_tri(s, a, c, d); /* at the poles one half has no area */
            if (j > 0) synth_tri(s, a, d, b);
        }
}

static inline void synth_light(synth *s, double x, double y, double z, double intensity, bool shadow)
{
    dm_light *l = &s->scene.lights[s->scene.light_count++];
    double len = sqrt(x * x + y * y + z * z);
    l->type = DM_LIGHT_DIRECTIONAL;
    l->direction[0] = (float)(x / len);
    l->direction[1] = (float)(y / len);
    l->direction[2] = (float)(z / len);
    l->color[0] = l->color[1] = l->color[2] = 1.0f;
    l->intensity = (float)intensity;
    l->casts_shadow = shadow;
}

static inline void synth_desc(synth *s, dm_ref_surface_desc *d)
{
    memset(d, 0, sizeof *d);
    d->scene = &s->scene;
    d->vertices = s->v;
    d->vertex_count = s->nv;
    d->indices = s->ix;
    d->index_count = s->ni;
}

static inline dm_ref_surface *synth_surface(const dm_ref_surface_desc *d)
{
    dm_ref_surface *out = NULL;
    dm_error err = {0};
    cr_assert_eq(dm_ref_surface_create(d, 0, &out, &err), DM_OK, "%s", err.detail);
    return out;
}

#endif
