/* dm_render_pack.h — the renderer's assets straight from an open pack.
 *
 * Every pointer in the assets points into the pack's mapping (nothing is copied), so the
 * pack must stay open while the assets, or a renderer being created from them, are used.
 * The scene and profile are parsed from the pack into caller-owned values. Entries that
 * the scene's effects do not need are simply absent from a pack and stay NULL here.
 *
 *   dm_pack pack; dm_scene scene; dm_profile profile; dm_render_assets assets;
 *   dm_pack_open("head.dpk", &pack, &err);
 *   dm_render_assets_from_pack(&pack, &scene, &profile, &assets, &err);
 *   dm_renderer_create(&assets, &desc, &renderer, &err);
 *   ...  dm_renderer_destroy(renderer); dm_pack_close(&pack);
 */
#ifndef DM_RENDER_PACK_H
#define DM_RENDER_PACK_H

#include "pack/dm_pack.h"
#include "core/dm_profile.h"
#include "core/dm_scene.h"
#include "render/dm_render.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fills scene, profile and assets (assets->scene = scene, assets->profile = profile).
 * Fails with DM_ERR_FORMAT when an entry has a shape the renderer cannot take (the
 * message names the entry), DM_ERR_EMPTY when the pack has no mesh. */
dm_result dm_render_assets_from_pack(const dm_pack *pack, dm_scene *scene, dm_profile *profile,
                                     dm_render_assets *assets, dm_error *err);

/* How many environments the pack holds: 1 + the scene's alternatives when it has env.*
 * entries (env<k>.* for k ≥ 1, dm_pack_needs.h), 0 when it has none. */
int dm_render_env_count(const dm_pack *pack);

/* The same as dm_render_assets_from_pack with environment `env` in [0, dm_render_env_count)
 * (0 = the main map, k = env<k>.*): the assets point at that environment's entries. Fails
 * with DM_ERR_RANGE for an index the pack does not hold. */
dm_result dm_render_assets_from_pack_env(const dm_pack *pack, int env, dm_scene *scene, dm_profile *profile,
                                         dm_render_assets *assets, dm_error *err);

/* The file name of environment `env`'s map ("venice_sunset_1k.hdr"), from its entries'
 * provenance source ("from NAME"), else from the scene's path; "" when unknown. Writes at
 * most size bytes into out and returns out. */
char *dm_render_env_name(const dm_pack *pack, const dm_scene *scene, int env, char *out, size_t size);

#ifdef __cplusplus
}
#endif
#endif
