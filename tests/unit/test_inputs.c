/* Inputs that are not regular files, too large, or named from a glTF outside its folder
 * (issue 31, point 2; docs/files.md): every tool refuses them promptly (a `timeout` makes a
 * hang a failure), with exit 2 and a message that says what the file is; a bad glTF gives
 * the same exit code from every tool. The rules themselves (core/dm_input.h,
 * core/dm_uri.h) are tested directly too. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/dm_input.h"
#include "pack/dm_pack.h"
#include "core/dm_uri.h"
#include "../common/gltf_write.h"
#include "../common/expect_tool.h"

#define HEAD DERMIS_ASSETS "/lps/LeePerrySmith.obj"

static char dir[256];
static void setup(void)
{
    cr_assert(test_tmpdir(dir, sizeof dir));
}
TestSuite(inputs, .init = setup, .timeout = 120);

#define in_dir(name) test_path_in(dir, name)
/* the tool under `timeout 20`: a hang fails instead of hanging */
#define expect(cmd, rc, n1, n2) ((void)test_expect_tool(dir, 20, cmd, rc, n1, n2))

static void fifo(const char *name)
{
    cr_assert_eq(mkfifo(in_dir(name), 0600), 0, "mkfifo %s", name);
}

static bool have_viewer(void)
{
    return access(DERMIS_BIN "/dermis-view", X_OK) == 0;
}

/* --- the rules ------------------------------------------------------------------------ */

Test(inputs, rules_refuse_fifo_device_directory_and_oversize)
{
    fifo("f.json");
    dm_error err = {0};
    char *text = NULL;
    size_t size = 0;
    cr_expect_eq(dm_input_read(in_dir("f.json"), DM_INPUT_JSON, &text, &size, &err), DM_ERR_FILE_OPEN);
    cr_expect(strstr(err.detail, "is a FIFO"), "%s", err.detail);
    cr_expect_eq(dm_input_read("/dev/zero", DM_INPUT_JSON, &text, &size, &err), DM_ERR_FILE_OPEN);
    cr_expect(strstr(err.detail, "/dev/zero: is a character device, not a regular file"), "%s", err.detail);
    cr_expect_eq(dm_input_check(dir, DM_INPUT_ANY, NULL, &err), DM_ERR_FILE_OPEN);
    cr_expect(strstr(err.detail, "is a directory"), "%s", err.detail);
    /* the cap: one byte over the script cap is refused, the cap itself is read */
    const char *big = in_dir("big.txt");
    FILE *f = fopen(big, "wb");
    cr_assert(f);
    cr_assert_eq(ftruncate(fileno(f), (off_t)dm_input_cap(DM_INPUT_SCRIPT)), 0);
    fclose(f);
    cr_expect_eq(dm_input_read(big, DM_INPUT_SCRIPT, &text, &size, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(size, dm_input_cap(DM_INPUT_SCRIPT));
    free(text);
    cr_assert_eq(truncate(big, (off_t)dm_input_cap(DM_INPUT_SCRIPT) + 1), 0);
    cr_expect_eq(dm_input_read(big, DM_INPUT_SCRIPT, &text, &size, &err), DM_ERR_FILE_OPEN);
    cr_expect(strstr(err.detail, "more than the 1 MiB limit for a viewer script"), "%s", err.detail);
    cr_expect_null(text);
    /* a regular file passes, and comes back whole */
    cr_assert_eq(test_write_bytes(in_dir("ok.json"), "{}", 2), 0);
    cr_expect_eq(dm_input_read(in_dir("ok.json"), DM_INPUT_JSON, &text, &size, &err), DM_OK, "%s", err.detail);
    cr_expect_str_eq(text, "{}");
    free(text);
}

Test(inputs, uri_confined_to_the_folder)
{
    cr_assert_eq(mkdir(in_dir("g"), 0755), 0);
    cr_assert_eq(test_write_bytes(in_dir("g/a b.bin"), "x", 1), 0);
    cr_assert_eq(test_write_bytes(in_dir("outside.bin"), "x", 1), 0);
    cr_assert_eq(symlink("../outside.bin", in_dir("g/link.bin")), 0);
    const char *gltf = in_dir("g/m.gltf");
    char out[4096];
    dm_error err = {0};
    bool missing = false;
    cr_expect_eq(dm_uri_resolve(gltf, "a%20b.bin", true, out, sizeof out, &missing, &err), DM_OK, "%s", err.detail);
    cr_expect(strstr(out, "/g/a b.bin"), "%s", out);
    static const struct { const char *uri, *why; } bad[] = {
        {"/etc/passwd", "an absolute path"},       {"%2Fetc%2Fpasswd", "an absolute path"},
        {"../outside.bin", "'..' component"},      {"sub/%2E%2E/%2E%2E/outside.bin", "'..' component"},
        {"..%2Foutside.bin", "'..' component"},     {"file:///etc/passwd", "names a scheme"},
        {"link.bin", "outside the folder"},        {"%00x", "%00"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        cr_expect_eq(dm_uri_resolve(gltf, bad[k].uri, true, out, sizeof out, &missing, &err), DM_ERR_FILE_OPEN,
                     "%s accepted", bad[k].uri);
        cr_expect(strstr(err.detail, bad[k].why) && strstr(err.detail, gltf), "%s: %s", bad[k].uri, err.detail);
        cr_expect(!missing, "%s", bad[k].uri);
    }
    cr_expect_eq(dm_uri_resolve(gltf, "none.bin", true, out, sizeof out, &missing, &err), DM_ERR_FILE_OPEN);
    cr_expect(missing, "%s", err.detail);
}

/* --- every tool ----------------------------------------------------------------------- */

Test(inputs, fifo_refused_by_every_tool)
{
    const char *names[] = {"f.obj", "f.hdr", "f.json", "f.dpk", "f.txt", "f.exr"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k) fifo(names[k]);
    const char *const needle = "is a FIFO";
    expect(DERMIS_BIN "/dermis-bake-stretch f.obj -o s.exr --size 16", 2, needle, "f.obj");
    expect(DERMIS_BIN "/dermis-bake-curvature f.obj -o c.exr --size 16", 2, needle, "f.obj");
    expect(DERMIS_BIN "/dermis-bake-stretch " HEAD " --profile f.json -o s.exr --size 16", 2, needle, "f.json");
    expect(DERMIS_BIN "/dermis-bake-env f.hdr -o e.exr", 2, needle, "f.hdr");
    expect(DERMIS_BIN "/dermis-bake-lut --tables preintegrated --profile f.json -o luts", 2, needle, "f.json");
    expect(DERMIS_BIN "/dermis-pack f.json -o p.dpk", 2, needle, "f.json");
    expect(DERMIS_BIN "/dermis-render f.dpk -o r.png", 2, needle, "f.dpk");
    expect(DERMIS_BIN "/dermis-render --synthetic quad --reference f.exr --size 8x8", 2, needle, "f.exr");
    expect(DERMIS_BIN "/dermis-reference f.dpk --texture-space 16 -o r.exr", 2, needle, "f.dpk");
    expect(DERMIS_BIN "/dermis-reference --merge f.exr -o r.exr", 2, needle, "f.exr");
    /* the validator's own codes: 1, the file failed (docs/files.md); --format-version: 2 */
    expect(DERMIS_BIN "/dermis-check f.json", 1, needle, "f.json");
    expect(DERMIS_BIN "/dermis-check --format-version f.dpk", 2, needle, "f.dpk");
    if (have_viewer()) { /* the pack and the script are read before any window opens */
        expect(DERMIS_BIN "/dermis-view f.dpk", 2, needle, "f.dpk");
        expect(DERMIS_BIN "/dermis-view --synthetic quad --script f.txt", 2, needle, "f.txt");
    }
    cr_expect_eq(test_count_files(dir, ".exr"), 1, "only the FIFO f.exr: nothing written");
}

Test(inputs, devices_and_directories_refused)
{
    expect(DERMIS_BIN "/dermis-render /dev/zero -o r.png", 2, "/dev/zero: is a character device", NULL);
    expect(DERMIS_BIN "/dermis-reference /dev/zero --texture-space 16 -o r.exr", 2, "is a character device", NULL);
    expect(DERMIS_BIN "/dermis-pack /dev/zero -o p.dpk", 2, "/dev/zero: is a character device", NULL);
    expect(DERMIS_BIN "/dermis-bake-stretch /dev/zero -o s.exr", 2, NULL, NULL); /* no mesh extension */
    cr_assert_eq(mkdir(in_dir("d.json"), 0755), 0);
    cr_assert_eq(mkdir(in_dir("d.dpk"), 0755), 0);
    cr_assert_eq(mkdir(in_dir("d.obj"), 0755), 0);
    expect(DERMIS_BIN "/dermis-pack d.json -o p.dpk", 2, "d.json: is a directory", NULL);
    expect(DERMIS_BIN "/dermis-render d.dpk -o r.png", 2, "d.dpk: is a directory", NULL);
    expect(DERMIS_BIN "/dermis-bake-stretch d.obj -o s.exr", 2, "d.obj: is a directory", NULL);
    expect(DERMIS_BIN "/dermis-check d.json", 1, "d.json: is a directory", NULL);
    if (have_viewer()) expect(DERMIS_BIN "/dermis-view /dev/zero", 2, "is a character device", NULL);
}

Test(inputs, empty_pack_said_empty)
{
    cr_assert_eq(test_write_bytes(in_dir("e.dpk"), "", 0), 0);
    expect(DERMIS_BIN "/dermis-render e.dpk -o r.png", 2, "e.dpk: the file is empty", NULL);
    expect(DERMIS_BIN "/dermis-check e.dpk", 1, "the file is empty", NULL);
    dm_pack pack;
    dm_error err = {0};
    cr_expect_eq(dm_pack_open(in_dir("e.dpk"), &pack, &err), DM_ERR_FORMAT);
    cr_expect(!strstr(err.detail, "aligned"), "%s", err.detail);
}

Test(inputs, oversize_json_refused_naming_the_cap)
{
    const char *big = in_dir("big.json");
    cr_assert_eq(test_write_bytes(big, "{", 1), 0);
    cr_assert_eq(truncate(big, (off_t)(16 << 20) + 1), 0); /* sparse: costs no disk */
    expect(DERMIS_BIN "/dermis-pack big.json -o p.dpk", 2, "more than the 16 MiB limit", "big.json");
    expect(DERMIS_BIN "/dermis-bake-stretch " HEAD " --profile big.json -o s.exr --size 16", 2,
           "more than the 16 MiB limit", NULL);
}

/* --- glTF URIs ------------------------------------------------------------------------ */

/* The quad of fuzz/corpus/gltf/quad-data.gltf with its buffer's URI replaced (buffer_uri),
 * or with a baseColor image of URI image_uri added. */
static void write_gltf(const char *name, const char *buffer_uri, const char *image_uri)
{
    char *src = test_slurp("fuzz/corpus/gltf/quad-data.gltf");
    cr_assert(src, "fuzz/corpus/gltf/quad-data.gltf (tests run from the checkout)");
    char *json = malloc(strlen(src) + 1024);
    char *uri = strstr(src, "\"uri\":\"data:"), *end = uri ? strchr(uri + 7, '"') : NULL;
    cr_assert(end);
    if (buffer_uri) {
        snprintf(json, strlen(src) + 1024, "%.*s\"uri\":\"%s%s", (int)(uri - src), src, buffer_uri, end);
    } else {
        char *ind = strstr(src, "\"indices\":3}");
        cr_assert(ind);
        size_t tail = strlen(src) - 1; /* before the last '}' */
        snprintf(json, strlen(src) + 1024,
                 "%.*s\"indices\":3,\"material\":0}%.*s,\"images\":[{\"uri\":\"%s\"}],\"textures\":[{\"source\":0}],"
                 "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]}",
                 (int)(ind - src), src, (int)(tail - (size_t)(ind - src) - 12), ind + 12, image_uri);
    }
    cr_assert_eq(test_write_bytes(in_dir(name), json, strlen(json)), 0);
    free(json);
    free(src);
}

Test(inputs, gltf_uris_outside_the_folder_refused_by_every_tool, .timeout = 240)
{
    cr_assert_eq(mkdir(in_dir("m"), 0755), 0);
    cr_assert_eq(symlink("/etc/passwd", in_dir("m/link.bin")), 0);
    static const struct { const char *buffer, *image, *needle; } cases[] = {
        {"/etc/passwd", NULL, "an absolute path"},
        {"../../../../etc/passwd", NULL, "'..' component"},
        {"%2Fetc%2Fpasswd", NULL, "an absolute path"},
        {"%2E%2E%2F%2E%2E%2Fetc%2Fpasswd", NULL, "'..' component"},
        {"link.bin", NULL, "outside the folder"},
        {NULL, "/dev/zero", "an absolute path"},
        {NULL, "../secret.png", "'..' component"},
        {NULL, "file:///etc/passwd", "names a scheme"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        write_gltf("m/q.gltf", cases[k].buffer, cases[k].image);
        const char *scene = "{\"format\":\"dermis-scene\",\"version\":1,\"mesh\":{\"path\":\"m/q.gltf\"},"
                            "\"effects\":{\"specular\":false}}";
        cr_assert_eq(test_write_bytes(in_dir("s.json"), scene, strlen(scene)), 0);
        expect(DERMIS_BIN "/dermis-bake-stretch m/q.gltf -o s.exr --size 16", 2, cases[k].needle,
               "a glTF may only name files in its own folder");
        expect(DERMIS_BIN "/dermis-bake-curvature m/q.gltf -o c.exr --size 16", 2, cases[k].needle, NULL);
        expect(DERMIS_BIN "/dermis-pack s.json -o p.dpk --quiet", 2, cases[k].needle, NULL);
    }
    cr_expect_eq(test_count_files(dir, ".exr"), 0);
    cr_expect_eq(test_count_files(dir, ".dpk"), 0);
}

/* A glTF that the mesh reader refuses with a code other than FORMAT (here points only,
 * DM_ERR_EMPTY, found while its primitives are read) is "cannot load an input" from every
 * tool: it was 2 from the bakers and 3 from dermis-pack. */
Test(inputs, bad_gltf_same_exit_code_from_every_tool)
{
    char *src = test_slurp("fuzz/corpus/gltf/quad-data.gltf");
    cr_assert(src);
    char *p = strstr(src, "\"indices\":3}");
    cr_assert(p);
    char json[8192];
    snprintf(json, sizeof json, "%.*s\"indices\":3,\"mode\":0%s", (int)(p - src), src, p + 11);
    free(src);
    cr_assert_eq(test_write_bytes(in_dir("points.gltf"), json, strlen(json)), 0);
    const char *scene = "{\"format\":\"dermis-scene\",\"version\":1,\"mesh\":{\"path\":\"points.gltf\"},"
                        "\"effects\":{\"specular\":false}}";
    cr_assert_eq(test_write_bytes(in_dir("s.json"), scene, strlen(scene)), 0);
    expect(DERMIS_BIN "/dermis-bake-stretch points.gltf -o s.exr --size 16", 2, "points.gltf", "no triangles");
    expect(DERMIS_BIN "/dermis-bake-curvature points.gltf -o c.exr --size 16", 2, "points.gltf", "no triangles");
    expect(DERMIS_BIN "/dermis-pack s.json -o p.dpk --quiet", 2, "points.gltf", "no triangles");
}
