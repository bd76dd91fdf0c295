/* dm_output.h — the rules every output of a dermis tool follows, checked right after the
 * options are parsed, before any input is read and before any work (docs/files.md):
 *   - its name ends in the extension of the format written, in any case (.EXR is fine);
 *     a tool that writes several formats writes the one the extension names;
 *   - it is not the same file as any input (same device and inode: a hard or symbolic
 *     link to an input counts; an output that does not exist yet cannot be one);
 *   - it is not a directory, FIFO or device;
 *   - its folder is writable, or can be made (missing folders are created when the output
 *     is written, core/dm_file.h): a probe file is created with O_EXCL in the folder, or in
 *     its nearest existing ancestor, and removed at once. Permission bits alone say nothing
 *     for root, read-only mounts or /proc; the probe is what the write will meet.
 * Messages name the user's path and the option that gave it, never a temporary name.
 *
 *   int format;
 *   int rc = dm_output_check_cli("-o", o.out, (const char *const[]){".png", ".exr", NULL},
 *                                (const char *const[]){o.pack, o.reference}, 2, &format);
 *   if (rc) return rc;   // the error is printed; rc is the exit code (1 or 4)
 */
#ifndef DM_OUTPUT_H
#define DM_OUTPUT_H

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The index in the NULL-terminated `extensions` (".exr", ...) that path ends in, compared
 * without regard to case; -1 when none. */
int dm_output_extension(const char *path, const char *const *extensions);

/* Checks one output (named by `option`, e.g. "-o" or "--beckmann", for messages) against
 * the rules above; inputs[0 .. input_count) are the files the tool reads (NULL entries are
 * skipped). *format (may be NULL) gets the extension's index. Returns
 * DM_ERR_INVALID_ARGUMENT for a wrong extension or an output that is an input or not a
 * regular file, DM_ERR_FILE_WRITE when the folder cannot be written. */
dm_result dm_output_check(const char *option, const char *path, const char *const *extensions,
                          const char *const *inputs, int input_count, int *format, dm_error *err);

/* dm_output_check for a tool: on failure prints "error: DETAIL" on stderr and returns the
 * exit code (core/dm_cli.h: DM_EXIT_USAGE for a wrong name, DM_EXIT_SAVE for a folder that
 * cannot be written); 0 when the output is fine. */
int dm_output_check_cli(const char *option, const char *path, const char *const *extensions,
                        const char *const *inputs, int input_count, int *format);

#ifdef __cplusplus
}
#endif
#endif
