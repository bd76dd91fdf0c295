/* Interrupts: every tool, Ctrl-C to the process group (as a terminal sends it) and
 * SIGTERM, at several moments and while the output is being written, leaves no temporary
 * file and ends by the signal (the shell's 130 / 143) — or had finished cleanly.
 * (TOOLCHAIN.md "Signals in tests": the child gets its own process group, then
 * kill(-pgid, SIGINT); a background job's SIGINT would be ignored otherwise.) */
#include <criterion/criterion.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "../common/tmpdir.h"

#define HEAD DERMIS_ASSETS "/lps/LeePerrySmith.obj"
#define ENV DERMIS_ASSETS "/env/venice_sunset_1k.hdr"

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

typedef struct outcome {
    int status;      /* waitpid status */
    bool saw_tmp;    /* a temporary file existed when the signal was sent */
    bool signalled;  /* the signal was sent before the process ended */
} outcome;

/* Runs `cmd` (through sh -c 'exec ...') in its own process group in `dir`; sends `sig` to
 * the group after delay_ms, or (delay_ms < 0) as soon as a "*.tmp.*" file appears in
 * `watch` (the output's folder). */
static outcome run_and_signal(const char *dir, const char *watch, const char *cmd, int sig, double delay_ms)
{
    char line[4096];
    snprintf(line, sizeof line, "cd '%s' && exec %s >/dev/null 2>&1", dir, cmd);
    pid_t pid = fork();
    cr_assert_neq(pid, -1);
    if (pid == 0) {
        setpgid(0, 0);
        signal(SIGINT, SIG_DFL);
        signal(SIGTERM, SIG_DFL);
        execl("/bin/sh", "sh", "-c", line, (char *)NULL);
        _exit(127);
    }
    setpgid(pid, pid);
    outcome o = {0};
    double t0 = now_ms();
    for (;;) {
        int st;
        if (waitpid(pid, &st, WNOHANG) == pid) { /* finished before the signal */
            o.status = st;
            return o;
        }
        double t = now_ms() - t0;
        bool go = delay_ms >= 0 ? t >= delay_ms : test_count_files(watch, ".tmp.") > 0;
        if (go || t > 120000) break;
        nanosleep(&(struct timespec){0, 2000000}, NULL);
    }
    o.saw_tmp = test_count_files(watch, ".tmp.") > 0;
    o.signalled = true;
    kill(-pid, sig);
    waitpid(pid, &o.status, 0);
    return o;
}

/* After the run: no temporary file; ended by the signal (or 128 + signal), or exit 0. */
static void expect_clean(const char *what, const char *dir, int sig, outcome o)
{
    cr_expect_eq(test_count_files(dir, ".tmp."), 0, "%s: a temporary file is left in %s", what, dir);
    bool by_signal = (WIFSIGNALED(o.status) && WTERMSIG(o.status) == sig) ||
                     (WIFEXITED(o.status) && WEXITSTATUS(o.status) == 128 + sig);
    bool finished = WIFEXITED(o.status) && WEXITSTATUS(o.status) == 0;
    cr_expect(by_signal || (finished && !o.saw_tmp), "%s: status %#x (expected the signal %d, or exit 0 before it)",
              what, o.status, sig);
}

static void fresh_dir(char *dir, size_t size)
{
    cr_assert(test_tmpdir(dir, size));
}

/* The stage that used to leak: the 4096² stretch EXR (535 MB) being written on several
 * threads, Ctrl-C to the group and SIGTERM. */
Test(signals, stretch_4096_interrupted_while_writing, .timeout = 300)
{
    const int sigs[] = {SIGINT, SIGTERM};
    for (int k = 0; k < 2; ++k) {
        char dir[256], out[300];
        fresh_dir(dir, sizeof dir);
        snprintf(out, sizeof out, "%s/out", dir); /* made by the tool */
        outcome o = run_and_signal(dir, out, DERMIS_BIN "/dermis-bake-stretch " HEAD " -o out/s.exr --size 4096 --quiet",
                                   sigs[k], -1);
        cr_expect(o.saw_tmp, "the signal was sent while the EXR was being written");
        expect_clean(sigs[k] == SIGINT ? "stretch 4096, SIGINT while writing" : "stretch 4096, SIGTERM while writing",
                     out, sigs[k], o);
        cr_expect_eq(test_count_files(out, NULL), 0, "nothing left in %s", out);
    }
}

/* Every tool, every stage: the signal at a spread of moments from start-up to the end. */
static void sweep(const char *name, const char *args, const double *delays, int delay_count)
{
    const int sigs[] = {SIGINT, SIGTERM};
    for (int d = 0; d < delay_count; ++d)
        for (int k = 0; k < 2; ++k) {
            char dir[256], cmd[2048], what[256];
            fresh_dir(dir, sizeof dir);
            snprintf(cmd, sizeof cmd, DERMIS_BIN "/%s %s", name, args);
            outcome o = run_and_signal(dir, dir, cmd, sigs[k], delays[d]);
            snprintf(what, sizeof what, "%s, %s after %.0f ms", name, sigs[k] == SIGINT ? "SIGINT" : "SIGTERM",
                     delays[d]);
            expect_clean(what, dir, sigs[k], o);
        }
}

Test(signals, bake_lut_any_moment, .timeout = 300)
{
    const double at[] = {5, 40, 80, 120, 200, -1};
    sweep("dermis-bake-lut", "-o luts --quiet", at, 6);
}

Test(signals, fit_profile_any_moment, .timeout = 300)
{
    const double at[] = {5, 50, 150, -1};
    sweep("dermis-fit-profile", "--dipole skin1 -o p.json --quiet", at, 4);
}

Test(signals, bake_env_any_moment, .timeout = 300)
{
    const double at[] = {5, 200, 600, -1};
    sweep("dermis-bake-env", ENV " -o e.exr --samples 64 --quiet", at, 4);
}

Test(signals, stretch_any_moment, .timeout = 300)
{
    const double at[] = {5, 100, 400, -1};
    sweep("dermis-bake-stretch", HEAD " -o s.exr --size 512 --quiet", at, 4);
}

Test(signals, seams_any_moment, .timeout = 300)
{
    const double at[] = {5, 100, 300, -1};
    sweep("dermis-bake-seams", HEAD " -o s.exr --size 2048 --quiet", at, 4);
}

/* dermis-pack (its bakes, then the 76 MiB pack being written), then dermis-render and
 * dermis-reference on the pack it made, and dermis-check reading it. */
Test(signals, pack_render_reference_check_any_moment, .timeout = 600)
{
    char cwd[512], dir[256], cmd[2048], args[1200];
    cr_assert(getcwd(cwd, sizeof cwd));
    const double at[] = {5, 300, 1200, -1};
    snprintf(args, sizeof args, "'%s/assets/scenes/lps-sss.json' -o p.dpk --quiet", cwd);
    sweep("dermis-pack", args, at, 4);
    /* a whole pack for the readers */
    fresh_dir(dir, sizeof dir);
    snprintf(cmd, sizeof cmd, "cd '%s' && " DERMIS_BIN "/dermis-pack %s", dir, args);
    cr_assert_eq(test_run(cmd, NULL), 0, "%s", cmd);
    const double at_render[] = {5, 150, 500, -1};
    snprintf(args, sizeof args, "'%s/p.dpk' -o r.png --size 320x180 --irradiance 256 --quiet", dir);
    sweep("dermis-render", args, at_render, 4);
    snprintf(args, sizeof args, "'%s/p.dpk' --texture-space 64 -o ref.exr --quiet", dir);
    sweep("dermis-reference", args, at_render, 4);
    snprintf(args, sizeof args, "--quiet '%s/p.dpk'", dir);
    const double at_check[] = {5, 100};
    sweep("dermis-check", args, at_check, 2);
}

Test(signals, thin_any_moment, .timeout = 300)
{
    const double at[] = {5, 100, 300, -1};
    sweep("dermis-bake-thin", HEAD " -o t.exr --size 1024 --threads 2 --quiet", at, 4);
}
