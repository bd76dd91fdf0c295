/* dm_pass_env.h — environment lighting: checks and uploads the prefiltered specular levels
 * and the env-BRDF LUT into the frame context (the binder binds them), and the background
 * pass, which owns the background texture. */
#ifndef DM_PASS_ENV_H
#define DM_PASS_ENV_H

#include "render/frame/dm_frame_pass.h"

typedef struct dmr_env {
    GLuint background;
} dmr_env;

dm_result dmr_env_check(const dmr_frame *f, const dm_render_assets *a, dm_error *err);
dm_result dmr_env_upload(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err);
bool dmr_background_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_background_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);

#endif
