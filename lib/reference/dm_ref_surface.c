#include "reference/dm_ref_surface.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_brdf.h"
#include "core/dm_parallel.h"
#include "core/dm_prov.h"

enum { RHO_C_INTERVALS = 1024, RHO_M_INTERVALS = 64, RHO_NODES = 48 };

/* ---- from a pack -------------------------------------------------------------------- */

static dm_result tex_entry(const dm_pack *pack, const char *name, dm_ref_texture *out, dm_error *err)
{
    memset(out, 0, sizeof *out);
    const dm_pack_entry *e;
    dm_result r = dm_pack_find_texture(pack, name, &e, err);
    if (r == DM_OK && e) *out = (dm_ref_texture){e->format, e->width, e->height, e->data, false};
    return r;
}

static dm_result pack_env(const dm_pack *pack, dm_ref_surface_desc *d, dm_error *err)
{
    const dm_pack_entry *sh = dm_pack_find(pack, "env.sh");
    if (sh) {
        if (sh->kind != DM_PACK_ENV_SH || sh->sh_order != 2 || sh->size != sizeof d->env_sh)
            return dm_fail(err, DM_ERR_FORMAT, "%s: env.sh of order %d, expected order 2 (9 RGB)", pack->what,
                           sh->sh_order);
        memcpy(d->env_sh, sh->data, sizeof d->env_sh);
        d->has_env_sh = true;
    }
    const dm_pack_entry *spec = dm_pack_find(pack, "env.specular");
    if (spec) {
        if (spec->kind != DM_PACK_TEXTURE || spec->levels != 1 || spec->layers < 1 ||
            spec->layers > DM_REF_ENV_LEVELS_MAX || !dm_tex_format_get(spec->format)->is_float)
            return dm_fail(err, DM_ERR_FORMAT, "%s: env.specular has %d layers, expected 1..%d float layers",
                           pack->what, spec->layers, DM_REF_ENV_LEVELS_MAX);
        dm_result r = dm_pack_env_level_m(pack, spec, d->env_level_m, err);
        if (r != DM_OK) return r;
        size_t layer_size = dm_pack_texture_level_size(spec, 0) / (size_t)spec->layers;
        for (int k = 0; k < spec->layers; ++k)
            d->env_levels[k] = (dm_ref_texture){spec->format, spec->width, spec->height,
                                                (const uint8_t *)spec->data + layer_size * (size_t)k, true};
        d->env_level_count = spec->layers;
    }
    dm_result r = tex_entry(pack, "env.background", &d->env_background, err);
    d->env_background.repeat_u = true;
    return r;
}

dm_result dm_ref_surface_desc_from_pack(const dm_pack *pack, const dm_scene *scene, dm_profile *profile,
                                        dm_ref_surface_desc *desc, dm_error *err)
{
    assert(pack && scene && profile && desc);
    memset(desc, 0, sizeof *desc);
    desc->scene = scene;
    *profile = scene->profile; /* the one route: the pack verified its "profile" entry agrees */
    desc->profile = profile;
    const dm_pack_entry *v, *ix;
    dm_result r = dm_pack_mesh(pack, &v, &ix, err);
    if (r != DM_OK) return r;
    desc->vertices = v->data;
    desc->vertex_count = (int32_t)v->vertex_count;
    desc->indices = ix->data;
    desc->index_count = (int32_t)ix->index_count;
    if ((r = tex_entry(pack, "albedo", &desc->albedo, err)) != DM_OK) return r;
    if ((r = tex_entry(pack, "normal", &desc->normal_map, err)) != DM_OK) return r;
    if ((r = tex_entry(pack, "specular", &desc->specular_map, err)) != DM_OK) return r;
    if ((r = tex_entry(pack, "roughness", &desc->roughness_map, err)) != DM_OK) return r;
    return pack_env(pack, desc, err);
}

/* ---- creation ----------------------------------------------------------------------- */

static dm_result check_texture(const dm_ref_texture *t, const char *what, dm_error *err)
{
    if (!t->texels) return DM_OK;
    if (!dm_tex_format_get(t->format))
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: texture format %d is not a dm_tex_format", what,
                       (int)t->format);
    if (t->width < 1 || t->height < 1 || t->width > DM_PACK_TEXTURE_SIZE_MAX || t->height > DM_PACK_TEXTURE_SIZE_MAX)
        return dm_fail(err, DM_ERR_RANGE, "%s: size %dx%d, expected 1..%d per side", what, t->width, t->height,
                       DM_PACK_TEXTURE_SIZE_MAX);
    return DM_OK;
}

static dm_result build_mesh(dm_ref_surface *s, dm_error *err)
{
    const dm_ref_surface_desc *d = &s->desc;
    if (!d->vertices || !d->indices || d->vertex_count < 1 || d->index_count < 3 || d->index_count % 3)
        return dm_fail(err, DM_ERR_EMPTY, "surface: %d vertices, %d indices: expected a triangle mesh",
                       (int)d->vertex_count, (int)d->index_count);
    dm_result r = dm_mesh_alloc(d->vertex_count, d->index_count / 3, &s->mesh, err);
    if (r != DM_OK) return r;
    for (int32_t i = 0; i < d->vertex_count; ++i)
        for (int c = 0; c < 3; ++c)
            s->mesh.positions[(size_t)i * 3 + c] = d->vertices[(size_t)i * DM_REF_VERTEX_FLOATS + c];
    for (int32_t k = 0; k < d->index_count; ++k) {
        uint32_t i = d->indices[k];
        if (i >= (uint32_t)d->vertex_count)
            return dm_fail(err, DM_ERR_RANGE, "surface: index %d is %u, expected < %d vertices", (int)k, i,
                           (int)d->vertex_count);
        const float *v = d->vertices + (size_t)i * DM_REF_VERTEX_FLOATS;
        s->mesh.indices[k] = i;
        s->mesh.uvs[(size_t)k * 2] = v[DM_PACK_VERTEX_UV / 4];
        s->mesh.uvs[(size_t)k * 2 + 1] = v[DM_PACK_VERTEX_UV / 4 + 1];
        for (int c = 0; c < 3; ++c) s->mesh.normals[(size_t)k * 3 + c] = v[DM_PACK_VERTEX_NORMAL / 4 + c];
    }
    for (int32_t i = 0; i < d->vertex_count; ++i)
        for (int c = 0; c < DM_REF_VERTEX_FLOATS; ++c)
            if (!isfinite(d->vertices[(size_t)i * DM_REF_VERTEX_FLOATS + c]))
                return dm_fail(err, DM_ERR_NON_FINITE, "surface: vertex %d float %d is not finite", (int)i, c);
    return dm_mesh_validate(&s->mesh, "surface", err);
}

typedef struct rho_job {
    dm_ref_surface *s;
    double m_fixed;
} rho_job;

static void rho_range(void *ctx, size_t begin, size_t end)
{
    rho_job *j = ctx;
    dm_ref_surface *s = j->s;
    for (size_t k = begin; k < end; ++k) {
        size_t mi = k / (size_t)s->rho_c_count, ci = k % (size_t)s->rho_c_count;
        double m = s->rho_m_count == 1 ? j->m_fixed : (double)mi / (s->rho_m_count - 1);
        double sq = (double)ci / (s->rho_c_count - 1), scale, bias;
        dm_ks_directional(sq * sq, m, RHO_NODES, &scale, &bias);
        s->rho[k] = DM_SKIN_F0 * scale + bias;
    }
}

static void resolve(dm_ref_surface *s)
{
    const dm_scene *sc = &s->scene;
    const dm_ref_surface_desc *d = &s->desc;
    const bool *fx = sc->effects;
    dm_ref_terms *t = &s->terms;
    t->subsurface = fx[DM_EFFECT_SUBSURFACE];
    t->specular = fx[DM_EFFECT_SPECULAR];
    t->energy = fx[DM_EFFECT_ENERGY_CONSERVATION] && t->specular;
    t->env_diffuse = fx[DM_EFFECT_ENVIRONMENT_LIGHTING] && d->has_env_sh;
    t->env_specular = fx[DM_EFFECT_ENVIRONMENT_LIGHTING] && t->specular && d->env_level_count > 0;
    t->background = fx[DM_EFFECT_ENVIRONMENT_LIGHTING] && sc->env_background && sc->environment[0] &&
                    d->env_background.texels;
    t->shadows = fx[DM_EFFECT_SHADOWS];
    s->light_count = sc->light_count;
    for (int i = 0; i < sc->light_count; ++i) {
        const dm_light *l = &sc->lights[i];
        bool dir = l->type == DM_LIGHT_DIRECTIONAL;
        const float *v = dir ? l->direction : l->position;
        double len = dir ? sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]) : 1.0;
        for (int c = 0; c < 3; ++c) {
            s->light_pos[i][c] = dir ? (len > 0 ? v[c] / len : 0.0) : v[c] * s->mm_per_unit;
            s->light_color[i][c] = (double)l->color[c] * l->intensity;
        }
        s->light_pos[i][3] = dir ? 0.0 : 1.0;
        s->light_shadow[i] = t->shadows && l->casts_shadow;
    }
    s->env_rotation_rad = sc->env_rotation_deg * 3.14159265358979323846 / 180.0;
}

dm_result dm_ref_surface_create(const dm_ref_surface_desc *desc, int thread_count, dm_ref_surface **out,
                                dm_error *err)
{
    assert(desc && desc->scene && out);
    *out = NULL;
    dm_ref_surface *s = calloc(1, sizeof *s);
    if (!s) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "surface: out of memory");
    s->scene = *desc->scene;
    s->profile = desc->profile ? *desc->profile : desc->scene->profile;
    s->desc = *desc;
    s->desc.scene = &s->scene;
    s->desc.profile = &s->profile;
    s->mm_per_unit = s->scene.mm_per_unit;
    dm_result r = DM_OK;
    if (!(s->mm_per_unit > 0) || !isfinite(s->mm_per_unit))
        r = dm_fail(err, DM_ERR_RANGE, "surface: mm_per_unit %g, expected a finite value > 0", s->mm_per_unit);
    const struct {
        const dm_ref_texture *t;
        const char *what;
    } maps[] = {{&desc->albedo, "albedo"},
                {&desc->normal_map, "normal_map"},
                {&desc->specular_map, "specular_map"},
                {&desc->roughness_map, "roughness_map"},
                {&desc->env_background, "env_background"}};
    for (size_t k = 0; r == DM_OK && k < sizeof maps / sizeof maps[0]; ++k) r = check_texture(maps[k].t, maps[k].what, err);
    if (r == DM_OK && (desc->env_level_count < 0 || desc->env_level_count > DM_REF_ENV_LEVELS_MAX))
        r = dm_fail(err, DM_ERR_RANGE, "surface: %d environment levels, expected 0..%d", desc->env_level_count,
                    DM_REF_ENV_LEVELS_MAX);
    for (int k = 0; r == DM_OK && k < desc->env_level_count; ++k) {
        r = check_texture(&desc->env_levels[k], "env_levels", err);
        if (r == DM_OK && !desc->env_levels[k].texels)
            r = dm_fail(err, DM_ERR_INVALID_ARGUMENT, "surface: environment level %d has no texels", k);
    }
    for (int k = 0; r == DM_OK && desc->has_env_sh && k < 27; ++k)
        if (!isfinite(desc->env_sh[k / 3][k % 3]))
            r = dm_fail(err, DM_ERR_NON_FINITE, "surface: env SH coefficient %d is not finite", k / 3);
    if (r == DM_OK) r = build_mesh(s, err);
    if (r == DM_OK) r = dm_raycast_create(&s->mesh, s->mm_per_unit, &s->rays, err);
    if (r == DM_OK) {
        s->eps_mm = dm_raycast_epsilon_mm(s->rays);
        resolve(s);
        s->rho_c_count = RHO_C_INTERVALS + 1;
        s->rho_m_count = desc->roughness_map.texels ? RHO_M_INTERVALS + 1 : 1;
        s->rho = malloc((size_t)s->rho_c_count * (size_t)s->rho_m_count * sizeof *s->rho);
        if (!s->rho) r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "surface: out of memory for the rho_dt table");
    }
    if (r == DM_OK) {
        double m = s->scene.roughness < 1.0f ? s->scene.roughness : 1.0;
        rho_job j = {s, m > 0 ? m : 0.0};
        dm_parallel_for((size_t)s->rho_c_count * (size_t)s->rho_m_count, 16, thread_count, rho_range, &j);
    }
    if (r != DM_OK) {
        dm_ref_surface_destroy(s);
        return r;
    }
    *out = s;
    return DM_OK;
}

void dm_ref_surface_destroy(dm_ref_surface *s)
{
    if (!s) return;
    dm_raycast_destroy(s->rays);
    dm_mesh_free(&s->mesh);
    free(s->rho);
    free(s);
}

double dm_ref_surface_rho_dt(const dm_ref_surface *s, double c, double m)
{
    c = c > 0 ? (c < 1 ? c : 1) : 0; /* NaN → 0 */
    double x = sqrt(c) * (s->rho_c_count - 1);
    int i = (int)x;
    if (i > s->rho_c_count - 2) i = s->rho_c_count - 2;
    double f = x - i;
    const double *col = s->rho;
    if (s->rho_m_count == 1) return (1 - f) * col[i] + f * col[i + 1];
    m = m > 0 ? (m < 1 ? m : 1) : 0;
    double y = m * (s->rho_m_count - 1);
    int j = (int)y;
    if (j > s->rho_m_count - 2) j = s->rho_m_count - 2;
    double g = y - j;
    const double *a = s->rho + (size_t)j * s->rho_c_count, *b = a + s->rho_c_count;
    return (1 - g) * ((1 - f) * a[i] + f * a[i + 1]) + g * ((1 - f) * b[i] + f * b[i + 1]);
}

/* ---- points ------------------------------------------------------------------------- */

static double normalize3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0)
        for (int c = 0; c < 3; ++c) v[c] /= l;
    return l;
}

/* dm_shading_normal of common.glsl, in double. */
static void shading_normal(const double n[3], const double t[4], const double map_rgb[3], bool has_map, double out[3])
{
    memcpy(out, n, 3 * sizeof *out);
    if (!has_map) return;
    double nt = n[0] * t[0] + n[1] * t[1] + n[2] * t[2];
    double T[3] = {t[0] - n[0] * nt, t[1] - n[1] * nt, t[2] - n[2] * nt};
    double tl = T[0] * T[0] + T[1] * T[1] + T[2] * T[2];
    if (tl < 1e-12) return;
    for (int c = 0; c < 3; ++c) T[c] /= sqrt(tl);
    double w = t[3] < 0.0 ? -1.0 : 1.0;
    double B[3] = {w * (n[1] * T[2] - n[2] * T[1]), w * (n[2] * T[0] - n[0] * T[2]), w * (n[0] * T[1] - n[1] * T[0])};
    double m[3] = {map_rgb[0] * 2 - 1, map_rgb[1] * 2 - 1, map_rgb[2] * 2 - 1}, r[3];
    for (int c = 0; c < 3; ++c) r[c] = T[c] * m[0] + B[c] * m[1] + n[c] * m[2];
    double rl = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    if (rl > 1e-12)
        for (int c = 0; c < 3; ++c) out[c] = r[c] / sqrt(rl);
}

void dm_ref_surface_point(const dm_ref_surface *s, int32_t tri, double b1, double b2, dm_ref_point *p)
{
    assert(tri >= 0 && tri < s->mesh.triangle_count);
    const dm_ref_surface_desc *d = &s->desc;
    const double w[3] = {1.0 - b1 - b2, b1, b2};
    double pos[3] = {0}, nrm[3] = {0}, tan[4] = {0}, uv[2] = {0};
    for (int k = 0; k < 3; ++k) {
        const float *v = d->vertices + (size_t)d->indices[(size_t)tri * 3 + k] * DM_REF_VERTEX_FLOATS;
        for (int c = 0; c < 3; ++c) {
            pos[c] += w[k] * v[DM_PACK_VERTEX_POSITION / 4 + c];
            nrm[c] += w[k] * v[DM_PACK_VERTEX_NORMAL / 4 + c];
        }
        for (int c = 0; c < 4; ++c) tan[c] += w[k] * v[DM_PACK_VERTEX_TANGENT / 4 + c];
        for (int c = 0; c < 2; ++c) uv[c] += w[k] * v[DM_PACK_VERTEX_UV / 4 + c];
    }
    p->triangle = tri;
    p->b1 = b1;
    p->b2 = b2;
    for (int c = 0; c < 3; ++c) p->p_mm[c] = pos[c] * s->mm_per_unit;
    p->uv[0] = uv[0];
    p->uv[1] = uv[1];
    /* the front normal the ray caster computed (mm; same direction as in mesh units) */
    double a[3], e1[3], e2[3];
    for (int c = 0; c < 3; ++c) {
        a[c] = s->mesh.positions[(size_t)d->indices[(size_t)tri * 3] * 3 + c];
        e1[c] = s->mesh.positions[(size_t)d->indices[(size_t)tri * 3 + 1] * 3 + c] - a[c];
        e2[c] = s->mesh.positions[(size_t)d->indices[(size_t)tri * 3 + 2] * 3 + c] - a[c];
    }
    p->ng[0] = e1[1] * e2[2] - e1[2] * e2[1];
    p->ng[1] = e1[2] * e2[0] - e1[0] * e2[2];
    p->ng[2] = e1[0] * e2[1] - e1[1] * e2[0];
    if (!(normalize3(p->ng) > 0)) memcpy(p->ng, (double[3]){0, 0, 1}, sizeof p->ng);
    memcpy(p->n, nrm, sizeof nrm);
    if (!(normalize3(p->n) > 1e-12)) memcpy(p->n, p->ng, sizeof p->n);
    double rgba[4], map[3] = {0.5, 0.5, 1.0};
    if (d->normal_map.texels) {
        dm_ref_texture_sample(&d->normal_map, uv[0], uv[1], rgba);
        memcpy(map, rgba, sizeof map);
    }
    shading_normal(p->n, tan, map, d->normal_map.texels != NULL, p->N);
    double m = s->scene.roughness;
    if (d->roughness_map.texels) {
        dm_ref_texture_sample(&d->roughness_map, uv[0], uv[1], rgba);
        m = rgba[0];
    }
    p->m = m < 1.0 ? (m > 0 ? m : 0.0) : 1.0;
    double spec = 1.0;
    if (d->specular_map.texels) {
        dm_ref_texture_sample(&d->specular_map, uv[0], uv[1], rgba);
        spec = rgba[0];
    }
    p->rho_s = s->scene.rho_s * spec;
    if (d->albedo.texels) {
        dm_ref_texture_sample(&d->albedo, uv[0], uv[1], rgba);
        for (int c = 0; c < 3; ++c) p->albedo[c] = rgba[c] > 0 ? rgba[c] : 0.0;
    } else {
        p->albedo[0] = p->albedo[1] = p->albedo[2] = 1.0;
    }
}

void dm_ref_surface_smooth_point(const dm_ref_surface *s, const dm_ref_point *p, double out_mm[3])
{
    assert(p->triangle >= 0 && p->triangle < s->mesh.triangle_count);
    const dm_ref_surface_desc *d = &s->desc;
    const double w[3] = {1.0 - p->b1 - p->b2, p->b1, p->b2};
    memcpy(out_mm, p->p_mm, 3 * sizeof *out_mm);
    for (int k = 0; k < 3; ++k) {
        const float *v = d->vertices + (size_t)d->indices[(size_t)p->triangle * 3 + k] * DM_REF_VERTEX_FLOATS;
        double n[3], h = 0;
        for (int c = 0; c < 3; ++c) n[c] = v[DM_PACK_VERTEX_NORMAL / 4 + c];
        if (!(normalize3(n) > 1e-12)) continue;
        for (int c = 0; c < 3; ++c) h += (p->p_mm[c] - v[DM_PACK_VERTEX_POSITION / 4 + c] * s->mm_per_unit) * n[c];
        /* below corner k's tangent plane by −h: lift by half of w_k of that, along n_k */
        if (h < 0)
            for (int c = 0; c < 3; ++c) out_mm[c] -= 0.5 * w[k] * h * n[c];
    }
}
