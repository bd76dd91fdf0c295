/* dm_render_pack.c — the renderer's assets from an open pack. dm_pack_open verified every
 * entry's kind, format, shape and values (pack/dm_pack_semantic.h), the one verification every
 * reader shares: nothing here refuses an entry again, the asserts only state what it promised. */
#include "render/dm_render_pack.h"

#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pack/dm_pack_semantic.h"
#include "core/dm_prov.h"
#include "core/dm_ssss_kernel.h"

_Static_assert((int)DM_PACK_ENV_LEVELS_MAX <= (int)DM_RENDER_ENV_LEVELS_MAX, "every env.specular a pack holds fits");

/* A single-level, single-layer texture entry as a dm_texture; absent → zero. */
static dm_result texture(const dm_pack *pack, const char *name, dm_texture *out, dm_error *err)
{
    memset(out, 0, sizeof *out);
    const dm_pack_entry *e;
    dm_result r = dm_pack_find_texture(pack, name, &e, err);
    if (r == DM_OK && e) *out = (dm_texture){e->format, e->width, e->height, e->data};
    return r;
}

/* Layer k of a layered single-level texture entry. */
static dm_texture layer(const dm_pack_entry *e, int k)
{
    size_t layer_size = dm_pack_texture_level_size(e, 0) / (size_t)e->layers;
    return (dm_texture){e->format, e->width, e->height, (const uint8_t *)e->data + layer_size * (size_t)k};
}

static dm_result mesh(const dm_pack *pack, dm_render_assets *a, dm_error *err)
{
    const dm_pack_entry *v, *ix;
    dm_result r = dm_pack_mesh(pack, &v, &ix, err);
    if (r != DM_OK) return r;
    a->vertices = v->data;
    a->vertex_count = (int)v->vertex_count;
    a->indices = ix->data;
    a->index_count = (int)ix->index_count;
    return DM_OK;
}

/* The entry name of environment env's "env.<what>" ("env2.sh" for env 2). */
static const char *env_entry(int env, const char *what, char out[DM_PACK_NAME_SIZE])
{
    if (env == 0)
        snprintf(out, DM_PACK_NAME_SIZE, "env.%s", what);
    else
        snprintf(out, DM_PACK_NAME_SIZE, "env%d.%s", env, what);
    return out;
}

static dm_result environment(const dm_pack *pack, int env, dm_render_assets *a, dm_error *err)
{
    char name[DM_PACK_NAME_SIZE];
    const dm_pack_entry *sh = dm_pack_find(pack, env_entry(env, "sh", name));
    if (sh) {
        assert(sh->sh_order == 2 && sh->size == sizeof a->env_sh);
        memcpy(a->env_sh, sh->data, sizeof a->env_sh);
        a->has_env_sh = true;
    }
    const dm_pack_entry *spec = dm_pack_find(pack, env_entry(env, "specular", name));
    if (spec) {
        assert(spec->levels == 1 && spec->layers >= 1 && spec->layers <= DM_PACK_ENV_LEVELS_MAX);
        dm_result r = dm_pack_env_level_m(pack, spec, a->env_level_m, err);
        if (r != DM_OK) return r;
        for (int k = 0; k < spec->layers; ++k) a->env_levels[k] = layer(spec, k);
        a->env_level_count = spec->layers;
    }
    return texture(pack, env_entry(env, "background", name), &a->env_background, err);
}

static dm_result stretch(const dm_pack *pack, dm_render_assets *a, dm_error *err)
{
    const dm_pack_entry *st = dm_pack_find(pack, "stretch");
    if (!st) return DM_OK;
    assert(st->levels == 1 && st->layers >= 1 && st->layers <= DM_PROFILE_MAX_GAUSSIANS); /* one per Gaussian */
    for (int k = 0; k < st->layers; ++k) a->stretch[k] = layer(st, k);
    a->stretch_level_count = st->layers;
    dm_result r = texture(pack, "stretch.mask", &a->stretch_mask, err);
    if (r == DM_OK) r = texture(pack, "seam", &a->seam, err);
    if (r == DM_OK) r = texture(pack, "thin", &a->thin, err);
    if (r == DM_OK) r = texture(pack, "gather.index", &a->gather_index, err);
    if (r == DM_OK) r = texture(pack, "gather.taps", &a->gather_taps, err);
    if (r == DM_OK) r = texture(pack, "gather.half.index", &a->gather_half_index, err);
    if (r == DM_OK) r = texture(pack, "gather.half.taps", &a->gather_half_taps, err);
    return r == DM_OK ? texture(pack, "thin.half", &a->thin_half, err) : r;
}

static bool has_env(const dm_pack *pack, int env)
{
    char name[DM_PACK_NAME_SIZE];
    return dm_pack_find(pack, env_entry(env, "sh", name)) || dm_pack_find(pack, env_entry(env, "specular", name)) ||
           dm_pack_find(pack, env_entry(env, "background", name));
}

int dm_render_env_count(const dm_pack *pack)
{
    int n = 0;
    while (n <= DM_SCENE_MAX_ENV_ALTERNATIVES && has_env(pack, n)) ++n;
    return n;
}

char *dm_render_env_name(const dm_pack *pack, const dm_scene *scene, int env, char *out, size_t size)
{
    static const char *const what[] = {"sh", "specular", "background"};
    const char *path = env == 0 ? scene->environment
                       : env > 0 && env <= scene->env_alternative_count ? scene->env_alternatives[env - 1] : "";
    const char *slash = strrchr(path, '/');
    snprintf(out, size, "%s", slash ? slash + 1 : path);
    for (int k = 0; k < 3; ++k) {
        char name[DM_PACK_NAME_SIZE];
        const dm_pack_entry *e = dm_pack_find(pack, env_entry(env, what[k], name));
        dm_provenance p;
        dm_error ignored;
        if (!e || !e->provenance_json || dm_prov_from_json(&p, e->provenance_json, pack->what, &ignored) != DM_OK)
            continue;
        const dm_param *src = dm_prov_find(&p, "source");
        if (src && src->type == DM_PARAM_STRING && src->s[0]) {
            snprintf(out, size, "%s", src->s);
            break;
        }
    }
    return out;
}

dm_result dm_render_assets_from_pack(const dm_pack *pack, dm_scene *scene, dm_profile *profile,
                                     dm_render_assets *assets, dm_error *err)
{
    return dm_render_assets_from_pack_env(pack, 0, scene, profile, assets, err);
}

dm_result dm_render_assets_from_pack_env(const dm_pack *pack, int env, dm_scene *scene, dm_profile *profile,
                                         dm_render_assets *assets, dm_error *err)
{
    memset(assets, 0, sizeof *assets);
    if (env != 0 && (env < 0 || env >= dm_render_env_count(pack)))
        return dm_fail(err, DM_ERR_RANGE, "%s: environment %d, expected 0..%d (the pack holds %d)", pack->what, env,
                       dm_render_env_count(pack) - 1, dm_render_env_count(pack));
    dm_result r = dm_pack_scene(pack, scene, err);
    if (r != DM_OK) return r;
    *profile = scene->profile; /* the one route: the pack verified its "profile" entry agrees */
    assets->scene = scene;
    assets->profile = profile;
    if ((r = mesh(pack, assets, err)) != DM_OK) return r;
    if ((r = texture(pack, "albedo", &assets->albedo, err)) != DM_OK) return r;
    if ((r = texture(pack, "normal", &assets->normal_map, err)) != DM_OK) return r;
    if ((r = texture(pack, "specular", &assets->specular_map, err)) != DM_OK) return r;
    if ((r = texture(pack, "roughness", &assets->roughness_map, err)) != DM_OK) return r;
    if ((r = texture(pack, "lut.beckmann", &assets->beckmann, err)) != DM_OK) return r;
    if ((r = texture(pack, "lut.rho_dt", &assets->rho_dt, err)) != DM_OK) return r;
    if ((r = texture(pack, "lut.env_brdf", &assets->env_brdf, err)) != DM_OK) return r;
    if ((r = stretch(pack, assets, err)) != DM_OK) return r;
    const dm_pack_entry *k = dm_pack_find(pack, "sss.kernel");
    if (k) { /* screen-space kernels: taps x rows RGBA32F texels, t_range their sizes (core/dm_ssss_kernel.h) */
        assert(k->format == DM_TEX_RGBA32F && k->width >= 3 && k->width <= DM_SSSS_MAX_TAPS && k->height >= 1 &&
               k->height <= DM_SSSS_MAX_ROWS && (k->has_t_range || k->height == 1));
        assets->ss_kernel = (const float *)k->data;
        assets->ss_kernel_taps = k->width;
        assets->ss_kernel_rows = k->height;
        assets->ss_kernel_mm_per_px = k->has_t_range ? k->t_range : NULL;
    }
    if ((r = texture(pack, "sss.preintegrated", &assets->preintegrated, err)) != DM_OK) return r;
    if ((r = texture(pack, "sss.curvature", &assets->curvature, err)) != DM_OK) return r;
    const dm_pack_entry *pi = dm_pack_find(pack, "sss.preintegrated");
    if (pi) { /* its rows span curvature t_range[0] = 0 .. t_range[1] (1/mm) */
        assert(pi->has_t_range && pi->t_range[0] == 0.0f && pi->t_range[1] > 0.0f);
        assets->preint_curvature_max_per_mm = pi->t_range[1];
    }
    return environment(pack, env, assets, err);
}

const dm_texture *dm_render_assets_seam_map(const dm_render_assets *a, int n)
{
    return a->seam.texels && a->seam.width == n && a->seam.height == n ? &a->seam : NULL;
}

const dm_texture *dm_render_assets_gather(const dm_render_assets *a, int n, const dm_texture **taps)
{
    for (int h = 0; h < 2; ++h) {
        const dm_texture *i = h ? &a->gather_half_index : &a->gather_index, *t = h ? &a->gather_half_taps : &a->gather_taps;
        if (i->texels && t->texels && i->width == n && i->height == n) return *taps = t, i;
    }
    return *taps = NULL, NULL;
}

const dm_texture *dm_render_assets_thin_map(const dm_render_assets *a, int n)
{
    for (int h = 0; h < 2; ++h) {
        const dm_texture *t = h ? &a->thin_half : &a->thin;
        if (t->texels && t->width == n && t->height == 2 * n) return t;
    }
    return NULL;
}
