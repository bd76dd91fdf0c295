#include "core/dm_hash.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

#include <unistd.h>

#include <xxhash.h>

#include "core/dm_input.h"

uint64_t dm_hash64(const void *data, size_t size)
{
    return XXH3_64bits(data, size);
}

uint64_t dm_hash64_pair(const void *a, size_t a_size, const void *b, size_t b_size)
{
    XXH3_state_t *st = XXH3_createState(); /* a few hundred bytes; NULL only when out of memory */
    if (!st) return 0;                     /* then a checksum mismatch is reported */
    XXH3_64bits_reset(st);
    if (a_size) XXH3_64bits_update(st, a, a_size);
    if (b_size) XXH3_64bits_update(st, b, b_size);
    uint64_t h = XXH3_64bits_digest(st);
    XXH3_freeState(st);
    return h;
}

static void format128(XXH128_hash_t h, char out[DM_HASH_HEX_SIZE])
{
    snprintf(out, DM_HASH_HEX_SIZE, "xxh3-128:%016llx%016llx", (unsigned long long)h.high64,
             (unsigned long long)h.low64);
}

void dm_hash_hex(const void *data, size_t size, char out[DM_HASH_HEX_SIZE])
{
    format128(XXH3_128bits(data, size), out);
}

dm_result dm_hash_file_hex(const char *path, char out[DM_HASH_HEX_SIZE], dm_error *err)
{
    int fd;
    dm_result r = dm_input_open(path, DM_INPUT_ANY, &fd, NULL, err); /* a FIFO or /dev/zero would never end */
    if (r != DM_OK) return r;
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        close(fd);
        return dm_fail(err, DM_ERR_FILE_OPEN, "%s: %s", path, strerror(errno));
    }
    XXH3_state_t *st = XXH3_createState();
    if (!st) {
        fclose(f);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: cannot allocate hash state", path);
    }
    XXH3_128bits_reset(st);
    unsigned char buf[1 << 16];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) XXH3_128bits_update(st, buf, n);
    int bad = ferror(f);
    fclose(f);
    XXH128_hash_t h = XXH3_128bits_digest(st);
    XXH3_freeState(st);
    if (bad) return dm_fail(err, DM_ERR_FILE_READ, "%s: read error while hashing", path);
    format128(h, out);
    return DM_OK;
}
