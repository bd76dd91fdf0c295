/* dm_pack.c — opening a pack (map, verify: dm_pack_verify.c) and closing it; the queries
 * over an opened pack are dm_pack_query.c. */
#include "pack/dm_pack.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include "core/dm_input.h"

#include "pack/dm_pack_impl.h"

dm_result dm_pack_open_memory(const void *data, size_t size, const char *what, dm_pack *pack, dm_error *err)
{
    memset(pack, 0, sizeof *pack);
    snprintf(pack->what, sizeof pack->what, "%s", what ? what : "(pack)");
    if ((uintptr_t)data % 16)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: pack bytes at an address that is not 16-byte aligned",
                       pack->what);
    pack->base = data;
    pack->size = size;
    dm_result r = dm_pack_verify(pack, err);
    if (r != DM_OK) dm_pack_close(pack);
    return r;
}

dm_result dm_pack_open(const char *path, dm_pack *pack, dm_error *err)
{
    memset(pack, 0, sizeof *pack);
    int fd;
    uint64_t file_size;
    dm_result r = dm_input_open(path, DM_INPUT_PACK, &fd, &file_size, err);
    if (r != DM_OK) return r;
    size_t size = (size_t)file_size;
    if (size == 0) {
        close(fd);
        return dm_fail(err, DM_ERR_FORMAT, "%s: the file is empty (0 bytes), expected a dermis pack", path);
    }
    void *m = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
    if (m == MAP_FAILED) {
        int e = errno;
        close(fd);
        return dm_fail(err, DM_ERR_FILE_READ, "%s: cannot map (%s)", path, strerror(e));
    }
    close(fd);
    r = dm_pack_open_memory(m, size, path, pack, err);
    if (r != DM_OK) {
        munmap(m, size);
        return r;
    }
    pack->mapped = true;
    return DM_OK;
}

void dm_pack_close(dm_pack *pack)
{
    if (!pack) return;
    for (int k = 0; k < pack->entry_count; ++k) free(pack->entries[k].provenance_json);
    free(pack->entries);
    free(pack->manifest);
    free(pack->scene);
    pack->scene = NULL;
    free(pack->profile);
    pack->profile = NULL;
    free(pack->provenance_json);
    if (pack->mapped) munmap((void *)(uintptr_t)pack->base, pack->size);
    pack->entries = NULL;
    pack->manifest = NULL;
    pack->provenance_json = NULL;
    pack->entry_count = 0;
    pack->mapped = false;
    pack->base = NULL;
    pack->size = 0;
}
