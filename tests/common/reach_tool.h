/* reach_tool.h — what the tests of the two reach tools (dermis-bake-seams, dermis-bake-thin)
 * share: reading their EXR and its provenance, the usage errors of their common command line
 * (bake/dm_bake_cli.h), their planes and counts against the bake, the default provenance,
 * --report's shared lines, the reach by either
 * route, the load and save failures that must leave no file, and the pack's entry of the
 * same map recording the same counts. */
#ifndef TEST_REACH_TOOL_H
#define TEST_REACH_TOOL_H

#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "expect_tool.h"
#include "tmpdir.h"
#include "bake/dm_seam_map.h"
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

/* img is width x height with the four channels names[0..3] (in any order in the file), each the
 * bake's interleaved texels[4 x + c] to the bit (a flag stored as half: 0 and 1 are exact).
 * Returns how many texels hold 1 in channel `flag`. */
static inline int64_t reach_tool_expect_texels(const dm_exr_image *img, int width, int height,
                                               const char *const names[4], const float *texels, int flag)
{
    cr_assert_eq(img->width, width);
    cr_assert_eq(img->height, height);
    cr_assert_eq(img->channel_count, 4);
    const float *plane[4];
    for (int c = 0; c < 4; ++c) cr_assert_not_null(plane[c] = dm_exr_find(img, names[c]), "channel %s missing", names[c]);
    int64_t flagged = 0;
    for (size_t x = 0; x < (size_t)width * (size_t)height; ++x) {
        for (int c = 0; c < 4; ++c)
            cr_assert_eq(plane[c][x], texels[4 * x + (size_t)c], "texel %zu channel %s: %g, the bake has %g", x,
                         names[c], plane[c][x], texels[4 * x + (size_t)c]);
        flagged += plane[flag][x] == 1.0f;
    }
    return flagged;
}

/* img's provenance holds every entry of want (the bake's counts as its *_stats_prov writes
 * them) with the same type and value. */
static inline void reach_tool_expect_counts(const dm_exr_image *img, const dm_provenance *want)
{
    cr_assert_gt(want->param_count, 0);
    for (int k = 0; k < want->param_count; ++k) {
        const dm_param *w = &want->params[k], *p = dm_prov_find(&img->prov, w->name);
        cr_assert_not_null(p, "the EXR's provenance has no '%s'", w->name);
        /* a whole double reads back as an int that keeps d (dm_prov_from_json) */
        bool same = w->type == DM_PARAM_INT ? p->type == DM_PARAM_INT && p->i == w->i
                                            : p->type != DM_PARAM_STRING && p->d == w->d;
        cr_expect(same, "'%s': %lld / %.17g, the bake %lld / %.17g", w->name, (long long)p->i, p->d, (long long)w->i,
                  w->d);
    }
}

/* gems3-skin's widest variance (mm^2): the reach by default is 3 sigma of it. */
#define REACH_TOOL_GEMS3_WIDEST_MM2 7.41

/* The provenance of a map made with the tool's defaults but --size: what made it (tool_name,
 * the mesh's content hash), width x height, 50 mm per unit, the reach from the built-in
 * gems3-skin. Returns that reach (mm). */
static inline double reach_tool_expect_default_prov(const dm_exr_image *img, const char *tool_name, int width,
                                                    int height)
{
    cr_assert(img->has_provenance);
    cr_assert_str_eq(img->prov.tool, tool_name);
    cr_assert(strncmp(img->prov.input_hash, "xxh3-128:", 9) == 0, "%s", img->prov.input_hash);
    cr_assert_eq(prov_int(img, "width"), width);
    cr_assert_eq(prov_int(img, "height"), height);
    cr_assert_eq(prov_double(img, "mm_per_unit"), 50.0);
    double reach = dm_seam_map_reach_mm(REACH_TOOL_GEMS3_WIDEST_MM2);
    cr_assert_eq(prov_double(img, "reach_mm"), reach);
    cr_assert_eq(prov_double(img, "largest_variance_mm2"), REACH_TOOL_GEMS3_WIDEST_MM2);
    cr_assert_str_eq(prov_string(img, "profile"), "gems3-skin");
    cr_assert_str_eq(prov_string(img, "profile_hash"), "builtin");
    return reach;
}

/* `tool_path head -o s.exr --size n --report`: exit 0, size_line and the mesh and time lines in
 * what it printed, which is returned (free it). */
static inline char *reach_tool_report(const char *dir, const char *tool_path, const char *head, int n,
                                      const char *size_line)
{
    char cmd[1024], mesh_line[512];
    snprintf(cmd, sizeof cmd, "%s %s -o s.exr --size %d --report", tool_path, head, n);
    test_expect_tool(dir, 60, cmd, 0, size_line, "time            load ");
    char *text = test_slurp(test_path_in(dir, "log.txt"));
    cr_assert_not_null(text);
    snprintf(mesh_line, sizeof mesh_line, "mesh            %s: ", head);
    cr_expect(strstr(text, mesh_line), "'%s' not in:\n%s", mesh_line, text);
    return text;
}

/* The reach: --reach-mm 3 as given, or 3 sigma of a profile whose widest variance is 1 mm^2,
 * recorded as such (the profile and its hash, or none), and the same texels by either route
 * (at --size n, each plane width x height), none continued beyond 3 mm. Fills r (--reach-mm 3)
 * and d (the default reach) for the tool's own counts to compare; free both with dm_exr_free. */
static inline void reach_tool_reach_routes(const char *dir, const char *tool_path, const char *head, int n, int height,
                                           dm_exr_image *r, dm_exr_image *d)
{
    FILE *f = fopen(test_path_in(dir, "narrow.json"), "w");
    cr_assert_not_null(f);
    fputs("{\"format\": \"dermis-profile\", \"version\": 1, \"name\": \"narrow\", \"gaussians\": ["
          "{\"variance_mm2\": 0.25, \"weights\": [0.5, 0.5, 0.5]}, {\"variance_mm2\": 1.0, \"weights\": [0.5, 0.5, 0.5]}]}\n",
          f);
    fclose(f);
    char cmd[2048];
    snprintf(cmd, sizeof cmd,
             "%s %s -o p.exr --size %d --profile narrow.json --quiet && %s %s -o r.exr --size %d --reach-mm 3 --quiet "
             "&& %s %s -o d.exr --size %d --quiet",
             tool_path, head, n, tool_path, head, n, tool_path, head, n);
    test_expect_tool(dir, 60, cmd, 0, NULL, NULL);
    dm_exr_image p;
    reach_tool_read(dir, "p.exr", &p), reach_tool_read(dir, "r.exr", r), reach_tool_read(dir, "d.exr", d);
    cr_expect_eq(prov_double(&p, "reach_mm"), 3.0); /* 3·√1 */
    cr_expect_str_eq(prov_string(&p, "profile"), "narrow");
    cr_expect(strncmp(prov_string(&p, "profile_hash"), "xxh3-128:", 9) == 0);
    cr_expect_eq(prov_double(r, "reach_mm"), 3.0);
    cr_expect_str_eq(prov_string(r, "profile"), ""); /* the profile played no part */
    cr_expect_null(dm_prov_find(&r->prov, "largest_variance_mm2"));
    /* the same reach by either route: the same texels */
    for (int c = 0; c < 4; ++c)
        cr_expect_eq(memcmp(p.planes[c], r->planes[c], sizeof(float) * (size_t)n * (size_t)height), 0, "channel %s differs", p.names[c]);
    cr_expect_leq(prov_double(r, "max_distance_mm"), 3.0);
    dm_exr_free(&p);
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
