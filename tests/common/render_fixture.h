/* render_fixture.h — the synthetic scene (lib/render/dm_render_synth.h) on an OSMesa context
 * with a renderer over it, for the renderer's tests: open, frame, read a target, close. */
#ifndef TEST_RENDER_FIXTURE_H
#define TEST_RENDER_FIXTURE_H

#include <criterion/criterion.h>
#include <stdlib.h>
#include <string.h>

#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_synth.h"

typedef struct fixture {
    dm_osmesa *ctx;
    dm_synth *synth;
    dm_renderer *r;
} fixture;

static inline void open_synth(fixture *f, dm_synth_options so)
{
    dm_error err = {0};
    memset(f, 0, sizeof *f);
    if (!so.beckmann_size) so.beckmann_size = 128;
    if (!so.directional_size) so.directional_size = 16;
    if (!so.stretch_size) so.stretch_size = 64;
    cr_assert_eq(dm_osmesa_create(&f->ctx, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_synth_create(&so, &f->synth, &err), DM_OK, "%s", err.detail);
}

static inline void open_renderer_desc(fixture *f, dm_render_desc d)
{
    dm_error err = {0};
    cr_assert_eq(dm_renderer_create(&f->synth->assets, &d, &f->r, &err), DM_OK, "%s", err.detail);
}

static inline void open_renderer(fixture *f, int w, int h, int irr)
{
    open_renderer_desc(f, (dm_render_desc){.width = w, .height = h, .irradiance_size = irr, .shadow_size = 256});
}

static inline void close_fixture(fixture *f)
{
    dm_renderer_destroy(f->r);
    dm_synth_free(f->synth);
    dm_osmesa_destroy(f->ctx);
}

static inline void only(dm_scene *s, const dm_effect *on, int n)
{
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) s->effects[e] = false;
    for (int i = 0; i < n; ++i) s->effects[on[i]] = true;
}

/* The synthetic sphere's lower half seen from inside: triangles with a corner above z = 0
 * dropped, normals and winding turned inwards (a concave bowl open at z = 0, facing the
 * camera on +z). Light from above the rim casts a real shadow into it. */
static inline void synth_bowl(dm_synth *s)
{
    float *v = s->vertices;
    int kept = 0;
    for (int t = 0; t < s->assets.index_count / 3; ++t) {
        const uint32_t *c = &s->indices[t * 3];
        bool lower = true;
        for (int k = 0; k < 3; ++k) lower = lower && v[(size_t)c[k] * DM_VERTEX_FLOATS + DM_VERTEX_POSITION + 2] < 1e-6f;
        if (!lower) continue;
        const uint32_t a = c[0], b = c[1], d = c[2];
        uint32_t *o = &s->indices[kept++ * 3];
        o[0] = a, o[1] = d, o[2] = b; /* clockwise seen from outside: front faces inwards */
    }
    s->assets.index_count = kept * 3;
    for (int i = 0; i < s->assets.vertex_count; ++i)
        for (int c = 0; c < 3; ++c) v[(size_t)i * DM_VERTEX_FLOATS + DM_VERTEX_NORMAL + c] *= -1.0f;
}

/* Target `name` of renderer r, read back (malloc'd; info says its size). */
static inline float *read_renderer_target(dm_renderer *r, const char *name, dm_target_info *info)
{
    int idx = dm_renderer_find_target(r, name);
    cr_assert_geq(idx, 0, "no target %s", name);
    dm_renderer_target_info(r, idx, info);
    float *px = malloc((size_t)info->width * info->height * info->channels * sizeof *px);
    dm_error err = {0};
    cr_assert_eq(dm_renderer_read_target(r, idx, px, &err), DM_OK, "%s", err.detail);
    return px;
}

static inline float *read_target(fixture *f, const char *name, dm_target_info *info)
{
    return read_renderer_target(f->r, name, info);
}

static inline void frame(fixture *f, dm_view view, int index)
{
    dm_error err = {0};
    dm_frame_options o = {.view = view, .view_index = index};
    cr_assert_eq(dm_render_frame(f->r, &o, &err), DM_OK, "%s", err.detail);
}

#endif
