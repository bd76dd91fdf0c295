/* dm_memory.h — will a run fit in memory? What the machine has available now, and the one
 * refusal every tool gives, before any work, when a run's estimate exceeds it (each tool
 * family's estimate from its options: render/dm_render_memory.h, packer/dm_pack_build.h,
 * reference/dm_reference.h).
 *
 *   uint64_t need = ...;                                  // the tool's estimate, bytes
 *   if (dm_memory_check(need, "--irradiance 8192", NULL, "lower --irradiance", &err) != DM_OK)
 *       fprintf(stderr, "error: %s\n", err.detail);      // and exit non-zero
 *
 * Available memory is the smallest of:
 *   - MemAvailable of /proc/meminfo (what can be allocated without swapping);
 *   - a cgroup's limit less its usage: /sys/fs/cgroup/memory.max − memory.current (v2),
 *     or memory/memory.limit_in_bytes − memory.usage_in_bytes (v1), when one is set;
 *   - DERMIS_MEM_AVAILABLE_MB, when set to a whole number of MiB: an override for tests
 *     (and for a user who wants a tool to stay under a bound); it replaces both above.
 * Unknown (no /proc, no variable): UINT64_MAX, and nothing is refused. */
#ifndef DM_MEMORY_H
#define DM_MEMORY_H

#include <stddef.h>
#include <stdint.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define DM_MEMORY_ENV "DERMIS_MEM_AVAILABLE_MB"

typedef struct dm_memory_available {
    uint64_t size;   /* bytes; UINT64_MAX when unknown */
    char source[64]; /* where it came from: "MemAvailable", "cgroup memory.max",
                      * "DERMIS_MEM_AVAILABLE_MB", "unknown" */
} dm_memory_available;

/* The memory available now (above). */
void dm_memory_available_get(dm_memory_available *out);

/* "812 MiB", "19.3 GiB" (binary units, 3 significant digits) into out (NUL-terminated). */
void dm_memory_size_text(uint64_t size, char *out, size_t out_size);

/* DM_OK when need_size fits in the memory available (dm_memory_available_get); otherwise
 * DM_ERR_OUT_OF_MEMORY with "WHAT needs about X of memory (DETAIL), more than the Y available
 * (SOURCE): ADVICE". what, detail and advice are short phrases ("the renderer at 64x36,
 * irradiance 8192", "texture space 12.2 GiB, ...", "lower --irradiance"); detail and advice
 * may be NULL. */
dm_result dm_memory_check(uint64_t need_size, const char *what, const char *detail, const char *advice,
                          dm_error *err);

/* The same against a given amount (tests; a caller that measured it another way). */
dm_result dm_memory_check_against(uint64_t need_size, const dm_memory_available *avail, const char *what,
                                  const char *detail, const char *advice, dm_error *err);

/* This process's peak resident set so far (getrusage ru_maxrss), bytes; 0 when unknown. */
uint64_t dm_memory_peak_rss(void);

#ifdef __cplusplus
}
#endif
#endif
