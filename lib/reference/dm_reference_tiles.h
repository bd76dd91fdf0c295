/* dm_reference_tiles.h — a farm's texture-space tiles back into one file.
 *
 * `dermis-reference --tile I/N` computes slice I of the covered texels (contiguous in row
 * order) and writes a full-size EXR whose A is 1 on that slice only, with provenance naming
 * tile_index, tile_count and the run's covered_texels. Every texel is computed on its own,
 * so the joined file equals the one-shot run's (tile 1/1) byte for byte. */
#ifndef DM_REFERENCE_TILES_H
#define DM_REFERENCE_TILES_H

#include <stdint.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Reads the count tiles (any order), checks that they are one run's (same provenance but for
 * tile_index, same size and channels, each index 1..N exactly once, N = count, the texels
 * they hold = covered_texels) and writes the joined EXR to out (temporary file + rename).
 * texels receives the texels joined. DM_ERR_FORMAT for a file that is no tile,
 * DM_ERR_MISMATCH for tiles that do not belong together, the EXR reader's and writer's
 * codes otherwise. */
dm_result dm_reference_merge_tiles(const char *const *paths, int count, const char *out, int64_t *texels,
                                   dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
