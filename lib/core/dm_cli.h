/* dm_cli.h — what every dermis tool shares: exit codes, checked numeric options, output
 * verbosity, timing and a progress bar (STYLE.md §6).
 *
 * Exit codes (documented in every --help):
 *   0 success, 1 usage error, 2 cannot load an input, 3 processing failed,
 *   4 cannot save an output. (dermis-check: 0 all pass, 1 a check failed, 2 usage; with
 *   --format-version, 1 a version this dermis does not read, 2 also a file without one.)
 */
#ifndef DM_CLI_H
#define DM_CLI_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_EXIT_OK = 0, DM_EXIT_USAGE = 1, DM_EXIT_LOAD = 2, DM_EXIT_PROCESS = 3, DM_EXIT_SAVE = 4 };

/* Parses a whole string as an integer in [min, max]; on failure prints
 * "error: OPTION: 'TEXT' is not an integer in [min, max]" to stderr and returns false. */
bool dm_cli_int(const char *option, const char *text, int64_t min, int64_t max, int64_t *out);
/* Same for a finite double in [min, max]. */
bool dm_cli_double(const char *option, const char *text, double min, double max, double *out);
/* Returns argv[*i + 1] and advances *i, or prints "error: OPTION needs a value" and
 * returns NULL. */
const char *dm_cli_value(int argc, char **argv, int *i);

/* True for "--version", after printing "TOOL VERSION" on stdout (every tool answers it). */
bool dm_cli_version(const char *arg, const char *tool);

/* The last line of defence before writing a picture: true when all n values are finite; else
 * prints "error: WHAT: K of N values are NaN or infinite (the first: value I); nothing
 * written" to stderr and returns false. */
bool dm_cli_finite(const float *values, size_t count, const char *what);

/* Monotonic clock in milliseconds. */
double dm_now_ms(void);
/* CPU time of the whole process (every thread, user + system), ms: a software renderer's
 * work, less sensitive than wall time to other users of shared cores. */
double dm_cpu_ms(void);

/* A one-line progress bar on stderr, drawn only when stderr is a terminal and not quiet. */
typedef struct dm_progress {
    const char *label;
    bool enabled;
    int last_percent;
} dm_progress;
void dm_progress_begin(dm_progress *p, const char *label, bool quiet);
void dm_progress_update(dm_progress *p, double fraction); /* fraction in [0, 1] */
void dm_progress_end(dm_progress *p);

#ifdef __cplusplus
}
#endif
#endif
