#include "render/dm_render_synth.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_brdf.h"
#include "core/dm_math.h"

void dm_synth_scene(dm_scene *s, float distance)
{
    dm_scene_defaults(s); /* every effect on, gems3-skin, 7 taps, 1280x720 ... */
    snprintf(s->path, sizeof s->path, "synthetic");
    snprintf(s->mesh, sizeof s->mesh, "synthetic");
    s->light_count = 1;
    dm_light *l = &s->lights[0];
    l->type = DM_LIGHT_DIRECTIONAL;
    float d[3] = {0.5f, 0.4f, 1.0f}, n = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int i = 0; i < 3; ++i) {
        l->direction[i] = d[i] / n;
        l->color[i] = 1.0f;
    }
    l->intensity = 1.5f;
    l->casts_shadow = true;
    snprintf(s->environment, sizeof s->environment, "synthetic-sky");
    s->env_intensity = 0.5f;
    s->camera_eye[2] = distance;
}

static void put_vertex(float *v, const float p[3], const float n[3], const float t[3], float sign, float u, float vv)
{
    memcpy(v + DM_VERTEX_POSITION, p, 3 * sizeof *v);
    memcpy(v + DM_VERTEX_NORMAL, n, 3 * sizeof *v);
    memcpy(v + DM_VERTEX_TANGENT, t, 3 * sizeof *v);
    v[DM_VERTEX_TANGENT + 3] = sign;
    v[DM_VERTEX_UV] = u;
    v[DM_VERTEX_UV + 1] = vv;
}

/* Sky radiance a + b·y (y up): SH L00 = a·2√π, L1−1 = b·√(4π/3); other terms 0. */
static const float sky_a[3] = {0.55f, 0.6f, 0.7f}, sky_b[3] = {0.25f, 0.3f, 0.4f};

static void sky_equirect(float *px, int w, int h)
{
    for (int j = 0; j < h; ++j) {
        double y = sin(((j + 0.5) / h - 0.5) * DM_PI); /* v = 0.5 + asin(y)/π */
        for (int i = 0; i < w; ++i)
            for (int c = 0; c < 4; ++c)
                px[((size_t)j * w + i) * 4 + c] = c == 3 ? 1.0f : (float)(sky_a[c] + sky_b[c] * y);
    }
}

dm_result dm_synth_create(const dm_synth_options *o, dm_synth **out, dm_error *err)
{
    *out = NULL;
    dm_synth *s = calloc(1, sizeof *s);
    if (!s) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "synthetic scene: cannot allocate");
    const bool sphere = o->shape == DM_SYNTH_SPHERE;
    int segs = o->sphere_segments > 2 ? o->sphere_segments : 96;
    int rings = o->sphere_rings > 1 ? o->sphere_rings : 96;
    int cells = o->quad_cells > 0 ? o->quad_cells : 16;
    float side_mm = o->quad_side_mm > 0 ? o->quad_side_mm : 64.0f;
    float inset = o->quad_uv_inset > 0 ? (o->quad_uv_inset < 0.45f ? o->quad_uv_inset : 0.45f) : 0.0f;
    int ss = o->stretch_size > 0 ? o->stretch_size : 256;
    int bs = o->beckmann_size > 0 ? o->beckmann_size : 256;
    int ds = o->directional_size > 0 ? o->directional_size : 32;

    dm_synth_scene(&s->scene, sphere ? 4.5f : 0.0f);
    const double mmpu = s->scene.mm_per_unit;
    const float side = (float)(side_mm / mmpu);
    if (!sphere) s->scene.camera_eye[2] = side * 2.0f;

    int nv = sphere ? (segs + 1) * (rings + 1) : (cells + 1) * (cells + 1);
    int ntri = sphere ? 2 * segs * rings - 2 * segs : 2 * cells * cells;
    s->vertices = malloc((size_t)nv * DM_VERTEX_STRIDE);
    s->indices = malloc((size_t)ntri * 3 * sizeof *s->indices);
    s->beckmann = malloc((size_t)bs * bs);
    s->rho_dt = malloc((size_t)ds * ds * sizeof(float));
    s->env_brdf = malloc((size_t)ds * ds * 2 * sizeof(float));
    s->stretch = malloc((size_t)ss * ss * 2 * sizeof(float));
    s->mask = malloc((size_t)ss * ss);
    s->env = malloc((size_t)64 * 32 * 4 * sizeof(float));
    s->background = malloc((size_t)256 * 128 * 4 * sizeof(float));
    if (!s->vertices || !s->indices || !s->beckmann || !s->rho_dt || !s->env_brdf || !s->stretch ||
        !s->mask || !s->env || !s->background) {
        dm_synth_free(s);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "synthetic scene: cannot allocate its arrays");
    }

    /* mesh */
    uint32_t *ix = s->indices;
    if (sphere) {
        for (int j = 0; j <= rings; ++j)
            for (int i = 0; i <= segs; ++i) {
                double u = (double)i / segs, v = (double)j / rings, th = v * DM_PI, ph = u * DM_2PI;
                float n[3] = {(float)(sin(th) * sin(ph)), (float)-cos(th), (float)(sin(th) * cos(ph))};
                float t[3] = {(float)cos(ph), 0.0f, (float)-sin(ph)};
                /* B = ∂P/∂θ direction; cross(N, T) = (cosθ sinφ, sinθ, cosθ cosφ)·… has the same sign */
                put_vertex(s->vertices + ((size_t)j * (segs + 1) + i) * DM_VERTEX_FLOATS, n, n, t, 1.0f, (float)u,
                           (float)v);
            }
        for (int j = 0; j < rings; ++j)
            for (int i = 0; i < segs; ++i) {
                uint32_t a = (uint32_t)(j * (segs + 1) + i), b = a + 1, c = a + (uint32_t)segs + 2,
                         d = a + (uint32_t)segs + 1;
                if (j != 0) {
                    *ix++ = a, *ix++ = b, *ix++ = c;
                }
                if (j != rings - 1) {
                    *ix++ = a, *ix++ = c, *ix++ = d;
                }
            }
    } else {
        float n[3] = {0, 0, 1}, t[3] = {1, 0, 0};
        for (int j = 0; j <= cells; ++j)
            for (int i = 0; i <= cells; ++i) {
                float u = (float)i / cells, v = (float)j / cells;
                float p[3] = {(u - 0.5f) * side, (v - 0.5f) * side, 0.0f};
                put_vertex(s->vertices + ((size_t)j * (cells + 1) + i) * DM_VERTEX_FLOATS, p, n, t, 1.0f,
                           inset + u * (1.0f - 2.0f * inset), inset + v * (1.0f - 2.0f * inset));
            }
        for (int j = 0; j < cells; ++j)
            for (int i = 0; i < cells; ++i) {
                uint32_t a = (uint32_t)(j * (cells + 1) + i), b = a + 1, c = a + (uint32_t)cells + 2,
                         d = a + (uint32_t)cells + 1;
                *ix++ = a, *ix++ = b, *ix++ = c;
                *ix++ = a, *ix++ = c, *ix++ = d;
            }
    }
    s->triangle_count = (int)((ix - s->indices) / 3);

    /* stretch: exact for both shapes (UV units per mm) */
    for (int j = 0; j < ss; ++j)
        for (int i = 0; i < ss; ++i) {
            float *st = s->stretch + ((size_t)j * ss + i) * 2;
            if (sphere) {
                double th = (j + 0.5) / ss * DM_PI, sn = fmax(sin(th), 0.05);
                st[0] = (float)(1.0 / (DM_2PI * sn * mmpu));
                st[1] = (float)(1.0 / (DM_PI * mmpu));
            } else {
                st[0] = st[1] = (1.0f - 2.0f * inset) / side_mm;
            }
            double u = (i + 0.5) / ss, v = (j + 0.5) / ss;
            bool in = sphere || (u > inset && u < 1.0 - inset && v > inset && v < 1.0 - inset);
            s->mask[(size_t)j * ss + i] = in ? 255 : 0;
        }

    /* tables, as dm_lut.h lays them out, from core/dm_brdf.h */
    for (int j = 0; j < bs; ++j)
        for (int i = 0; i < bs; ++i)
            s->beckmann[(size_t)j * bs + i] = dm_beckmann_encode8(dm_beckmann((i + 0.5) / bs, (j + 0.5) / bs));
    for (int j = 0; j < ds; ++j)
        for (int i = 0; i < ds; ++i) {
            double sc, bi;
            dm_ks_directional((i + 0.5) / ds, (j + 0.5) / ds, 24, &sc, &bi);
            size_t k = (size_t)j * ds + i;
            s->env_brdf[2 * k] = (float)sc;
            s->env_brdf[2 * k + 1] = (float)bi;
            s->rho_dt[k] = (float)(DM_SKIN_F0 * sc + bi);
        }
    sky_equirect(s->env, 64, 32);
    sky_equirect(s->background, 256, 128);
    s->albedo[0] = 224, s->albedo[1] = 172, s->albedo[2] = 150, s->albedo[3] = 255;

    dm_render_assets *a = &s->assets;
    a->scene = &s->scene;
    a->vertices = s->vertices;
    a->vertex_count = nv;
    a->indices = s->indices;
    a->index_count = s->triangle_count * 3;
    a->albedo = (dm_texture){DM_TEX_RGBA8_SRGB, 1, 1, s->albedo};
    a->beckmann = (dm_texture){DM_TEX_R8, bs, bs, s->beckmann};
    a->rho_dt = (dm_texture){DM_TEX_R32F, ds, ds, s->rho_dt};
    a->env_brdf = (dm_texture){DM_TEX_RG32F, ds, ds, s->env_brdf};
    a->stretch_level_count = 1;
    a->stretch[0] = (dm_texture){DM_TEX_RG32F, ss, ss, s->stretch};
    a->stretch_mask = (dm_texture){DM_TEX_R8, ss, ss, s->mask};
    a->has_env_sh = true;
    for (int c = 0; c < 3; ++c) {
        a->env_sh[0][c] = (float)(sky_a[c] * 2.0 * sqrt(DM_PI));
        a->env_sh[1][c] = (float)(sky_b[c] * sqrt(4.0 * DM_PI / 3.0));
    }
    a->env_level_count = 2;
    a->env_level_m[0] = 0.05f;
    a->env_level_m[1] = 0.6f;
    a->env_levels[0] = a->env_levels[1] = (dm_texture){DM_TEX_RGBA32F, 64, 32, s->env};
    a->env_background = (dm_texture){DM_TEX_RGBA32F, 256, 128, s->background};
    *out = s;
    return DM_OK;
}

void dm_synth_free(dm_synth *s)
{
    if (!s) return;
    free(s->vertices);
    free(s->indices);
    free(s->beckmann);
    free(s->mask);
    free(s->rho_dt);
    free(s->env_brdf);
    free(s->stretch);
    free(s->env);
    free(s->background);
    free(s);
}
