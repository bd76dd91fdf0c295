/* Scene asset resolution (dm_scene_read_assets): beside the scene first, then --assets
 * folders, then DERMIS_ASSETS (':'-separated), and an error naming every place looked;
 * and dm_file's output folders (created when missing) and stale temporary files. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "../common/tmpdir.h"
#include "core/dm_file.h"
#include "core/dm_scene.h"

static char dir[256];
static dm_scene scene;

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    cr_assert(f, "%s", path);
    fputs(text, f);
    fclose(f);
}

static void setup(void)
{
    cr_assert(test_tmpdir(dir, sizeof dir));
    unsetenv("DERMIS_ASSETS");
}

/* A scene in DIR/scenes naming a relative mesh "lib/m.obj". */
static void write_scene(char *scene_path, size_t size)
{
    char p[512];
    snprintf(p, sizeof p, "%s/scenes", dir);
    mkdir(p, 0777);
    snprintf(scene_path, size, "%s/scenes/s.json", dir);
    write_text(scene_path, "{\"mesh\": {\"path\": \"lib/m.obj\"}, \"effects\": {}}");
}

static void make_asset(const char *folder)
{
    char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, folder);
    mkdir(p, 0777);
    snprintf(p, sizeof p, "%s/%s/lib", dir, folder);
    mkdir(p, 0777);
    snprintf(p, sizeof p, "%s/%s/lib/m.obj", dir, folder);
    write_text(p, "v 0 0 0\n");
}

Test(assets, beside_the_scene_wins, .init = setup)
{
    char sp[512], a[512], want[512];
    write_scene(sp, sizeof sp);
    make_asset("scenes");
    make_asset("a");
    snprintf(a, sizeof a, "%s/a", dir);
    const char *dirs[] = {a};
    dm_error err = {0};
    cr_assert_eq(dm_scene_read_assets(sp, dirs, 1, &scene, &err), DM_OK, "%s", err.detail);
    snprintf(want, sizeof want, "%s/scenes/lib/m.obj", dir);
    cr_expect_str_eq(scene.mesh, want);
}

Test(assets, option_folders_in_order_then_environment, .init = setup)
{
    char sp[512], a[512], b[512], env[1100], want[700];
    write_scene(sp, sizeof sp);
    make_asset("b");
    make_asset("e");
    snprintf(a, sizeof a, "%s/a", dir); /* has no lib/m.obj */
    snprintf(b, sizeof b, "%s/b", dir);
    const char *dirs[] = {a, b};
    dm_error err = {0};
    cr_assert_eq(dm_scene_read_assets(sp, dirs, 2, &scene, &err), DM_OK, "%s", err.detail);
    snprintf(want, sizeof want, "%s/lib/m.obj", b);
    cr_expect_str_eq(scene.mesh, want);
    /* no option folders: the second folder of DERMIS_ASSETS */
    snprintf(env, sizeof env, "%s/none:%s/e", dir, dir);
    setenv("DERMIS_ASSETS", env, 1);
    cr_assert_eq(dm_scene_read(sp, &scene, &err), DM_OK, "%s", err.detail);
    snprintf(want, sizeof want, "%s/e/lib/m.obj", dir);
    cr_expect_str_eq(scene.mesh, want);
    unsetenv("DERMIS_ASSETS");
}

Test(assets, not_found_names_every_place, .init = setup)
{
    char sp[512], a[512], env[512], needle[600];
    write_scene(sp, sizeof sp);
    snprintf(a, sizeof a, "%s/opt", dir);
    snprintf(env, sizeof env, "%s/env", dir);
    setenv("DERMIS_ASSETS", env, 1);
    const char *dirs[] = {a};
    dm_error err = {0};
    cr_assert_eq(dm_scene_read_assets(sp, dirs, 1, &scene, &err), DM_ERR_FILE_OPEN);
    unsetenv("DERMIS_ASSETS");
    const char *needles[] = {"$.mesh.path", "\"lib/m.obj\" not found", "(the scene's folder)", "(--assets)",
                             "(DERMIS_ASSETS)", "--assets DIR"};
    for (size_t k = 0; k < sizeof needles / sizeof needles[0]; ++k)
        cr_expect(strstr(err.detail, needles[k]), "'%s' not in: %s", needles[k], err.detail);
    snprintf(needle, sizeof needle, "%s/scenes/lib/m.obj", dir);
    cr_expect(strstr(err.detail, needle), "%s", err.detail);
    snprintf(needle, sizeof needle, "%s/lib/m.obj", a);
    cr_expect(strstr(err.detail, needle), "%s", err.detail);
    snprintf(needle, sizeof needle, "%s/lib/m.obj", env);
    cr_expect(strstr(err.detail, needle), "%s", err.detail);
}

/* Parsing a string (how packs re-read their stored scene) never touches the disk. */
Test(assets, parse_does_not_search, .init = setup)
{
    dm_error err = {0};
    cr_assert_eq(dm_scene_parse("{\"mesh\": {\"path\": \"lib/m.obj\"}, \"effects\": {}}", "/x/s.json", &scene, &err),
                 DM_OK, "%s", err.detail);
    cr_expect_str_eq(scene.mesh, "/x/lib/m.obj");
}

Test(assets, output_folders_are_created, .init = setup)
{
    char out[512];
    snprintf(out, sizeof out, "%s/new/deeper/o.txt", dir);
    dm_atomic_file af;
    dm_error err = {0};
    cr_assert_eq(dm_atomic_open(&af, out, &err), DM_OK, "%s", err.detail);
    fputs("x", af.fp);
    cr_assert_eq(dm_atomic_commit(&af, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(access(out, R_OK), 0);
    /* a file in the way of a folder is an error naming it */
    snprintf(out, sizeof out, "%s/new/deeper/o.txt/x.txt", dir);
    cr_expect_eq(dm_atomic_begin(&af, out, &err), DM_ERR_FILE_WRITE);
    cr_expect(strstr(err.detail, "is not a folder"), "%s", err.detail);
}

/* Leaves the temporary of `target` as a run killed with SIGKILL leaves it (a child that
 * _exits inside the write); returns the child's (dead) PID. */
static pid_t leave_temporary(const char *target)
{
    pid_t child = fork();
    if (child == 0) {
        dm_atomic_file af;
        dm_error err = {0};
        _exit(dm_atomic_begin(&af, target, &err) == DM_OK ? 0 : 1);
    }
    int st = 0;
    waitpid(child, &st, 0);
    cr_assert(WIFEXITED(st) && WEXITSTATUS(st) == 0);
    return child;
}

/* A temporary file of a dead process (kill -9) is removed by the next write of the same
 * target; one of a live process, other targets' files, and files named like temporaries
 * without dermis's marker (core/dm_file.h) are left alone. */
Test(assets, stale_temporaries_of_dead_processes_removed, .init = setup)
{
    char stale[512], live[512], other[512], out[512], other_out[512], old_style[512];
    snprintf(out, sizeof out, "%s/o.txt", dir);
    snprintf(other_out, sizeof other_out, "%s/p.txt", dir);
    pid_t child = leave_temporary(out), other_child = leave_temporary(other_out);
    snprintf(stale, sizeof stale, "%s/o.txt.tmp.%ld.dermis", dir, (long)child);
    snprintf(other, sizeof other, "%s/p.txt.tmp.%ld.dermis", dir, (long)other_child);
    snprintf(live, sizeof live, "%s/o.txt.tmp.%ld.dermis", dir, (long)getppid()); /* no marker, live PID */
    snprintf(old_style, sizeof old_style, "%s/o.txt.tmp.%ld", dir, (long)child);  /* the user's own */
    write_text(live, "half");
    write_text(old_style, "mine");
    cr_assert_eq(access(stale, F_OK), 0);
    dm_atomic_file af;
    dm_error err = {0};
    cr_assert_eq(dm_atomic_open(&af, out, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_atomic_commit(&af, &err), DM_OK, "%s", err.detail);
    cr_expect_neq(access(stale, F_OK), 0, "stale file kept");
    cr_expect_eq(access(live, F_OK), 0, "a file without the marker removed");
    cr_expect_eq(access(old_style, F_OK), 0, "a user's file named like an old temporary removed");
    cr_expect_eq(access(other, F_OK), 0, "another target's file removed");
}

/* A relative asset folder (DERMIS_ASSETS=../shared/assets, as make test exports it) gives
 * an absolute path: the scene is stored in packs and copied to other folders. */
Test(assets, relative_asset_folder_gives_an_absolute_path, .init = setup)
{
    char sp[512];
    write_scene(sp, sizeof sp);
    make_asset("e");
    cr_assert_eq(chdir(dir), 0);
    setenv("DERMIS_ASSETS", "e", 1);
    dm_error err = {0};
    cr_assert_eq(dm_scene_read(sp, &scene, &err), DM_OK, "%s", err.detail);
    unsetenv("DERMIS_ASSETS");
    cr_expect_eq(scene.mesh[0], '/', "%s", scene.mesh);
    cr_expect(strstr(scene.mesh, "/e/lib/m.obj"), "%s", scene.mesh);
}
