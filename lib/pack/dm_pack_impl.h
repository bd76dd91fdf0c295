/* dm_pack_impl.h — internals of the pack reader, one way down: dm_pack.c (open, close)
 * calls dm_pack_verify.c (VERIFIED ON OPEN), which calls dm_pack_manifest.c (the strict
 * manifest reader), dm_pack_semantic.c and the queries (dm_pack_query.c), all of them over
 * the format (dm_pack_format.c). Not a public API. */
#ifndef DM_PACK_IMPL_H
#define DM_PACK_IMPL_H

#include <stdint.h>

#include "pack/dm_pack_query.h"

/* Copies the manifest (size bytes) into pack->manifest and parses it strictly into
 * pack->provenance_json and pack->entries (descriptors only: data pointers, bounds and
 * checksums are dm_pack_verify's). Messages name the JSON path, the value, the expectation. */
dm_result dm_pack_manifest_parse(dm_pack *pack, const uint8_t *bytes, uint64_t size, dm_error *err);

/* Everything of VERIFIED ON OPEN (dm_pack.h) over pack->base / pack->size. */
dm_result dm_pack_verify(dm_pack *pack, dm_error *err);

#endif
