/* dm_pack_impl.h — internals shared by the pack reader's files (dm_pack.c: open, close,
 * find; dm_pack_format.c: kinds, formats, header, sizes; dm_pack_manifest.c: the strict
 * manifest reader; dm_pack_verify.c: VERIFIED ON OPEN). Not a public API. */
#ifndef DM_PACK_IMPL_H
#define DM_PACK_IMPL_H

#include <stdint.h>

#include "pack/dm_pack.h"

static inline uint32_t get32(const uint8_t *p)
{
    uint32_t v = 0;
    for (int k = 3; k >= 0; --k) v = (v << 8) | p[k];
    return v;
}
static inline uint64_t get64(const uint8_t *p)
{
    uint64_t v = 0;
    for (int k = 7; k >= 0; --k) v = (v << 8) | p[k];
    return v;
}

/* Texels along one side at mip level `level` (at least 1). */
static inline uint64_t level_dim(int size, int level)
{
    uint64_t d = (uint64_t)size >> level;
    return d ? d : 1;
}

/* Copies the manifest (size bytes) into pack->manifest and parses it strictly into
 * pack->provenance_json and pack->entries (descriptors only: data pointers, bounds and
 * checksums are dm_pack_verify's). Messages name the JSON path, the value, the expectation. */
dm_result dm_pack_manifest_parse(dm_pack *pack, const uint8_t *bytes, uint64_t size, dm_error *err);

/* Everything of VERIFIED ON OPEN (dm_pack.h) over pack->base / pack->size. */
dm_result dm_pack_verify(dm_pack *pack, dm_error *err);

#endif
