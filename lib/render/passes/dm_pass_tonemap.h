/* dm_pass_tonemap.h — tonemap: exposure, the filmic curve and sRGB into the 8-bit display
 * target, adding the glow (f->glow_tex) when the plan puts it there. */
#ifndef DM_PASS_TONEMAP_H
#define DM_PASS_TONEMAP_H

#include "render/frame/dm_frame_pass.h"

typedef struct dmr_tonemap {
    GLuint display_tex, display_fbo; /* read by dm_renderer_read_display and blit_display */
} dmr_tonemap;

dm_result dmr_tonemap_targets(dmr_frame *f, void *st, dm_error *err);
bool dmr_tonemap_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
/* 0: only the head's pixels run (state 0 clears and tests depth), 1: every pixel. */
int dmr_tonemap_variant(const dmr_frame *f, const void *st);
void dmr_tonemap_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);

#endif
