/* libFuzzer target: dermis-view's script reader (tools/view/dm_viewer_script.c,
 * dm_script_parse) on arbitrary bytes: what it accepts has known commands, argument counts
 * within bounds, finite numbers and non-decreasing times; what it refuses explains itself. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "dm_viewer_script.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    dm_script s;
    dm_error err = {0};
    if (dm_script_parse(text, "fuzz.txt", &s, &err) == DM_OK) {
        double last = 0;
        for (int i = 0; i < s.count; ++i) {
            const dm_script_event *e = &s.events[i];
            if (!(e->time_s >= last) || !isfinite(e->time_s) || e->arg_count < 0 || e->arg_count > DM_SCRIPT_MAX_ARGS ||
                !e->command[0])
                abort();
            last = e->time_s;
        }
        dm_script_free(&s);
    } else if (!err.detail[0]) {
        abort(); /* every failure explains itself */
    }
    free(text);
    return 0;
}
