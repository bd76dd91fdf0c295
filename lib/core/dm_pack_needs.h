/* dm_pack_needs.h — the one table that says which baked pack entries each effect needs.
 *
 * "Simulate only the effects a scene calls for" (DESIGN.md) starts here: dermis-pack bakes
 * and packs an entry only when it applies to the scene, dm_pack_open refuses a pack that
 * lacks an entry its scene needs, and dermis-check refuses one that holds an entry its
 * scene does not need. An entry applies when (it has no effects, i.e. the base shading
 * needs it, or one of its effects is on) and its input condition holds (e.g. the scene
 * names a specular map).
 *
 * `pending` marks entries whose producer (mesh + stretch)
 * is not wired into dermis-pack yet: they are listed and explained but not yet required.
 * Wiring one = add its bake step to tools/dermis-pack.c and clear its flag here.
 */
#ifndef DM_PACK_NEEDS_H
#define DM_PACK_NEEDS_H

#include <stdbool.h>

#include "core/dm_pack.h"
#include "core/dm_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum dm_need_when {
    DM_NEED_ALWAYS = 0,
    DM_NEED_IF_ALBEDO,        /* the scene names an albedo map */
    DM_NEED_IF_NORMAL_MAP,    /* ... a normal map */
    DM_NEED_IF_SPECULAR_MAP,  /* ... a specular map */
    DM_NEED_IF_ROUGHNESS_MAP, /* ... a roughness map */
    DM_NEED_IF_BACKGROUND     /* ... an environment shown as background */
} dm_need_when;

#define DM_FX(e) (1u << (e))

typedef struct dm_pack_need {
    const char *entry;   /* pack entry name */
    dm_pack_kind kind;
    int format;          /* dm_tex_format for textures, -1 for other kinds */
    unsigned effects;    /* DM_FX bits: needed when any is on; 0 = needed by the base shading */
    dm_need_when when;
    bool pending;        /* producer not wired yet: not required (see above) */
    const char *why;     /* one line for --explain */
} dm_pack_need;

/* The table; *count receives its length. */
const dm_pack_need *dm_pack_needs(int *count);
/* The row for an entry name, or NULL. */
const dm_pack_need *dm_pack_need_find(const char *entry);
/* Whether the row applies to the scene (pending rows included: check .pending). */
bool dm_pack_need_applies(const dm_pack_need *n, const dm_scene *s);
/* "albedo map", "normal map", ...: the input a condition asks for; "" for DM_NEED_ALWAYS. */
const char *dm_need_when_text(dm_need_when w);

#ifdef __cplusplus
}
#endif
#endif
