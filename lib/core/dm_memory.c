/* dm_memory.c — available memory (MemAvailable, a cgroup's limit, DERMIS_MEM_AVAILABLE_MB)
 * and the refusal of runs that would not fit (dm_memory.h). */
#include "core/dm_memory.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

/* The first unsigned number in a file ("max" and anything else: false). */
static int read_u64(const char *path, uint64_t *out)
{
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    unsigned long long v = 0;
    int got = fscanf(f, "%llu", &v);
    fclose(f);
    if (got != 1) return 0;
    *out = v;
    return 1;
}

static int meminfo_available(uint64_t *out)
{
    FILE *f = fopen("/proc/meminfo", "r");
    if (!f) return 0;
    char line[256];
    int found = 0;
    while (!found && fgets(line, sizeof line, f)) {
        unsigned long long kib = 0;
        if (sscanf(line, "MemAvailable: %llu kB", &kib) == 1) *out = (uint64_t)kib * 1024u, found = 1;
    }
    fclose(f);
    return found;
}

/* A cgroup's limit less its usage, when a limit is set (v2, then v1; v1 says "no limit"
 * with a huge number, which the MemAvailable bound then wins). */
static int cgroup_available(uint64_t *out)
{
    uint64_t max = 0, cur = 0;
    if (read_u64("/sys/fs/cgroup/memory.max", &max) && read_u64("/sys/fs/cgroup/memory.current", &cur)) {
        *out = max > cur ? max - cur : 0;
        return 1;
    }
    if (read_u64("/sys/fs/cgroup/memory/memory.limit_in_bytes", &max) &&
        read_u64("/sys/fs/cgroup/memory/memory.usage_in_bytes", &cur)) {
        *out = max > cur ? max - cur : 0;
        return 1;
    }
    return 0;
}

void dm_memory_available_get(dm_memory_available *out)
{
    out->size = UINT64_MAX;
    snprintf(out->source, sizeof out->source, "unknown");
    const char *env = getenv(DM_MEMORY_ENV);
    if (env && *env) {
        char *end = NULL;
        errno = 0;
        unsigned long long mb = strtoull(env, &end, 10);
        if (!*end && !errno && env[0] != '-' && mb < (UINT64_MAX >> 20)) {
            out->size = (uint64_t)mb << 20;
            snprintf(out->source, sizeof out->source, "%s", DM_MEMORY_ENV);
            return;
        }
    }
    uint64_t v = 0;
    if (meminfo_available(&v)) {
        out->size = v;
        snprintf(out->source, sizeof out->source, "MemAvailable");
    }
    if (cgroup_available(&v) && v < out->size) {
        out->size = v;
        snprintf(out->source, sizeof out->source, "cgroup memory limit");
    }
}

void dm_memory_size_text(uint64_t size, char *out, size_t out_size)
{
    double mib = (double)size / 1048576.0;
    if (mib >= 1024.0) snprintf(out, out_size, "%.3g GiB", mib / 1024.0);
    else if (mib >= 1.0) snprintf(out, out_size, "%.0f MiB", mib);
    else snprintf(out, out_size, "%.0f KiB", (double)size / 1024.0);
}

dm_result dm_memory_check_against(uint64_t need_size, const dm_memory_available *avail, const char *what,
                                  const char *detail, const char *advice, dm_error *err)
{
    if (need_size <= avail->size) return DM_OK;
    char need[32], have[32];
    dm_memory_size_text(need_size, need, sizeof need);
    dm_memory_size_text(avail->size, have, sizeof have);
    return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s needs about %s of memory%s%s%s, more than the %s available (%s)%s%s",
                   what, need, detail ? " (" : "", detail ? detail : "", detail ? ")" : "", have, avail->source,
                   advice ? ": " : "", advice ? advice : "");
}

dm_result dm_memory_check(uint64_t need_size, const char *what, const char *detail, const char *advice,
                          dm_error *err)
{
    dm_memory_available avail;
    dm_memory_available_get(&avail);
    return dm_memory_check_against(need_size, &avail, what, detail, advice, err);
}

uint64_t dm_memory_peak_rss(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0) return 0;
    return (uint64_t)ru.ru_maxrss * 1024u; /* KiB on Linux */
}
