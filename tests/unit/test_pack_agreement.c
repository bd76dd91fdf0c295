/* dermis-check and dermis-render agree on every pack (issue #31 point 1): the real packs
 * pass both, and each reproduction of finite but absurd data (tests/common/pack_absurd.h)
 * is refused by both, with a non-zero exit and the same message naming the entry, because
 * both read it through the one verification of dm_pack_open. */
#include <criterion/criterion.h>
#include <criterion/parameterized.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/pack_absurd.h"

/* Runs `tool` on the pack (dermis-render writes dir/out.exr); returns its exit code and
 * leaves what it printed in *text (free it). */
static int run_tool(const char *dir, const char *tool, const char *pack, char **text)
{
    char cmd[2048], log[512];
    snprintf(log, sizeof log, "%s/%s.log", dir, tool);
    if (!strcmp(tool, "dermis-render"))
        snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-render '%s' -o '%s/out.exr' --quiet", pack, dir);
    else
        snprintf(cmd, sizeof cmd, DERMIS_BIN "/%s '%s'", tool, pack);
    int rc = test_run(cmd, log);
    *text = test_slurp(log);
    return rc;
}

Test(pack_agreement, real_packs_pass_both, .timeout = 120)
{
    static const char *const techniques[] = {"texture-space", "screen-space", "pre-integrated"};
    char dir[256], path[512];
    cr_assert(test_tmpdir(dir, sizeof dir));
    for (int k = 0; k < 3; ++k) {
        cr_assert(absurd_base_pack(dir, techniques[k], path, sizeof path), "dermis-pack %s", techniques[k]);
        char *text = NULL;
        cr_expect_eq(run_tool(dir, "dermis-check", path, &text), 0, "%s: %s", techniques[k], text ? text : "");
        free(text);
        cr_expect_eq(run_tool(dir, "dermis-render", path, &text), 0, "%s: %s", techniques[k], text ? text : "");
        free(text);
    }
}

/* Parameters are indices: a worker may not share the table's addresses. */
ParameterizedTestParameters(pack_agreement, absurd_refused_by_both)
{
    static int index[ABSURD_CASE_COUNT];
    for (int k = 0; k < ABSURD_CASE_COUNT; ++k) index[k] = k;
    return cr_make_param_array(int, index, ABSURD_CASE_COUNT);
}

ParameterizedTest(int *k, pack_agreement, absurd_refused_by_both, .timeout = 120)
{
    const absurd_case *c = &absurd_cases[*k];
    char dir[256], path[512], absurd[600];
    cr_assert(test_tmpdir(dir, sizeof dir));
    cr_assert(absurd_base_pack(dir, c->technique, path, sizeof path), "dermis-pack %s", c->technique);
    size_t size;
    uint8_t *buf = test_pack_load(path, &size);
    cr_assert_not_null(buf);
    cr_assert(absurd_apply(c, buf, size), "%s: the edit did not apply", c->name);
    snprintf(absurd, sizeof absurd, "%s/%s.dpk", dir, c->name);
    cr_assert(test_pack_save(absurd, buf, size));
    free(buf);
    char *text = NULL;
    int rc = run_tool(dir, "dermis-check", absurd, &text);
    cr_expect_eq(rc, 1, "%s: dermis-check exit %d: %s", c->name, rc, text ? text : "");
    cr_expect(text && strstr(text, c->expect), "%s: dermis-check: '%s' not in: %s", c->name, c->expect,
              text ? text : "");
    free(text);
    rc = run_tool(dir, "dermis-render", absurd, &text);
    cr_expect_eq(rc, 2, "%s: dermis-render exit %d (2: cannot load): %s", c->name, rc, text ? text : "");
    cr_expect(text && strstr(text, c->expect), "%s: dermis-render: '%s' not in: %s", c->name, c->expect,
              text ? text : "");
    free(text);
    char out[600];
    snprintf(out, sizeof out, "%s/out.exr", dir);
    cr_expect_null(fopen(out, "rb"), "%s: dermis-render wrote %s", c->name, out);
}
