/* The README's and docs/' shell examples run as printed, in order, from a fresh copy of
 * the checkout (scripts/run-examples.sh says which few lines it does not run as printed,
 * and why). About 5 minutes on 2 cores, 11 under the sanitizers. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>

#include "../common/tmpdir.h"

/* The timeout guards against a hang, not a speed (speed is measured in benchmarks): under
 * make config=sanitize the 78 commands took 637 s on the shared 2 cores (2026-12-02). */
Test(examples, readme_and_docs_run_as_printed, .timeout = 1500)
{
    char dir[256], log[320], cmd[1200];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(log, sizeof log, "%s/examples.log", dir);
    snprintf(cmd, sizeof cmd, "DERMIS_BIN='%s' DERMIS_ASSETS='%s' DERMIS_TEST_TMP='%s' bash scripts/run-examples.sh",
             DERMIS_BIN, DERMIS_ASSETS, dir);
    int rc = test_run(cmd, log);
    char *text = test_slurp(log);
    if (rc != 0 && text) {
        size_t n = strlen(text);
        fprintf(stderr, "%s\n", n > 6000 ? text + n - 6000 : text);
    }
    cr_expect_eq(rc, 0, "scripts/run-examples.sh failed (its output above; log %s)", log);
    free(text);
}
