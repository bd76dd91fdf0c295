/* dm_pass_glow.h — glow: bright pass at half resolution, a separable Gaussian (in GL, or on the
 * CPU where the texture-space blur would run there), added back onto the screen. Publishes
 * its result (f->glow_tex) for the tonemap, which adds it when the plan says so. */
#ifndef DM_PASS_GLOW_H
#define DM_PASS_GLOW_H

#include "render/frame/dm_frame_pass.h"

typedef struct dmr_glow {
    GLuint tex[2], fbo[2]; /* glow_a, glow_b */
    bool cpu;              /* the Gaussian on the CPU */
    float *buf[2];         /* its two half-resolution RGBA images */
} dmr_glow;

dm_result dmr_glow_targets(dmr_frame *f, void *st, dm_error *err);
void dmr_glow_free(dmr_frame *f, void *st);
bool dmr_glow_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_glow_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);

#endif
