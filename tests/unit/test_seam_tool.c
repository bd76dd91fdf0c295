/* dermis-bake-seams as a user runs it: the head at 256², its named channels holding the
 * library's bake texel for texel, provenance and identical reruns, --report stating the
 * bake's own counts, the reach from --reach-mm or a profile, the usage errors and exit
 * codes, no file left behind by a failed run, and the pack's seam entry recording the same
 * counts. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/expect_tool.h"
#include "../common/reach_tool.h"
#include "../common/tmpdir.h"
#include "bake/dm_seam_map.h"
#include "image/dm_exr.h"
#include "mesh/dm_mesh.h"

#define TOOL DERMIS_BIN "/dermis-bake-seams"
#define HEAD DERMIS_ASSETS "/lps/LeePerrySmith.obj"
enum { N = 256 };

static char dir[256];
static void setup(void) { cr_assert(test_tmpdir(dir, sizeof dir)); }

/* The library's bake of the head, as the tool's defaults make it (50 mm per unit). */
static void bake_head(double reach_mm, dm_seam_map *map, dm_seam_map_stats *st)
{
    dm_error err = {0};
    dm_mesh m;
    cr_assert_eq(dm_mesh_load(HEAD, &(dm_mesh_load_options){0}, &m, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_seam_map_bake(&m, &(dm_seam_map_options){N, 50.0, reach_mm}, map, st, &err), DM_OK, "%s",
                 err.detail);
    dm_mesh_free(&m);
}

static void read_exr(const char *name, dm_exr_image *img) { reach_tool_read(dir, name, img); }

Test(seam_tool, writes_the_bake_as_named_channels_with_provenance_and_identical_reruns, .init = setup, .timeout = 120)
{
    test_expect_tool(dir, 60, TOOL " " HEAD " -o a.exr --size 256 --quiet && " TOOL " " HEAD " -o b.exr --size 256 --quiet",
                     0, NULL, NULL);
    test_expect_tool(dir, 10, "cmp a.exr b.exr", 0, NULL, NULL); /* byte-identical */
    dm_exr_image img;
    read_exr("a.exr", &img);

    /* provenance: what made it, from what, with which parameters and what it found */
    double reach = reach_tool_expect_default_prov(&img, "dermis-bake-seams", N, N);

    /* the library's bake, texel for texel */
    dm_seam_map map;
    dm_seam_map_stats st;
    bake_head(reach, &map, &st);
    cr_assert_gt(st.continued_texels, 1000);
    static const char *const names[4] = {"seam.u", "seam.v", "seam.continued", "seam.mm"};
    cr_assert_eq(reach_tool_expect_texels(&img, N, N, names, map.texels, 2), st.continued_texels);
    dm_provenance counts;
    dm_prov_init(&counts, "");
    dm_seam_map_stats_prov(&st, &counts);
    reach_tool_expect_counts(&img, &counts);
    dm_seam_map_free(&map);
    dm_exr_free(&img);
}

/* Each --report line that counts something states the library's count for the same bake. */
Test(seam_tool, report_states_the_bakes_counts, .init = setup, .timeout = 120)
{
    char *text = reach_tool_report(dir, TOOL, HEAD, N, "size            256x256");
    dm_seam_map map;
    dm_seam_map_stats st;
    double reach = dm_seam_map_reach_mm(REACH_TOOL_GEMS3_WIDEST_MM2);
    bake_head(reach, &map, &st);
    dm_seam_map_free(&map);
    char want[512];
    snprintf(want, sizeof want, "seam edges      %lld: %lld cut (two sides), %lld boundary, %lld non-manifold",
             (long long)st.seam_edges, (long long)st.cut_edges, (long long)st.boundary_edges,
             (long long)st.nonmanifold_edges);
    cr_expect(strstr(text, want), "'%s' not in:\n%s", want, text);
    snprintf(want, sizeof want, "degenerate      %lld edge sides", (long long)st.degenerate_sides);
    cr_expect(strstr(text, want), "'%s' not in:\n%s", want, text);
    snprintf(want, sizeof want, "gutter texels   %lld continued, %lld lost", (long long)st.continued_texels,
             (long long)st.lost_texels);
    cr_expect(strstr(text, want), "'%s' not in:\n%s", want, text);
    snprintf(want, sizeof want, "%lld ended", (long long)st.ended_texels);
    cr_expect(strstr(text, want), "'%s' not in:\n%s", want, text);
    snprintf(want, sizeof want, "max distance    %.3f mm", st.max_distance_mm);
    cr_expect(strstr(text, want), "'%s' not in:\n%s", want, text);
    snprintf(want, sizeof want, "reach           %.3f mm beyond an edge (3 sigma of gems3-skin's widest", reach);
    cr_expect(strstr(text, want), "'%s' not in:\n%s", want, text);
    /* the head is closed: its seams are all cuts, and the bake continues across them */
    cr_expect_gt(st.cut_edges, 0);
    cr_expect_gt(st.continued_texels, 0);
    cr_expect(st.max_distance_mm > 0 && st.max_distance_mm <= reach, "max %g mm, reach %g", st.max_distance_mm, reach);
    free(text);
}

/* The reach: --reach-mm as given, else 3 sigma of the profile's widest Gaussian; a shorter
 * reach continues fewer texels and none farther than it. */
Test(seam_tool, reach_from_the_option_or_the_profile, .init = setup, .timeout = 120)
{
    dm_exr_image r, d;
    reach_tool_reach_routes(dir, TOOL, HEAD, N, N, &r, &d);
    cr_expect_lt(prov_int(&r, "continued_texels"), prov_int(&d, "continued_texels"));
    dm_exr_free(&r), dm_exr_free(&d);
}

Test(seam_tool, usage_errors_say_what_is_wrong, .init = setup)
{
    reach_tool_usage_errors(dir, TOOL, "dermis-bake-seams", HEAD);
    test_expect_tool(dir, 30, TOOL " " HEAD " -o s.exr --threads 2", 1, "error:", "--threads"); /* one pass */
}

Test(seam_tool, load_and_save_failures_leave_no_file, .init = setup, .timeout = 60)
{
    reach_tool_failures_leave_no_file(dir, TOOL, HEAD);
}

/* dermis-pack's seam entry records the counts the tool records, under the same keys
 * (dm_seam_map_stats_prov), for the same mesh, size and reach. */
Test(seam_tool, the_packs_seam_entry_records_the_same_counts, .init = setup, .timeout = 60)
{
    static const char *const keys[] = {"seam_edges",       "cut_edges",        "boundary_edges",
                                       "nonmanifold_edges", "degenerate_sides", "continued_texels",
                                       "lost_texels",       "ended_texels",     "max_distance_mm"};
    reach_tool_pack_agrees(dir, TOOL, HEAD, N, "seam", keys, (int)(sizeof keys / sizeof keys[0]));
}
