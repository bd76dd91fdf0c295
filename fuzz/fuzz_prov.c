/* libFuzzer target: the provenance JSON reader (dm_prov_from_json) on arbitrary bytes.
 * Whatever it accepts must print and read back to the same provenance. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_prov.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    static dm_provenance p, q;
    static char json[1 << 16];
    dm_error err = {0};
    if (dm_prov_from_json(&p, text, "fuzz", &err) == DM_OK) {
        if (dm_prov_to_json(&p, json, sizeof json, &err) == DM_OK) {
            if (dm_prov_from_json(&q, json, "again", &err) != DM_OK) abort();
            if (strcmp(p.tool, q.tool) || p.param_count != q.param_count) abort();
        }
    } else if (!err.detail[0]) {
        abort();
    }
    free(text);
    return 0;
}
