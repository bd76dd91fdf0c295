/* dermis-view's subsurface technique switch (issue 13) under Xvfb: key T and the script's
 * `technique` command switch texture-space ↔ screen-space; `technique split` shows the other
 * technique beside it through the comparison layouts (C cycles them); an unimplemented
 * technique and a technique the pack holds no data for fail clearly. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/png_inflate.h"
#include "../common/tmpdir.h"
#include "../common/view_test.h"

#define VIEW DERMIS_BIN "/dermis-view"
#define SIZE "--size 192x108 --irradiance 128"

static int run_script(const char *dir, const char *source, const char *script, char **out)
{
    char path[256], line[1024], log[256];
    snprintf(path, sizeof path, "%s/script.txt", dir);
    FILE *f = fopen(path, "w");
    cr_assert(f);
    fputs(script, f);
    fclose(f);
    snprintf(line, sizeof line, VIEW " %s " SIZE " --script %s", source, path);
    snprintf(log, sizeof log, "%s/log.txt", dir);
    int rc = test_run(line, log);
    *out = test_slurp(log);
    return rc;
}

static uint16_t *picture(const char *dir, const char *name)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s.png", dir, name);
    int w = 0, h = 0, c = 0, bits = 0;
    uint16_t *px = tpng_read(path, &w, &h, &c, &bits);
    cr_assert(px, "%s: missing or not a PNG", path);
    cr_assert(w == 192 && h == 108 && c == 4, "%s: %dx%d x%d", path, w, h, c);
    return px;
}

static bool same(const uint16_t *a, const uint16_t *b)
{
    return memcmp(a, b, (size_t)192 * 108 * 4 * sizeof *a) == 0;
}

Test(view_technique, switch_split_and_cycle, .timeout = 180)
{
    need_display();
    char dir[64], script[2048], *out = NULL;
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(script, sizeof script,
             "0 screenshot %s/tsd.png\n0.1 technique screen-space\n0.1 screenshot %s/ss.png\n"
             "0.2 technique split\n0.2 screenshot %s/split.png\n0.3 key C\n0.3 screenshot %s/error.png\n"
             "0.4 technique nosplit\n0.4 key T\n0.4 screenshot %s/back.png\n0.5 toggle translucency on\n"
             "0.5 key T\n0.5 screenshot %s/ss_trans.png\n0.6 quit\n",
             dir, dir, dir, dir, dir, dir);
    int rc = run_script(dir, "--synthetic sphere", script, &out);
    cr_assert_eq(rc, 0, "dermis-view exited %d:\n%s", rc, out);
    cr_expect(strstr(out, "0 failed, 0 GL errors"), "no clean summary:\n%s", out);
    free(out);
    uint16_t *tsd = picture(dir, "tsd"), *ss = picture(dir, "ss"), *split = picture(dir, "split"),
             *err = picture(dir, "error"), *back = picture(dir, "back"), *sst = picture(dir, "ss_trans");
    cr_expect(!same(tsd, ss), "screen-space shows the same picture as texture-space");
    cr_expect(!same(split, ss) && !same(split, tsd), "the split shows neither technique alone");
    cr_expect(!same(err, split), "C did not change the comparison layout");
    cr_expect(same(back, tsd), "back to texture-space is not the first picture");
    cr_expect(sst != NULL);
    free(tsd), free(ss), free(split), free(err), free(back), free(sst);
}

Test(view_technique, unavailable_techniques_fail_clearly, .timeout = 180)
{
    need_display();
    char dir[64], script[512], *out = NULL;
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(script, sizeof script, "0 technique pre-integrated\n0.1 quit\n");
    int rc = run_script(dir, "--synthetic sphere", script, &out);
    cr_expect_eq(rc, 3, "exit %d:\n%s", rc, out);
    cr_expect(strstr(out, "pre-integrated table"), "%s", out); /* the synthetic sphere has none */
    free(out);
    /* a screen-space pack has no stretch maps: texture-space is refused, naming them */
    char pack[160], line[1024];
    snprintf(pack, sizeof pack, "%s/ss.dpk", dir);
    snprintf(line, sizeof line, DERMIS_BIN "/dermis-pack assets/scenes/lps-screen-space.json -o %s --quiet", pack);
    cr_assert_eq(test_run(line, NULL), 0, "dermis-pack failed on assets/scenes/lps-screen-space.json");
    snprintf(script, sizeof script, "0 screenshot %s/ss.png\n0.1 technique texture-space\n0.2 quit\n", dir);
    rc = run_script(dir, pack, script, &out);
    cr_expect_eq(rc, 3, "exit %d:\n%s", rc, out);
    cr_expect(strstr(out, "stretch"), "the refusal does not name the stretch maps:\n%s", out);
    free(out);
}

/* Key T cycles through every technique the pack supports: a pre-integrated pack holds the
 * table and curvature map but no stretch chain, so T goes pre-integrated → screen-space →
 * pre-integrated (texture-space skipped, never a failed rebuild). */
Test(view_technique, key_t_cycles_through_pre_integrated, .timeout = 180)
{
    need_display();
    char dir[64], script[1024], pack[160], line[1024], *out = NULL;
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(pack, sizeof pack, "%s/pi.dpk", dir);
    snprintf(line, sizeof line, DERMIS_BIN "/dermis-pack assets/scenes/lps-pre-integrated.json -o %s --quiet", pack);
    cr_assert_eq(test_run(line, NULL), 0, "dermis-pack failed on assets/scenes/lps-pre-integrated.json");
    snprintf(script, sizeof script,
             "0 screenshot %s/pi.png\n0.1 key T\n0.1 screenshot %s/ss.png\n0.2 key T\n0.2 screenshot %s/back.png\n"
             "0.3 quit\n",
             dir, dir, dir);
    int rc = run_script(dir, pack, script, &out);
    cr_assert_eq(rc, 0, "dermis-view exited %d:\n%s", rc, out);
    cr_expect(strstr(out, "0 failed, 0 GL errors"), "no clean summary:\n%s", out);
    free(out);
    uint16_t *pi = picture(dir, "pi"), *ss = picture(dir, "ss"), *back = picture(dir, "back");
    cr_expect(!same(pi, ss), "T did not switch to screen-space");
    cr_expect(same(back, pi), "the second T did not come back to pre-integrated");
    free(pi), free(ss), free(back);
}
