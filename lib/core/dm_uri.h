/* dm_uri.h — a file named by another file (a glTF's buffers and images) turned into a path
 * that stays inside the naming file's folder (docs/files.md). The URI is percent-decoded
 * first (so "%2F" and "%2E%2E" cannot hide a separator or a parent), then refused when it
 * is empty, holds a NUL, names a scheme ("file:", "http:"; data: URIs are the caller's),
 * is absolute ("/etc/passwd", "\\x"), has a ".." component, or resolves (symbolic links
 * followed, realpath) outside the folder. Every refusal is DM_ERR_FILE_OPEN, naming the
 * referring file and the URI as written:
 *   "scene.gltf: URI \"/etc/passwd\": an absolute path; a glTF may only name files in its
 *    own folder and below"
 * A URI that is fine but names no existing file gives DM_ERR_FILE_OPEN with ENOENT's text,
 * and `*missing` (when not NULL) set, so a caller may treat a missing optional file apart.
 */
#ifndef DM_URI_H
#define DM_URI_H

#include <stdbool.h>
#include <stddef.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Percent-decodes uri into out (RFC 3986 %XX only; other bytes as they are). False when
 * out_size is too small or a %00 would put a NUL inside the name. */
bool dm_uri_decode(const char *uri, char *out, size_t out_size);

/* Resolves uri (decoded first when `decode`; tinygltf hands its callbacks decoded names)
 * against the folder of `referrer` into out ("FOLDER/URI", not canonicalised). */
dm_result dm_uri_resolve(const char *referrer, const char *uri, bool decode, char *out, size_t out_size,
                         bool *missing, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
