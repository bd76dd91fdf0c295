#include "bake/dm_pack_env.h"

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
    dm_env_bake bake;
    memset(&bake, 0, sizeof bake);
    if (lighting) {
        dm_env_options opt = {.threads = threads};
        r = dm_env_bake_run(&map, &opt, &bake, err);
    }
    if (r == DM_OK && lighting) {
        for (int k = 0; k < 9; ++k)
            for (int c = 0; c < 3; ++c) out->sh[k][c] = (float)bake.sh[k][c];
        base_prov(&out->sh_prov, tool, "radiance SH, order 2", hash, path);
        dm_prov_add_string(&out->sh_prov, "irradiance", "E(n) = sum A_l L_lm Y_lm(n), A = pi, 2pi/3, pi/4");
        const dm_env_level *top = &bake.levels[0];
        out->spec_width = top->width;
        out->spec_height = top->height;
        out->spec_layers = bake.level_count;
        size_t layer = (size_t)top->width * top->height * 4;
        out->spec_rgba = malloc(layer * (size_t)bake.level_count * sizeof(float));
        if (!out->spec_rgba) r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
        base_prov(&out->spec_prov, tool, "Beckmann-prefiltered radiance, one layer per m", hash, path);
        dm_prov_add_int(&out->spec_prov, "samples", bake.samples);
        for (int k = 0; k < bake.level_count && r == DM_OK; ++k) {
            const dm_env_level *lv = &bake.levels[k];
            float *dst = out->spec_rgba + layer * (size_t)k;
            for (int y = 0; y < top->height; ++y)
                for (int x = 0; x < top->width; ++x) {
                    float *px = dst + ((size_t)y * top->width + x) * 4;
                    if (lv->width == top->width)
                        memcpy(px, lv->rgb + ((size_t)y * lv->width + x) * 3, 3 * sizeof(float));
                    else
                        sample_rgb(lv->rgb, lv->width, lv->height, (x + 0.5) / top->width,
                                   (y + 0.5) / top->height, px);
                    px[3] = 1.0f;
                }
            char name[32];
            snprintf(name, sizeof name, "m%d", k);
            dm_prov_add_double(&out->spec_prov, name, lv->m);
            snprintf(name, sizeof name, "error_rms%d", k);
            dm_prov_add_double(&out->spec_prov, name, lv->error.texels ? lv->error.rms_rel : -1.0);
        }
    }
    if (r == DM_OK && background) {
        int w = map.width, h = map.height;
        float *rgb = malloc((size_t)w * h * 3 * sizeof(float));
        out->background_rgba = malloc((size_t)w * h * 4 * sizeof(float));
        if (!rgb || !out->background_rgba) {
            r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
        } else {
            dm_env_background(&map, w, 0.0, threads, rgb);
            for (size_t i = 0; i < (size_t)w * h; ++i) {
                memcpy(out->background_rgba + 4 * i, rgb + 3 * i, 3 * sizeof(float));
                out->background_rgba[4 * i + 3] = 1.0f;
            }
            out->background_width = w;
            out->background_height = h;
            base_prov(&out->background_prov, tool, "background radiance", hash, path);
        }
        free(rgb);
    }
    dm_env_bake_free(&bake);
    dm_envmap_free(&map);
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
