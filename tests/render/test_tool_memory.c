/* dermis-pack's and dermis-reference's memory estimates (packer/dm_pack_build.h,
 * reference/dm_reference.h) against their peak resident sets, and their refusals before any work
 * of what does not fit (issue #31: an 8192 irradiance packed a 3.3 GB file; dermis-reference
 * --texture-space 8192 reached 15 GB in a minute with nothing printed). The refusals are
 * tested by pretending less memory is available (DERMIS_MEM_AVAILABLE_MB, core/dm_memory.h). */
#define _DEFAULT_SOURCE 1 /* wait4 */
#include <criterion/criterion.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "../common/tmpdir.h"
#include "packer/dm_pack_build.h"
#include "reference/dm_reference.h"
#include "core/dm_cli.h"
#include "pack/dm_pack.h"
#include "render/dm_render_memory.h"

#define PACK DERMIS_BIN "/dermis-pack"
#define REF DERMIS_BIN "/dermis-reference"
#define SCENE "assets/scenes/lps-sss.json"

/* Peak RSS (bytes) of `sh -c cmd` (its largest descendant: wait4 on the shell, which execs). */
static uint64_t peak_of(const char *cmd, int *code)
{
    pid_t pid = fork();
    cr_assert_geq(pid, 0);
    if (pid == 0) {
        FILE *q = freopen("/dev/null", "w", stdout);
        (void)q;
        execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
        _exit(127);
    }
    int st = 0;
    struct rusage ru;
    cr_assert_eq(wait4(pid, &st, 0, &ru), pid);
    *code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return (uint64_t)ru.ru_maxrss * 1024u;
}

static void expect_ratio(const char *what, uint64_t est, uint64_t peak)
{
    double ratio = (double)est / (double)peak;
    fprintf(stderr, "memory: %s: estimate %.1f MiB, peak RSS %.1f MiB, ratio %.2f\n", what, est / 1048576.0,
            peak / 1048576.0, ratio);
    cr_expect(ratio >= 0.8 && ratio <= 1.5, "%s: estimate %.1f MiB, measured %.1f MiB (%.2f)", what, est / 1048576.0,
              peak / 1048576.0, ratio);
}

/* A copy of the scene with another irradiance size, beside the original's assets. */
static void scene_with_size(const char *dir, int n, char *out, size_t out_size)
{
    snprintf(out, out_size, "%s/sss%d.json", dir, n);
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "cp " SCENE " %s && sed -i 's/\"irradiance_size\": [0-9]*/\"irradiance_size\": %d/' %s", out,
             n, out);
    cr_assert_eq(test_run(cmd, NULL), 0);
}

static uint64_t pack_estimate(const char *scene)
{
    dm_pack_build *b = malloc(sizeof *b);
    dm_pack_build_options o = {.quiet = true};
    dm_error err = {0};
    cr_assert(b);
    cr_assert_eq(dm_pack_build_begin(b, scene, NULL, 0, &o, &err), DM_OK, "%s", err.detail);
    dm_pack_build_memory m;
    dm_pack_build_memory_estimate(b, &m);
    dm_pack_build_free(b);
    free(b);
    return m.total_size;
}

Test(tool_memory, pack_estimate_within_its_factor, .timeout = 180)
{
#ifdef __SANITIZE_ADDRESS__
    cr_skip_test("peak RSS means nothing under AddressSanitizer (shadow memory, quarantine): measured in release builds");
#endif
    char dir[64], scene[128], cmd[1024];
    cr_assert(test_tmpdir(dir, sizeof dir));
    const int sizes[] = {1024, 2048};
    for (int i = 0; i < 2; ++i) {
        scene_with_size(dir, sizes[i], scene, sizeof scene);
        snprintf(cmd, sizeof cmd, PACK " %s -o %s/p.dpk --quiet", scene, dir);
        int code = -1;
        uint64_t peak = peak_of(cmd, &code);
        cr_assert_eq(code, 0, "%s", cmd);
        char what[64];
        snprintf(what, sizeof what, "dermis-pack irradiance_size %d", sizes[i]);
        expect_ratio(what, pack_estimate(scene), peak);
    }
}

/* The reproduction: a scene at irradiance_size 8192 where 4000 MiB are available. */
Test(tool_memory, pack_refused_before_any_work, .timeout = 60)
{
    char dir[64], scene[128], cmd[1024], log[128];
    cr_assert(test_tmpdir(dir, sizeof dir));
    scene_with_size(dir, 8192, scene, sizeof scene);
    snprintf(log, sizeof log, "%s/log", dir);
    snprintf(cmd, sizeof cmd, "DERMIS_MEM_AVAILABLE_MB=4000 " PACK " %s -o %s/big.dpk", scene, dir);
    double t0 = dm_now_ms();
    cr_expect_eq(test_run(cmd, log), 3);
    cr_expect_lt(dm_now_ms() - t0, 10000.0, "refused after the work, not before");
    char *text = test_slurp(log);
    cr_assert(text);
    /* base 176 MiB + twice the pack's grid-sized entries: N² (8·6 + 1 + 16 + 32 + 8) bytes each (the
     * thin-part map at N and N/2) and the thin gather at N/2 (4096², its largest): its index
     * (N²/4 · 16) and taps (up to 2^25 of 8 bytes), 0.5 GiB */
    cr_expect(strstr(text, "(irradiance_size 8192) needs about 14.") && strstr(text, "GiB of memory"), "%s", text);
    cr_expect(strstr(text, "more than the 3.91 GiB available (DERMIS_MEM_AVAILABLE_MB)"), "%s", text);
    cr_expect(strstr(text, "lower $.effects.subsurface.irradiance_size"), "%s", text);
    cr_expect(strstr(text, "GiB in the pack"), "%s", text);
    free(text);
    cr_expect_eq(test_count_files(dir, "big.dpk"), 0);
}

static char g_dir[64], g_pack[128];

static void packed(void)
{
    cr_assert(test_tmpdir(g_dir, sizeof g_dir));
    snprintf(g_pack, sizeof g_pack, "%s/lps-sss.dpk", g_dir);
    char cmd[512];
    snprintf(cmd, sizeof cmd, PACK " " SCENE " -o %s --quiet", g_pack);
    cr_assert_eq(test_run(cmd, NULL), 0);
}

static uint64_t reference_estimate(const dm_reference_memory_options *mo)
{
    dm_pack pack;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open(g_pack, &pack, &err), DM_OK, "%s", err.detail);
    dm_reference_memory_options o = *mo;
    dm_render_memory rm = {0};
    if (o.texture_space) {
        dm_render_desc d = {.width = 64, .height = 64, .irradiance_size = o.texture_space};
        cr_assert_eq(dm_render_memory_estimate_pack(&pack, &d, true, &rm, &err), DM_OK, "%s", err.detail);
        o.irradiance_render_size = rm.total_size;
    }
    dm_reference_memory m;
    dm_reference_memory_estimate(&pack, &o, &m);
    dm_pack_close(&pack);
    return m.total_size;
}

Test(tool_memory, reference_estimate_within_its_factor, .init = packed, .timeout = 240)
{
#ifdef __SANITIZE_ADDRESS__
    cr_skip_test("peak RSS means nothing under AddressSanitizer (shadow memory, quarantine): measured in release builds");
#endif
    static const struct { const char *args; dm_reference_memory_options o; } runs[] = {
        {"--texture-space 64", {.texture_space = 64}},
        {"--frame --size 64x36 --atlas 256", {.width = 64, .height = 36, .atlas_size = 256}},
        {"--frame --size 64x36 --atlas 1024 --atlas-samples 2", {.width = 64, .height = 36, .atlas_size = 1024, .atlas_samples = 2}},
    };
    for (size_t i = 0; i < sizeof runs / sizeof runs[0]; ++i) {
        char cmd[1024];
        snprintf(cmd, sizeof cmd, REF " %s %s -o %s/r.exr --quiet", g_pack, runs[i].args, g_dir);
        int code = -1;
        uint64_t peak = peak_of(cmd, &code);
        cr_assert_eq(code, 0, "%s", cmd);
        char what[96];
        snprintf(what, sizeof what, "dermis-reference %s", runs[i].args);
        expect_ratio(what, reference_estimate(&runs[i].o), peak);
    }
}

/* The reproduction: --texture-space 8192 where 8000 MiB are available. */
Test(tool_memory, reference_refused_before_any_work, .init = packed, .timeout = 60)
{
    char cmd[1024], log[128];
    snprintf(log, sizeof log, "%s/log", g_dir);
    snprintf(cmd, sizeof cmd, "DERMIS_MEM_AVAILABLE_MB=8000 " REF " %s --texture-space 8192 -o %s/big.exr", g_pack, g_dir);
    double t0 = dm_now_ms();
    cr_expect_eq(test_run(cmd, log), 3);
    cr_expect_lt(dm_now_ms() - t0, 10000.0, "refused after the work, not before");
    char *text = test_slurp(log);
    cr_assert(text);
    cr_expect(strstr(text, "--texture-space 8192 needs about ") && strstr(text, "GiB of memory"), "%s", text);
    cr_expect(strstr(text, "more than the 7.81 GiB available (DERMIS_MEM_AVAILABLE_MB): lower --texture-space"), "%s",
              text);
    free(text);
    snprintf(cmd, sizeof cmd, "DERMIS_MEM_AVAILABLE_MB=100 " REF " %s --frame --atlas 2048 -o %s/big.exr", g_pack, g_dir);
    cr_expect_eq(test_run(cmd, log), 3);
    text = test_slurp(log);
    cr_expect(text && strstr(text, "lower --atlas, --atlas-samples or --size"), "%s", text ? text : "");
    free(text);
    cr_expect_eq(test_count_files(g_dir, "big.exr"), 0);
}
