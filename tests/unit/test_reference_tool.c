/* dermis-reference as a user runs it on the packed head: tiles merge into the one-shot
 * file byte for byte, the thread count changes nothing, the renderer's irradiance given as
 * a file gives the same result, levels, the frame, and every usage and load error. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../common/tmpdir.h"
#include "image/dm_exr.h"

#define REF DERMIS_BIN "/dermis-reference"

static char dir[512], pack[600];

static void setup(void)
{
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(pack, sizeof pack, "%s/lps-sss.dpk", dir);
    char cmd[8192];
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack assets/scenes/lps-sss.json -o %s --quiet", pack);
    cr_assert_eq(test_run(cmd, NULL), 0);
}

static int run(const char *args)
{
    char cmd[8192], log[700];
    int n = snprintf(cmd, sizeof cmd, REF " %s", args);
    if (n < 0 || (size_t)n >= sizeof cmd) return -1; /* too long to run as given */
    snprintf(log, sizeof log, "%s/log.txt", dir);
    return test_run(cmd, log);
}

static int same_file(const char *a, const char *b)
{
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "cmp -s %s %s", a, b);
    return test_run(cmd, NULL) == 0;
}

Test(reference_tool, tiles_threads_and_irradiance_file, .init = setup, .timeout = 240)
{
    char a[8192];
    snprintf(a, sizeof a, "%s --texture-space 32 --levels --threads 2 -o %s/one.exr --quiet", pack, dir);
    cr_assert_eq(run(a), 0);
    snprintf(a, sizeof a, "%s --texture-space 32 --levels --threads 1 -o %s/one1.exr --quiet", pack, dir);
    cr_assert_eq(run(a), 0);
    char x[700], y[700];
    snprintf(x, sizeof x, "%s/one.exr", dir);
    snprintf(y, sizeof y, "%s/one1.exr", dir);
    cr_expect(same_file(x, y), "1 and 2 threads differ");
    for (int t = 1; t <= 3; ++t) {
        snprintf(a, sizeof a, "%s --texture-space 32 --levels --tile %d/3 -o %s/t%d.exr --quiet", pack, t, dir, t);
        cr_assert_eq(run(a), 0);
    }
    snprintf(a, sizeof a, "--merge %s/t3.exr %s/t1.exr %s/t2.exr -o %s/merged.exr --quiet", dir, dir, dir, dir);
    cr_assert_eq(run(a), 0);
    snprintf(y, sizeof y, "%s/merged.exr", dir);
    cr_expect(same_file(x, y), "merged tiles differ from the one-shot file");
    /* a tile missing, or given twice: refused */
    snprintf(a, sizeof a, "--merge %s/t1.exr %s/t2.exr -o %s/bad.exr", dir, dir, dir);
    cr_expect_eq(run(a), 2);
    snprintf(a, sizeof a, "--merge %s/t1.exr %s/t1.exr %s/t2.exr -o %s/bad.exr", dir, dir, dir, dir);
    cr_expect_eq(run(a), 2);
    /* a tile holding an infinite value: refused naming it, nothing written (was merged) */
    {
        dm_exr_image t;
        dm_error e = {0};
        snprintf(y, sizeof y, "%s/t2.exr", dir);
        cr_assert_eq(dm_exr_read(y, &t, &e), DM_OK, "%s", e.detail);
        dm_exr_channel ch[4 + 6 * 3];
        for (int c = 0; c < t.channel_count; ++c) ch[c] = (dm_exr_channel){t.names[c], t.planes[c], DM_EXR_FLOAT};
        t.planes[0][5] = INFINITY;
        snprintf(y, sizeof y, "%s/t2inf.exr", dir);
        cr_assert_eq(dm_exr_write(y, t.width, t.height, ch, t.channel_count, &t.prov, &e), DM_OK, "%s", e.detail);
        dm_exr_free(&t);
        snprintf(a, sizeof a, "--merge %s/t1.exr %s/t2inf.exr %s/t3.exr -o %s/inf.exr", dir, dir, dir, dir);
        cr_expect_eq(run(a), 2);
        char log[700];
        snprintf(log, sizeof log, "%s/log.txt", dir);
        char *text = test_slurp(log);
        cr_expect(text && strstr(text, "t2inf.exr: channel") && strstr(text, "is inf"), "%s", text ? text : "");
        free(text);
        snprintf(y, sizeof y, "%s/inf.exr", dir);
        cr_expect(access(y, F_OK) != 0, "a merge of a tile with Inf was written");
    }
    /* the renderer's irradiance as a file: the same reference */
    snprintf(a, sizeof a, DERMIS_BIN "/dermis-render %s --view irradiance --size 32x32 --irradiance 32 -o %s/irr.exr", pack,
             dir);
    cr_assert_eq(test_run(a, NULL), 0);
    snprintf(a, sizeof a, "%s --texture-space 32 --irradiance %s/irr.exr -o %s/fromfile.exr --quiet", pack, dir, dir);
    cr_assert_eq(run(a), 0);
    dm_exr_image p, q;
    dm_error err = {0};
    snprintf(y, sizeof y, "%s/fromfile.exr", dir);
    cr_assert_eq(dm_exr_read(x, &p, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_exr_read(y, &q, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(p.width, 32);
    cr_expect(p.channel_count == 4 + 6 * 3, "R G B A + 6 levels: %d channels", p.channel_count);
    const char *ch[4] = {"R", "G", "B", "A"};
    int covered = 0;
    for (int c = 0; c < 4; ++c)
        for (int i = 0; i < 32 * 32; ++i) {
            float u = dm_exr_find(&p, ch[c])[i], v = dm_exr_find(&q, ch[c])[i];
            cr_expect(u == v, "%s[%d] %g vs %g", ch[c], i, u, v);
            if (c == 3) covered += u == 1.0f;
            else cr_expect(u >= 0.0f && u < 1e6f, "finite, non-negative: %g", u);
        }
    cr_expect(covered > 500, "%d covered texels", covered);
    cr_expect(!strcmp(p.prov.tool, "dermis-reference"));
    dm_exr_free(&p);
    dm_exr_free(&q);
}

Test(reference_tool, frame, .init = setup, .timeout = 240)
{
    char a[8192];
    snprintf(a, sizeof a, "%s --frame --size 64x36 --atlas 64 -o %s/frame.exr --quiet", pack, dir);
    cr_assert_eq(run(a), 0);
    dm_exr_image img;
    dm_error err = {0};
    char x[700];
    snprintf(x, sizeof x, "%s/frame.exr", dir);
    cr_assert_eq(dm_exr_read(x, &img, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(img.width, 64);
    cr_expect_eq(img.height, 36);
    int skin = 0;
    for (int i = 0; i < 64 * 36; ++i) skin += dm_exr_find(&img, "A")[i] == 1.0f;
    cr_expect(skin > 100, "%d skin pixels", skin);
    dm_exr_free(&img);
    snprintf(x, sizeof x, "test -s %s/frame.png", dir);
    cr_expect_eq(test_run(x, NULL), 0, "the PNG beside the EXR");
    /* --refine: named in the provenance */
    snprintf(a, sizeof a, "%s --frame --size 64x36 --atlas 64 --pixel-samples 2 --refine 4 -o %s/refined.exr --quiet", pack, dir);
    cr_assert_eq(run(a), 0);
    snprintf(x, sizeof x, "%s/refined.exr", dir);
    cr_assert_eq(dm_exr_read(x, &img, &err), DM_OK, "%s", err.detail);
    const dm_param *rp = dm_prov_find(&img.prov, "refine_samples");
    cr_expect(rp && rp->i == 4, "provenance refine_samples");
    dm_exr_free(&img);
}

/* --without: the decomposed comparison's runs (bench/accuracy). Albedo and normal map out,
 * shadows out: the frame differs from the full one; with subsurface out too it differs
 * again (Lambert at the point), and the provenance names what was left out. */
Test(reference_tool, without, .init = setup, .timeout = 240)
{
    const char *runs[3] = {"", "--without albedo,normal-map,shadows", "--without albedo,normal-map,shadows,subsurface"};
    float *rgb[3] = {NULL};
    for (int k = 0; k < 3; ++k) {
        char a[8192], x[700];
        snprintf(a, sizeof a, "%s --frame --size 64x36 --atlas 64 --pixel-samples 2 %s -o %s/w%d.exr --quiet", pack, runs[k], dir, k);
        cr_assert_eq(run(a), 0, "%s", runs[k]);
        dm_exr_image img;
        dm_error err = {0};
        snprintf(x, sizeof x, "%s/w%d.exr", dir, k);
        cr_assert_eq(dm_exr_read(x, &img, &err), DM_OK, "%s", err.detail);
        const dm_param *w = dm_prov_find(&img.prov, "without"), *d = dm_prov_find(&img.prov, "diffusion");
        cr_expect(w && !strcmp(w->s, k ? runs[k] + 10 : ""), "provenance 'without' of run %d", k);
        cr_expect(d && !strcmp(d->s, "pixel"));
        rgb[k] = malloc(sizeof(float) * 64 * 36);
        memcpy(rgb[k], dm_exr_find(&img, "R"), sizeof(float) * 64 * 36);
        dm_exr_free(&img);
    }
    double d01 = 0, d12 = 0;
    for (int i = 0; i < 64 * 36; ++i) d01 += fabs(rgb[0][i] - rgb[1][i]), d12 += fabs(rgb[1][i] - rgb[2][i]);
    cr_expect_gt(d01, 1.0, "leaving the maps and shadows out changes nothing");
    cr_expect_gt(d12, 0.1, "leaving subsurface out changes nothing");
    for (int k = 0; k < 3; ++k) free(rgb[k]);
    char a[8192];
    snprintf(a, sizeof a, "%s --frame --size 64x36 --without albedo,speculars -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "an unknown term");
    snprintf(a, sizeof a, "%s --texture-space 32 --without shadows -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "--without is a frame option");
    snprintf(a, sizeof a, "%s --texture-space 32 --diffusion-at-centre -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "--diffusion-at-centre is a frame option");
}

Test(reference_tool, errors, .init = setup)
{
    char a[8192];
    cr_expect_eq(run("--help"), 0);
    cr_expect_eq(run("--version"), 0);
    snprintf(a, sizeof a, "%s -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "neither --texture-space nor --frame");
    snprintf(a, sizeof a, "%s --texture-space 32 --frame -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "both");
    snprintf(a, sizeof a, "%s --texture-space 7 -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "size out of range");
    snprintf(a, sizeof a, "%s --texture-space 32 --tile 4/3 -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "tile out of range");
    snprintf(a, sizeof a, "%s --texture-space 32 -o %s/x.png", pack, dir);
    cr_expect_eq(run(a), 1, "not an EXR");
    snprintf(a, sizeof a, "%s --texture-space 32 --multipole skin1 -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "--multipole without --thickness");
    snprintf(a, sizeof a, "%s --texture-space 32 --dipole nope -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "unknown medium");
    snprintf(a, sizeof a, "%s --texture-space 32 --radial-gaussians 8 -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "--radial-gaussians without a medium");
    snprintf(a, sizeof a, "%s --texture-space 32 --refine 4 -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "--refine is a frame option");
    snprintf(a, sizeof a, "%s --frame --size 64x36 --refine 3 -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "--refine 3 over the 3 default pixel samples");
    snprintf(a, sizeof a, "%s --frame --size 64x36 --refine 17 -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "--refine above 16");
    snprintf(a, sizeof a, "%s/missing.dpk --texture-space 32 -o %s/x.exr", dir, dir);
    cr_expect_eq(run(a), 2, "no pack");
    snprintf(a, sizeof a, "%s --texture-space 32 --irradiance %s/missing.exr -o %s/x.exr", pack, dir, dir);
    cr_expect_eq(run(a), 2, "no irradiance file");
    snprintf(a, sizeof a, "%s --texture-space 32 -o /dev/null/no/such/dir/x.exr", pack);
    cr_expect_eq(run(a), 4, "cannot save");
    cr_expect_eq(test_count_files(dir, ".tmp"), 0, "no temporary file left");
}

/* A dipole instead of the pack's Gaussians: its name in the provenance, finite output. */
Test(reference_tool, dipole, .init = setup, .timeout = 120)
{
    char a[8192];
    snprintf(a, sizeof a, "%s --texture-space 32 --dipole skin1 -o %s/dipole.exr --quiet", pack, dir);
    cr_assert_eq(run(a), 0);
    dm_exr_image img;
    dm_error err = {0};
    char x[700];
    snprintf(x, sizeof x, "%s/dipole.exr", dir);
    cr_assert_eq(dm_exr_read(x, &img, &err), DM_OK, "%s", err.detail);
    const dm_param *p = dm_prov_find(&img.prov, "profile");
    cr_expect(p && !strcmp(p->s, "dipole:skin1"), "profile %s", p ? p->s : "(none)");
    cr_expect(dm_prov_find(&img.prov, "radial_gaussians") != NULL);
    for (int i = 0; i < 32 * 32; ++i) cr_expect(isfinite(dm_exr_find(&img, "R")[i]));
    dm_exr_free(&img);
}

/* The physical skin's own profile (--skin-preset, --skin) instead of the pack's Gaussians:
 * its residual printed, its parameters in the provenance, finite non-negative output; bad
 * skins are usage errors naming the parameter. */
Test(reference_tool, skin, .init = setup, .timeout = 120)
{
    char a[8192], x[700], log[700];
    snprintf(a, sizeof a, "%s --texture-space 32 --skin-preset fitzpatrick-2 --radial-gaussians 24 -o %s/skin.exr", pack,
             dir);
    cr_assert_eq(run(a), 0);
    snprintf(log, sizeof log, "%s/log.txt", dir);
    char *out = test_slurp(log);
    cr_expect(out && strstr(out, "--skin-preset fitzpatrick-2 in 24 Gaussians") && strstr(out, "(residual)"), "%s",
              out ? out : "");
    free(out);
    dm_exr_image img;
    dm_error err = {0};
    snprintf(x, sizeof x, "%s/skin.exr", dir);
    cr_assert_eq(dm_exr_read(x, &img, &err), DM_OK, "%s", err.detail);
    const dm_param *p = dm_prov_find(&img.prov, "profile"), *s = dm_prov_find(&img.prov, "skin");
    cr_expect(p && !strcmp(p->s, "skin:fitzpatrick-2"), "profile %s", p ? p->s : "(none)");
    cr_expect(s && strstr(s->s, "melanin=0.0089999999999999993,") && strstr(s->s, "epidermis-mm=0.074999999999999997,"), "skin %s", s ? s->s : "(none)");
    for (int i = 0; i < 32 * 32; ++i) cr_expect(isfinite(dm_exr_find(&img, "R")[i]) && dm_exr_find(&img, "R")[i] >= 0.0f);
    dm_exr_free(&img);
    snprintf(a, sizeof a, "%s --texture-space 32 --skin melanin=0.9,eumelanin=0.5,blood=0.01 -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "melanin out of range");
    out = test_slurp(log);
    cr_expect(out && strstr(out, "melanin_fraction (melanin, Cm) = 0.9, expected a value in [0, 0.5]"), "%s", out ? out : "");
    free(out);
    snprintf(a, sizeof a, "%s --texture-space 32 --skin-preset caucasian --dipole skin1 -o %s/x.exr", pack, dir);
    cr_expect_eq(run(a), 1, "two radial sources");
}
