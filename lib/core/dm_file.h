/* dm_file.h — writing outputs safely: a temporary name beside the target, fsync, rename.
 * A failed run never leaves a half-written file under the final name.
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
    char tmp_path[4200]; /* "<path>.tmp.<pid>" in the same folder, so rename is atomic */
    FILE *fp;            /* set by dm_atomic_open, else NULL */
} dm_atomic_file;

/* Chooses the temporary name and checks that the target's folder is writable. */
dm_result dm_atomic_begin(dm_atomic_file *af, const char *path, dm_error *err);
/* dm_atomic_begin, then opens tmp_path for binary writing into af->fp. */
dm_result dm_atomic_open(dm_atomic_file *af, const char *path, dm_error *err);
/* Flushes and closes af->fp if open, fsyncs tmp_path, renames it to path. On failure
 * the temporary file is removed. */
dm_result dm_atomic_commit(dm_atomic_file *af, dm_error *err);
/* Closes and removes the temporary file; safe to call twice. */
void dm_atomic_abort(dm_atomic_file *af);

/* Reads a whole file into a malloc'd buffer (NUL-terminated; *size excludes the NUL).
 * Free with free(). */
dm_result dm_read_file(const char *path, char **data, size_t *size, dm_error *err);

/* The folder part of path ("." when none), into out. */
void dm_dirname(const char *path, char *out, size_t out_size);

#ifdef __cplusplus
}
#endif
#endif
