/* dm_env_bake.h — the whole environment bake of dermis-bake-env and its one output file.
 *
 *   dm_envmap map;   dm_envmap_load("sky.hdr", DM_ENVMAP_NEGATIVE_TOLERANCE_DEFAULT, &map, &err);
 *   dm_env_options opt = {0};                 // zero means defaults
 *   dm_env_bake bake;  dm_env_bake_run(&map, &opt, &bake, &err);
 *   dm_env_write("env.exr", &bake, &prov, &err);   dm_env_bake_free(&bake);
 *
 * Products (all of the map rotated by rotate_deg about +Y, core/dm_equirect.h):
 *   - sh: 9 RGB radiance coefficients, order 2 (bake/dm_env_sh.h; irradiance E(n) from
 *     core/dm_sh.h: A0 = π, A1 = 2π/3, A2 = π/4).
 *   - levels: prefiltered specular radiance for a few Beckmann roughnesses m, increasing,
 *     each at its own resolution (bake/dm_env_prefilter.h); the renderer computes
 *         specular ≈ P(R, m) · (F0 · scale + bias) · rho_s
 *     with scale/bias from the env-BRDF table (bake/dm_lut.h), P interpolated between the
 *     two levels bracketing m. Each level carries the error its sample count leaves.
 *   - background: the map itself at the viewer's resolution (box-filtered from the source
 *     pyramid when smaller, bilinear otherwise; an exact copy at the source size when the
 *     rotation is a whole number of texels).
 *
 * The output file: ONE scanline OpenEXR, channels R, G, B as 32-bit float, laid out as an
 * atlas of rectangles (rows bottom-up as everywhere in dermis; x = 0 for all):
 *   row 0                       the 9 SH coefficients, texel k = coefficient k (x 0..8)
 *   rows background_y …         the background, background_width × background_height
 *   rows level<k>_y …           level k, level<k>_width × level<k>_width/2
 * the rest zero. Every rectangle's place, each level's m and measured error, and every bake
 * parameter are typed provenance attributes (dm.level0_m, dm.level0_y, dm.level0_width,
 * dm.level0_error_rms, dm.level0_error_max, dm.background_y, …; image/dm_exr.h).
 * Why this shape: one file is one provenance, one input hash and one path for the pack;
 * the levels need different resolutions, which one EXR part can only hold as rectangles
 * (dm_exr writes one part; subsampled channels are poorly supported by readers); 32-bit
 * float because suns exceed half's 65504 (royal_esplanade reaches 49664, tests use 1e6);
 * the SH as 9 texels keeps them with the data they describe, exact to float, which is
 * what the GPU receives. dm_env_read takes the file apart again.
 */
#ifndef DM_ENV_BAKE_H
#define DM_ENV_BAKE_H

#include "bake/dm_env_prefilter.h"
#include "bake/dm_envmap.h"
#include "core/dm_prov.h"
#include "core/dm_result.h"
#include "core/dm_sh.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    DM_ENV_LEVEL_MAX = 6,
    DM_ENV_LEVELS_DEFAULT = 6,
    DM_ENV_SAMPLES_DEFAULT = 1024,
    DM_ENV_SPEC_SIZE_DEFAULT = 256, /* widest level */
    DM_ENV_CHECK_TEXELS_DEFAULT = 32,
    DM_ENV_BACKGROUND_MAX = 8192
};
#define DM_ENV_M_FIRST 0.1 /* default levels: m evenly spaced over [0.1, 1] */
#define DM_ENV_M_LAST 1.0

typedef struct dm_env_options {
    int samples;         /* per texel, 0 = DM_ENV_SAMPLES_DEFAULT; 1..DM_ENV_SAMPLES_MAX */
    int level_count;     /* 0 = DM_ENV_LEVELS_DEFAULT; used when roughness_count is 0 */
    int roughness_count; /* > 0: explicit m list below, strictly increasing */
    double roughness[DM_ENV_LEVEL_MAX];
    int spec_size;        /* widest level, 0 = DM_ENV_SPEC_SIZE_DEFAULT; 4..DM_ENVMAP_SIZE_MAX */
    int background_width; /* 0 = source width; 4..DM_ENV_BACKGROUND_MAX, even */
    double rotate_deg;    /* about +Y, any value */
    int check_texels;     /* texels per level compared with the reference; 0 = default, < 0 = none */
    int threads;          /* 0 = all cores */
    void (*progress)(void *ctx, double fraction); /* optional, called on the calling thread */
    void *progress_ctx;
} dm_env_options;

typedef struct dm_env_level {
    double m;
    int width, height; /* height = width / 2 */
    float *rgb;        /* width*height*3, bottom-up; owned */
    dm_env_error error; /* texels = 0 when not checked */
    double ms;
} dm_env_level;

typedef struct dm_env_bake {
    double sh[DM_SH9_COUNT][3];
    int samples;
    double rotate_deg;
    int level_count;
    dm_env_level levels[DM_ENV_LEVEL_MAX];
    int background_width, background_height;
    float *background; /* RGB, bottom-up; owned */
    double sh_ms, background_ms, prefilter_ms, check_ms;
} dm_env_bake;

/* The m of level k of `count` default levels (evenly spaced over [0.1, 1]). */
double dm_env_default_m(int k, int count);

/* Bakes everything. Fails on out-of-range options (DM_ERR_RANGE), lack of memory, or a
 * non-finite result (DM_ERR_NON_FINITE, an internal error). Free with dm_env_bake_free,
 * also after a failure. */
dm_result dm_env_bake_run(const dm_envmap *map, const dm_env_options *options, dm_env_bake *out, dm_error *err);
void dm_env_bake_free(dm_env_bake *bake);

/* The background alone: width × width/2 texels into caller-owned out_rgb. */
void dm_env_background(const dm_envmap *map, int width, double rotate_deg, int threads, float *out_rgb);

/* Writes the atlas file described above. prov holds the tool's parameters; this adds the
 * layout and per-level parameters (so prov needs DM_ENV_PROV_PARAMS free slots). */
enum { DM_ENV_PROV_PARAMS = 5 + 5 * DM_ENV_LEVEL_MAX };
dm_result dm_env_write(const char *path, const dm_env_bake *bake, const dm_provenance *prov, dm_error *err);

/* Reads a file written by dm_env_write back into a dm_env_bake (sh, background, levels
 * with m and recorded errors; timings 0). prov (may be NULL) receives the provenance. */
dm_result dm_env_read(const char *path, dm_env_bake *out, dm_provenance *prov, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
