/* libFuzzer target: the bake side's EXR reader (lib/image/dm_exr.c, dm_exr_read through
 * OpenEXR's C API: the stretch chain and environment files dermis-pack takes) on arbitrary
 * bytes, given to it as an in-memory file (memfd). What it accepts has sane dimensions and
 * channel planes; what it refuses explains itself. */
#define _GNU_SOURCE /* memfd_create */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <unistd.h>

#include "image/dm_exr.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    int fd = memfd_create("fuzz.exr", 0);
    if (fd < 0) return 0;
    if (write(fd, data, size) != (ssize_t)size) {
        close(fd);
        return 0;
    }
    char path[64];
    snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
    dm_exr_image img;
    dm_error err = {0};
    if (dm_exr_read(path, &img, &err) == DM_OK) {
        if (img.width < 1 || img.height < 1 || img.channel_count < 1) abort();
        for (int c = 0; c < img.channel_count; ++c)
            if (!dm_exr_find(&img, img.names[c])) abort();
        dm_exr_free(&img);
    } else if (!err.detail[0]) {
        abort(); /* every failure explains itself */
    }
    close(fd);
    return 0;
}
