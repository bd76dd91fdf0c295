/* dm_hash.h — content hashes (xxHash XXH3, from Debian's libxxhash).
 * Used for input hashes in provenance and for the pack file's checksums. */
#ifndef DM_HASH_H
#define DM_HASH_H

#include <stddef.h>
#include <stdint.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_HASH_HEX_SIZE = 48 }; /* "xxh3-128:" + 32 hex digits + NUL fits */

/* 64-bit XXH3 of a buffer (size bytes; data may be NULL when size is 0). */
uint64_t dm_hash64(const void *data, size_t size);
/* 64-bit XXH3 of a followed by b, without joining them (either may be NULL when its size is 0). */
uint64_t dm_hash64_pair(const void *a, size_t a_size, const void *b, size_t b_size);
/* "xxh3-128:<32 hex>" of a buffer, into out (DM_HASH_HEX_SIZE bytes). */
void dm_hash_hex(const void *data, size_t size, char out[DM_HASH_HEX_SIZE]);
/* The same over a whole file, streamed; the file under the input rules (core/dm_input.h). */
dm_result dm_hash_file_hex(const char *path, char out[DM_HASH_HEX_SIZE], dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
