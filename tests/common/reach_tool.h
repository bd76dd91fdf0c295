/* reach_tool.h — what the tests of the two reach tools (dermis-bake-seams, dermis-bake-thin)
 * share: reading their EXR and its provenance, the usage errors of their common command line
 * (bake/dm_bake_cli.h), the load and save failures that must leave no file, and the pack's
 * entry of the same map recording the same counts. */
#ifndef TEST_REACH_TOOL_H
#define TEST_REACH_TOOL_H

#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>

#include "expect_tool.h"
#include "tmpdir.h"
#include "image/dm_exr.h"
#include "pack/dm_pack.h"

static inline void reach_tool_read(const char *dir, const char *name, dm_exr_image *img)
{
    dm_error err = {0};
    cr_assert_eq(dm_exr_read(test_path_in(dir, name), img, &err), DM_OK, "%s", err.detail);
}

static inline int64_t prov_int(const dm_exr_image *img, const char *name)
{
    const dm_param *p = dm_prov_find(&img->prov, name);
    cr_assert(p && p->type == DM_PARAM_INT, "provenance has no int '%s'", name);
    return p->i;
}

static inline double prov_double(const dm_exr_image *img, const char *name)
{
    const dm_param *p = dm_prov_find(&img->prov, name);
    /* a whole number reads back as an int (dm_prov_from_json), which keeps d too */
    cr_assert(p && p->type != DM_PARAM_STRING, "provenance has no number '%s'", name);
    return p->d;
}

static inline const char *prov_string(const dm_exr_image *img, const char *name)
{
    const dm_param *p = dm_prov_find(&img->prov, name);
    cr_assert(p && p->type == DM_PARAM_STRING, "provenance has no string '%s'", name);
    return p->s;
}

/* The usage errors of the shared command line, each said on stderr with exit 1; then --help
 * (naming "Usage: TOOL MESH -o OUT.exr" and --reach-mm) and --version; no file written. */
static inline void reach_tool_usage_errors(const char *dir, const char *tool_path, const char *tool_name,
                                           const char *head)
{
    static const struct {
        const char *args, *says;
    } bad[] = {
        {"", "no output given (-o OUT.exr)"},
        {"-o s.exr", "no MESH given"},
        {"-o s.exr --size 8", "--size: '8' is not an integer in [16, 16384]"},
        {"-o s.exr --size 20000", "--size"},
        {"-o s.exr --mm-per-unit 0", "--mm-per-unit"},
        {"-o s.exr --reach-mm 0", "--reach-mm: '0'"},
        {"-o s.exr --reach-mm 5000", "--reach-mm"},
        {"-o s.exr --reach-mm far", "--reach-mm: 'far'"},
        {"-o s.exr --reach-mm", "--reach-mm needs a value"},
        {"-o s.exr --reach-mm 4 --profile p.json", "--reach-mm and --profile exclude each other"},
        {"-o s.exr -v --quiet", "--quiet conflicts with -v"},
        {"-o s.exr --report --quiet", "--quiet conflicts with --report"},
        {"-o s.exr --levels 3", "unknown option '--levels'"},
        {"-o s.exr MORE", "one mesh expected"},
        {"-o s.png", ".exr"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        char cmd[1024], args[512];
        snprintf(args, sizeof args, "%s", bad[k].args);
        char *more = strstr(args, "MORE");
        if (more) snprintf(more, sizeof args - (size_t)(more - args), "%s", head);
        /* "no MESH given" is the one case without the mesh */
        snprintf(cmd, sizeof cmd, "%s %s %s", tool_path, k == 1 ? "" : head, args);
        test_expect_tool(dir, 30, cmd, 1, "error:", bad[k].says);
    }
    char cmd[1024], says[256];
    snprintf(cmd, sizeof cmd, "%s --help", tool_path);
    snprintf(says, sizeof says, "Usage: %s MESH -o OUT.exr", tool_name);
    test_expect_tool(dir, 10, cmd, 0, says, "--reach-mm MM");
    snprintf(cmd, sizeof cmd, "%s --version", tool_path);
    snprintf(says, sizeof says, "%s ", tool_name);
    test_expect_tool(dir, 10, cmd, 0, says, NULL);
    cr_expect_eq(test_count_files(dir, ".exr"), 0, "a usage error wrote a file");
}

/* Exit 2 for what cannot be loaded, 4 for what cannot be saved; a failed run leaves no
 * file, neither the output nor a temporary. */
static inline void reach_tool_failures_leave_no_file(const char *dir, const char *tool_path, const char *head)
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "%s missing.obj -o s.exr --size 16", tool_path);
    test_expect_tool(dir, 30, cmd, 2, "error:", "missing.obj");
    snprintf(cmd, sizeof cmd, "%s %s -o s.exr --size 16 --profile missing.json", tool_path, head);
    test_expect_tool(dir, 30, cmd, 2, "error:", "missing.json");
    FILE *f = fopen(test_path_in(dir, "t.stl"), "w"); /* a mesh without UVs */
    cr_assert_not_null(f);
    fputs("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
          "endsolid t\n",
          f);
    fclose(f);
    snprintf(cmd, sizeof cmd, "%s t.stl -o s.exr --size 16", tool_path);
    test_expect_tool(dir, 30, cmd, 2, "error:", "no texture coordinates");
    /* a folder that cannot be made (root writes anywhere else): refused before any work */
    snprintf(cmd, sizeof cmd, "%s %s -o /dev/null/d/s.exr --size 16", tool_path, head);
    test_expect_tool(dir, 30, cmd, 4, "error:", "/dev/null/d/s.exr");
    cr_expect_eq(test_count_files(dir, ".exr"), 0, "a failed run left an output");
    cr_expect_eq(test_count_files(dir, ".tmp"), 0, "a failed run left a temporary");
}

/* The pack's entry of the tool's map (dermis-pack of a texture-space scene of the head at
 * irradiance size n, 50 mm per unit, gems3-skin: the tool's defaults at --size n) records in
 * its provenance each of keys[0..key_count) with the type and value the tool's EXR records:
 * integers exactly, doubles to 1e-14 relative (the file holds 17 digits, but the pack reader
 * keeps an entry's provenance as cJSON prints it again, which may keep 15 when they read back
 * within its own tolerance: 0.64919006824493408 comes back as ...397). */
static inline void reach_tool_pack_agrees(const char *dir, const char *tool_path, const char *head, int n,
                                          const char *entry, const char *const *keys, int key_count)
{
    FILE *f = fopen(test_path_in(dir, "pack.json"), "w");
    cr_assert_not_null(f);
    fprintf(f, "{\"mesh\": {\"path\": \"%s\", \"mm_per_unit\": 50}, "
               "\"effects\": {\"subsurface\": {\"profile\": \"gems3-skin\", \"irradiance_size\": %d}}, "
               "\"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1]}]}\n",
            head, n);
    fclose(f);
    char cmd[1024];
    snprintf(cmd, sizeof cmd,
             DERMIS_BIN "/dermis-pack pack.json -o p.dpk --beckmann-size 16 --lut-size 8 --lut-nodes 8 --quiet && "
                        "%s %s -o t.exr --size %d --quiet",
             tool_path, head, n);
    test_expect_tool(dir, 60, cmd, 0, NULL, NULL);

    dm_error err = {0};
    dm_pack pack;
    cr_assert_eq(dm_pack_open(test_path_in(dir, "p.dpk"), &pack, &err), DM_OK, "%s", err.detail);
    const dm_pack_entry *e = dm_pack_find(&pack, entry);
    cr_assert_not_null(e, "the pack has no '%s'", entry);
    dm_provenance packed;
    cr_assert_eq(dm_prov_from_json(&packed, e->provenance_json, entry, &err), DM_OK, "%s", err.detail);
    dm_pack_close(&pack);
    dm_exr_image img;
    reach_tool_read(dir, "t.exr", &img);
    for (int k = 0; k < key_count; ++k) {
        const dm_param *p = dm_prov_find(&packed, keys[k]), *t = dm_prov_find(&img.prov, keys[k]);
        cr_assert(p && t, "'%s': in the pack %s, in the tool's EXR %s", keys[k], p ? "yes" : "no", t ? "yes" : "no");
        cr_expect(p->type == t->type && p->i == t->i && fabs(p->d - t->d) <= 1e-14 * fabs(t->d),
                  "'%s': the pack %lld / %.17g, the tool %lld / %.17g", keys[k], (long long)p->i, p->d, (long long)t->i,
                  t->d);
    }
    dm_exr_free(&img);
}

#endif
