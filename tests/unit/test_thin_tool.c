/* dermis-bake-thin as a user runs it: the head at 256 (an EXR of 256 x 512), its named
 * channels holding the library's bake texel for texel, provenance and identical reruns for any
 * thread count, --report stating the bake's own counts, the reach from --reach-mm or a
 * profile, the usage errors and exit codes, no file left behind by a failed run, and the pack's
 * thin entry recording the same counts. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/expect_tool.h"
#include "../common/reach_tool.h"
#include "../common/tmpdir.h"
#include "bake/dm_seam_map.h"
#include "bake/dm_thin_map.h"
#include "image/dm_exr.h"
#include "mesh/dm_mesh.h"

#define TOOL DERMIS_BIN "/dermis-bake-thin"
#define HEAD DERMIS_ASSETS "/lps/LeePerrySmith.obj"
enum { N = 256, H = DM_THIN_MAP_CANDIDATES * N };

static char dir[256];
static void setup(void) { cr_assert(test_tmpdir(dir, sizeof dir)); }

/* The library's bake of the head, as the tool's defaults make it (50 mm per unit). */
static void bake_head(double reach_mm, dm_thin_map *map, dm_thin_map_stats *st)
{
    dm_error err = {0};
    dm_mesh m;
    cr_assert_eq(dm_mesh_load(HEAD, &(dm_mesh_load_options){0}, &m, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_thin_map_bake(&m, &(dm_thin_map_options){N, 50.0, reach_mm, 0}, map, st, &err), DM_OK, "%s",
                 err.detail);
    dm_mesh_free(&m);
}

static void read_exr(const char *name, dm_exr_image *img) { reach_tool_read(dir, name, img); }

Test(thin_tool, writes_the_bake_as_named_channels_with_provenance_and_identical_reruns, .init = setup, .timeout = 120)
{
    test_expect_tool(dir, 60,
                     TOOL " " HEAD " -o a.exr --size 256 --threads 1 --quiet && " TOOL " " HEAD
                          " -o b.exr --size 256 --threads 2 --quiet",
                     0, NULL, NULL);
    test_expect_tool(dir, 10, "cmp a.exr b.exr", 0, NULL, NULL); /* byte-identical for 1 and 2 threads */
    dm_exr_image img;
    read_exr("a.exr", &img);

    /* provenance: what made it, from what, with which parameters and what it found */
    double reach = reach_tool_expect_default_prov(&img, "dermis-bake-thin", N, H);

    /* the library's bake, texel for texel */
    dm_thin_map map;
    dm_thin_map_stats st;
    bake_head(reach, &map, &st);
    cr_assert_gt(st.one_candidate_texels, 100);
    static const char *const names[4] = {"thin.u", "thin.v", "thin.mm", "thin.candidate"};
    cr_assert_eq(reach_tool_expect_texels(&img, N, H, names, map.texels, 3),
                 st.one_candidate_texels + 2 * st.two_candidate_texels);
    dm_provenance counts;
    dm_prov_init(&counts, "");
    dm_thin_map_stats_prov(&st, &counts);
    reach_tool_expect_counts(&img, &counts);
    dm_thin_map_free(&map);
    dm_exr_free(&img);
}

/* Each --report line that counts something states the library's count for the same bake. */
Test(thin_tool, report_states_the_bakes_counts, .init = setup, .timeout = 120)
{
    char *text = reach_tool_report(dir, TOOL, HEAD, N, "size            256x512");
    dm_thin_map map;
    dm_thin_map_stats st;
    double reach = dm_seam_map_reach_mm(REACH_TOOL_GEMS3_WIDEST_MM2);
    bake_head(reach, &map, &st);
    dm_thin_map_free(&map);
    char want[512];
    snprintf(want, sizeof want, "covered texels  %lld: %lld with one candidate, %lld with two",
             (long long)st.covered_texels, (long long)st.one_candidate_texels, (long long)st.two_candidate_texels);
    cr_expect(strstr(text, want), "'%s' not in:\n%s", want, text);
    snprintf(want, sizeof want, "dropped         %lld texels had more surfaces across: weight %.4f in all, %.4f at most",
             (long long)st.dropped_texels, st.dropped_weight_sum, st.dropped_weight_max);
    cr_expect(strstr(text, want), "'%s' not in:\n%s", want, text);
    snprintf(want, sizeof want, "hits            %lld on zero-UV-area triangles, %lld lost", (long long)st.zero_uv_area_hits,
             (long long)st.lost_hits);
    cr_expect(strstr(text, want), "'%s' not in:\n%s", want, text);
    snprintf(want, sizeof want, "distance        %.3f mm at most, %.3f mm mean", st.max_distance_mm, st.mean_distance_mm);
    cr_expect(strstr(text, want), "'%s' not in:\n%s", want, text);
    snprintf(want, sizeof want, "reach           %.3f mm (3 sigma of gems3-skin's widest", reach);
    cr_expect(strstr(text, want), "'%s' not in:\n%s", want, text);
    cr_expect(st.max_distance_mm > 0 && st.max_distance_mm <= reach, "max %g mm, reach %g", st.max_distance_mm, reach);
    free(text);
}

/* The reach: --reach-mm as given, else 3 sigma of the profile's widest Gaussian; a shorter
 * reach finds fewer surfaces and none farther than it. */
Test(thin_tool, reach_from_the_option_or_the_profile, .init = setup, .timeout = 120)
{
    dm_exr_image r, d;
    reach_tool_reach_routes(dir, TOOL, HEAD, N, H, &r, &d);
    cr_expect_lt(prov_int(&r, "one_candidate_texels") + prov_int(&r, "two_candidate_texels"),
                 prov_int(&d, "one_candidate_texels") + prov_int(&d, "two_candidate_texels"));
    dm_exr_free(&r), dm_exr_free(&d);
}

Test(thin_tool, usage_errors_say_what_is_wrong, .init = setup)
{
    reach_tool_usage_errors(dir, TOOL, "dermis-bake-thin", HEAD);
    test_expect_tool(dir, 30, TOOL " " HEAD " -o s.exr --threads 65", 1, "error:", "--threads");
}

Test(thin_tool, load_and_save_failures_leave_no_file, .init = setup, .timeout = 60)
{
    reach_tool_failures_leave_no_file(dir, TOOL, HEAD);
}

/* dermis-pack's thin entry records the counts the tool records, under the same keys
 * (dm_thin_map_stats_prov), for the same mesh, size and reach. */
Test(thin_tool, the_packs_thin_entry_records_the_same_counts, .init = setup, .timeout = 60)
{
    static const char *const keys[] = {"covered_texels",     "one_candidate_texels", "two_candidate_texels",
                                       "dropped_texels",     "dropped_weight_sum",   "dropped_weight_max",
                                       "zero_uv_area_hits",  "lost_hits",            "max_distance_mm",
                                       "mean_distance_mm"};
    reach_tool_pack_agrees(dir, TOOL, HEAD, N, "thin", keys, (int)(sizeof keys / sizeof keys[0]));
}
