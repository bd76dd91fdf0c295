/* dm_pack.h — the .dpk pack file: everything a renderer needs for one scene, GPU-ready,
 * verified on open, handed out without copying. The layout, the manifest and the entry
 * descriptor: pack/dm_pack_format.h; the opened pack and its queries (dm_pack_find ...):
 * pack/dm_pack_query.h. Both are included here.
 *
 * VERIFIED ON OPEN, in this order; the first failure is reported, naming the file, the
 * field or entry, the value and what was expected: header size, magic, version, flags,
 * file size, manifest bounds, header+manifest checksum, manifest schema (strict: unknown
 * keys refused), each entry's descriptor and its size against its format, bounds and
 * overlaps, zero padding, each blob's checksum, contents (finite floats, indices in range,
 * JSON blobs parse), that every entry the scene's effects need is there (dm_pack_needs.h),
 * and last every dermis entry's kind, format, shape and values in their physical ranges
 * (unit normals, mesh bounds, LUT, table and environment magnitudes, stretch, kernel,
 * t_range, layer_values: pack/dm_pack_semantic.h), over every value, nothing sampled.
 */
#ifndef DM_PACK_H
#define DM_PACK_H

#include <stddef.h>

#include "core/dm_result.h"
#include "pack/dm_pack_format.h"
#include "pack/dm_pack_query.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Maps the file read-only and verifies all of it (see VERIFIED ON OPEN). On success the
 * pack owns the mapping; entry data pointers stay valid until dm_pack_close. On failure
 * nothing is left open (dm_pack_close is still safe). */
dm_result dm_pack_open(const char *path, dm_pack *pack, dm_error *err);
/* The same over bytes in memory, which are not copied: the caller keeps them alive and
 * unchanged until dm_pack_close. `what` names them in messages. data must be 16-byte
 * aligned (malloc's is), so that blobs are aligned for their element types. */
dm_result dm_pack_open_memory(const void *data, size_t size, const char *what, dm_pack *pack, dm_error *err);
void dm_pack_close(dm_pack *pack);

#ifdef __cplusplus
}
#endif
#endif
