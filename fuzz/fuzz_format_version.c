/* libFuzzer target: dm_format_version_read (pack/dm_format_version.h) on arbitrary files.
 * Every input either reports a known format with the verdict its version implies and a
 * summary, or fails with a message; nothing reads outside its buffers (ASan). The function
 * takes a path, so each input is first written to one scratch file in the working folder
 * (build/fuzz when run by scripts/run-fuzz.sh), removed at exit. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "pack/dm_format_version.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char path[64];

static void remove_scratch(void)
{
    remove(path);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!path[0]) {
        snprintf(path, sizeof path, "fuzz_format_version.%d.input", (int)getpid());
        atexit(remove_scratch);
    }
    FILE *f = fopen(path, "wb");
    if (!f || (size && fwrite(data, 1, size, f) != size) || fclose(f) != 0) abort();
    dm_format_version v;
    dm_error err = {0};
    if (dm_format_version_read(path, &v, &err) == DM_OK) {
        if (!dm_format_name(v.kind) || v.verdict != dm_format_judge(v.version, v.reads) || !v.summary[0]) abort();
    } else if (!err.detail[0]) {
        abort(); /* every failure explains itself */
    }
    return 0;
}
