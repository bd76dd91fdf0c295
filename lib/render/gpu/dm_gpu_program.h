/* dm_gpu_program.h — GLSL 330 programs from source: both stages from one pass file after a
 * shared file, with the caller's defines; attribute locations bound by name. */
#ifndef DM_GPU_PROGRAM_H
#define DM_GPU_PROGRAM_H

#include "render/gpu/dm_gpu.h"

/* Compiles `src` (named `name` in messages) twice, after "#version 330 core", DM_VERTEX or
 * DM_FRAGMENT, `defines` and `common` ("#line" directives keep messages in each file's
 * numbering: source 1 = common, 2 = the pass), and links them with attribute i at location
 * attribs[i] (attrib_count of them). The program is recorded in g; the shaders are freed. */
dm_result dmg_program(dmg *g, const char *name, const char *defines, const char *common, const char *src,
                      const char *const *attribs, int attrib_count, GLuint *out, dm_error *err);

#endif
