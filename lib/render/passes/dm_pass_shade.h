/* dm_pass_shade.h — the head on screen: the G-buffer pass, the final pass (deferred) and the
 * final pass while rasterising. Publishes the specular view's exposure gain (f->view_gain).
 * No state of its own: what they read is the frame's, bound by the binder. */
#ifndef DM_PASS_SHADE_H
#define DM_PASS_SHADE_H

#include "render/frame/dm_frame_pass.h"

bool dmr_gbuffer_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_gbuffer_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);
bool dmr_final_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_final_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);
void dmr_final_forward_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);
/* 1 (wireframe state) for the wireframe view, else 0. */
int dmr_final_forward_variant(const dmr_frame *f, const void *st);

#endif
