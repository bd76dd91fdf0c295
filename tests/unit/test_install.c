/* make install into a staged DESTDIR (PREFIX=/usr), checked as a packager and an engine
 * programmer would: scripts/test-install.sh says what each mode checks. Each test installs
 * the build it belongs to (build/<config>/, from DERMIS_BIN) into its own temporary tree. */
#include <criterion/criterion.h>
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/tmpdir.h"

/* Runs scripts/test-install.sh MODE; on failure prints the end of its log. */
static void run_mode(const char *mode)
{
    char dir[256], log[320], cmd[1400], bin[512];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(bin, sizeof bin, "%s", DERMIS_BIN); /* .../build/<config>/bin */
    const char *config = basename(dirname(bin));
    snprintf(log, sizeof log, "%s/install-%s.log", dir, mode);
    snprintf(cmd, sizeof cmd, "DERMIS_CONFIG='%s' DERMIS_ASSETS='%s' DERMIS_TEST_TMP='%s' bash scripts/test-install.sh %s",
             config, DERMIS_ASSETS, dir, mode);
    int rc = test_run(cmd, log);
    char *text = test_slurp(log);
    if (rc != 0 && text) {
        size_t n = strlen(text);
        fprintf(stderr, "%s\n", n > 6000 ? text + n - 6000 : text);
    }
    cr_expect_eq(rc, 0, "scripts/test-install.sh %s failed (its output above; log %s)", mode, log);
    free(text);
}

Test(install, tree_runs_without_the_checkout, .timeout = 300) { run_mode("tree"); }
Test(install, man_pages_hold_every_option, .timeout = 300) { run_mode("man"); }
Test(install, completion_knows_every_option, .timeout = 300) { run_mode("completion"); }
Test(install, pkgconfig_and_headers, .timeout = 300) { run_mode("pkgconfig"); }
Test(install, examples_build_against_the_install, .timeout = 300) { run_mode("examples"); }
Test(install, uninstall_removes_everything, .timeout = 300) { run_mode("uninstall"); }
