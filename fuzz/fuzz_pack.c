/* libFuzzer target: the pack reader (dm_pack_open_memory) on arbitrary bytes.
 * When the first byte is odd, the header+manifest checksum is recomputed after the
 * mutation, so the fuzzer also reaches the manifest schema and layout checks behind it. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_pack.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

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
