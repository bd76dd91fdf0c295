/* dermis-bake-stretch as a user runs it: named channels, provenance and identical reruns,
 * its exit codes, and dermis-pack taking a matching baked file. */
#define _DEFAULT_SOURCE /* mkdtemp (tests/common/tmpdir.h) */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "../common/tmpdir.h"
#include "image/dm_exr.h"
#include "pack/dm_pack.h"

#define HEAD DERMIS_ASSETS "/lps/LeePerrySmith.obj"

/* ---- the tool --------------------------------------------------------------------- */

/* build/<config>/bin/dermis-bake-stretch, found beside this test binary. */
static void tool_path(char *out, size_t size)
{
    char self[900];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    cr_assert_gt(n, 0);
    self[n] = '\0';
    char *unit = strstr(self, "/tests/unit/");
    cr_assert_not_null(unit);
    *unit = '\0';
    snprintf(out, size, "%s/bin/dermis-bake-stretch", self);
    cr_assert_eq(access(out, X_OK), 0, "%s is not built", out);
}

static int run(const char *cmd)
{
    int status = system(cmd);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

Test(stretch, tool_writes_named_channels_provenance_and_identical_reruns)
{
    char tool[1024], cmd[8192];
    tool_path(tool, sizeof tool);
    char dir[] = "/tmp/dm_test_tool_XXXXXX";
    cr_assert_not_null(mkdtemp(dir));
    snprintf(cmd, sizeof cmd, "%s %s -o %s/a.exr --size 64 --quiet && %s %s -o %s/b.exr --size 64 --threads 1 --quiet",
             tool, HEAD, dir, tool, HEAD, dir);
    cr_assert_eq(run(cmd), 0);
    snprintf(cmd, sizeof cmd, "cmp -s %s/a.exr %s/b.exr", dir, dir);
    cr_assert_eq(run(cmd), 0, "reruns differ");
    char path[256];
    snprintf(path, sizeof path, "%s/a.exr", dir);
    dm_exr_image img;
    dm_error err = {0};
    cr_assert_eq(dm_exr_read(path, &img, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(img.channel_count, 13);
    cr_assert_not_null(dm_exr_find(&img, "stretch0.u"));
    cr_assert_not_null(dm_exr_find(&img, "stretch5.v"));
    cr_assert_not_null(dm_exr_find(&img, "mask"));
    cr_assert(img.has_provenance);
    cr_assert_str_eq(img.prov.tool, "dermis-bake-stretch");
    cr_assert(strncmp(img.prov.input_hash, "xxh3-128:", 9) == 0);
    const dm_param *mm = dm_prov_find(&img.prov, "mm_per_unit"), *pr = dm_prov_find(&img.prov, "profile");
    cr_assert(mm && mm->d == 50.0);
    cr_assert(pr && strcmp(pr->s, "gems3-skin") == 0);
    cr_assert(dm_prov_find(&img.prov, "variance_mm2_5"));
    dm_exr_free(&img);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    run(cmd);
}

Test(stretch, tool_exit_codes)
{
    char tool[1024], cmd[8192];
    tool_path(tool, sizeof tool);
    snprintf(cmd, sizeof cmd, "%s %s 2>/dev/null", tool, HEAD); /* no -o */
    cr_assert_eq(run(cmd), 1);
    snprintf(cmd, sizeof cmd, "%s %s -o /tmp/x.exr --size 8 2>/dev/null", tool, HEAD); /* out of range */
    cr_assert_eq(run(cmd), 1);
    snprintf(cmd, sizeof cmd, "%s %s -o /tmp/x.exr -v --quiet 2>/dev/null", tool, HEAD); /* conflict */
    cr_assert_eq(run(cmd), 1);
    snprintf(cmd, sizeof cmd, "%s %s -o /tmp/x.exr --levels 7 2>/dev/null", tool, HEAD); /* 6 Gaussians */
    cr_assert_eq(run(cmd), 1);
    snprintf(cmd, sizeof cmd, "%s /nonexistent.obj -o /tmp/x.exr 2>/dev/null", tool);
    cr_assert_eq(run(cmd), 2);
    snprintf(cmd, sizeof cmd, "%s %s -o /tmp/x.exr --profile /nonexistent.json 2>/dev/null", tool, HEAD);
    cr_assert_eq(run(cmd), 2);
    snprintf(cmd, sizeof cmd, "%s %s -o /dev/null/dir/x.exr --size 16 --quiet 2>/dev/null", tool, HEAD);
    cr_assert_eq(run(cmd), 4);
    snprintf(cmd, sizeof cmd, "%s --help >/dev/null", tool);
    cr_assert_eq(run(cmd), 0);
}

/* dermis-pack --stretch takes dermis-bake-stretch's file when it matches the scene, and the
 * packed chain is then the one the packer would bake itself, byte for byte. */
Test(stretch_tool, pack_takes_a_matching_baked_file, .timeout = 180)
{
    char dir[64], cmd[1024], exr[160], small[160], a[160], b[160], log[160];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(exr, sizeof exr, "%s/st.exr", dir);
    snprintf(small, sizeof small, "%s/st512.exr", dir);
    snprintf(a, sizeof a, "%s/baked.dpk", dir);
    snprintf(b, sizeof b, "%s/file.dpk", dir);
    snprintf(log, sizeof log, "%s/log", dir);
    /* lps-sss.json: irradiance 1024, mm_per_unit 50, gems3-skin */
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-bake-stretch %s/lps/LeePerrySmith.obj -o %s --size 1024 --quiet && "
             DERMIS_BIN "/dermis-bake-stretch %s/lps/LeePerrySmith.obj -o %s --size 512 --quiet",
             DERMIS_ASSETS, exr, DERMIS_ASSETS, small);
    cr_assert_eq(test_run(cmd, NULL), 0);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack assets/scenes/lps-sss.json -o %s --quiet", a);
    cr_assert_eq(test_run(cmd, NULL), 0);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack assets/scenes/lps-sss.json -o %s --stretch %s", b, exr);
    cr_assert_eq(test_run(cmd, log), 0);
    char *text = test_slurp(log);
    cr_expect(text && strstr(text, "from st.exr"), "the file was not used:\n%s", text ? text : "");
    free(text);
    dm_pack pa, pb;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open(a, &pa, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_pack_open(b, &pb, &err), DM_OK, "%s", err.detail);
    const char *names[2] = {"stretch", "stretch.mask"};
    for (int k = 0; k < 2; ++k) {
        const dm_pack_entry *ea = dm_pack_find(&pa, names[k]), *eb = dm_pack_find(&pb, names[k]);
        cr_assert(ea && eb && ea->size == eb->size, "%s missing or sized differently", names[k]);
        cr_expect_eq(memcmp(ea->data, eb->data, ea->size), 0, "%s differs from the packer's own bake", names[k]);
    }
    dm_pack_close(&pa);
    dm_pack_close(&pb);
    /* the wrong size is refused, naming it; nothing is written */
    snprintf(cmd, sizeof cmd, "rm -f %s; " DERMIS_BIN "/dermis-pack assets/scenes/lps-sss.json -o %s --stretch %s", b,
             b, small);
    cr_expect_eq(test_run(cmd, log), 2);
    text = test_slurp(log);
    cr_expect(text && strstr(text, "512x512") && strstr(text, "1024"), "%s", text ? text : "");
    free(text);
    cr_expect_eq(test_count_files(dir, "file.dpk"), 0);
}
