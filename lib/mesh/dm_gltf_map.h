/* dm_gltf_map.h — the texture maps a glTF 2.0 file's material gives (baseColor, normal),
 * for scenes whose mesh is a .gltf/.glb and that name no maps of their own.
 *
 * The material is the one of the first triangle primitive of the meshes dm_mesh_load
 * reads from the file (same scene traversal, same mesh_name filter). Its texture's image
 * is an external file (the URI %XX-decoded, then resolved inside the glTF file's folder:
 * core/dm_uri.h) or
 * embedded (a GLB buffer view or a data URI): external files are read where they are,
 * embedded bytes through a temporary file (in $TMPDIR, removed before returning), both
 * with dm_image_read. Like the mesh, the glTF file is parsed in a child process
 * (dm_isolate.h): a malformed file is an error, never a crash. glTF's texture images are
 * top-down like every image file; dm_image_read's rows come bottom-up, matching the
 * v flip of TEXCOORD_0. KHR_texture_transform and texCoord ≠ 0 are not applied.
 */
#ifndef DM_GLTF_MAP_H
#define DM_GLTF_MAP_H

#include <stddef.h>

#include "image/dm_image.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum dm_gltf_map {
    DM_GLTF_MAP_BASE_COLOR, /* pbrMetallicRoughness.baseColorTexture (sRGB) */
    DM_GLTF_MAP_NORMAL      /* normalTexture (tangent space, +y up like dermis) */
} dm_gltf_map;

/* 1 when path names a glTF file (.gltf or .glb, any case). */
int dm_gltf_is_file(const char *path);

/* Looks the map up: *found = 1 when the material has that texture (with an image),
 * 0 when not (no material, no texture: not an error). source (may be NULL, size
 * source_size) receives a description: "images[N] \"uri\"" or "images[N] (image/png,
 * embedded)". Fails like dm_mesh_load on a malformed file, DM_ERR_FORMAT on a texture
 * or image index out of range. mesh_name may be NULL. */
dm_result dm_gltf_map_find(const char *path, const char *mesh_name, dm_gltf_map which, int *found, char *source,
                           size_t source_size, dm_error *err);

/* Reads the map's image (dm_image_read's contract: `type`, rows bottom-up). A material
 * without that texture is DM_ERR_EMPTY. Free out with dm_image_free, also after a
 * failure. source as for dm_gltf_map_find. */
dm_result dm_gltf_map_read(const char *path, const char *mesh_name, dm_gltf_map which, dm_pixel_type type,
                           dm_image *out, char *source, size_t source_size, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
