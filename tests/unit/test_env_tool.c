/* dermis-bake-env as a person runs it: every bundled map bakes, exit codes, no partial
 * file, byte-identical reruns, a bad texel named by its position. Small options keep the
 * bakes quick; the numerics are in test_env.c. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/tmpdir.h"
#include "image/dm_exr.h"
#include "pack/dm_pack.h"

#define BIN DERMIS_BIN "/dermis-bake-env"
#define FAST "--samples 32 --levels 2 --spec-size 32 --background-size 64 --check-texels 2 --quiet"

Test(env_tool, every_bundled_map_bakes, .timeout = 120)
{
    const char *maps[] = {"venice_sunset_1k.hdr", "royal_esplanade_1k.hdr", "studio.exr", "courtyard.exr",
                          "night.exr"};
    char dir[64], cmd[1024], out[160];
    cr_assert(test_tmpdir(dir, sizeof dir));
    for (int k = 0; k < 5; ++k) {
        snprintf(out, sizeof out, "%s/%d.exr", dir, k);
        snprintf(cmd, sizeof cmd, BIN " " DERMIS_ASSETS "/env/%s -o %s " FAST, maps[k], out);
        cr_expect_eq(test_run(cmd, NULL), 0, "%s", maps[k]);
        dm_exr_image img;
        dm_error err = {0};
        cr_expect_eq(dm_exr_read(out, &img, &err), DM_OK, "%s: %s", maps[k], err.detail);
        cr_expect(img.has_provenance, "%s: no provenance", maps[k]);
        cr_expect(img.prov.input_hash[0], "%s: no input hash", maps[k]);
        dm_exr_free(&img);
    }
}

Test(env_tool, deterministic_reruns)
{
    char dir[64], cmd[1024], a[160], b[160];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(a, sizeof a, "%s/a.exr", dir);
    snprintf(b, sizeof b, "%s/b.exr", dir);
    snprintf(cmd, sizeof cmd, BIN " " DERMIS_ASSETS "/env/studio.exr -o %s " FAST " -j 1", a);
    cr_assert_eq(test_run(cmd, NULL), 0);
    snprintf(cmd, sizeof cmd, BIN " " DERMIS_ASSETS "/env/studio.exr -o %s " FAST " -j 2", b);
    cr_assert_eq(test_run(cmd, NULL), 0);
    snprintf(cmd, sizeof cmd, "cmp -s %s %s", a, b);
    cr_expect_eq(test_run(cmd, NULL), 0, "reruns on 1 and 2 threads differ");
}

Test(env_tool, exit_codes_and_no_partial_file)
{
    char dir[64], cmd[1024], log[160], bad[160];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(log, sizeof log, "%s/log", dir);
    /* usage */
    cr_expect_eq(test_run(BIN " " DERMIS_ASSETS "/env/studio.exr", NULL), 1, "no -o");
    cr_expect_eq(test_run(BIN " " DERMIS_ASSETS "/env/studio.exr -o /tmp/x.exr --levels 2 --roughness 0.1,0.5", NULL),
                 1, "conflicting options");
    cr_expect_eq(test_run(BIN " " DERMIS_ASSETS "/env/studio.exr -o /tmp/x.exr --samples 0", NULL), 1);
    /* load: missing, not an image, not 2:1 */
    snprintf(cmd, sizeof cmd, BIN " /nonexistent.hdr -o %s/o.exr", dir);
    cr_expect_eq(test_run(cmd, NULL), 2);
    snprintf(cmd, sizeof cmd, BIN " " DERMIS_ASSETS "/lps/Map-COL.jpg -o %s/o.exr", dir);
    cr_expect_eq(test_run(cmd, log), 2, "a square image is not an equirect map");
    char *text = test_slurp(log);
    cr_expect(text && strstr(text, "Map-COL.jpg"), "the message names the file: %s", text ? text : "");
    free(text);
    /* a NaN texel, named by its position */
    snprintf(bad, sizeof bad, "%s/nan.exr", dir);
    float *px = calloc(16 * 8, sizeof *px);
    px[(8 - 1 - 2) * 16 + 5] = NAN; /* file x 5, y 2 from the top (memory rows are bottom-up) */
    dm_provenance p;
    dm_prov_init(&p, "test");
    dm_exr_channel ch[3] = {{"R", px, DM_EXR_FLOAT}, {"G", px, DM_EXR_FLOAT}, {"B", px, DM_EXR_FLOAT}};
    cr_assert_eq(dm_exr_write(bad, 16, 8, ch, 3, &p, NULL), DM_OK);
    free(px);
    snprintf(cmd, sizeof cmd, BIN " %s -o %s/o.exr", bad, dir);
    cr_expect_eq(test_run(cmd, log), 2);
    text = test_slurp(log);
    cr_expect(text && strstr(text, "5") && strstr(text, "2"), "the message names (5, 2): %s", text ? text : "");
    free(text);
    /* save */
    cr_expect_eq(test_run(BIN " " DERMIS_ASSETS "/env/studio.exr -o /dev/null/dir/o.exr " FAST, NULL), 4);
    cr_expect_eq(test_count_files(dir, ".tmp."), 0);
    cr_expect_eq(test_count_files(dir, "o.exr"), 0, "no output after failures");
}

/* dermis-pack takes dermis-bake-env's output for the map it was baked from. */
Test(env_tool, pack_takes_the_baked_file_for_its_map, .timeout = 120)
{
    char dir[64], cmd[1024], ven[160], rot[160], roy[160], pack[160], log[160];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(ven, sizeof ven, "%s/venice.exr", dir);
    snprintf(rot, sizeof rot, "%s/venice-rot.exr", dir);
    snprintf(roy, sizeof roy, "%s/royal.exr", dir);
    snprintf(pack, sizeof pack, "%s/env.dpk", dir);
    snprintf(log, sizeof log, "%s/log", dir);
    snprintf(cmd, sizeof cmd, BIN " " DERMIS_ASSETS "/env/venice_sunset_1k.hdr -o %s " FAST, ven);
    cr_assert_eq(test_run(cmd, NULL), 0);
    snprintf(cmd, sizeof cmd, BIN " " DERMIS_ASSETS "/env/venice_sunset_1k.hdr -o %s --rotate 30 " FAST, rot);
    cr_assert_eq(test_run(cmd, NULL), 0);
    snprintf(cmd, sizeof cmd, BIN " " DERMIS_ASSETS "/env/royal_esplanade_1k.hdr -o %s " FAST, roy);
    cr_assert_eq(test_run(cmd, NULL), 0);

    /* the matching file serves (its 2 levels, not the packer's 6), the other map's is ignored */
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack assets/scenes/lps-env.json -o %s --env %s --env %s", pack, roy,
             ven);
    cr_assert_eq(test_run(cmd, log), 0);
    char *text = test_slurp(log);
    cr_expect(text && strstr(text, "warning: --env") && strstr(text, "royal.exr"), "no warning for royal.exr: %s",
              text ? text : "");
    free(text);
    dm_pack p;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open(pack, &p, &err), DM_OK, "%s", err.detail);
    const dm_pack_entry *spec = dm_pack_find(&p, "env.specular");
    cr_assert_not_null(spec);
    cr_expect_eq(spec->layers, 2, "env.specular has %d layers: the file was not used", spec->layers);
    cr_expect(strstr(spec->provenance_json, "venice.exr") != NULL, "%s", spec->provenance_json);
    dm_pack_close(&p);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-check %s", pack);
    cr_expect_eq(test_run(cmd, NULL), 0);

    /* a file for this map baked rotated cannot serve: an error that says why, no pack */
    snprintf(cmd, sizeof cmd, "rm -f %s; " DERMIS_BIN "/dermis-pack assets/scenes/lps-env.json -o %s --env %s", pack,
             pack, rot);
    cr_expect_eq(test_run(cmd, log), 2);
    text = test_slurp(log);
    cr_expect(text && strstr(text, "rotate 30"), "%s", text ? text : "");
    free(text);
    cr_expect_eq(test_count_files(dir, "env.dpk"), 0, "a refused pack was written");
}
