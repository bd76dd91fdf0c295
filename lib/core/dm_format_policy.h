/* dm_format_policy.h — the version policy of docs/dermis-dpk.5.md and docs/dermis-scene.5.md
 * in one place: the formats' names, the verdict on a declared version, and the advice a
 * refusal gives (dm_scene_read and dm_pack_open word theirs with it; pack/dm_format_version.h
 * reads the version a file declares). Pure functions of their arguments.
 */
#ifndef DM_FORMAT_POLICY_H
#define DM_FORMAT_POLICY_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_FORMAT_SCENE_SIZE_MAX = 16 << 20, DM_FORMAT_SUMMARY_SIZE = 192 };

typedef enum dm_format_kind {
    DM_FORMAT_PACK = 0, /* "dermis-pack": a .dpk (dm_pack.h) */
    DM_FORMAT_SCENE,    /* "dermis-scene": a scene JSON (dm_scene.h) */
    DM_FORMAT_KIND_COUNT
} dm_format_kind;

typedef enum dm_format_verdict {
    DM_FORMAT_READABLE = 0, /* the version this dermis reads */
    DM_FORMAT_NEWER,        /* a later version: written by (for) a newer dermis */
    DM_FORMAT_OLDER,        /* an earlier version: dermis never upgrades one in place */
    DM_FORMAT_VERDICT_COUNT
} dm_format_verdict;

/* "dermis-pack", "dermis-scene"; NULL for out-of-range values. */
const char *dm_format_name(dm_format_kind kind);
/* The verdict on a declared version for a reader of version `reads`. */
dm_format_verdict dm_format_judge(int64_t version, int64_t reads);
/* What a refused file's owner should do, e.g. "written by a newer dermis; update dermis";
 * "" for DM_FORMAT_READABLE and out-of-range values. A static string. */
const char *dm_format_advice(dm_format_kind kind, dm_format_verdict verdict);

#ifdef __cplusplus
}
#endif
#endif
