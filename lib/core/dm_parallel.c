#include "core/dm_parallel.h"

#include <pthread.h>
#include <stdatomic.h>
#include <unistd.h>

typedef struct job {
    size_t count, chunk;
    atomic_size_t next;
    dm_range_fn fn;
    void *ctx;
} job;

int dm_cpu_count(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

static void *worker(void *arg)
{
    job *j = arg;
    for (;;) {
        size_t begin = atomic_fetch_add(&j->next, j->chunk);
        if (begin >= j->count) break;
        size_t end = begin + j->chunk < j->count ? begin + j->chunk : j->count;
        j->fn(j->ctx, begin, end);
    }
    return NULL;
}

void dm_parallel_for(size_t count, size_t chunk, int thread_count, dm_range_fn fn, void *ctx)
{
    if (count == 0) return;
    int threads = thread_count > 0 ? thread_count : dm_cpu_count();
    if (threads > 64) threads = 64;
    if (chunk == 0) chunk = count / (8 * (size_t)threads);
    if (chunk == 0) chunk = 1;
    job j = {.count = count, .chunk = chunk, .fn = fn, .ctx = ctx};
    atomic_init(&j.next, 0);
    pthread_t tid[64];
    int started = 0;
    for (int t = 1; t < threads && (size_t)t * chunk < count; ++t)
        if (pthread_create(&tid[started], NULL, worker, &j) == 0) ++started;
    worker(&j);
    for (int t = 0; t < started; ++t) pthread_join(tid[t], NULL);
}
