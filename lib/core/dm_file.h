/* dm_file.h — writing outputs safely: a temporary name beside the target, fsync, rename.
 * A failed run never leaves a half-written file under the final name, and an interrupted
 * one leaves no temporary file:
 *   - the temporary is "<path>.tmp.<PID>.dermis" (".tmp.<PID>-<K>.dermis" when taken),
 *     created with O_EXCL, so it is always a new file and never one that was there;
 *   - every temporary name is registered here from dm_atomic_begin until commit/abort;
 *     the first registration installs handlers for SIGINT, SIGTERM and SIGHUP (not for a
 *     signal the process ignores, as a background job ignores SIGINT) that unlink every
 *     registered name, then restore the previous disposition and re-raise, so the shell
 *     sees 130 (Ctrl-C), 143 (SIGTERM) or 129 and a parent handler still runs; a name is
 *     registered only after this process created it, so the handler removes only its own;
 *   - a run killed with SIGKILL cannot clean up. The next dm_atomic_begin for the same
 *     target removes such a leftover only when it can prove it is a dead dermis run's
 *     own, with a note on stderr naming it. A name can be chosen by anyone (a user's
 *     "o.png.tmp.999999" once was deleted), so the proof is a marker the tool wrote: the
 *     extended attribute "user.dermis.tmp" = "dermis-tmp 1 HOST PID START" set on the new
 *     file, START the process's start time since boot. A leftover is removed when its name
 *     has the form above, it carries the marker, the marker's host is this host and its
 *     PID the name's, and that process is gone (or the PID now belongs to a process
 *     started at another time). Files without the marker are never touched, whatever
 *     their name; a file system without extended attributes gets a warning naming the
 *     leftover instead. (O_TMPFILE + linkat would need no marker, but the EXR writer opens
 *     its output by name, and a name is what a signal handler can unlink.)
 * Missing folders of the target are created (mkdir -p). Errors name the target, never the
 * temporary. Tools check their outputs before any work with core/dm_output.h.
 *
 *   dm_atomic_file af;
 *   if (dm_atomic_begin(&af, "out.png", &err) != DM_OK) return ...;
 *   ... write to af.tmp_path (by name, or through af.fp when opened with dm_atomic_open) ...
 *   return dm_atomic_commit(&af, &err);       // or dm_atomic_abort(&af) on failure
 */
#ifndef DM_FILE_H
#define DM_FILE_H

#include <stdio.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_atomic_file {
    char path[4096];     /* the final name */
    char tmp_path[4200]; /* "<path>.tmp.<pid>.dermis" in the same folder, so rename is atomic */
    FILE *fp;            /* set by dm_atomic_open, else NULL */
    int cleanup_slot;    /* dm_cleanup_register's slot for tmp_path, or -1 */
} dm_atomic_file;

/* Creates the target's folder when missing (with its parents, mode 0777 less the umask),
 * removes the target's temporary files provably left by dead runs, creates the temporary
 * file (empty, marked) and registers tmp_path for cleanup on a signal. */
dm_result dm_atomic_begin(dm_atomic_file *af, const char *path, dm_error *err);
/* dm_atomic_begin, then opens tmp_path for binary writing into af->fp. */
dm_result dm_atomic_open(dm_atomic_file *af, const char *path, dm_error *err);
/* Flushes and closes af->fp if open, fsyncs tmp_path, renames it to path. On failure
 * the temporary file is removed. */
dm_result dm_atomic_commit(dm_atomic_file *af, dm_error *err);
/* Closes and removes the temporary file; safe to call twice. */
void dm_atomic_abort(dm_atomic_file *af);

/* Registers a file to unlink if a SIGINT, SIGTERM or SIGHUP ends the process (copied;
 * at most 32 at once: beyond that, -1 and no cleanup). Installs the handlers on first use.
 * Thread-safe. Returns the slot for dm_cleanup_unregister. */
int dm_cleanup_register(const char *path);
/* Forgets a slot (-1 is ignored). Does not unlink. */
void dm_cleanup_unregister(int slot);
/* Creates a folder and its missing parents (mkdir -p); an existing folder is fine. */
dm_result dm_mkdir_p(const char *dir, dm_error *err);

/* Reads a whole file into a malloc'd buffer (NUL-terminated; *size excludes the NUL).
 * Free with free(). The input rules of core/dm_input.h with the largest cap: a reader that
 * knows its kind calls dm_input_read with it. */
dm_result dm_read_file(const char *path, char **data, size_t *size, dm_error *err);

/* The folder part of path ("." when none), into out. */
void dm_dirname(const char *path, char *out, size_t out_size);

#ifdef __cplusplus
}
#endif
#endif
