/* dermis-render as a person runs it: exit codes, no partial output, --compare-exact. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/tmpdir.h"

#define BIN DERMIS_BIN "/dermis-render"
#define SMALL "--synthetic sphere --size 96x64 --irradiance 128"

Test(render_tool, exit_codes_and_no_partial_file)
{
    char dir[64], cmd[512], log[160];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(log, sizeof log, "%s/log", dir);
    cr_expect_eq(test_run(BIN " " SMALL " --pcf-taps 3", NULL), 1);
    cr_expect_eq(test_run(BIN " " SMALL " --shadow-size 8", NULL), 1);
    cr_expect_eq(test_run(BIN " " SMALL " --shadow-size 16384", NULL), 1);
    cr_expect_eq(test_run(BIN " " SMALL " --blur-reduce-shift 2", NULL), 1, "shift without from");
    cr_expect_eq(test_run(BIN " " SMALL " --view nope", NULL), 1);
    cr_expect_eq(test_run(BIN " /nonexistent.dpk -o /tmp/x.png", log), 2);
    char *text = test_slurp(log);
    cr_expect(text && strstr(text, "/nonexistent.dpk"), "%s", text ? text : "");
    free(text);
    snprintf(cmd, sizeof cmd, "printf garbage > %s/bad.dpk; " BIN " %s/bad.dpk -o %s/x.png", dir, dir, dir);
    cr_expect_eq(test_run(cmd, NULL), 2, "a corrupt pack is a load error");
    cr_expect_eq(test_run(BIN " " SMALL " -o /dev/null/dir/x.png", NULL), 4);
    snprintf(cmd, sizeof cmd, BIN " " SMALL " -o %s/ok.png", dir);
    cr_expect_eq(test_run(cmd, NULL), 0);
    cr_expect_eq(test_count_files(dir, ".tmp."), 0);
    cr_expect_eq(test_count_files(dir, "x.png"), 0);
}

/* dermis-render SMALL --compare-exact FLAGS: its report, and the number after `key` in it */
static char *compare_exact(const char *flags, const char *log)
{
    char cmd[512];
    snprintf(cmd, sizeof cmd, BIN " " SMALL " --compare-exact %s", flags);
    cr_assert_eq(test_run(cmd, log), 0, "%s", cmd);
    char *text = test_slurp(log);
    cr_assert(text && strstr(text, "compare-exact: this setting"), "%s", text ? text : "");
    return text;
}

static double number_after(const char *text, const char *key)
{
    double v = 0;
    const char *at = strstr(text, key);
    cr_assert(at && sscanf(at + strlen(key), "%lf", &v) == 1, "no '%s' in:\n%s", key, text);
    return v;
}

/* Every speed setting reports its error against the exact path and both times. */
Test(render_tool, compare_exact_reports_error_and_time, .timeout = 120)
{
    char dir[64], log[160];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(log, sizeof log, "%s/log", dir);
    /* the default with the levels summed per pixel equals the exact path (9 PCF taps, the sum
     * per pixel) to float rounding: no display step */
    char *text = compare_exact("--frames 2 --diffusion-per-pixel", log);
    cr_expect(strstr(text, "display: 0 steps"), "the per-pixel default differs from exact:\n%s", text);
    cr_expect(strstr(text, "blur5"), "no blur level compared:\n%s", text);
    free(text);
    /* the default's per-texel sum parts from it only along chart edges: the same levels (blur5
     * to float rounding), at most one display step */
    text = compare_exact("--frames 2", log);
    cr_expect_leq(number_after(text, "blur5 (coverage-normalised): max |d| "), 1e-5, "the levels differ:\n%s", text);
    cr_expect(strstr(text, "display: 0 steps") || strstr(text, "display: 1 steps"), "more than one step:\n%s", text);
    free(text);
    /* a real trade shows a real difference */
    text = compare_exact("--pcf-taps 1 --blur-reduce-from 3", log);
    cr_expect_gt(number_after(text, "max |d| "), 0.0, "a one-tap shadow and half-resolution blurs changed nothing:\n%s",
                 text);
    free(text);
}
