/* libFuzzer target: the scene parser (dm_scene_parse) on arbitrary bytes.
 * Paths resolve under a folder that does not exist, so no input reaches real files. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    static dm_scene scene;
    dm_error err = {0};
    if (dm_scene_parse(text, "/nonexistent-dermis-fuzz/scene.json", &scene, &err) == DM_OK) {
        char *json = NULL; /* what parses must print and parse again */
        if (dm_scene_to_json(&scene, &json, &err) == DM_OK) {
            static dm_scene again;
            if (dm_scene_parse(json, "/nonexistent-dermis-fuzz/scene.json", &again, &err) != DM_OK) abort();
        }
        free(json);
    } else if (!err.detail[0]) {
        abort(); /* every failure explains itself */
    }
    free(text);
    return 0;
}
