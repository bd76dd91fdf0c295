/* libFuzzer target: the profile JSON reader (dm_profile_from_json) on arbitrary bytes.
 * Whatever it accepts must validate; every refusal explains itself. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_profile.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    dm_profile p;
    dm_error err = {0};
    if (dm_profile_from_json(text, "fuzz", &p, &err) == DM_OK) {
        if (dm_profile_validate(&p, "fuzz", &err) != DM_OK) abort(); /* accepted means valid */
        double rgb[3];
        dm_profile_eval(&p, 0.5, rgb);
    } else if (!err.detail[0]) {
        abort();
    }
    free(text);
    return 0;
}
