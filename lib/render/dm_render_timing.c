/* dm_render_timing.c — per-pass timing of a frame: the clock around glFinish on software
 * renderers (llvmpipe's timer queries return implausible numbers; wall time, or with
 * timings_cpu the process CPU time of every llvmpipe thread), GL_TIME_ELAPSED queries
 * elsewhere. Off unless dm_render_desc.timings. */
#include "core/dm_cli.h"
#include "render/dm_render_internal.h"

/* wall clock, or the process CPU clock with dm_render_desc.timings_cpu */
static double now_ms(const dm_renderer *r)
{
    return r->desc.timings_cpu ? dm_cpu_ms() : dm_now_ms();
}

void dmr_timing_frame_begin(dm_renderer *r, double *t_frame)
{
    *t_frame = 0;
    if (!r->desc.timings) return;
    glFinish();
    *t_frame = now_ms(r);
}

void dmr_timing_pass_begin(dm_renderer *r, int i, double *t0)
{
    *t0 = 0;
    if (!r->desc.timings) return;
    if (r->timing_cpu) {
        glFinish();
        *t0 = now_ms(r);
    } else {
        glBeginQuery(GL_TIME_ELAPSED, r->queries[i]);
    }
}

void dmr_timing_pass_end(dm_renderer *r, int i, double t0)
{
    if (!r->desc.timings) return;
    if (r->timing_cpu) {
        glFinish();
        r->pass_ms[i] = now_ms(r) - t0;
    } else {
        glEndQuery(GL_TIME_ELAPSED);
    }
}

void dmr_timing_frame_end(dm_renderer *r, double t_frame, const bool *skipped)
{
    if (!r->desc.timings) return;
    glFinish();
    r->frame_ms = now_ms(r) - t_frame;
    if (r->timing_cpu) return;
    double sum = 0;
    for (int i = 0; i < r->plan.pass_count; ++i) {
        if (skipped[i]) continue; /* no query ran, pass_ms already 0 */
        GLuint ns = 0;
        glGetQueryObjectuiv(r->queries[i], GL_QUERY_RESULT, &ns);
        r->pass_ms[i] = ns * 1e-6;
        sum += r->pass_ms[i];
    }
    r->frame_ms = sum;
}

void dm_renderer_last_timings(const dm_renderer *r, double *pass_ms, double *frame_ms)
{
    if (pass_ms)
        for (int i = 0; i < r->plan.pass_count; ++i) pass_ms[i] = r->desc.timings ? r->pass_ms[i] : 0.0;
    if (frame_ms) *frame_ms = r->desc.timings ? r->frame_ms : 0.0;
}

const char *dm_renderer_gl_name(const dm_renderer *r)
{
    return r->gl_name;
}

bool dm_renderer_timing_on_cpu(const dm_renderer *r)
{
    return r->timing_cpu;
}
