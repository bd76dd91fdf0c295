/* dm_viewer_script.h — timed input for dermis-view (--script FILE), so the viewer is
 * tested under Xvfb the way a person uses it, through the same actions as the mouse,
 * keyboard and panel.
 *
 * Format: one event per line, `TIME COMMAND ARGS...`; TIME in seconds from the first
 * frame (non-decreasing); '#' starts a comment; blank lines are skipped.
 *   key NAME                       a key press as typed: F1 F12 H S R B V C Q TAB SPACE
 *                                  ESCAPE PLUS MINUS 1..7, "shift+" before any of them
 *   drag X0 Y0 X1 Y1 [BUTTON]      a mouse drag in window pixels (y down); BUTTON is
 *                                  left (orbit, default), right or middle (pan), or
 *                                  light (shift + left: moves the light)
 *   scroll STEPS                   the wheel (positive zooms in)
 *   toggle EFFECT [on|off]         an effect's panel checkbox (flips without on/off);
 *                                  EFFECT as in the scene file, or "background"
 *   view NAME                      the debug-view selector (final, irradiance, blur3, ...)
 *   set NAME VALUE...              a panel slider: exposure, mix, blur_scale,
 *                                  roughness_scale, view_scale, env_intensity,
 *                                  env_rotation, light, light_intensity, light_color R G B,
 *                                  light_rotation, rotate (0/1), irradiance
 *   compare MODE                   the reference comparison (--reference): off, side,
 *                                  split or error (set split X, set error_scale X)
 *   screenshot FILE                the picture as PNG with provenance (after the frame
 *                                  showing every earlier event)
 *   window-shot FILE               the whole window, panel included (PNG)
 *   quit                           exit (also at the end of the script)
 * An event runs at the first frame at or after its time, and never before the frame
 * showing the events before it is done (llvmpipe frames take longer than a script's gaps).
 */
#ifndef DM_VIEWER_SCRIPT_H
#define DM_VIEWER_SCRIPT_H

#include <stdbool.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_SCRIPT_ARG_SIZE = 1024, DM_SCRIPT_MAX_ARGS = 6 };

typedef struct dm_script_event {
    double time_s;
    int line;
    char command[16];
    int arg_count;
    char args[DM_SCRIPT_MAX_ARGS][DM_SCRIPT_ARG_SIZE];
} dm_script_event;

typedef struct dm_script {
    const char *path;
    int count, next;
    dm_script_event *events; /* count of them; free with dm_script_free */
} dm_script;

/* Reads and checks every line (command names, argument counts, numbers, times), so a
 * script fails before the window opens: "FILE:LINE: error: what, expected what". */
dm_result dm_script_read(const char *path, dm_script *s, dm_error *err);
/* The same over NUL-terminated text (modified in place: lines and words are cut); path names
 * it in messages. */
dm_result dm_script_parse(char *text, const char *path, dm_script *s, dm_error *err);
/* Every screenshot and window-shot name against core/dm_output.h's rules (a writable
 * folder, not one of the inputs), before the window opens: 0, or the exit code (1, 4) after
 * "error: FILE:LINE: ..." on stderr. (Their .png extension is checked while parsing.) */
int dm_script_check_outputs(const dm_script *s, const char *const *inputs, int input_count);
void dm_script_free(dm_script *s);

#ifdef __cplusplus
}
#endif
#endif
