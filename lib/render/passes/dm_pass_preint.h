/* dm_pass_preint.h — the pre-integrated technique (Penner 2011): no pass of its own; checks and
 * uploads its table and curvature into the frame context (f->preint), which the binder binds
 * for the final pass. No state of its own. */
#ifndef DM_PASS_PREINT_H
#define DM_PASS_PREINT_H

#include "render/frame/dm_frame_pass.h"

dm_result dmr_preint_check(const dmr_frame *f, const dm_render_assets *a, dm_error *err);
dm_result dmr_preint_upload(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err);

#endif
