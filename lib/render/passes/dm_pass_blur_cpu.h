/* dm_pass_blur_cpu.h — the texture-space blurs on the CPU, where OpenGL itself runs on the
 * CPU: the blur_u/blur_v rows taken when f->blur_cpu, and a diffusion row that uploads the sum
 * they made. Reads the levels the GPU passes publish (level_tex/fbo, diff_tex) and publishes
 * the levels' sync (f->levels) for whoever reads a level whose upload it deferred. */
#ifndef DM_PASS_BLUR_CPU_H
#define DM_PASS_BLUR_CPU_H

#include "core/dm_level_sum.h"
#include "render/frame/dm_frame_pass.h"

typedef struct dmr_blur_cpu {
    float *buf[3];                           /* padded level images (core/dm_level_blur.h) */
    float *step[DM_PROFILE_MAX_GAUSSIANS][2]; /* level k's stretch per texel: U, V pass */
    float *level, *tmp;                      /* texel (0, 0) of level `held`, of U's result */
    int held, tmp_level;                     /* −1: none */
    float *sum;    /* the diffusion pass's sum, level by level (full-resolution levels) */
    int sum_level; /* the last level added to it; −1: none this frame */
    dm_level_sum_thin thin; /* the thin-part map's candidates, when the GL pass has it (f->tex_thin) */
    dm_level_sum_gather gather; /* the thin gather, with the thin-part map at this size (mean[0] set) */
    bool syncing;  /* the sync is running the chain */
    bool summing;  /* this frame's chain feeds the sum, and no pass reads the levels in GL:
                    * their uploads wait until something does (f->levels) */
} dmr_blur_cpu;

/* Decides where the blur runs (desc.blur_path, the GL renderer, the level format) and, on the
 * CPU, allocates its buffers and samples the stretch per texel. After the targets. */
dm_result dmr_blur_cpu_setup(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err);
void dmr_blur_cpu_free(dmr_frame *f, void *st);
bool dmr_blur_cpu_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_blur_cpu_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);
/* The diffusion pass from the sum the chain made: taken when it holds every level. */
bool dmr_blur_cpu_sum_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_blur_cpu_sum_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);

#endif
