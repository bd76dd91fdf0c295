/* The version policy (docs/dermis-dpk.5.md, docs/dermis-scene.5.md): dm_format_version_read
 * reports what a file declares and the verdict from the header alone, so it answers for a pack
 * of a version the full reader refuses; the full readers refuse with the same advice; and
 * dermis-check --format-version prints one line per file, exit 0 / 1 / 2.
 * The packs here are the committed fixture (tests/fixtures/pack-v1, test_pack_fixture.c) with
 * its version changed and the header+manifest checksum recomputed, so only the version differs.
 * Run from the repository root (scripts/run-tests.sh, make test). */
#include <criterion/criterion.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/tmpdir.h"
#include "pack/dm_format_version.h"
#include "pack/dm_pack.h"
#include "core/dm_scene.h"

#define FIXTURE "tests/fixtures/pack-v1/pack-v1.dpk"

static uint8_t *fixture_bytes(size_t *size)
{
    char *text = NULL;
    FILE *f = fopen(FIXTURE, "rb");
    cr_assert_not_null(f, "%s: missing; run the tests from the repository root", FIXTURE);
    fseek(f, 0, SEEK_END);
    *size = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    text = malloc(*size);
    cr_assert_eq(fread(text, 1, *size, f), *size);
    fclose(f);
    return (uint8_t *)text;
}

static void put32(uint8_t *p, uint32_t v)
{
    for (int k = 0; k < 4; ++k) p[k] = (uint8_t)(v >> (8 * k));
}

/* The header's checksum field recomputed over the (changed) header and manifest. */
static void reseal(uint8_t *b)
{
    dm_pack_header h;
    dm_pack_header_decode(b, &h);
    h.checksum = dm_pack_header_checksum(b, b + DM_PACK_HEADER_SIZE, h.manifest_size);
    dm_pack_header_encode(&h, b);
}

static void write_file(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    cr_assert_not_null(f, "%s", path);
    cr_assert_eq(fwrite(data, 1, size, f), size);
    fclose(f);
}

/* The fixture with header version `version` (resealed) as DIR/NAME; the path in out. */
static void pack_of_version(const char *dir, const char *name, uint32_t version, char *out, size_t out_size)
{
    size_t size;
    uint8_t *b = fixture_bytes(&size);
    put32(b + 8, version);
    reseal(b);
    snprintf(out, out_size, "%s/%s", dir, name);
    write_file(out, b, size);
    free(b);
}

static void expect_verdict(const char *path, dm_format_kind kind, int64_t version, dm_format_verdict verdict,
                           const char *summary)
{
    dm_format_version v;
    dm_error err = {0};
    cr_assert_eq(dm_format_version_read(path, &v, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(v.kind, kind, "%s", path);
    cr_expect_eq(v.version, version, "%s: version %lld", path, (long long)v.version);
    cr_expect_eq(v.verdict, verdict, "%s", path);
    cr_expect_str_eq(v.summary, summary);
}

/* The full reader refuses the pack with DM_ERR_UNSUPPORTED and the policy's words. */
static void expect_open_refused(const char *path, const char *words)
{
    dm_pack pack;
    dm_error err = {0};
    cr_expect_eq(dm_pack_open(path, &pack, &err), DM_ERR_UNSUPPORTED, "%s", err.detail);
    cr_expect(strstr(err.detail, words), "'%s' not in: %s", words, err.detail);
    dm_pack_close(&pack);
}

Test(format_version, pack_v1_is_read)
{
    expect_verdict(FIXTURE, DM_FORMAT_PACK, 1, DM_FORMAT_READABLE,
                   "dermis-pack version 1 (this dermis reads version 1: ok)");
}

Test(format_version, pack_v2_refused_as_newer)
{
    char dir[256], path[320];
    cr_assert(test_tmpdir(dir, sizeof dir));
    pack_of_version(dir, "v2.dpk", 2, path, sizeof path);
    expect_verdict(path, DM_FORMAT_PACK, 2, DM_FORMAT_NEWER,
                   "dermis-pack version 2 (this dermis reads version 1: refused, written by a newer dermis; "
                   "update dermis)");
    expect_open_refused(path, "version 2, expected 1 (written by a newer dermis; update dermis)");
}

Test(format_version, pack_v0_refused_as_older)
{
    char dir[256], path[320];
    cr_assert(test_tmpdir(dir, sizeof dir));
    pack_of_version(dir, "v0.dpk", 0, path, sizeof path);
    expect_verdict(path, DM_FORMAT_PACK, 0, DM_FORMAT_OLDER,
                   "dermis-pack version 0 (this dermis reads version 1: refused, written by an older dermis; "
                   "re-pack it from its scene with this dermis)");
    expect_open_refused(path, "version 0, expected 1 (written by an older dermis; re-pack it from its scene");
}

/* A pack of a future version is read from its header alone: what follows may be anything. */
Test(format_version, future_pack_from_its_header_alone)
{
    char dir[256], path[320];
    cr_assert(test_tmpdir(dir, sizeof dir));
    uint8_t b[DM_PACK_HEADER_SIZE + 16];
    memset(b, 0xab, sizeof b);
    dm_pack_header h = {.version = 7, .file_size = 1u << 30};
    dm_pack_header_encode(&h, b);
    snprintf(path, sizeof path, "%s/future.dpk", dir);
    write_file(path, b, sizeof b);
    expect_verdict(path, DM_FORMAT_PACK, 7, DM_FORMAT_NEWER,
                   "dermis-pack version 7 (this dermis reads version 1: refused, written by a newer dermis; "
                   "update dermis)");
}

/* Header version 1 but the manifest says 2 (same length, resealed): the manifest's is reported,
 * as the full reader refuses it next. */
Test(format_version, manifest_version_when_the_header_is_1)
{
    size_t size;
    uint8_t *b = fixture_bytes(&size);
    char *m = strstr((char *)b + DM_PACK_HEADER_SIZE, "\"version\":\t1,"); /* the manifest's first */
    cr_assert(m && m < (char *)b + 200, "the fixture's manifest has no \"version\":\\t1 near its start");
    m[11] = '2';
    reseal(b);
    char dir[256], path[320];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(path, sizeof path, "%s/m2.dpk", dir);
    write_file(path, b, size);
    free(b);
    expect_verdict(path, DM_FORMAT_PACK, 2, DM_FORMAT_NEWER,
                   "dermis-pack version 2 (this dermis reads version 1: refused, written by a newer dermis; "
                   "update dermis)");
    dm_pack pack;
    dm_error err = {0};
    cr_expect_neq(dm_pack_open(path, &pack, &err), DM_OK);
    cr_expect(strstr(err.detail, "$.version: 2"), "%s", err.detail);
    dm_pack_close(&pack);
}

Test(format_version, scenes)
{
    char dir[256], path[320];
    cr_assert(test_tmpdir(dir, sizeof dir));
    static const struct {
        const char *json, *summary;
        int64_t version;
        dm_format_verdict verdict;
    } cases[] = {
        {"{\"format\": \"dermis-scene\", \"version\": 1, \"mesh\": {\"path\": \"a.obj\"}, \"effects\": {}}",
         "dermis-scene version 1 (this dermis reads version 1: ok)", 1, DM_FORMAT_READABLE},
        {"{\"mesh\": {\"path\": \"a.obj\"}, \"effects\": {}}",
         "dermis-scene version 1, not stated (this dermis reads version 1: ok)", 1, DM_FORMAT_READABLE},
        {"{\"format\": \"dermis-scene\", \"version\": 2, \"lights\": \"whatever a later version holds\"}",
         "dermis-scene version 2 (this dermis reads version 1: refused, written for a newer dermis; update dermis)", 2,
         DM_FORMAT_NEWER},
        {"{\"format\": \"dermis-scene\", \"version\": 0}",
         "dermis-scene version 0 (this dermis reads version 1: refused, an older scene version; rewrite it for "
         "this dermis, see dermis-scene(5))",
         0, DM_FORMAT_OLDER},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        snprintf(path, sizeof path, "%s/s%zu.json", dir, k);
        write_file(path, cases[k].json, strlen(cases[k].json));
        expect_verdict(path, DM_FORMAT_SCENE, cases[k].version, cases[k].verdict, cases[k].summary);
    }
    /* the full reader refuses version 2 with the same advice */
    dm_scene *s = malloc(sizeof *s);
    dm_error err = {0};
    cr_expect_eq(dm_scene_parse(cases[2].json, "s2.json", s, &err), DM_ERR_UNSUPPORTED);
    cr_expect_str_eq(err.detail, "s2.json: $.version: 2 is not 1 (written for a newer dermis; update dermis)");
    free(s);
}

/* No version to report: not a pack or a scene, truncated, missing, a version that is no integer. */
Test(format_version, files_without_a_version)
{
    char dir[256], path[320];
    cr_assert(test_tmpdir(dir, sizeof dir));
    static const struct {
        const char *name, *bytes, *words;
        size_t size;
        dm_result code;
    } cases[] = {
        {"plain.txt", "hello", "neither a dermis pack", 5, DM_ERR_FORMAT},
        {"profile.json", "{\"format\": \"dermis-profile\", \"version\": 1}", "\"format\" \"dermis-profile\"", 42,
         DM_ERR_FORMAT},
        {"other.json", "{\"width\": 3}", "neither \"format\" nor \"mesh\"", 12, DM_ERR_FORMAT},
        {"string.json", "{\"format\": \"dermis-scene\", \"version\": \"1\"}", "\"version\" \"1\", expected an integer",
         42, DM_ERR_FORMAT},
        {"short.dpk", "\x89" "DPK\r\n\x1a\n\x01\0\0\0", "12 bytes, expected at least the 64-byte pack header", 12,
         DM_ERR_FORMAT},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        snprintf(path, sizeof path, "%s/%s", dir, cases[k].name);
        write_file(path, cases[k].bytes, cases[k].size);
        dm_format_version v;
        dm_error err = {0};
        cr_expect_eq(dm_format_version_read(path, &v, &err), cases[k].code, "%s: %s", path, err.detail);
        cr_expect(strstr(err.detail, cases[k].words), "%s: '%s' not in: %s", cases[k].name, cases[k].words,
                  err.detail);
    }
    snprintf(path, sizeof path, "%s/missing.dpk", dir);
    dm_format_version v;
    dm_error err = {0};
    cr_expect_eq(dm_format_version_read(path, &v, &err), DM_ERR_FILE_OPEN);
    /* larger than any scene: refused without being read (a sparse file) */
    snprintf(path, sizeof path, "%s/huge.bin", dir);
    FILE *f = fopen(path, "wb");
    cr_assert(f && fseek(f, DM_FORMAT_SCENE_SIZE_MAX, SEEK_SET) == 0 && fputc('{', f) == '{');
    fclose(f);
    cr_expect_eq(dm_format_version_read(path, &v, &err), DM_ERR_FORMAT);
    cr_expect(strstr(err.detail, "over the 16777216 a scene may have"), "%s", err.detail);
}

/* dermis-check --format-version: a line per file on stdout, errors on stderr; exit 0 when every
 * file is of a version this dermis reads, 1 when one is not, 2 when one has no version (or for
 * usage errors), whatever the others. */
Test(format_version, dermis_check_exit_codes)
{
    char dir[256], cmd[2048], log[320], v2[320], v0[320];
    cr_assert(test_tmpdir(dir, sizeof dir));
    pack_of_version(dir, "v2.dpk", 2, v2, sizeof v2);
    pack_of_version(dir, "v0.dpk", 0, v0, sizeof v0);
    snprintf(log, sizeof log, "%s/out.log", dir);
    static const struct {
        const char *args;
        int code;
        const char *words;
    } cases[] = {
        {FIXTURE " assets/scenes/lps.json", 0,
         FIXTURE ": dermis-pack version 1 (this dermis reads version 1: ok)\n"
                 "assets/scenes/lps.json: dermis-scene version 1 (this dermis reads version 1: ok)\n"},
        {FIXTURE " %s/v2.dpk", 1, "/v2.dpk: dermis-pack version 2 (this dermis reads version 1: refused, written by a "
                                  "newer dermis; update dermis)\n"},
        {"%s/v0.dpk", 1, "/v0.dpk: dermis-pack version 0 (this dermis reads version 1: refused, written by an older "
                         "dermis; re-pack it from its scene with this dermis)\n"},
        {"%s/v2.dpk tests/fixtures/pack-v1/albedo.png", 2, "error: tests/fixtures/pack-v1/albedo.png: neither"},
        {"%s/none.dpk " FIXTURE, 2, "/none.dpk: No such file"},
        {"--quiet " FIXTURE " %s/v0.dpk", 1, "/v0.dpk: dermis-pack version 0"},
        {"--json " FIXTURE, 2, "error: --format-version and -v/--json conflict"},
        {"-v " FIXTURE, 2, "error: --format-version and -v/--json conflict"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        char args[1024];
        snprintf(args, sizeof args, cases[k].args, dir);
        snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-check --format-version %s", args);
        int rc = test_run(cmd, log);
        char *text = test_slurp(log);
        cr_expect_eq(rc, cases[k].code, "%s: exit %d\n%s", cmd, rc, text ? text : "");
        cr_expect(text && strstr(text, cases[k].words), "%s: '%s' not in:\n%s", cmd, cases[k].words,
                  text ? text : "");
        if (k == 5) cr_expect(text && !strstr(text, ": ok)"), "--quiet printed an ok line:\n%s", text);
        free(text);
    }
}
