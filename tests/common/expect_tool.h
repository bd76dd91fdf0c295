/* expect_tool.h — running a tool in a test's folder and checking its exit code and what it
 * printed (include <criterion/criterion.h> first). */
#ifndef TEST_EXPECT_TOOL_H
#define TEST_EXPECT_TOOL_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tmpdir.h"

/* dir/name in one of 8 rotating buffers (so a call may take a few such paths). */
static inline const char *test_path_in(const char *dir, const char *name)
{
    static char path[8][512];
    static int k;
    k = (k + 1) % 8;
    snprintf(path[k], sizeof path[k], "%s/%s", dir, name);
    return path[k];
}

/* Runs cmd in dir (under `timeout timeout_s` when > 0, so a hang fails instead of hanging);
 * expects exit code rc and each needle (n1, n2; NULL: none) in its output, the log in
 * dir/log.txt. Returns the seconds it took. */
static inline double test_expect_tool(const char *dir, int timeout_s, const char *cmd, int rc, const char *n1,
                                      const char *n2)
{
    char line[4096], log[320], limit[32] = "";
    if (timeout_s > 0) snprintf(limit, sizeof limit, "timeout %d ", timeout_s);
    snprintf(log, sizeof log, "%s/log.txt", dir);
    snprintf(line, sizeof line, "cd '%s' && %s%s", dir, limit, cmd);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    int got = test_run(line, log);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    char *text = test_slurp(log);
    cr_expect_eq(got, rc, "%s: exit %d, expected %d: %s", cmd, got, rc, text ? text : "");
    if (n1) cr_expect(text && strstr(text, n1), "%s: '%s' not in: %s", cmd, n1, text ? text : "");
    if (n2) cr_expect(text && strstr(text, n2), "%s: '%s' not in: %s", cmd, n2, text ? text : "");
    free(text);
    return (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
}

/* A usage error and what it must say: `tool ARGS -o dir/x.json` (no -o where `says` names
 * -o itself) exits 1 printing "error:" and `says`. */
typedef struct test_usage_case {
    const char *args, *says;
} test_usage_case;

static inline void test_expect_usage_errors(const char *tool, const char *dir, const test_usage_case *bad, size_t n)
{
    char cmd[2048], log[320];
    snprintf(log, sizeof log, "%s/log", dir);
    for (size_t k = 0; k < n; ++k) {
        if (strstr(bad[k].says, "-o")) snprintf(cmd, sizeof cmd, "%s %s", tool, bad[k].args);
        else snprintf(cmd, sizeof cmd, "%s %s -o %s/x.json", tool, bad[k].args, dir);
        cr_expect_eq(test_run(cmd, log), 1, "'%s' should be a usage error", bad[k].args);
        char *out = test_slurp(log);
        cr_expect(out && strstr(out, "error:") && strstr(out, bad[k].says), "'%s' printed: %s", bad[k].args, out);
        free(out);
    }
}

#endif
