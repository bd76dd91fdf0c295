/* dm_result.h — dermis's one error model (STYLE.md §5).
 *
 * A broken contract (NULL where the header says non-NULL, a size of zero where one is
 * required) is an assert. A recoverable failure returns a dm_result; the function also
 * fills the caller's dm_error, when one is given, with a detail line that names the file,
 * the value and what was expected. There is no global error state.
 *
 *   dm_error err = {0};
 *   if (dm_something(..., &err) != DM_OK) fprintf(stderr, "error: %s\n", err.detail);
 */
#ifndef DM_RESULT_H
#define DM_RESULT_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* X-macro: name, message. The message table is the one place the words live. */
#define DM_RESULT_TABLE(X)                                                        \
    X(DM_OK, "success")                                                           \
    X(DM_ERR_INVALID_ARGUMENT, "invalid argument")                                \
    X(DM_ERR_OUT_OF_MEMORY, "out of memory")                                      \
    X(DM_ERR_FILE_OPEN, "cannot open file")                                       \
    X(DM_ERR_FILE_READ, "cannot read file")                                       \
    X(DM_ERR_FILE_WRITE, "cannot write file")                                     \
    X(DM_ERR_FORMAT, "malformed or unrecognised file contents")                   \
    X(DM_ERR_UNSUPPORTED, "unsupported format or feature")                        \
    X(DM_ERR_NON_FINITE, "NaN or infinite value")                                 \
    X(DM_ERR_RANGE, "value out of range")                                         \
    X(DM_ERR_CHECKSUM, "checksum mismatch")                                       \
    X(DM_ERR_MISMATCH, "inputs do not belong together")                           \
    X(DM_ERR_EMPTY, "nothing to work on")                                         \
    X(DM_ERR_GL, "OpenGL error")                                                  \
    X(DM_ERR_INTERNAL, "internal error")

typedef enum dm_result {
#define DM_X_ENUM(name, msg) name,
    DM_RESULT_TABLE(DM_X_ENUM)
#undef DM_X_ENUM
    DM_RESULT_COUNT
} dm_result;

/* Caller-owned error detail. Zero-initialise; functions overwrite it on failure only. */
typedef struct dm_error {
    dm_result code;
    char detail[1024]; /* "FILE: what was found, what was expected" */
} dm_error;

/* The enum's identifier, e.g. "DM_ERR_FORMAT"; "DM_UNKNOWN" for out-of-range values. */
const char *dm_result_name(dm_result r);
/* The enum's message, e.g. "malformed or unrecognised file contents". */
const char *dm_result_message(dm_result r);

/* Records a failure: fills err (may be NULL) with code and a printf-formatted detail,
 * and returns code, so callers write `return dm_fail(err, DM_ERR_X, "%s: ...", path);`. */
dm_result dm_fail(dm_error *err, dm_result code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#ifdef __cplusplus
}
#endif
#endif
