/* Outputs checked before the work (issue 31, point 3; docs/files.md, core/dm_output.h): the
 * extension names the format (any case), an output is never an input, an unwritable
 * folder is refused before any work, messages name the user's path and never a temporary,
 * and only temporaries provably a dead dermis run's own are removed (core/dm_file.h). */
#include <criterion/criterion.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "core/dm_file.h"
#include "../common/gltf_write.h"
#include "../common/expect_tool.h"

#define HEAD DERMIS_ASSETS "/lps/LeePerrySmith.obj"
#define ENV DERMIS_ASSETS "/env/venice_sunset_1k.hdr"

static char dir[256], ro[300];
static bool immutable;

static void setup(void)
{
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(ro, sizeof ro, "%s/ro", dir);
}

/* The unwritable folder must not outlive the test (the run's scratch root is removed). */
static void teardown(void)
{
    char cmd[400];
    if (immutable) snprintf(cmd, sizeof cmd, "chattr -i '%s'", ro), test_run(cmd, NULL);
    chmod(ro, 0755);
}
TestSuite(outputs, .init = setup, .fini = teardown, .timeout = 120);

#define in_dir(name) test_path_in(dir, name)
/* the tool under `timeout 60`; the seconds it took */
#define expect(cmd, rc, n1, n2) test_expect_tool(dir, 60, cmd, rc, n1, n2)

static bool starts_with_bytes(const char *path, const char *magic, size_t n)
{
    char *text = test_slurp(path);
    bool ok = text && memcmp(text, magic, n) == 0;
    free(text);
    return ok;
}

static bool have_viewer(void)
{
    return access(DERMIS_BIN "/dermis-view", X_OK) == 0;
}

#define EXT "expected a name ending in"

Test(outputs, extension_names_the_format_in_any_case)
{
    const char *scene = "{\"format\":\"dermis-scene\",\"version\":1,\"mesh\":{\"path\":\"" HEAD "\"},\"effects\":{}}";
    cr_assert_eq(test_write_bytes(in_dir("s.json"), scene, strlen(scene)), 0);
    expect(DERMIS_BIN "/dermis-bake-stretch " HEAD " -o o.png", 1, "-o o.png: " EXT " .exr", NULL);
    expect(DERMIS_BIN "/dermis-bake-curvature " HEAD " -o o.png", 1, EXT " .exr", NULL);
    expect(DERMIS_BIN "/dermis-bake-env " ENV " -o e.png", 1, EXT " .exr", NULL);
    expect(DERMIS_BIN "/dermis-bake-lut --beckmann b.exr", 1, "--beckmann b.exr: " EXT " .png", NULL);
    expect(DERMIS_BIN "/dermis-bake-lut --rho-dt r.png", 1, "--rho-dt r.png: " EXT " .exr", NULL);
    expect(DERMIS_BIN "/dermis-bake-lut --env-brdf e.png", 1, EXT " .exr", NULL);
    expect(DERMIS_BIN "/dermis-bake-lut --float f.png", 1, EXT " .exr", NULL);
    expect(DERMIS_BIN "/dermis-bake-lut --tables preintegrated --preintegrated p.png", 1, EXT " .exr", NULL);
    expect(DERMIS_BIN "/dermis-fit-profile --preset gems3-skin -o p.exr", 1, EXT " .json", NULL);
    expect(DERMIS_BIN "/dermis-pack s.json -o p.png", 1, EXT " .dpk", NULL);
    expect(DERMIS_BIN "/dermis-reference x.dpk --texture-space 16 -o r.png", 1, EXT " .exr", NULL);
    expect(DERMIS_BIN "/dermis-render --synthetic quad -o r.jpg", 1, EXT " .png or .exr", NULL);
    expect(DERMIS_BIN "/dermis-render --synthetic quad --reference x.exr -o r.exr", 1, EXT " .png", NULL);
    if (have_viewer()) { /* the script is read before any window opens */
        cr_assert_eq(test_write_bytes(in_dir("shot.txt"), "0 screenshot x.exr\n", 19), 0);
        expect(DERMIS_BIN "/dermis-view --synthetic quad --script shot.txt", 1, "screenshot x.exr: " EXT " .png",
               "shot.txt:1:");
    }
    cr_expect_eq(test_count_files(dir, NULL), have_viewer() ? 3 : 2, "nothing written but s.json, shot.txt, the log");
    /* capitals are the same extension; the extension picks the format */
    expect(DERMIS_BIN "/dermis-bake-stretch " HEAD " -o S.EXR --size 16 --quiet", 0, NULL, NULL);
    expect(DERMIS_BIN "/dermis-fit-profile --preset gems3-skin -o P.Json --quiet", 0, NULL, NULL);
    expect(DERMIS_BIN "/dermis-bake-lut --tables beckmann --size 16 --beckmann B.PNG --quiet", 0, NULL, NULL);
    expect(DERMIS_BIN "/dermis-render --synthetic quad --size 16x16 --irradiance 16 -o R.PNG --quiet", 0, NULL, NULL);
    expect(DERMIS_BIN "/dermis-render --synthetic quad --size 16x16 --irradiance 16 -o R.Exr --quiet", 0, NULL, NULL);
    cr_expect(starts_with_bytes(in_dir("S.EXR"), "\x76\x2f\x31\x01", 4), "S.EXR is not an EXR");
    cr_expect(starts_with_bytes(in_dir("B.PNG"), "\x89PNG", 4), "B.PNG is not a PNG");
    cr_expect(starts_with_bytes(in_dir("R.PNG"), "\x89PNG", 4), "R.PNG is not a PNG");
    cr_expect(starts_with_bytes(in_dir("R.Exr"), "\x76\x2f\x31\x01", 4), "R.Exr is not an EXR");
}

/* An input given as the output (by name, hard link or symbolic link) is refused before it
 * is read, and stays as it was, byte for byte. */
Test(outputs, output_that_is_an_input_refused)
{
    const char *bytes = "an input that must not change\n";
    const char *names[] = {"e.exr", "t.exr", "s.dpk", "p.png"};
    for (int k = 0; k < 4; ++k) cr_assert_eq(test_write_bytes(in_dir(names[k]), bytes, strlen(bytes)), 0);
    cr_assert_eq(link(in_dir("e.exr"), in_dir("hard.exr")), 0);
    cr_assert_eq(symlink("e.exr", in_dir("sym.exr")), 0);
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "cp '%s' head.obj", HEAD);
    expect(cmd, 0, NULL, NULL);
    const char *same = "the same file as the input";
    expect(DERMIS_BIN "/dermis-bake-stretch head.obj -o head.obj", 1, EXT " .exr", NULL); /* the case */
    expect(DERMIS_BIN "/dermis-bake-env e.exr -o e.exr", 1, "-o e.exr: the same file as the input e.exr", NULL);
    expect(DERMIS_BIN "/dermis-bake-env e.exr -o hard.exr", 1, same, NULL);
    expect(DERMIS_BIN "/dermis-bake-env e.exr -o sym.exr", 1, same, NULL);
    expect(DERMIS_BIN "/dermis-reference --merge t.exr -o t.exr", 1, same, NULL);
    expect(DERMIS_BIN "/dermis-reference s.dpk --texture-space 16 --irradiance t.exr -o t.exr", 1, same, NULL);
    expect(DERMIS_BIN "/dermis-pack s.dpk -o s.dpk", 1, same, NULL);
    expect(DERMIS_BIN "/dermis-render p.png -o p.png", 1, same, NULL);
    for (int k = 0; k < 4; ++k) {
        char *text = test_slurp(in_dir(names[k]));
        cr_expect(text && !strcmp(text, bytes), "%s changed", names[k]);
        free(text);
    }
    char *head = test_slurp(in_dir("head.obj")), *orig = test_slurp(HEAD);
    cr_expect(head && orig && !strcmp(head, orig), "head.obj changed");
    free(head), free(orig);
}

/* A folder no file can be made in: read-only to a user; root needs the immutable flag. */
static void make_unwritable(void)
{
    cr_assert_eq(mkdir(ro, 0755), 0);
    char cmd[400];
    if (geteuid() == 0) {
        snprintf(cmd, sizeof cmd, "chattr +i '%s'", ro);
        immutable = test_run(cmd, NULL) == 0;
        if (!immutable) cr_skip_test("root without chattr +i: no folder root cannot write");
    } else {
        cr_assert_eq(chmod(ro, 0555), 0);
    }
}

/* Refused before any work: dermis-reference at 128² works 9 s before writing; refused in
 * well under a second, naming the path. The missing folders below an unwritable one too. */
Test(outputs, unwritable_folder_refused_before_the_work, .timeout = 180)
{
    char cmd[2048], cwd[1024];
    cr_assert(getcwd(cwd, sizeof cwd));
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack '%s/assets/scenes/lps-sss.json' -o p.dpk --quiet", cwd);
    expect(cmd, 0, NULL, NULL);
    make_unwritable();
    double s = expect(DERMIS_BIN "/dermis-reference p.dpk --texture-space 128 -o ro/r.exr", 4, "-o ro/r.exr",
                      "cannot write in the folder");
    cr_expect_lt(s, 1.0, "refused after %.2f s: the check came after the work", s);
    s = expect(DERMIS_BIN "/dermis-bake-stretch " HEAD " -o ro/new/s.exr --size 4096", 4, "ro/new/s.exr", NULL);
    cr_expect_lt(s, 1.0, "refused after %.2f s", s);
    expect(DERMIS_BIN "/dermis-bake-curvature " HEAD " -o ro/c.exr", 4, "ro/c.exr", NULL);
    expect(DERMIS_BIN "/dermis-bake-env " ENV " -o ro/e.exr", 4, "ro/e.exr", NULL);
    expect(DERMIS_BIN "/dermis-bake-lut -o ro", 4, "ro/beckmann.png", NULL);
    expect(DERMIS_BIN "/dermis-fit-profile --dipole skin1 -o ro/p.json", 4, "ro/p.json", NULL);
    expect(DERMIS_BIN "/dermis-render p.dpk -o ro/r.png", 4, "ro/r.png", NULL);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack '%s/assets/scenes/lps-sss.json' -o ro/p.dpk", cwd);
    expect(cmd, 4, "ro/p.dpk", NULL);
    if (have_viewer()) {
        cr_assert_eq(test_write_bytes(in_dir("shot.txt"), "0 screenshot ro/x.png\n", 22), 0);
        expect(DERMIS_BIN "/dermis-view --synthetic quad --script shot.txt", 4, "shot.txt:1:", "ro/x.png");
    }
    cr_expect_eq(test_count_files(ro, NULL), 0);
}

/* The error names the user's path, never a temporary (it named "/proc/version.png.tmp.N"). */
Test(outputs, messages_name_the_output_not_a_temporary)
{
    char log[320];
    snprintf(log, sizeof log, "%s/log.txt", dir);
    expect(DERMIS_BIN "/dermis-render --synthetic quad --size 16x16 -o /proc/version.png", 4, "-o /proc/version.png:",
           NULL);
    char *text = test_slurp(log);
    cr_expect(text && !strstr(text, ".tmp") && !strstr(text, ".dermis"), "%s", text ? text : "");
    free(text);
    /* the writer's own message, for callers that write without dm_output_check */
    dm_atomic_file af;
    dm_error err = {0};
    cr_expect_eq(dm_atomic_open(&af, "/proc/version.png", &err), DM_ERR_FILE_WRITE);
    cr_expect(strstr(err.detail, "/proc/version.png:") && !strstr(err.detail, ".tmp"), "%s", err.detail);
}

/* A user's own "o.png.tmp.999999", and a file named exactly like a dermis temporary but
 * without its marker, survive a run writing o.png; a real leftover of a killed run (made
 * by a child that _exits inside a write, as SIGKILL leaves it) is removed. */
Test(outputs, only_provable_temporaries_removed)
{
    pid_t child = fork();
    cr_assert_neq(child, -1);
    if (child == 0) {
        dm_atomic_file af;
        dm_error err = {0};
        _exit(dm_atomic_begin(&af, in_dir("o.png"), &err) == DM_OK ? 0 : 1); /* no cleanup: as SIGKILL */
    }
    int st;
    waitpid(child, &st, 0);
    cr_assert(WIFEXITED(st) && WEXITSTATUS(st) == 0);
    char leftover[512], user[512], lookalike[512];
    snprintf(leftover, sizeof leftover, "%s/o.png.tmp.%ld.dermis", dir, (long)child);
    cr_assert_eq(access(leftover, F_OK), 0, "the child left no %s", leftover);
    snprintf(user, sizeof user, "%s/o.png.tmp.999999", dir);
    pid_t dead = fork(); /* a PID certainly dead */
    if (dead == 0) _exit(0);
    waitpid(dead, NULL, 0);
    snprintf(lookalike, sizeof lookalike, "%s/o.png.tmp.%ld.dermis", dir, (long)dead);
    cr_assert_eq(test_write_bytes(user, "mine", 4), 0);
    cr_assert_eq(test_write_bytes(lookalike, "mine too", 8), 0);
    expect(DERMIS_BIN "/dermis-render --synthetic quad --size 16x16 --irradiance 16 -o o.png", 0,
           "removed", "left by an interrupted run");
    cr_expect_neq(access(leftover, F_OK), 0, "the killed run's temporary is still there");
    char *a = test_slurp(user), *b = test_slurp(lookalike);
    cr_expect(a && !strcmp(a, "mine"), "the user's o.png.tmp.999999 was removed or changed");
    cr_expect(b && !strcmp(b, "mine too"), "a file without the marker was removed");
    free(a), free(b);
    cr_expect(starts_with_bytes(in_dir("o.png"), "\x89PNG", 4));
}
