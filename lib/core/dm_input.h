/* dm_input.h — the rules every file input of dermis follows (docs/files.md):
 *   - it must be a regular file: a FIFO, a device, a socket or a directory is refused with
 *     a message that says which ("x.json: is a FIFO, not a regular file");
 *   - it is opened with O_NONBLOCK (opening a FIFO cannot hang) and O_CLOEXEC, checked with
 *     fstat on the descriptor (not the name: no race between the check and the read), and
 *     O_NONBLOCK is cleared before reading;
 *   - it is at most the size cap of its kind (the table below, docs/files.md), so that no
 *     input is read without a bound; a larger one is refused naming the cap.
 * Every refusal is DM_ERR_FILE_OPEN (the tools' exit 2, cannot load an input).
 *
 * Where a library opens the file itself (OpenImageIO, OpenEXR, OpenMesh, tinygltf),
 * dm_input_check applies the same rule to the name first; the file could still be swapped
 * between the check and the library's open, which is the user's own doing, not an attack
 * dermis defends against.
 *
 *   char *text; size_t size;
 *   if (dm_input_read(path, DM_INPUT_JSON, &text, &size, &err) != DM_OK) return ...;
 *   ... free(text);
 */
#ifndef DM_INPUT_H
#define DM_INPUT_H

#include <stddef.h>
#include <stdint.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define DM_MIB ((uint64_t)1 << 20)
#define DM_GIB ((uint64_t)1 << 30)

/* X-macro: kind, what it is (for messages), size cap in bytes. The one table of caps;
 * docs/files.md repeats it. DM_INPUT_ANY is for readers of any file (hashing, dermis-check):
 * the largest cap. */
#define DM_INPUT_KIND_TABLE(X)                                                                  \
    X(DM_INPUT_JSON, "a scene or profile JSON", 16 * DM_MIB)                                    \
    X(DM_INPUT_SCRIPT, "a viewer script", 1 * DM_MIB)                                           \
    X(DM_INPUT_SHADER, "a shader source", 1 * DM_MIB)                                           \
    X(DM_INPUT_MESH, "a mesh (OBJ, PLY, OFF, STL, OM, glTF, GLB) or a glTF's file", 4 * DM_GIB) \
    X(DM_INPUT_IMAGE, "an image (PNG, JPEG, HDR, EXR)", 8 * DM_GIB)                             \
    X(DM_INPUT_PACK, "a pack (.dpk)", 64 * DM_GIB)                                              \
    X(DM_INPUT_ANY, "any input", 64 * DM_GIB)

typedef enum dm_input_kind {
#define DM_X_ENUM(name, what, cap) name,
    DM_INPUT_KIND_TABLE(DM_X_ENUM)
#undef DM_X_ENUM
    DM_INPUT_KIND_COUNT
} dm_input_kind;

/* The size cap of a kind, bytes. */
uint64_t dm_input_cap(dm_input_kind kind);
/* What a kind is, e.g. "a scene or profile JSON". */
const char *dm_input_kind_name(dm_input_kind kind);

/* Opens path under the rules above. On success *fd is a blocking, close-on-exec
 * descriptor of a regular file (close it) and *size (may be NULL) its size at open. */
dm_result dm_input_open(const char *path, dm_input_kind kind, int *fd, uint64_t *size, dm_error *err);
/* dm_input_open, then close: for a name handed to a library that opens it itself. size may
 * be NULL. */
dm_result dm_input_check(const char *path, dm_input_kind kind, uint64_t *size, dm_error *err);
/* Reads a whole input into a malloc'd buffer, NUL-terminated (*size excludes the NUL;
 * free with free()). A file that grows past its cap while being read is refused too. */
dm_result dm_input_read(const char *path, dm_input_kind kind, char **data, size_t *size, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
