/* dm_render_timing.c — per-pass timing of a frame: the clock around glFinish on software
 * renderers (llvmpipe's timer queries return implausible numbers; wall time, or with
 * timings_cpu the process CPU time of every llvmpipe thread), GL_TIME_ELAPSED queries
 * elsewhere. Off unless dm_render_desc.timings. And the record of a run's timings for their
 * medians (dm_render_timing.h). */
#include "render/dm_render_timing.h"

#include <stdlib.h>
#include <string.h>

#include "core/dm_cli.h"
#include "core/dm_sort.h"
#include "render/dm_render_internal.h"

/* wall clock, or the process CPU clock with dm_render_desc.timings_cpu */
static double now_ms(const dm_renderer *r)
{
    return r->f.desc.timings_cpu ? dm_cpu_ms() : dm_now_ms();
}

void dmr_timing_frame_begin(dm_renderer *r, double *t_frame)
{
    *t_frame = 0;
    if (!r->f.desc.timings) return;
    glFinish();
    *t_frame = now_ms(r);
}

void dmr_timing_pass_begin(dm_renderer *r, int i, double *t0)
{
    *t0 = 0;
    if (!r->f.desc.timings) return;
    if (r->f.software_gl) {
        glFinish();
        *t0 = now_ms(r);
    } else {
        glBeginQuery(GL_TIME_ELAPSED, r->queries[i]);
    }
}

void dmr_timing_pass_end(dm_renderer *r, int i, double t0)
{
    if (!r->f.desc.timings) return;
    if (r->f.software_gl) {
        glFinish();
        r->pass_ms[i] = now_ms(r) - t0;
    } else {
        glEndQuery(GL_TIME_ELAPSED);
    }
}

void dmr_timing_frame_end(dm_renderer *r, double t_frame, const bool *skipped)
{
    if (!r->f.desc.timings) return;
    glFinish();
    r->frame_ms = now_ms(r) - t_frame;
    if (r->f.software_gl) return;
    double sum = 0;
    for (int i = 0; i < r->f.plan.pass_count; ++i) {
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
        for (int i = 0; i < r->f.plan.pass_count; ++i) pass_ms[i] = r->f.desc.timings ? r->pass_ms[i] : 0.0;
    if (frame_ms) *frame_ms = r->f.desc.timings ? r->frame_ms : 0.0;
}

const char *dm_renderer_gl_name(const dm_renderer *r)
{
    return r->gl_name;
}

bool dm_renderer_timing_on_cpu(const dm_renderer *r)
{
    return r->f.software_gl;
}

/* ---- the timings of a run (dm_render_timing.h) ---- */

dm_result dm_render_timing_log_init(dm_render_timing_log *log, int frame_capacity, bool passes, dm_error *err)
{
    memset(log, 0, sizeof *log);
    if (frame_capacity < 1) frame_capacity = 1;
    log->columns = passes ? DM_PLAN_MAX_PASSES + 1 : 1;
    size_t values = (size_t)frame_capacity * (size_t)log->columns;
    log->ms = malloc(values * sizeof *log->ms);
    log->scratch = malloc((size_t)frame_capacity * sizeof *log->scratch);
    if (!log->ms || !log->scratch) {
        dm_render_timing_log_free(log);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "timings of %d frames: cannot allocate %zu bytes", frame_capacity,
                       (values + (size_t)frame_capacity) * sizeof(double));
    }
    /* written now, not as frames come: the pages are resident before the first frame. Not
     * with zeros: a compiler may turn malloc + memset(0) into calloc, whose fresh pages stay
     * unmapped until each frame's row is written (the resident set then grows a row a frame) */
    for (size_t i = 0; i < values; ++i) log->ms[i] = -1.0;
    for (int f = 0; f < frame_capacity; ++f) log->scratch[f] = -1.0;
    log->frame_capacity = frame_capacity;
    return DM_OK;
}

void dm_render_timing_log_add(dm_render_timing_log *log, const dm_renderer *r)
{
    if (!log->ms || log->frame_count >= log->frame_capacity) return;
    double *row = log->ms + (size_t)log->frame_count++ * (size_t)log->columns;
    if (log->columns > 1) dm_renderer_last_timings(r, row, row + DM_PLAN_MAX_PASSES);
    else dm_renderer_last_timings(r, NULL, row);
}

double dm_render_timing_log_median(dm_render_timing_log *log, int pass)
{
    if (!log->ms || !log->frame_count || pass >= log->columns - 1) return 0.0;
    int col = pass < 0 ? log->columns - 1 : pass;
    for (int f = 0; f < log->frame_count; ++f) log->scratch[f] = log->ms[(size_t)f * (size_t)log->columns + (size_t)col];
    return dm_median_doubles(log->scratch, (size_t)log->frame_count);
}

void dm_render_timing_log_print(dm_render_timing_log *log, const dm_renderer *r, const char *clock, FILE *out)
{
    const dm_render_plan *plan = dm_renderer_plan(r);
    fprintf(out, "%-14s %10s   (median over %d frame%s; %s on %s)\n", "pass", "ms", log->frame_count,
            log->frame_count > 1 ? "s" : "", clock, dm_renderer_gl_name(r));
    for (int i = 0; i <= plan->pass_count; ++i)
        fprintf(out, "%-14s %10.2f\n", i < plan->pass_count ? plan->passes[i].name : "frame",
                dm_render_timing_log_median(log, i < plan->pass_count ? i : -1));
}

void dm_render_timing_log_free(dm_render_timing_log *log)
{
    free(log->ms);
    free(log->scratch);
    memset(log, 0, sizeof *log);
}
