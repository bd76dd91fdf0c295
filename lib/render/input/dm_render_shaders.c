#include "render/input/dm_render_shaders.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_input.h"

/* Defined by the generated file (scripts/embed-shaders.sh). */
typedef struct dm_embedded_shader {
    const char *name;
    const char *source;
} dm_embedded_shader;
extern const dm_embedded_shader dm_embedded_shaders[];
extern const int dm_embedded_shader_count;

dm_result dm_render_shader_source(const char *dir, const char *name, char **out, dm_error *err)
{
    *out = NULL;
    if (dir) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", dir, name);
        size_t size = 0;
        return dm_input_read(path, DM_INPUT_SHADER, out, &size, err);
    }
    for (int i = 0; i < dm_embedded_shader_count; ++i)
        if (strcmp(dm_embedded_shaders[i].name, name) == 0) {
            size_t n = strlen(dm_embedded_shaders[i].source);
            *out = malloc(n + 1);
            if (!*out) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: cannot copy the embedded shader", name);
            memcpy(*out, dm_embedded_shaders[i].source, n + 1);
            return DM_OK;
        }
    return dm_fail(err, DM_ERR_INTERNAL, "%s: no such embedded shader (is it in shaders/?)", name);
}
