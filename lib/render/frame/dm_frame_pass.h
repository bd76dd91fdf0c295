/* dm_frame_pass.h — what a pass is: one row of the renderer's pass table (dm_render_passes.c).
 * A row names its pass kind, shader and defines, the shading inputs the binder binds for it,
 * its GL state and clears as data (applied by the frame loop before `run`, the default state
 * restored after), and its hooks. The renderer walks the rows for create (check → upload →
 * targets → setup) and destroy (free); the frame loop runs, for each pass of the plan, the
 * first row of its kind whose `prepare` takes it. A hook that does nothing is NULL; the
 * module hooks (check .. setup, free) sit on one row of a module. `st` is the module's own
 * state (a struct its header declares); passes share data only through the frame context. */
#ifndef DM_FRAME_PASS_H
#define DM_FRAME_PASS_H

#include "render/frame/dm_frame.h"

enum {
    DMR_CLEAR_COLOR = 1u,  /* the bound draw buffers' colour to clear_color */
    DMR_CLEAR_DEPTH = 2u,  /* depth to 1 */
    DMR_CLEAR_SCREEN = 4u, /* colour to 0 unless the plan's background pass writes every pixel the
                            * head leaves (alpha 0 too, as the clear would): 16 bytes a pixel
                            * not written twice */
    DMR_CLEAR_COLOR0 = 8u  /* draw buffer 0 only, to clear_color */
};

/* GL state for one pass; zero is the default every pass ends in (no depth test, depth writes,
 * no culling, filled polygons, no blending, no polygon offset, no clear). */
typedef struct dmr_gl_state {
    GLenum depth_test;       /* the depth function; 0: no depth test */
    bool depth_read_only;    /* depth writes off */
    bool cull_back;          /* back faces culled */
    bool wireframe;          /* polygons as lines */
    bool blend_add;          /* colour added (ONE, ONE) */
    float polygon_offset[2]; /* factor, units; 0, 0: off */
    unsigned clear;          /* DMR_CLEAR_*, after the state is set */
    float clear_color[4];
} dmr_gl_state;

/* Sets s (and clears the bound target as it says). */
void dmr_state_apply(const dmr_frame *f, const dmr_gl_state *s);
/* Back to the default state. */
void dmr_state_reset(void);

/* Where a pass draws this frame: fbo 0: the pass binds its own targets, or draws none. */
typedef struct dmr_output {
    GLuint fbo;
    int width, height;
    int draw_buffers; /* > 1: glDrawBuffers of that many colour attachments */
} dmr_output;

typedef struct dmr_pass_row {
    dm_pass_kind kind;     /* DM_PASS_KIND_COUNT: a module with no pass of its own (hooks only) */
    const char *shader;    /* shaders/<file>; kinds sharing a file and defines share one program */
    const char *defines;   /* appended to the frame's defines for this kind's program, or NULL */
    const char *module;    /* the file that owns it */
    bool texture_space;    /* its result depends on lights and scene only (reuse may skip it) */
    unsigned binds;        /* the shading inputs the binder binds before run (DMR_BIND_*) */
    dmr_gl_state state[2]; /* state[variant] (variant 0 without the hook) */
    size_t state_offset;   /* the module's state within the renderer */

    /* create and destroy, in this order for every row */
    dm_result (*check)(const dmr_frame *f, const dm_render_assets *a, dm_error *err);
    dm_result (*upload)(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err);
    dm_result (*targets)(dmr_frame *f, void *st, dm_error *err);
    dm_result (*setup)(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err);
    void (*free)(dmr_frame *f, void *st);
    /* each frame */
    int (*variant)(const dmr_frame *f, const void *st);
    /* Makes ready what the pass reads and says where it draws; false: not this row (the next
     * of its kind is asked; none: the pass has nothing to do this frame). NULL: true, fbo 0. */
    bool (*prepare)(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
    /* Draws (program f->prog[ps->kind] in use, inputs bound, state set); opt may be NULL. */
    void (*run)(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);
} dmr_pass_row;

#endif
