/* dm_pack_needs.h — the one table that says which baked pack entries each effect needs.
 *
 * "Simulate only the effects a scene calls for" (DESIGN.md) starts here: dermis-pack bakes
 * and packs an entry only when it applies to the scene, dm_pack_open refuses a pack that
 * lacks an entry its scene needs, and dermis-check refuses one that holds an entry its
 * scene does not need. An entry applies when (it has no effects, i.e. the base shading
 * needs it, or one of its effects is on) and its input condition holds (e.g. the scene
 * names a specular map).
 *
 * Several environments: the rows "env.sh", "env.specular", "env.background" stand for one
 * entry per packed environment: copy 0 is the main map (the row's own name), copy k =
 * 1..scene's env_alternative_count its k-th alternative, named "env<k>.sh" ... Each copy
 * applies exactly when its row does.
 */
#ifndef DM_PACK_NEEDS_H
#define DM_PACK_NEEDS_H

#include <stdbool.h>

#include "pack/dm_pack_format.h"
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
    DM_NEED_IF_BACKGROUND,    /* ... an environment shown as background */
    DM_NEED_IF_TEXTURE_SPACE, /* ... subsurface by the texture-space technique */
    DM_NEED_IF_SCREEN_SPACE,  /* ... subsurface by the screen-space technique */
    DM_NEED_IF_PRE_INTEGRATED /* ... subsurface by the pre-integrated technique */
} dm_need_when;

#define DM_FX(e) (1u << (e))

typedef struct dm_pack_need {
    const char *entry;   /* pack entry name */
    dm_pack_kind kind;
    int format;          /* dm_tex_format for textures, -1 for other kinds */
    unsigned effects;    /* DM_FX bits: needed when any is on; 0 = needed by the base shading */
    dm_need_when when;
    const char *why;     /* one line for --explain */
    bool optional;       /* dermis-pack makes it when it applies, but a pack without it is read (a
                          * newer map: without it the runtime does what it did before it) */
} dm_pack_need;

/* The table; *count receives its length. */
const dm_pack_need *dm_pack_needs(int *count);
/* The row for an entry name ("env2.sh" gives the "env.sh" row), or NULL. */
const dm_pack_need *dm_pack_need_find(const char *entry);
/* The same, with *copy = the environment index k of an "env<k>." entry (0 otherwise);
 * k is in [1, DM_SCENE_MAX_ENV_ALTERNATIVES]. copy may be NULL. */
const dm_pack_need *dm_pack_need_find_copy(const char *entry, int *copy);
/* How many entries the row stands for in this scene: 1 + s->env_alternative_count for an
 * environment row, 1 for any other. */
int dm_pack_need_copies(const dm_pack_need *n, const dm_scene *s);
/* Writes copy k's entry name into out[DM_PACK_NAME_SIZE]: the row's name for k = 0, "env<k>.sh"
 * for k > 0 of an environment row. Returns out. */
char *dm_pack_need_entry_name(const dm_pack_need *n, int copy, char *out);
/* Whether the entry named `entry` applies to the scene: its row applies and its copy index
 * is below dm_pack_need_copies. False for names no row knows. */
bool dm_pack_entry_applies(const char *entry, const dm_scene *s);
/* Whether the row applies to the scene. */
bool dm_pack_need_applies(const dm_pack_need *n, const dm_scene *s);
/* "albedo map", "normal map", ...: the input a condition asks for; "" for DM_NEED_ALWAYS. */
const char *dm_need_when_text(dm_need_when w);

#ifdef __cplusplus
}
#endif
#endif
