/* dm_scene_paths.h — where a scene's file paths point (internal to the scene reader,
 * dm_scene.c): relative to the scene's folder, else, when reading a scene file, looked up
 * in the asset search path (core/dm_scene.h: --assets folders, DERMIS_ASSETS, the build's
 * default). Not a public API. */
#ifndef DM_SCENE_PATHS_H
#define DM_SCENE_PATHS_H

#include <stdbool.h>

#include "core/dm_jread.h"
#include "core/dm_scene.h"

typedef struct dm_scene_paths {
    char dir[DM_SCENE_PATH_SIZE];  /* the scene's folder */
    bool search;                   /* reading a file: relative paths must exist, searched */
    const char *const *asset_dirs; /* a tool's --assets, searched first; may be NULL */
    int asset_dir_count;
} dm_scene_paths;

/* Resolves `value` (the string at JSON path jpath) into out. "" stays "", an absolute
 * path is kept, a relative one is taken against p->dir; with p->search, a relative path
 * missing there is looked up in the asset search path, and a path found there is made
 * absolute. False, with the error in j (its JSON path, every place looked), when the
 * result does not fit DM_SCENE_PATH_SIZE or the file is nowhere. */
bool dm_scene_resolve_path(const dm_scene_paths *p, dm_jread *j, const char *jpath, const char *value,
                           char out[DM_SCENE_PATH_SIZE]);

#endif
