/* bench_util.h — what every benchmark shares: the machine it ran on, medians, and the
 * results file. Header-only (benches are one .c each). */
#ifndef BENCH_UTIL_H
#define BENCH_UTIL_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>

/* "CPU model, N cores, Linux release arch" into out. */
static inline void bench_machine(char *out, size_t size)
{
    char model[256] = "unknown CPU";
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (f) {
        char line[512];
        while (fgets(line, sizeof line, f))
            if (!strncmp(line, "model name", 10)) {
                char *c = strchr(line, ':');
                if (c) {
                    snprintf(model, sizeof model, "%s", c + 2);
                    model[strcspn(model, "\n")] = 0;
                }
                break;
            }
        fclose(f);
    }
    struct utsname u;
    uname(&u);
    snprintf(out, size, "%s, %ld cores, %s %s %s", model, sysconf(_SC_NPROCESSORS_ONLN), u.sysname, u.release,
             u.machine);
}

static inline int bench_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of n values (sorts them in place). */
static inline double bench_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, bench_cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Peak resident memory of this process so far, in MiB. */
static inline double bench_peak_rss_mib(void)
{
    struct rusage r;
    getrusage(RUSAGE_SELF, &r);
    return r.ru_maxrss / 1024.0;
}

/* Opens DIR/NAME for the Markdown report and writes its title, date and machine. */
static inline FILE *bench_open(const char *dir, const char *name, const char *title)
{
    char path[1024], machine[512], date[64];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "error: %s: cannot write the report\n", path);
        return NULL;
    }
    time_t now = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", gmtime(&now));
    bench_machine(machine, sizeof machine);
    fprintf(f, "# %s\n\nRun %s on: %s.\n\n", title, date, machine);
    printf("%s — %s\n", title, machine);
    return f;
}

#endif
