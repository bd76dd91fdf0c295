/* dm_format_policy.c — the formats' names, the verdict on a version, the advice
 * (core/dm_format_policy.h). */
#include "core/dm_format_policy.h"

#include <stddef.h>

static const char *const names[DM_FORMAT_KIND_COUNT] = {"dermis-pack", "dermis-scene"};

/* The one table of the policy's advice: [kind][verdict]. */
static const char *const advice[DM_FORMAT_KIND_COUNT][DM_FORMAT_VERDICT_COUNT] = {
    {"", "written by a newer dermis; update dermis",
     "written by an older dermis; re-pack it from its scene with this dermis"},
    {"", "written for a newer dermis; update dermis",
     "an older scene version; rewrite it for this dermis, see dermis-scene(5)"},
};

const char *dm_format_name(dm_format_kind kind)
{
    return (unsigned)kind < DM_FORMAT_KIND_COUNT ? names[kind] : NULL;
}

dm_format_verdict dm_format_judge(int64_t version, int64_t reads)
{
    return version == reads ? DM_FORMAT_READABLE : version > reads ? DM_FORMAT_NEWER : DM_FORMAT_OLDER;
}

const char *dm_format_advice(dm_format_kind kind, dm_format_verdict verdict)
{
    if ((unsigned)kind >= DM_FORMAT_KIND_COUNT || (unsigned)verdict >= DM_FORMAT_VERDICT_COUNT) return "";
    return advice[kind][verdict];
}

