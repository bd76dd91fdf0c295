/* dm_parallel.h — a deterministic parallel for-loop over [0, count) on pthreads.
 * The range is cut into fixed, contiguous chunks; each index is processed exactly once.
 * Results are byte-identical for any thread count as long as fn writes only the slots
 * of its own indices. */
#ifndef DM_PARALLEL_H
#define DM_PARALLEL_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* fn(ctx, begin, end) handles indices [begin, end). */
typedef void (*dm_range_fn)(void *ctx, size_t begin, size_t end);

/* Number of online processors (at least 1). */
int dm_cpu_count(void);
/* Runs fn over [0, count) on thread_count threads (0 = dm_cpu_count()); the calling
 * thread takes part. chunk is the grain (0 = count / (8 * threads), at least 1). */
void dm_parallel_for(size_t count, size_t chunk, int thread_count, dm_range_fn fn, void *ctx);

#ifdef __cplusplus
}
#endif
#endif
