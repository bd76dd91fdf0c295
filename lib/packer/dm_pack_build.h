/* dm_pack_build.h — a scene baked into a pack: the steps dermis-pack runs, each adding only
 * the entries the scene's effects need (pack/dm_pack_needs.h), into a pack writer
 * (pack/dm_pack_write.h). The tool is the pipeline: parse options → dm_pack_build_begin (the
 * scene, read once) → dm_pack_build_run → dm_pack_build_write → report. */
#ifndef DM_PACK_BUILD_H
#define DM_PACK_BUILD_H

#include <stdbool.h>
#include <stddef.h>

#include "mesh/dm_mesh.h"
#include "pack/dm_pack_write.h"
#include "core/dm_hash.h"
#include "core/dm_result.h"
#include "core/dm_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

#define DM_PACK_BUILD_TOOL "dermis-pack" /* the provenance's tool: what made the pack */

enum { DM_PACK_BUILD_ENV_FILES = 8, DM_PACK_BUILD_ROWS = 64 };

typedef struct dm_pack_build_options {
    const char *beckmann, *rho_dt, *env_brdf; /* LUT files to pack instead of baking; NULL = bake */
    const char *env_files[DM_PACK_BUILD_ENV_FILES]; /* baked environments to use (--env) */
    int env_file_count;
    const char *stretch_file; /* a baked stretch chain to pack instead of baking; NULL = bake */
    bool verbose, quiet;
    int beckmann_size, lut_size, lut_nodes, threads; /* 0 threads = all cores */
} dm_pack_build_options;

/* One entry added: its name, where it came from, its size and the step's time so far. */
typedef struct dm_pack_build_row {
    char entry[DM_PACK_NAME_SIZE];
    char source[160];
    size_t size;
    double ms;
} dm_pack_build_row;

typedef struct dm_pack_build {
    const dm_pack_build_options *opt;
    const char *scene_path;
    dm_scene scene;
    char scene_hash[DM_HASH_HEX_SIZE];
    dm_pack_writer w;
    dm_pack_build_row rows[DM_PACK_BUILD_ROWS];
    int row_count;
    double step_t0;
    bool env_file_used[DM_PACK_BUILD_ENV_FILES]; /* which env_files served a map */
    dm_mesh mesh;                               /* loaded once, for the mesh and stretch steps */
    bool mesh_loaded;
    char mesh_hash[DM_HASH_HEX_SIZE];
    bool input_failed; /* the failure of dm_pack_build_run was an input (the mesh, a map) that
                        * did not load, whatever its code: the tools' exit 2 */
    dm_scene_skin skin; /* the scene's physical skin as read (given: the profile was fitted to
                         * it here, and the scene then holds that profile inline) */
    char skin_spec[256]; /* its parameters as dermis-fit-profile --skin takes them, exact */
    double skin_total_rgb[3]; /* its colorimetric total diffuse reflectance, linear sRGB (with
                               * material.albedo_from "skin" the albedo step bakes it into the
                               * albedo entry, and the pack's scene says "map": the entry holds it) */
} dm_pack_build;

/* Reads the scene (relative paths searched in asset_dirs, core/dm_scene.h), hashes it, and
 * takes a glTF mesh's material maps where the scene names none (a note on stderr unless
 * quiet). b is zeroed first; free with dm_pack_build_free. */
dm_result dm_pack_build_begin(dm_pack_build *b, const char *scene_path, const char *const *asset_dirs, int asset_count,
                              const dm_pack_build_options *opt, dm_error *err);
/* Whether the scene needs the pack entry `entry`. */
bool dm_pack_build_wants(const dm_pack_build *b, const char *entry);
/* Runs every step one of whose entries applies, in pack order, with a progress bar on a
 * terminal; on failure *failed_step (when not NULL) names the step. */
dm_result dm_pack_build_run(dm_pack_build *b, const char **failed_step, dm_error *err);
/* Writes the pack to `path` (temporary name, renamed; read back and verified,
 * pack/dm_pack_write.h) with the pack's provenance: the scene, its hash and the options.
 * *written_size (when not NULL) gets the file's size. */
dm_result dm_pack_build_write(const dm_pack_build *b, const char *path, size_t *written_size, dm_error *err);
/* What a pack build holds at its peak, from the scene's sizes, before any work (bytes; N the
 * irradiance size, L the profile's Gaussians):
 *   base       DM_PACK_BUILD_MEMORY_BASE_SIZE: the libraries, the mesh, the decoded maps, the
 *              LUTs and the environment bakes at the bundled assets' sizes (1024² maps, two 1k
 *              HDRs), and the blobs they add; measured, not computed (larger maps add theirs)
 *   + the largest step that scales with N:
 *   stretch    N² (24 L + 6): the chain (s_u, s_v per level, float) and its mask as baked, the
 *              interleaved RG32F copy and R8 mask, and the writer's copy of both (texture space)
 *   curvature  N² x 16: the map, its mask, the writer's copy (pre-integrated)
 *   write      2 x the pack's N²-sized entries: the blobs and the file read back to verify
 * The pack file itself: about N² (8 L + 1) for the stretch chain, N² x 16 for the seam map,
 * N² x 40 for the thin-part maps at N and N/2 (texture space), N² x 16 and about N² x 160 for
 * the thin gather at N (up to DM_THIN_GATHER_TAPS_MAX taps of 8 bytes) and a quarter of that at
 * N/2, N² x 4 for the curvature,
 * and the rest (~27 MiB with the bundled assets). Measured against dermis-pack's peak RSS:
 * 0.9..1.1 from N = 512 to 4096 (docs/dermis-render.md, Memory). */
#define DM_PACK_BUILD_MEMORY_BASE_SIZE ((uint64_t)176 << 20)
typedef struct dm_pack_build_memory {
    uint64_t base_size, stretch_size, curvature_size, write_size, total_size;
    uint64_t pack_size; /* the file's N²-sized entries */
} dm_pack_build_memory;
void dm_pack_build_memory_estimate(const dm_pack_build *b, dm_pack_build_memory *out);
/* The estimate against the memory available (core/dm_memory.h): DM_ERR_OUT_OF_MEMORY naming
 * both and the scene key to lower when it does not fit. After dm_pack_build_begin. */
dm_result dm_pack_build_memory_check(const dm_pack_build *b, dm_error *err);
/* Prints, per pack entry, whether the scene needs it and which effect asks for it. */
void dm_pack_build_explain(const dm_scene *s);
void dm_pack_build_free(dm_pack_build *b);

#ifdef __cplusplus
}
#endif
#endif
