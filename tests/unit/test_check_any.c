/* dermis-check accepts every file a dermis tool writes (issue 17 point 6: the environment
 * EXR and the --float Beckmann EXR were refused) and says which tool and version made it;
 * a file without dermis provenance is still refused. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/tmpdir.h"

static void expect_ok(const char *dir, const char *file, const char *type, const char *tool)
{
    char cmd[1024], log[300], want[200];
    snprintf(log, sizeof log, "%s/check.log", dir);
    snprintf(cmd, sizeof cmd, "cd '%s' && " DERMIS_BIN "/dermis-check %s", dir, file);
    int rc = test_run(cmd, log);
    char *text = test_slurp(log);
    cr_expect_eq(rc, 0, "%s: %s", file, text ? text : "");
    snprintf(want, sizeof want, "%s: ok (%s, made by %s ", file, type, tool);
    cr_expect(text && strstr(text, want), "'%s' not in: %s", want, text ? text : "");
    free(text);
}

Test(check_any, every_tool_output, .timeout = 120)
{
    char dir[256], cmd[1024];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(cmd, sizeof cmd,
             "cd '%s' && " DERMIS_BIN "/dermis-bake-lut -o luts --float luts/exact.exr --quiet && " DERMIS_BIN
             "/dermis-bake-env " DERMIS_ASSETS "/env/venice_sunset_1k.hdr -o env.exr --samples 16 --quiet && " DERMIS_BIN
             "/dermis-render --synthetic sphere --size 64x48 --irradiance 64 -o sphere.png --quiet && " DERMIS_BIN
             "/dermis-render --synthetic sphere --size 64x48 --irradiance 64 -o sphere.exr --quiet && " DERMIS_BIN
             "/dermis-fit-profile --dipole skin1 -n 2 -o p.json --quiet",
             dir);
    cr_assert_eq(test_run(cmd, NULL), 0, "%s", cmd);
    expect_ok(dir, "env.exr", "env", "dermis-bake-env");
    expect_ok(dir, "luts/exact.exr", "lut.beckmann.float", "dermis-bake-lut");
    expect_ok(dir, "luts/beckmann.png", "lut.beckmann", "dermis-bake-lut");
    expect_ok(dir, "luts/rho_dt.exr", "lut.rho_dt", "dermis-bake-lut");
    expect_ok(dir, "luts/env_brdf.exr", "lut.env_brdf", "dermis-bake-lut");
    expect_ok(dir, "sphere.png", "picture", "dermis-render");
    expect_ok(dir, "sphere.exr", "image", "dermis-render");
}

Test(check_any, foreign_files_refused)
{
    char dir[256], cmd[1024];
    cr_assert(test_tmpdir(dir, sizeof dir));
    /* an EXR and a PNG that no dermis tool made (OpenImageIO's own writer) */
    snprintf(cmd, sizeof cmd, "cd '%s' && oiiotool --pattern constant:color=0.5 8x8 3 -o plain.exr && "
             "oiiotool --pattern constant:color=0.5 8x8 1 -d uint8 -o plain.png", dir);
    cr_assert_eq(test_run(cmd, NULL), 0, "%s", cmd);
    snprintf(cmd, sizeof cmd, "cd '%s' && " DERMIS_BIN "/dermis-check plain.exr", dir);
    cr_expect_eq(test_run(cmd, NULL), 1);
    snprintf(cmd, sizeof cmd, "cd '%s' && " DERMIS_BIN "/dermis-check plain.png", dir);
    cr_expect_eq(test_run(cmd, NULL), 1);
}
