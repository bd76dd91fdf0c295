/* dm_pack_env.h — the environment entries of a pack, GPU-ready, from an HDR map.
 *
 *   env.sh          9 RGB float radiance SH coefficients (order 2, the order of core/dm_sh.h);
 *                   the renderer evaluates irradiance with A0 = π, A1 = 2π/3, A2 = π/4.
 *   env.specular    RGBA32F, one layer per prefiltered Beckmann roughness, every layer at
 *                   the sharpest level's size (coarser levels resampled bilinearly, wrapping
 *                   in u); layer k's m is provenance parameter "m<k>", its measured error
 *                   "error_rms<k>".
 *   env.background  RGBA32F equirect radiance at the source's width.
 * Float32 because HDR suns exceed half's 65504. All unrotated: the renderer turns the
 * environment by the scene's rotation at run time (the viewer turns it live). Alpha = 1.
 * Each provenance names the map's file name (no folder) as string parameter "source".
 */
#ifndef DM_PACK_ENV_H
#define DM_PACK_ENV_H

#include <stdbool.h>

#include "core/dm_prov.h"
#include "pack/dm_pack.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_pack_env {
    float sh[9][3];
    dm_provenance sh_prov;
    int spec_width, spec_height, spec_layers;
    float *spec_rgba; /* spec_layers × spec_height × spec_width × 4, bottom-up; owned */
    float spec_m[DM_PACK_LAYER_VALUES_MAX]; /* the Beckmann m of each layer */
    dm_provenance spec_prov;
    int background_width, background_height;
    float *background_rgba; /* owned; NULL when not asked for */
    dm_provenance background_prov;
    double bake_ms;
} dm_pack_env;

/* Loads `path` and bakes what is asked: lighting (SH + specular levels) and/or the
 * background. tool names the provenance. Free with dm_pack_env_free, also after failure. */
dm_result dm_pack_env_bake(const char *path, bool lighting, bool background, const char *tool, int threads,
                           dm_pack_env *out, dm_error *err);
/* The same from a file written by dermis-bake-env (bake/dm_env_bake.h) instead of baking:
 * the file's provenance must name `path`'s content hash (else DM_ERR_MISMATCH with
 * *same_map false: try another file), and then be unrotated and hold a background when one
 * is asked for (else DM_ERR_MISMATCH with *same_map true: the file is for this map but
 * unusable). */
dm_result dm_pack_env_from_file(const char *file, const char *path, bool lighting, bool background, const char *tool,
                                dm_pack_env *out, bool *same_map, dm_error *err);
void dm_pack_env_free(dm_pack_env *env);

#ifdef __cplusplus
}
#endif
#endif
