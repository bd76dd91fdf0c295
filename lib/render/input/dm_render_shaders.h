/* dm_render_shaders.h — where lib/render gets its GLSL: the copies embedded at build time
 * (scripts/embed-shaders.sh → build/<config>/gen/dm_shaders_gen.c) or, for development,
 * shaders/<name> under a folder given at run time (dermis-render --shader-dir).
 * Internal to lib/render.
 */
#ifndef DM_RENDER_SHADERS_H
#define DM_RENDER_SHADERS_H

#include "core/dm_result.h"

/* The source of shader `name` ("final.glsl"), malloc'd and NUL-terminated: read from
 * dir/name when dir is not NULL, else the embedded copy. Free with free(). */
dm_result dm_render_shader_source(const char *dir, const char *name, char **out, dm_error *err);

#endif
