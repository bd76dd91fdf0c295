/* dm_pass_tsd.h — texture-space diffusion's passes on the GPU: the surface G-buffer in the
 * atlas, the irradiance pass, the stretch-corrected blurs. Publishes in the frame context the
 * stretch chain, the seam map, the levels (level_tex/fbo: irradiance, blurK) and the diffusion sum's target. */
#ifndef DM_PASS_TSD_H
#define DM_PASS_TSD_H

#include "render/frame/dm_frame_pass.h"

typedef struct dmr_tsd {
    /* level k's U pass target (shared between levels of one size) */
    GLuint tmp_tex[DM_PROFILE_MAX_GAUSSIANS], tmp_fbo[DM_PROFILE_MAX_GAUSSIANS];
    GLuint gbuf_tex[4], gbuf_fbo, depth; /* the texture-space G-buffer and its coverage depth */
    bool gbuf_valid;                     /* made for the current scene (cleared by set_scene) */
    GLuint seam_mark;                    /* seam_mark.glsl's program (with a seam map) */
    GLuint seam_points;                  /* seam_points.glsl's program (with a seam map) */
} dmr_tsd;

dm_result dmr_tsd_check(const dmr_frame *f, const dm_render_assets *a, dm_error *err);
/* Whether the renderer uses the pack's thin-part map: texture-space, the levels summed per
 * texel (f->diffusion_sum), the map baked at this irradiance size. */
bool dmr_tsd_thin_usable(const dmr_frame *f, const dm_render_assets *a);
dm_result dmr_tsd_upload(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err);
dm_result dmr_tsd_targets(dmr_frame *f, void *st, dm_error *err);
dm_result dmr_tsd_setup(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err);
void dmr_tsd_free(dmr_frame *f, void *st);
bool dmr_ts_gbuffer_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_ts_gbuffer_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);
bool dmr_irradiance_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_irradiance_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);
/* The blurs in GL: not taken when they run on the CPU (f->blur_cpu). */
bool dmr_blur_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_blur_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);

#endif
