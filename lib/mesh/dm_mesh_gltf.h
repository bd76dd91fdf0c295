/* dm_mesh_gltf.h — internal: the glTF 2.0 reader behind dm_mesh_load (dm_mesh.h says
 * what it reads and refuses) and the glTF material maps (dm_gltf_map.h). */
#ifndef DM_MESH_GLTF_H
#define DM_MESH_GLTF_H

#include "mesh/dm_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 1 when path ends in .gltf or .glb (any case). */
int dm_mesh_is_gltf(const char *path);

/* Reads a .gltf/.glb into out in this process, with tinygltf (dm_mesh_load runs it in a
 * child process unless in_process). out->normals are filled only when normals_from_file;
 * dm_mesh_load finishes (finite checks, computed normals). */
dm_result dm_mesh_read_gltf(const char *path, const dm_mesh_load_options *o, dm_mesh *out, dm_error *err);

#ifdef __cplusplus
}

#include <vector>

namespace tinygltf {
class Model;
}
namespace dm_gltf {
/* Loads the file (GLB header checked first: magic, version 2, length = file size).
 * keep_images: image bytes kept as they are in the file (Image::image, as_is), else
 * dropped. Fails with DM_ERR_FORMAT naming the file and tinygltf's reason. */
dm_result load(const char *path, bool keep_images, tinygltf::Model *model, dm_error *err);

/* A mesh placed in the scene, with its world matrix (column-major, glTF's). */
struct instance {
    int mesh;
    double m[16];
};
/* The meshes the default scene (else scene 0) places, depth first in node order; every
 * mesh once, identity, when the file has no scene. mesh_name (NULL/"": all) filters by
 * name (DM_ERR_MISMATCH listing the names when none matches). Node cycles, indices out
 * of range and malformed transforms are DM_ERR_FORMAT. */
dm_result instances(const char *path, const tinygltf::Model &model, const char *mesh_name,
                    std::vector<instance> *out, dm_error *err);
} // namespace dm_gltf
#endif
#endif
