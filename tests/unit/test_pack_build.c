/* Pack building as a library (packer/dm_pack_build.h): the scene read once, only the entries
 * its effects need, and the same bytes as dermis-pack, which is this API behind options. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/tmpdir.h"
#include "packer/dm_pack_build.h"
#include "pack/dm_pack.h"
#include "pack/dm_pack_needs.h"

#define HEAD DERMIS_ASSETS "/lps/LeePerrySmith.obj"

static char dir[256];
static void setup(void) { cr_assert(test_tmpdir(dir, sizeof dir)); }

/* specular + energy conservation: scene, mesh, lut.beckmann, lut.rho_dt; no stretch. */
static void write_scene(char *path, size_t size)
{
    snprintf(path, size, "%s/spec.json", dir);
    FILE *f = fopen(path, "w");
    cr_assert(f);
    fprintf(f, "{\"mesh\": {\"path\": \"%s\", \"mm_per_unit\": 50}, "
               "\"effects\": {\"specular\": true, \"energy_conservation\": true}, "
               "\"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1]}]}\n",
            HEAD);
    fclose(f);
}

/* Small, fast tables: the smallest sizes the tool accepts. */
static const dm_pack_build_options small = {.beckmann_size = 16, .lut_size = 8, .lut_nodes = 8, .quiet = true};

Test(pack_build, library_pack_equals_the_tools_and_holds_only_what_is_needed, .init = setup)
{
    char scene[320], lib_pack[320], tool_pack[320], cmd[1200];
    write_scene(scene, sizeof scene);
    snprintf(lib_pack, sizeof lib_pack, "%s/lib.dpk", dir);
    snprintf(tool_pack, sizeof tool_pack, "%s/tool.dpk", dir);

    dm_pack_build *b = malloc(sizeof *b);
    cr_assert(b);
    dm_error err = {0};
    cr_assert_eq(dm_pack_build_begin(b, scene, NULL, 0, &small, &err), DM_OK, "%s", err.detail);
    cr_expect(dm_pack_build_wants(b, "lut.beckmann"));
    cr_expect(dm_pack_build_wants(b, "lut.rho_dt"));
    cr_expect(!dm_pack_build_wants(b, "stretch"));
    cr_expect(!dm_pack_build_wants(b, "lut.env_brdf"));
    cr_expect(!dm_pack_build_wants(b, "no.such.entry"));
    const char *failed = "";
    cr_assert_eq(dm_pack_build_run(b, &failed, &err), DM_OK, "%s: %s", failed, err.detail);
    size_t size = 0;
    cr_assert_eq(dm_pack_build_write(b, lib_pack, &size, &err), DM_OK, "%s", err.detail);
    cr_expect_gt(size, 0);

    /* every entry the writer holds has its report row, in the same order */
    cr_assert_eq(b->row_count, b->w.count);
    for (int k = 0; k < b->row_count; ++k) {
        cr_expect_str_eq(b->rows[k].entry, b->w.blobs[k].desc.name);
        cr_expect(dm_pack_build_wants(b, b->rows[k].entry), "%s packed but not needed", b->rows[k].entry);
    }

    dm_pack pack;
    cr_assert_eq(dm_pack_open(lib_pack, &pack, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(pack.entry_count, b->row_count);
    cr_expect(dm_pack_find(&pack, "mesh.vertices") && dm_pack_find(&pack, "lut.beckmann"));
    cr_expect(!dm_pack_find(&pack, "stretch"));
    dm_pack_close(&pack);
    dm_pack_build_free(b);
    free(b);

    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack '%s' -o '%s' --beckmann-size 16 --lut-size 8 --lut-nodes 8 --quiet",
             scene, tool_pack);
    cr_assert_eq(test_run(cmd, NULL), 0, "%s", cmd);
    snprintf(cmd, sizeof cmd, "cmp -s '%s' '%s'", lib_pack, tool_pack);
    cr_expect_eq(test_run(cmd, NULL), 0, "the library's pack and dermis-pack's differ");
}

Test(pack_build, missing_scene_is_a_load_error_and_free_is_safe, .init = setup)
{
    char scene[320];
    snprintf(scene, sizeof scene, "%s/none.json", dir);
    dm_pack_build *b = malloc(sizeof *b);
    cr_assert(b);
    dm_error err = {0};
    cr_expect_eq(dm_pack_build_begin(b, scene, NULL, 0, &small, &err), DM_ERR_FILE_OPEN);
    cr_expect(strstr(err.detail, "none.json"), "%s", err.detail);
    dm_pack_build_free(b);
    free(b);
}
