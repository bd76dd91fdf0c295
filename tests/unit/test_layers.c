/* scripts/check-layers.sh: the house rules of docs/architecture.md hold for this checkout and
 * its build, and each rule fires on a small tree that breaks it (so the check cannot pass by
 * checking nothing). */
#include <criterion/criterion.h>
#include <libgen.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../common/expect_tool.h"

/* The script's absolute path (tests run from the repository root). */
static const char *script(void)
{
    static char path[PATH_MAX + 64];
    char cwd[PATH_MAX];
    cr_assert(getcwd(cwd, sizeof cwd));
    snprintf(path, sizeof path, "%s/scripts/check-layers.sh", cwd);
    return path;
}

/* Writes root/rel (folders made) holding `text`. */
static void put(const char *root, const char *rel, const char *text)
{
    char path[1024], cmd[1200];
    snprintf(path, sizeof path, "%s/%s", root, rel);
    snprintf(cmd, sizeof cmd, "mkdir -p \"$(dirname '%s')\"", path);
    cr_assert_eq(system(cmd), 0);
    FILE *f = fopen(path, "w");
    cr_assert(f, "cannot write %s", path);
    fputs(text, f);
    fclose(f);
}

/* A tree that keeps every rule: core below pack below render, a pass with its own header. */
static void good_tree(const char *root)
{
    put(root, "lib/core/dm_a.h", "#include <stdio.h>\n");
    put(root, "lib/core/dm_a.c", "#include \"core/dm_a.h\"\n");
    put(root, "lib/pack/dm_p.c", "#include \"core/dm_a.h\"\n#include \"pack/dm_p.h\"\n");
    put(root, "lib/pack/dm_p.h", "#include \"core/dm_a.h\"\n");
    put(root, "lib/render/dm_render.h", "#include \"pack/dm_p.h\"\n");
    put(root, "lib/render/gpu/dm_gpu.h", "#include \"core/dm_a.h\"\n");
    put(root, "lib/render/frame/dm_frame.h", "#include \"render/gpu/dm_gpu.h\"\n#include \"render/dm_render.h\"\n");
    put(root, "lib/render/passes/dm_pass_x.h", "#include \"render/frame/dm_frame.h\"\n");
    put(root, "lib/render/passes/dm_pass_x_run.c", "#include \"render/passes/dm_pass_x.h\"\n");
    put(root, "lib/render/dm_render.c", "#include \"render/passes/dm_pass_x.h\"\n");
}

/* Runs the check on a tree made by good_tree plus one more file; expects exit rc and `needle`. */
static void expect_rule(const char *rel, const char *text, int rc, const char *needle)
{
    char dir[256], cmd[PATH_MAX + 512];
    cr_assert(test_tmpdir(dir, sizeof dir));
    good_tree(dir);
    if (rel) put(dir, rel, text);
    snprintf(cmd, sizeof cmd, "bash '%s' --root '%s'", script(), dir);
    test_expect_tool(dir, 60, cmd, rc, needle, NULL);
}

Test(layers, this_checkout_and_its_build_keep_every_rule, .timeout = 120)
{
    char bin[512], cmd[PATH_MAX + 600];
    snprintf(bin, sizeof bin, "%s", DERMIS_BIN); /* .../build/<config>/bin */
    const char *build = dirname(bin);
    char cwd[PATH_MAX];
    cr_assert(getcwd(cwd, sizeof cwd));
    snprintf(cmd, sizeof cmd, "bash '%s' --root '%s' --build '%s'", script(), cwd, build);
    char dir[256];
    cr_assert(test_tmpdir(dir, sizeof dir));
    test_expect_tool(dir, 100, cmd, 0, "every layer rule holds", NULL);
}

Test(layers, a_tree_that_keeps_the_rules_passes) { expect_rule(NULL, NULL, 0, "every layer rule holds"); }

Test(layers, an_include_from_a_room_above_fails)
{
    expect_rule("lib/mesh/dm_m.c", "#include \"reference/dm_r.h\"\n", 1, "[order]");
}

Test(layers, a_runtime_room_including_an_offline_one_fails)
{
    expect_rule("lib/render/dm_render_x.c", "#include \"mesh/dm_mesh.h\"\n", 1, "[runtime]");
    expect_rule("lib/pack/dm_q.c", "#include <OpenEXR/openexr.h>\n", 1, "[runtime]");
}

Test(layers, gpu_naming_the_renderer_or_the_scene_fails)
{
    expect_rule("lib/render/gpu/dm_gpu.c", "#include \"render/dm_render.h\"\n", 1, "[render]");
    expect_rule("lib/render/gpu/dm_gpu.c", "#include \"core/dm_scene.h\"\n", 1, "[render]");
    expect_rule("lib/render/frame/dm_frame.c", "#include \"render/passes/dm_pass_x.h\"\n", 1, "[render]");
}

Test(layers, a_pass_including_another_pass_fails)
{
    expect_rule("lib/render/passes/dm_pass_y.c", "#include \"render/passes/dm_pass_x.h\"\n", 1, "[passes]");
}

Test(layers, two_files_including_each_other_fail)
{
    char dir[256], cmd[PATH_MAX + 512];
    cr_assert(test_tmpdir(dir, sizeof dir));
    good_tree(dir);
    put(dir, "lib/core/dm_b.h", "\n");
    put(dir, "lib/core/dm_b.c", "#include \"core/dm_a.h\"\n");
    put(dir, "lib/core/dm_a.c", "#include \"core/dm_b.h\"\n");
    snprintf(cmd, sizeof cmd, "bash '%s' --root '%s'", script(), dir);
    test_expect_tool(dir, 60, cmd, 1, "[mutual]", "'core/dm_a' and 'core/dm_b'");
}
