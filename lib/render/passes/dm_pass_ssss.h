/* dm_pass_ssss.h — screen-space separable subsurface scattering (Jimenez et al. 2015): the
 * shade pass into three targets, a horizontal and a vertical blur. Publishes the kernel's
 * tap count (a program define) in the frame context. */
#ifndef DM_PASS_SSSS_H
#define DM_PASS_SSSS_H

#include "core/dm_ssss_kernel.h"
#include "render/frame/dm_frame_pass.h"

typedef struct dmr_ssss {
    float kernel[DM_SSSS_MAX_ROWS * DM_SSSS_MAX_TAPS][4]; /* row after row: rgb weight, a = offset px */
    float rows_per_octave, row0_log2_mm_per_px;           /* row coordinate = (log2 mm/px − row0) · that */
    GLuint diff_tex, aux_tex, spec_tex, fbo, tmp_tex, tmp_fbo;
} dmr_ssss;

dm_result dmr_ssss_check(const dmr_frame *f, const dm_render_assets *a, dm_error *err);
dm_result dmr_ssss_targets(dmr_frame *f, void *st, dm_error *err);
dm_result dmr_ssss_setup(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err);
bool dmr_ss_shade_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_ss_shade_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);
bool dmr_ss_blur_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_ss_blur_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);

#endif
