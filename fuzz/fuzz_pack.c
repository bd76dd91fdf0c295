/* libFuzzer target: the pack reader (dm_pack_open_memory) on arbitrary bytes.
 * When the first byte is odd, the header+manifest checksum is recomputed after the
 * mutation, so the fuzzer also reaches the manifest schema and layout checks behind it,
 * and every blob's checksum in the manifest is rewritten first to match the mutated blob,
 * so the content checks of every blob kind (finite floats, index ranges, the JSON blobs,
 * the needs of the scene) are reached as well (a valid pack's first byte, 0x89, is odd:
 * blob checksum failures themselves are covered by test_pack's every-bit-flip test). */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_hash.h"
#include "core/dm_pack.h"
#include "core/dm_pack_impl.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Rewrites each entry's "xxh3" in the manifest to the hash of the bytes it names. */
static void fix_blob_checksums(uint8_t *buf, size_t size, uint64_t msize)
{
    dm_pack scratch;
    memset(&scratch, 0, sizeof scratch);
    dm_error err = {0};
    if (dm_pack_manifest_parse(&scratch, buf + DM_PACK_HEADER_SIZE, msize, &err) == DM_OK) {
        char *m = (char *)buf + DM_PACK_HEADER_SIZE;
        for (int k = 0; k < scratch.entry_count; ++k) {
            const dm_pack_entry *e = &scratch.entries[k];
            if (e->offset > size || e->size > size - e->offset) continue;
            char old[17], now[17];
            dm_pack_hex64(e->xxh3, old);
            dm_pack_hex64(dm_hash64(buf + e->offset, (size_t)e->size), now);
            /* the first "xxh3" value equal to the old one, inside the manifest */
            for (uint64_t i = 0; i + 16 <= msize; ++i)
                if (!memcmp(m + i, old, 16)) {
                    memcpy(m + i, now, 16);
                    break;
                }
        }
    }
    dm_pack_close(&scratch);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    bool fix = data[0] & 1;
    uint8_t *buf = aligned_alloc(64, ((size + 63) / 64) * 64);
    if (!buf) return 0;
    memcpy(buf, data, size);
    if (fix && size >= DM_PACK_HEADER_SIZE) {
        uint64_t msize = 0;
        for (int k = 7; k >= 0; --k) msize = (msize << 8) | buf[32 + k];
        if (msize <= size - DM_PACK_HEADER_SIZE) fix_blob_checksums(buf, size, msize);
        if (msize <= size - DM_PACK_HEADER_SIZE) {
            uint64_t sum = dm_pack_header_checksum(buf, buf + DM_PACK_HEADER_SIZE, (size_t)msize);
            for (int k = 0; k < 8; ++k) buf[56 + k] = (uint8_t)(sum >> (8 * k));
        }
    }
    dm_pack pack;
    dm_error err = {0};
    if (dm_pack_open_memory(buf, size, "fuzz.dpk", &pack, &err) == DM_OK) {
        /* touch every blob the reader hands out */
        volatile uint8_t x = 0;
        for (int k = 0; k < pack.entry_count; ++k) {
            const dm_pack_entry *e = &pack.entries[k];
            if (e->size) x ^= ((const uint8_t *)e->data)[0] ^ ((const uint8_t *)e->data)[e->size - 1];
        }
        (void)x;
    } else if (!err.detail[0]) {
        abort();
    }
    dm_pack_close(&pack);
    free(buf);
    return 0;
}
