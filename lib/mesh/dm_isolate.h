/* dm_isolate.h — running a reader that trusts its input in a forked child process, so
 * that a crash, an abort or a hang on a malformed file becomes an error, not the end of
 * the caller. The mesh readers (OpenMesh, tinygltf) and the glTF material reader go
 * through it (dm_mesh_load, dm_gltf_map_read).
 *
 *   the child runs child(ctx, fd): does the work and writes its reply to fd with
 *       dm_isolate_write / dm_isolate_write_result, then leaves with _exit (no atexit
 *       work of the parent runs twice); its stdout and stderr go to /dev/null;
 *   the parent runs parent(ctx, pipe, err): reads the reply with dm_isolate_read /
 *       dm_isolate_read_result and decodes it. A short read (the child died or hung)
 *       marks pipe->lost; parent then returns anything, after freeing what it made,
 *       and dm_isolate_run reports the child's fate as DM_ERR_FORMAT naming `path`:
 *       "the reader crashed on this file (signal N)", "did not finish in S s",
 *       "stopped early (exit status N)".
 *
 * Fork from a point where no other thread holds a lock (tools load before they start
 * worker threads). Not reentrant across threads; no global state.
 */
#ifndef DM_ISOLATE_H
#define DM_ISOLATE_H

#include <stddef.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_isolate_pipe {
    int fd;             /* read end */
    double deadline_ms; /* dm_now_ms clock */
    int timed_out;      /* set when a read ran past the deadline */
    int lost;           /* set when a read came up short (EOF, error or time out) */
} dm_isolate_pipe;

typedef void (*dm_isolate_child_fn)(void *ctx, int fd);
typedef dm_result (*dm_isolate_parent_fn)(void *ctx, dm_isolate_pipe *pipe, dm_error *err);

/* The time a reader of `path` gets: 30 s + 1 s per MB of the file (generous: the head's
 * 1.8 MB OBJ reads in ~60 ms; a hang is what this catches). */
double dm_isolate_limit_ms(const char *path);

/* Forks, runs child in the child and parent here, waits for the child (killing it after
 * limit_ms). Returns parent's result, or DM_ERR_FORMAT when the reply was lost,
 * DM_ERR_INTERNAL when pipe or fork failed. */
dm_result dm_isolate_run(const char *path, double limit_ms, dm_isolate_child_fn child, dm_isolate_parent_fn parent,
                         void *ctx, dm_error *err);

/* Child side: writes size bytes; 0 on failure (the parent then sees a lost reply). */
int dm_isolate_write(int fd, const void *data, size_t size);
/* Child side: the result code and error detail, the usual first part of a reply. */
int dm_isolate_write_result(int fd, dm_result r, const dm_error *e);

/* Parent side: reads exactly size bytes before the deadline; 0 (and pipe->lost) if not. */
int dm_isolate_read(dm_isolate_pipe *pipe, void *data, size_t size);
/* Parent side: reads what dm_isolate_write_result sent; returns 0 if lost. *r receives
 * the child's result; when it is not DM_OK, err gets the child's detail. */
int dm_isolate_read_result(dm_isolate_pipe *pipe, dm_result *r, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
