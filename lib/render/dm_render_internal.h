/* dm_render_internal.h — the renderer itself: the frame context and every pass module's state
 * in one struct, and what the top-level files share (not installed, not a public API).
 *
 * The renderer is a list of passes. Its layers, each including only those above it:
 *   gpu/      GL only: the object registry (every GL object made and freed through it), named
 *             targets, programs from source and defines (dm_gpu*.c)
 *   input/    no GL: the pack adapter, the synthetic scene, the plan of passes, the shader
 *             sources, the blur kernel and stretch values, the memory estimate (dm_render_*.c)
 *   picture/  no GL: font, legend, image writers, comparison with a reference, provenance
 *   frame/    what every pass shares: the frame context (dm_frame.h), sampler units, the
 *             mesh and material uploads, lights and camera, program defines, the pass row
 *             type with its GL state as data (dm_frame_pass.h), the one binder of shading
 *             inputs (dm_frame_bind.h)
 *   passes/   one file per technique or effect, each with its state in its own header:
 *             shadow, tsd (atlas G-buffer, irradiance, GL blurs), blur_cpu, diffusion, ssss,
 *             preint, translucency, shade (G-buffer, final), env (uploads, background), glow,
 *             tonemap, view. Passes never include or call each other.
 *   top       dm_render.c (create, destroy, frame, set_scene), dm_render_passes.c (the one
 *             table of rows and the frame loop's step), dm_render_readback.c,
 *             dm_render_views.c, dm_render_timing.c, dm_render_limits.c, dm_render_finite.c:
 *             the only files that name techniques and hold the public dm_renderer_* functions.
 * Public headers (dm_render.h, dm_render_plan.h, dm_render_memory.h, ...) stay here at the top.
 */
#ifndef DM_RENDER_INTERNAL_H
#define DM_RENDER_INTERNAL_H

#include "render/frame/dm_frame_pass.h"
#include "render/passes/dm_pass_blur_cpu.h"
#include "render/passes/dm_pass_env.h"
#include "render/passes/dm_pass_glow.h"
#include "render/passes/dm_pass_shadow.h"
#include "render/passes/dm_pass_ssss.h"
#include "render/passes/dm_pass_tonemap.h"
#include "render/passes/dm_pass_tsd.h"
#include "render/passes/dm_pass_view.h"

struct dm_renderer {
    dmr_frame f; /* first: a row's state_offset 0 means no state */
    /* each module's own state (its header) */
    dmr_shadow shadow;
    dmr_tsd tsd;
    dmr_blur_cpu blur_cpu;
    dmr_ssss ssss;
    dmr_env env;
    dmr_glow glow;
    dmr_tonemap tonemap;
    dmr_view view;

    bool ts_valid;                           /* texture-space results reusable (reuse_texture_space) */
    int ts_pass_count;                       /* shadow + irradiance + blur passes of the final plan */
    float ts_rotation;                       /* the light rotation they were made with, */
    float ts_blur_scale, ts_roughness_scale; /* and the per-frame scales */
    bool tonemapped;   /* the last frame's display came from the tonemap pass */
    bool glow_pending; /* the tonemap added the glow; the screen gets it when read (dmr_glow_settle) */
    bool has_frame;    /* a frame has run: the display holds a picture */
    GLuint blit_tex, blit_fbo; /* the CPU-built display that dm_renderer_blit_display blits from
                                * when the frame is not tonemapped (made on first use) */
    GLuint queries[DM_PLAN_MAX_PASSES];
    double pass_ms[DM_PLAN_MAX_PASSES], frame_ms;
    char gl_name[256];
};

/* ---- dm_render_passes.c: the one table ---- */
const dmr_pass_row *dmr_pass_rows(int *count);
/* The first row of a kind (its shader, defines, texture_space). */
const dmr_pass_row *dmr_pass_first(dm_pass_kind kind);
/* A row's module state within r (NULL: none). */
void *dmr_pass_state(dm_renderer *r, const dmr_pass_row *row);
/* Whether the plan made at create needs this kind's program. */
bool dmr_pass_needed(const dm_renderer *r, dm_pass_kind kind);
/* Runs one pass of the plan: the first row of its kind that takes it, its target bound, its
 * state and clears applied, its program in use and inputs bound; the default state after. */
void dmr_run_pass(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);
/* Adds the glow to the screen if the last frame's tonemap added it to the display only. */
void dmr_glow_settle(dm_renderer *r);

/* ---- dm_render_limits.c ---- */
/* Refuses, naming the limit and the largest size that fits, targets beyond the context's
 * limits (dm_render_gl_limits_get, proxy textures); then the estimate beyond the memory
 * available (desc.memory_available_size, else core/dm_memory.h). */
dm_result dmr_check_limits(const dm_renderer *r, const dm_render_assets *a, dm_error *err);

/* ---- dm_render_timing.c ---- */
void dmr_timing_frame_begin(dm_renderer *r, double *t_frame);
void dmr_timing_pass_begin(dm_renderer *r, int i, double *t0);
void dmr_timing_pass_end(dm_renderer *r, int i, double t0);
/* skipped[i]: pass i did not run (texture-space reuse), its time reads 0 */
void dmr_timing_frame_end(dm_renderer *r, double t_frame, const bool *skipped);

#endif
