/* dm_pass_shadow.h — shadow maps: a depth map per casting light, published in the frame
 * context (shadow_tex) for the shading passes, translucency and the shadow view. */
#ifndef DM_PASS_SHADOW_H
#define DM_PASS_SHADOW_H

#include "render/frame/dm_frame_pass.h"

typedef struct dmr_shadow {
    GLuint fbo[DM_PLAN_MAX_SHADOWS];
} dmr_shadow;

dm_result dmr_shadow_targets(dmr_frame *f, void *st, dm_error *err);
bool dmr_shadow_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_shadow_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);

#endif
