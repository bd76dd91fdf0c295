/* dm_format_version.h — which dermis format and version a file declares, and whether this
 * dermis reads it: the version policy of docs/dermis-dpk.5.md and docs/dermis-scene.5.md
 * (core/dm_format_policy.h) applied to a file (dermis-check --format-version; the refusals of dm_pack_open and
 * dm_scene_read word their advice through dm_format_advice).
 *
 * It reads only what names the version, so it answers for a file the full reader refuses:
 *   pack (the file starts with DM_PACK_MAGIC): the 64-byte header; when the header's
 *     version is DM_PACK_VERSION, also the manifest (at most DM_PACK_MANIFEST_MAX bytes),
 *     whose "version" is then the one reported (the full reader requires both to match);
 *   scene (any other file of at most DM_FORMAT_SCENE_SIZE_MAX bytes; a larger one is refused
 *     unread): JSON, of which only the top-level "format" ("dermis-scene", or absent with a
 *     "mesh" key, as the scene reader allows) and "version" (absent: 1, the reader's
 *     default) are looked at.
 * Nothing else is verified: dermis-check FILE does that. A pack of the version this dermis
 * reads may still be refused by the full reader, e.g. for a manifest key added by a later
 * dermis of the same version (the policy: additive keys do not bump the version).
 */
#ifndef DM_FORMAT_VERSION_H
#define DM_FORMAT_VERSION_H

#include <stdbool.h>
#include <stdint.h>

#include "core/dm_format_policy.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_format_version {
    dm_format_kind kind;
    int64_t version;           /* as declared (a scene without "version": 1) */
    bool stated;               /* false only for a scene without "version" */
    int64_t reads;             /* the version this dermis reads: DM_PACK_VERSION or DM_SCENE_VERSION */
    dm_format_verdict verdict; /* version against reads */
    /* "dermis-pack version 1 (this dermis reads version 1: ok)", or "...: refused, ADVICE)" */
    char summary[DM_FORMAT_SUMMARY_SIZE];
} dm_format_version;

/* Fills *out with the format and version `path` declares and the verdict. DM_OK whatever the
 * verdict; a failure only when no version can be found, naming the file: DM_ERR_FILE_OPEN /
 * DM_ERR_FILE_READ, DM_ERR_FORMAT (a pack's header or manifest truncated or unreadable, a
 * "version" that is not an integer, a file that is neither a pack nor a scene),
 * DM_ERR_OUT_OF_MEMORY. */
dm_result dm_format_version_read(const char *path, dm_format_version *out, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
