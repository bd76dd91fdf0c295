/* dermis-render's pictures record every speed/accuracy setting of dm_render_desc in their
 * provenance (issue 17 point 7), defaults resolved, and --compare-exact reports medians of
 * warm frames. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/tmpdir.h"

/* The whole file (binary: PNG), and whether `needle` occurs in it. */
static bool file_holds(const char *path, const char *needle)
{
    FILE *f = fopen(path, "rb");
    if (!f) return false;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = malloc((size_t)n);
    size_t got = fread(b, 1, (size_t)n, f);
    fclose(f);
    size_t m = strlen(needle);
    bool found = false;
    for (size_t i = 0; !found && i + m <= got; ++i) found = memcmp(b + i, needle, m) == 0;
    free(b);
    return found;
}

Test(render_provenance, every_speed_setting_recorded, .timeout = 120)
{
    char dir[256], cmd[1024], png[300];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(png, sizeof png, "%s/a.png", dir);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-render --synthetic sphere --size 64x48 --irradiance 64 -o %s --quiet",
             png);
    cr_assert_eq(test_run(cmd, NULL), 0);
    const char *plain[] = {"\"shadow_pcf_taps\":4", "\"shadow_size\":2048", "\"blur_reduce_from\":0",
                           "\"blur_reduce_shift\":0", "\"blur_half_float\":0", "\"reuse_texture_space\":0",
                           "\"blur_on\":\"cpu\"", /* llvmpipe, float levels */
                           "\"diffusion_sum\":\"per_texel\""};
    for (size_t k = 0; k < sizeof plain / sizeof plain[0]; ++k)
        cr_expect(file_holds(png, plain[k]), "%s not in the provenance of %s", plain[k], png);
    snprintf(png, sizeof png, "%s/b.png", dir);
    snprintf(cmd, sizeof cmd,
             DERMIS_BIN "/dermis-render --synthetic sphere --size 64x48 --irradiance 64 --pcf-taps 1 "
                        "--shadow-size 512 --blur-reduce-from 3 --blur-reduce-shift 2 --half-float -o %s --quiet",
             png);
    cr_assert_eq(test_run(cmd, NULL), 0);
    const char *set[] = {"\"shadow_pcf_taps\":1", "\"shadow_size\":512", "\"blur_reduce_from\":3", "\"blur_reduce_shift\":2",
                         "\"blur_half_float\":1", "\"blur_on\":\"gl\"",
                         "\"diffusion_sum\":\"per_pixel\""}; /* reduced levels: always per pixel */
    for (size_t k = 0; k < sizeof set / sizeof set[0]; ++k)
        cr_expect(file_holds(png, set[k]), "%s not in the provenance of %s", set[k], png);
}

Test(render_provenance, compare_exact_uses_warm_medians, .timeout = 120)
{
    char dir[256], cmd[1024], log[300];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(log, sizeof log, "%s/log", dir);
    snprintf(cmd, sizeof cmd,
             DERMIS_BIN "/dermis-render --synthetic sphere --size 64x48 --irradiance 64 --pcf-taps 1 --compare-exact "
                        "--frames 2");
    cr_assert_eq(test_run(cmd, log), 0);
    char *text = test_slurp(log);
    cr_expect(text && strstr(text, "median of 2 warm frames, after one warm-up frame each"), "%s", text ? text : "");
    free(text);
}
