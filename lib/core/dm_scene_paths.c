/* dm_scene_paths.c — a scene's file paths resolved against its folder and the asset
 * search path (dm_scene_paths.h). */
#define _XOPEN_SOURCE 700 /* realpath */
#include "core/dm_scene_paths.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Joins dir and value into out (dir "." or "" adds nothing); false when too long. */
static bool join_path(char out[DM_SCENE_PATH_SIZE], const char *dir, const char *value)
{
    int n = !*dir || strcmp(dir, ".") == 0 ? snprintf(out, DM_SCENE_PATH_SIZE, "%s", value)
                                           : snprintf(out, DM_SCENE_PATH_SIZE, "%s/%s", dir, value);
    return n >= 0 && n < DM_SCENE_PATH_SIZE;
}

static bool is_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* The asset search path after the scene's folder, in order: the caller's folders, each
 * folder of $DERMIS_ASSETS (':'-separated), the build's default. Calls visit(dir, origin)
 * until it returns true. */
static bool each_asset_dir(const dm_scene_paths *p, bool (*visit)(void *, const char *, const char *), void *user)
{
    for (int k = 0; k < p->asset_dir_count; ++k)
        if (p->asset_dirs[k] && *p->asset_dirs[k] && visit(user, p->asset_dirs[k], "--assets")) return true;
    const char *env = getenv("DERMIS_ASSETS");
    while (env && *env) {
        const char *colon = strchr(env, ':');
        size_t len = colon ? (size_t)(colon - env) : strlen(env);
        char d[DM_SCENE_PATH_SIZE];
        if (len > 0 && len < sizeof d) {
            memcpy(d, env, len);
            d[len] = '\0';
            if (visit(user, d, "DERMIS_ASSETS")) return true;
        }
        env = colon ? colon + 1 : NULL;
    }
#ifdef DM_ASSETS_DEFAULT
    if (visit(user, DM_ASSETS_DEFAULT, "the build's default, make ASSETS=")) return true;
#endif
    return false;
}

typedef struct search_state {
    const char *value;
    char *out;
    char looked[700];
} search_state;

static bool try_dir(void *user, const char *dir, const char *origin)
{
    search_state *st = user;
    char cand[DM_SCENE_PATH_SIZE];
    if (!join_path(cand, dir, st->value)) return false;
    if (is_file(cand)) {
        /* absolute: an asset folder given relative to the working directory (DERMIS_ASSETS=
         * ../shared/assets) must not make the path relative to it in a stored scene */
        char abs[PATH_MAX];
        const char *use = realpath(cand, abs) && strlen(abs) < DM_SCENE_PATH_SIZE ? abs : cand;
        memcpy(st->out, use, strlen(use) + 1);
        return true;
    }
    size_t n = strlen(st->looked);
    snprintf(st->looked + n, sizeof st->looked - n, "%s%s (%s)", n ? ", " : "", cand, origin);
    return false;
}

bool dm_scene_resolve_path(const dm_scene_paths *p, dm_jread *j, const char *jpath, const char *value,
                           char out[DM_SCENE_PATH_SIZE])
{
    bool fits = !*value || value[0] == '/' ? join_path(out, "", value) : join_path(out, p->dir, value);
    if (!fits) {
        j->r = dm_fail(j->err, DM_ERR_RANGE, "%s: %s: \"%.60s...\" is too long, expected a path under %d bytes",
                       j->where, jpath, value, DM_SCENE_PATH_SIZE);
        return false;
    }
    if (!p->search || !*value || value[0] == '/' || is_file(out)) return true;
    search_state st = {.value = value, .out = out};
    snprintf(st.looked, sizeof st.looked, "%s (the scene's folder)", out);
    if (each_asset_dir(p, try_dir, &st)) return true;
    j->r = dm_fail(j->err, DM_ERR_FILE_OPEN,
                   "%s: %s: \"%s\" not found; looked in %s; expected the asset folder in --assets DIR or "
                   "DERMIS_ASSETS",
                   j->where, jpath, value, st.looked);
    return false;
}
