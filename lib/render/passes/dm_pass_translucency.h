/* dm_pass_translucency.h — light through thin parts: no pass of its own; makes the sampler
 * that reads the shadow maps' raw depths (f->tdepth_sampler), which the binder binds with the
 * transmittance's numbers for every shading pass. No state of its own. */
#ifndef DM_PASS_TRANSLUCENCY_H
#define DM_PASS_TRANSLUCENCY_H

#include "render/frame/dm_frame_pass.h"

dm_result dmr_translucency_check(const dmr_frame *f, const dm_render_assets *a, dm_error *err);
dm_result dmr_translucency_setup(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err);

#endif
