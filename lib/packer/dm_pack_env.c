#include "packer/dm_pack_env.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_env_bake.h"
#include "bake/dm_envmap.h"
#include "core/dm_cli.h"
#include "core/dm_hash.h"

/* Bilinear lookup of an RGB equirect image at texel-centre coordinates, wrapping in u. */
static void sample_rgb(const float *rgb, int w, int h, double u, double v, float out[3])
{
    double x = u * w - 0.5, y = v * h - 0.5;
    if (y < 0) y = 0;
    if (y > h - 1) y = h - 1;
    int x0 = (int)floor(x), y0 = (int)y;
    double fx = x - x0, fy = y - y0;
    int y1 = y0 + 1 < h ? y0 + 1 : y0;
    int xa = ((x0 % w) + w) % w, xb = (xa + 1) % w;
    for (int c = 0; c < 3; ++c) {
        double a = rgb[((size_t)y0 * w + xa) * 3 + c] * (1 - fx) + rgb[((size_t)y0 * w + xb) * 3 + c] * fx;
        double b = rgb[((size_t)y1 * w + xa) * 3 + c] * (1 - fx) + rgb[((size_t)y1 * w + xb) * 3 + c] * fx;
        out[c] = (float)(a * (1 - fy) + b * fy);
    }
}

/* source: the map's file name (no folder, so packs do not depend on where they were made). */
static void base_prov(dm_provenance *p, const char *tool, const char *what, const char *hash, const char *path)
{
    dm_prov_init(p, tool);
    snprintf(p->input_hash, sizeof p->input_hash, "%s", hash);
    dm_prov_add_string(p, "product", what);
    const char *slash = strrchr(path, '/');
    dm_prov_add_string(p, "source", slash ? slash + 1 : path);
}

/* SH and the layered specular levels of a bake, as pack data. */
static dm_result lighting_from_bake(const dm_env_bake *bake, const char *tool, const char *hash, const char *path,
                                    dm_pack_env *out, dm_error *err)
{
    if (bake->level_count < 1 || bake->level_count > DM_PACK_LAYER_VALUES_MAX)
        return dm_fail(err, DM_ERR_FORMAT, "%s: %d prefiltered specular levels, expected 1..%d", path,
                       bake->level_count, DM_PACK_LAYER_VALUES_MAX);
    for (int k = 0; k < 9; ++k)
        for (int c = 0; c < 3; ++c) out->sh[k][c] = (float)bake->sh[k][c];
    base_prov(&out->sh_prov, tool, "radiance SH, order 2", hash, path);
    dm_prov_add_string(&out->sh_prov, "irradiance", "E(n) = sum A_l L_lm Y_lm(n), A = pi, 2pi/3, pi/4");
    const dm_env_level *top = &bake->levels[0];
    out->spec_width = top->width;
    out->spec_height = top->height;
    out->spec_layers = bake->level_count;
    size_t layer = (size_t)top->width * top->height * 4;
    out->spec_rgba = malloc(layer * (size_t)bake->level_count * sizeof(float));
    if (!out->spec_rgba) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    base_prov(&out->spec_prov, tool, "Beckmann-prefiltered radiance, one layer per m", hash, path);
    dm_prov_add_int(&out->spec_prov, "samples", bake->samples);
    for (int k = 0; k < bake->level_count; ++k) {
        const dm_env_level *lv = &bake->levels[k];
        float *dst = out->spec_rgba + layer * (size_t)k;
        for (int y = 0; y < top->height; ++y)
            for (int x = 0; x < top->width; ++x) {
                float *px = dst + ((size_t)y * top->width + x) * 4;
                if (lv->width == top->width)
                    memcpy(px, lv->rgb + ((size_t)y * lv->width + x) * 3, 3 * sizeof(float));
                else
                    sample_rgb(lv->rgb, lv->width, lv->height, (x + 0.5) / top->width, (y + 0.5) / top->height,
                               px);
                px[3] = 1.0f;
            }
        out->spec_m[k] = (float)lv->m;
        char name[32];
        snprintf(name, sizeof name, "m%d", k);
        dm_prov_add_double(&out->spec_prov, name, lv->m);
        snprintf(name, sizeof name, "error_rms%d", k);
        dm_prov_add_double(&out->spec_prov, name, lv->error.texels ? lv->error.rms_rel : -1.0);
    }
    return DM_OK;
}

/* An RGB background as RGBA pack data. */
static dm_result background_from_rgb(const float *rgb, int w, int h, const char *tool, const char *hash,
                                     const char *path, dm_pack_env *out, dm_error *err)
{
    out->background_rgba = malloc((size_t)w * h * 4 * sizeof(float));
    if (!out->background_rgba) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    for (size_t i = 0; i < (size_t)w * h; ++i) {
        memcpy(out->background_rgba + 4 * i, rgb + 3 * i, 3 * sizeof(float));
        out->background_rgba[4 * i + 3] = 1.0f;
    }
    out->background_width = w;
    out->background_height = h;
    base_prov(&out->background_prov, tool, "background radiance", hash, path);
    return DM_OK;
}

dm_result dm_pack_env_bake(const char *path, bool lighting, bool background, const char *tool, int threads,
                           dm_pack_env *out, dm_error *err)
{
    memset(out, 0, sizeof *out);
    double t0 = dm_now_ms();
    char hash[DM_HASH_HEX_SIZE];
    dm_result r = dm_hash_file_hex(path, hash, err);
    if (r != DM_OK) return r;
    dm_envmap map;
    r = dm_envmap_load(path, DM_ENVMAP_NEGATIVE_TOLERANCE_DEFAULT, &map, err);
    if (r != DM_OK) return r;
    if (lighting) {
        dm_env_bake bake;
        memset(&bake, 0, sizeof bake);
        dm_env_options opt = {.threads = threads};
        r = dm_env_bake_run(&map, &opt, &bake, err);
        if (r == DM_OK) r = lighting_from_bake(&bake, tool, hash, path, out, err);
        dm_env_bake_free(&bake);
    }
    if (r == DM_OK && background) {
        float *rgb = malloc((size_t)map.width * map.height * 3 * sizeof(float));
        if (!rgb) {
            r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
        } else {
            dm_env_background(&map, map.width, 0.0, threads, rgb);
            r = background_from_rgb(rgb, map.width, map.height, tool, hash, path, out, err);
        }
        free(rgb);
    }
    dm_envmap_free(&map);
    out->bake_ms = dm_now_ms() - t0;
    return r;
}

dm_result dm_pack_env_from_file(const char *file, const char *path, bool lighting, bool background, const char *tool,
                                dm_pack_env *out, bool *same_map, dm_error *err)
{
    memset(out, 0, sizeof *out);
    *same_map = false;
    double t0 = dm_now_ms();
    char hash[DM_HASH_HEX_SIZE];
    dm_result r = dm_hash_file_hex(path, hash, err);
    if (r != DM_OK) return r;
    dm_env_bake bake;
    dm_provenance prov;
    r = dm_env_read(file, &bake, &prov, err);
    if (r != DM_OK) return r;
    if (strcmp(prov.input_hash, hash) != 0) {
        r = dm_fail(err, DM_ERR_MISMATCH, "%s: baked from a map with hash %s, %s has %s", file,
                    prov.input_hash[0] ? prov.input_hash : "(none)", path, hash);
    } else {
        *same_map = true;
        if (bake.rotate_deg != 0.0)
            r = dm_fail(err, DM_ERR_MISMATCH,
                        "%s: baked with --rotate %g, expected 0 (packs hold the map unrotated; the scene's "
                        "rotation_deg turns it at run time)",
                        file, bake.rotate_deg);
        else if (background && !bake.background)
            r = dm_fail(err, DM_ERR_MISMATCH, "%s: holds no background, the scene shows one", file);
    }
    if (r == DM_OK && lighting) r = lighting_from_bake(&bake, tool, hash, path, out, err);
    if (r == DM_OK && background)
        r = background_from_rgb(bake.background, bake.background_width, bake.background_height, tool, hash, path,
                                out, err);
    if (r == DM_OK && lighting) {
        dm_prov_add_string(&out->sh_prov, "baked_file", file);
        dm_prov_add_string(&out->spec_prov, "baked_file", file);
    }
    if (r == DM_OK && background) dm_prov_add_string(&out->background_prov, "baked_file", file);
    dm_env_bake_free(&bake);
    out->bake_ms = dm_now_ms() - t0;
    return r;
}

void dm_pack_env_free(dm_pack_env *env)
{
    if (!env) return;
    free(env->spec_rgba);
    free(env->background_rgba);
    memset(env, 0, sizeof *env);
}
