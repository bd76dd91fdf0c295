/* dm_render_timing.h — the timings of a run of frames, kept for their medians (dermis-render
 * --timings, --compare-exact; the viewer's own averages are elsewhere).
 *
 *   dm_render_timing_log log;
 *   if (dm_render_timing_log_init(&log, frames, true, &err) != DM_OK) ...;
 *   for (...) { dm_render_frame(r, ...); dm_render_timing_log_add(&log, r); }
 *   dm_render_timing_log_print(&log, r, what_clock, stdout);
 *   dm_render_timing_log_free(&log);
 *
 * The record is frame_capacity x (DM_PLAN_MAX_PASSES + 1) doubles (392 bytes a frame; one
 * double a frame with passes false) and a scratch column for the medians, allocated AND
 * written at init: the memory is taken once, before the first frame, so a long run's resident
 * set stays flat while it renders (a calloc'd record filled frame by frame grew it by one
 * row, 392 bytes, a frame: issue #31's "380 B a frame"). */
#ifndef DM_RENDER_TIMING_H
#define DM_RENDER_TIMING_H

#include <stdbool.h>
#include <stdio.h>

#include "core/dm_result.h"
#include "render/dm_render.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_render_timing_log {
    double *ms;      /* frame_capacity rows of `columns` values: each pass (plan order), frame */
    double *scratch; /* frame_capacity values */
    int frame_capacity, frame_count, columns;
} dm_render_timing_log;

/* Room for frame_capacity (>= 1) frames: every pass and the frame (passes true), or the frame
 * total only. DM_ERR_OUT_OF_MEMORY naming the bytes. Free with dm_render_timing_log_free. */
dm_result dm_render_timing_log_init(dm_render_timing_log *log, int frame_capacity, bool passes, dm_error *err);
/* Records r's last frame (dm_renderer_last_timings); ignored once full. */
void dm_render_timing_log_add(dm_render_timing_log *log, const dm_renderer *r);
/* The median over the recorded frames of pass `pass` (plan order), or of the frame totals
 * for pass < 0; 0 when nothing is recorded. */
double dm_render_timing_log_median(dm_render_timing_log *log, int pass);
/* The --timings table: "pass ms" per pass of r's plan and the frame, medians, with a header
 * naming the clock (clock: e.g. "wall clock around glFinish") and r's GL. */
void dm_render_timing_log_print(dm_render_timing_log *log, const dm_renderer *r, const char *clock, FILE *out);
void dm_render_timing_log_free(dm_render_timing_log *log);

#ifdef __cplusplus
}
#endif
#endif
