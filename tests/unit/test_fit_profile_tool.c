/* dermis-fit-profile as a user runs it: outputs, byte-identical reruns, the JSON read
 * back through core's dm_profile_read (what dermis-bake-stretch --profile uses), the
 * table, and the exit codes of STYLE.md §6. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/expect_tool.h"
#include "../common/tmpdir.h"
#include "image/dm_exr.h"
#include "core/dm_profile.h"

#define BIN DERMIS_BIN "/dermis-fit-profile"

Test(fit_profile_tool, dipole_output_reads_back_normalised)
{
    char dir[64], cmd[1024], path[256];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(path, sizeof path, "%s/skin1.json", dir);
    snprintf(cmd, sizeof cmd, BIN " --dipole skin1 -n 5 -o %s --quiet", path);
    cr_assert_eq(test_run(cmd, NULL), 0);
    dm_profile p;
    dm_error err = {0};
    cr_assert_eq(dm_profile_read(path, &p, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(p.count, 5);
    cr_assert_str_eq(p.name, "skin1-dipole");
    double s[3];
    dm_profile_channel_sums(&p, s);
    for (int c = 0; c < 3; ++c) cr_assert(fabs(s[c] - 1.0) < 1e-12, "channel %d sums to %.17g", c, s[c]);
    char *json = test_slurp(path);
    cr_assert(json && strstr(json, "\"provenance\"") && strstr(json, "\"sigma_a_per_mm\"") &&
              strstr(json, "\"relative_rgb\"") && strstr(json, "\"blur_passes\": 8"));
    free(json);
    cr_assert_eq(test_count_files(dir, ".tmp."), 0, "temporary file left behind");
}

Test(fit_profile_tool, reruns_are_byte_identical)
{
    char dir[64], cmd[1024], a[256], b[256];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(a, sizeof a, "%s/a.json", dir);
    snprintf(b, sizeof b, "%s/b.json", dir);
    snprintf(cmd, sizeof cmd, BIN " --multipole 0.05,0.2,0.5,1.0,1.2,1.4,1.4 --thickness 0.8 -o %s --quiet", a);
    cr_assert_eq(test_run(cmd, NULL), 0);
    snprintf(cmd, sizeof cmd, BIN " --multipole 0.05,0.2,0.5,1.0,1.2,1.4,1.4 --thickness 0.8 -o %s --quiet", b);
    cr_assert_eq(test_run(cmd, NULL), 0);
    char *x = test_slurp(a), *y = test_slurp(b);
    cr_assert(x && y);
    cr_assert_str_eq(x, y);
    free(x);
    free(y);
}

Test(fit_profile_tool, gems3_preset_is_reproduced)
{
    char dir[64], cmd[1024], path[256];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(path, sizeof path, "%s/g.json", dir);
    snprintf(cmd, sizeof cmd, BIN " --preset gems3-skin -o %s --quiet", path);
    cr_assert_eq(test_run(cmd, NULL), 0);
    dm_profile p, ref;
    cr_assert_eq(dm_profile_read(path, &p, NULL), DM_OK);
    dm_profile_gems3_skin(&ref);
    /* The fit recovers the table it was given (error ~1e-15); 1e-6 on each number. */
    for (int k = 0; k < 6; ++k) {
        cr_assert(fabs(p.variance_mm2[k] / ref.variance_mm2[k] - 1.0) < 1e-6);
        for (int c = 0; c < 3; ++c) cr_assert(fabs(p.weight[k][c] - ref.weight[k][c]) < 1e-6);
    }
}

Test(fit_profile_tool, table_lists_every_n_with_its_passes)
{
    char dir[64], log[256];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(log, sizeof log, "%s/log", dir);
    cr_assert_eq(test_run(BIN " --dipole skin2 --table", log), 0);
    char *out = test_slurp(log);
    cr_assert(out && strstr(out, "passes") && strstr(out, "err_max"), "%s", out);
    cr_assert(strstr(out, "\n6   10 ") && strstr(out, "\n8   14 ") && strstr(out, "\n1   0 "), "%s", out);
    free(out);
}

Test(fit_profile_tool, invalid_parameters_are_usage_errors_with_a_message)
{
    char dir[64], log[256];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(log, sizeof log, "%s/log", dir);
    const test_usage_case bad[] = {
        {"--dipole -0.1,1,1.3", "sigma_a_per_mm[R] = -0.1"},
        {"--dipole nan,1,1.3", "sigma_a_per_mm[R] = nan"},
        {"--dipole 0.1,0,1.3", "sigma_s_prime_per_mm[R] = 0"},
        {"--dipole 0.1,1,0.5", "eta = 0.5"},
        {"--dipole 0.1,1", "expected 3"},
        {"--dipole skin9", "unknown"},
        {"--multipole skin1", "--thickness"},
        {"--multipole skin1 --thickness -2", "--thickness"},
        {"--dipole skin1 --thickness 1", "--multipole only"},
        {"--preset gems3-skin --dipole skin1", "exclude"},
        {"--preset other", "unknown"},
        {"--dipole skin1 -n 9", "-n"},
        {"--dipole skin1 -n 0", "-n"},
        {"--dipole skin1 --nodes 600", "odd"},
        {"--dipole skin1", "-o"},
        {"--dipole skin1 --bogus", "unknown option"},
    };
    test_expect_usage_errors(BIN, dir, bad, sizeof bad / sizeof bad[0]);
    cr_expect_eq(test_count_files(dir, "x.json"), 0, "an output was written despite the error");
    cr_expect_eq(test_run(BIN " --help", NULL), 0);
}

Test(fit_profile_tool, unwritable_output_is_exit_4)
{
    cr_expect_eq(test_run(BIN " --dipole skin1 -n 2 -o /dev/null/folder/p.json --quiet", NULL), 4);
}

/* Issue 4's hand-over: a fitted profile JSON drives dermis-bake-stretch's chain. The
 * stretch EXR must have one level per fitted Gaussian and record exactly its variances. */
Test(fit_profile_tool, fitted_json_is_consumed_by_bake_stretch, .timeout = 60)
{
    char dir[64], cmd[1024], json[160], exr[160];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(json, sizeof json, "%s/skin1.json", dir);
    snprintf(exr, sizeof exr, "%s/stretch.exr", dir);
    snprintf(cmd, sizeof cmd, BIN " --dipole skin1 -n 4 -o %s --quiet", json);
    cr_assert_eq(test_run(cmd, NULL), 0);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-bake-stretch %s/lps/LeePerrySmith.obj -o %s --size 128 --profile %s --quiet",
             DERMIS_ASSETS, exr, json);
    cr_assert_eq(test_run(cmd, NULL), 0, "%s", cmd);
    dm_profile p;
    dm_error err = {0};
    cr_assert_eq(dm_profile_read(json, &p, &err), DM_OK, "%s", err.detail);
    dm_exr_image img;
    cr_assert_eq(dm_exr_read(exr, &img, &err), DM_OK, "%s", err.detail);
    for (int k = 0; k < p.count; ++k) {
        char name[32];
        snprintf(name, sizeof name, "stretch%d.u", k);
        cr_expect_not_null(dm_exr_find(&img, name), "level %d missing", k);
        snprintf(name, sizeof name, "variance_mm2_%d", k);
        const dm_param *v = dm_prov_find(&img.prov, name);
        cr_assert_not_null(v, "no %s in the stretch provenance", name);
        cr_expect_eq(v->d, p.variance_mm2[k], "level %d: %.17g vs the fit's %.17g", k, v->d, p.variance_mm2[k]);
    }
    cr_expect_null(dm_exr_find(&img, "stretch4.u"), "more levels than Gaussians");
    dm_exr_free(&img);
}
