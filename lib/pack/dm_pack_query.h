/* dm_pack_query.h — an opened pack (dm_pack) and what a caller asks of it: an entry by
 * name, a texture of one level and layer, an environment's roughness per layer, the mesh in
 * the dermis layout, the scene. Reads only what opening (pack/dm_pack.h) filled in; knows
 * nothing of how it was verified. */
#ifndef DM_PACK_QUERY_H
#define DM_PACK_QUERY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/dm_result.h"
#include "core/dm_scene.h"
#include "pack/dm_pack_format.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_pack {
    char what[1024];       /* the file name (or label) messages use */
    const uint8_t *base;   /* the whole file */
    size_t size;           /* bytes */
    bool mapped;           /* dm_pack_open mapped it; dm_pack_close unmaps */
    uint32_t version, flags;
    char *manifest;        /* NUL-terminated copy of the manifest */
    char *provenance_json; /* the packer's provenance, NUL-terminated */
    int entry_count;
    dm_pack_entry *entries; /* in manifest order */
    struct dm_scene *scene; /* the scene entry, parsed once while verifying (dm_pack_scene) */
    struct dm_profile *profile; /* the "profile" entry, parsed while verifying and checked
                                 * to hold the scene's Gaussians; renderers take the scene's */
} dm_pack;

/* The entry with that name, or NULL. */
const dm_pack_entry *dm_pack_find(const dm_pack *pack, const char *name);
/* The single-level, single-layer texture entry `name`: *out is the entry, or NULL when the
 * pack has none (DM_OK); DM_ERR_FORMAT, naming the entry, for any other shape. */
dm_result dm_pack_find_texture(const dm_pack *pack, const char *name, const dm_pack_entry **out, dm_error *err);
/* The Beckmann roughness of each layer of a prefiltered environment entry (env*.specular),
 * from its "layer_values": m receives e->layers values. DM_ERR_FORMAT when it has none
 * (a pack from before they were written: pack the scene again). */
dm_result dm_pack_env_level_m(const dm_pack *pack, const dm_pack_entry *e, float *m, dm_error *err);
/* The pack's mesh: its "mesh.vertices" and "mesh.indices" entries, the vertices in the
 * dermis layout (DM_PACK_VERTEX_STRIDE, position, normal, uv, tangent at their offsets)
 * and both counts within int32. DM_ERR_EMPTY without them, DM_ERR_FORMAT naming what the
 * layout lacks, DM_ERR_RANGE when too large. */
dm_result dm_pack_mesh(const dm_pack *pack, const dm_pack_entry **vertices, const dm_pack_entry **indices,
                       dm_error *err);
/* Parses the pack's "scene" entry. */
dm_result dm_pack_scene(const dm_pack *pack, dm_scene *scene, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
