#include "core/dm_cli.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <string.h>
#include <unistd.h>

#include "core/dm_math.h"
#include "core/dm_version.h"

bool dm_cli_int(const char *option, const char *text, int64_t min, int64_t max, int64_t *out)
{
    char *end = NULL;
    errno = 0;
    long long v = text ? strtoll(text, &end, 10) : 0;
    if (!text || !*text || *end || errno || v < min || v > max) {
        fprintf(stderr, "error: %s: '%s' is not an integer in [%" PRId64 ", %" PRId64 "]\n", option,
                text ? text : "", min, max);
        return false;
    }
    *out = v;
    return true;
}

bool dm_cli_double(const char *option, const char *text, double min, double max, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = text ? strtod(text, &end) : 0;
    if (!text || !*text || *end || errno || !isfinite(v) || v < min || v > max) {
        fprintf(stderr, "error: %s: '%s' is not a number in [%g, %g]\n", option, text ? text : "", min, max);
        return false;
    }
    *out = v;
    return true;
}

const char *dm_cli_value(int argc, char **argv, int *i)
{
    if (*i + 1 >= argc) {
        fprintf(stderr, "error: %s needs a value\n", argv[*i]);
        return NULL;
    }
    return argv[++*i];
}

bool dm_cli_version(const char *arg, const char *tool)
{
    if (!arg || strcmp(arg, "--version") != 0) return false;
    printf("%s %s\n", tool, DM_VERSION);
    return true;
}

double dm_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

double dm_cpu_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

void dm_progress_begin(dm_progress *p, const char *label, bool quiet)
{
    p->label = label;
    p->enabled = !quiet && isatty(STDERR_FILENO);
    p->last_percent = -1;
}

void dm_progress_update(dm_progress *p, double fraction)
{
    if (!p->enabled) return;
    int pct = (int)(fraction * 100.0);
    if (pct < 0) pct = 0;
    if (pct > 100) pct = 100;
    if (pct == p->last_percent) return;
    p->last_percent = pct;
    char bar[41];
    int filled = pct * 40 / 100;
    for (int k = 0; k < 40; ++k) bar[k] = k < filled ? '#' : '.';
    bar[40] = '\0';
    fprintf(stderr, "\r%s [%s] %3d%%", p->label, bar, pct);
    fflush(stderr);
}

void dm_progress_end(dm_progress *p)
{
    if (!p->enabled) return;
    dm_progress_update(p, 1.0);
    fprintf(stderr, "\n");
}

bool dm_cli_finite(const float *values, size_t count, const char *what)
{
    size_t first, bad = dm_count_nonfinite(values, count, &first);
    if (bad)
        fprintf(stderr, "error: %s: %zu of %zu values are NaN or infinite (the first: value %zu); nothing written\n",
                what, bad, count, first);
    return bad == 0;
}
