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
#define GEMS3_WIDEST_MM2 7.41

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
    cr_assert_eq(img.width, N);
    cr_assert_eq(img.height, H);
    cr_assert_eq(img.channel_count, 4);
    const float *plane[4] = {dm_exr_find(&img, "thin.u"), dm_exr_find(&img, "thin.v"), dm_exr_find(&img, "thin.mm"),
                             dm_exr_find(&img, "thin.candidate")};
    for (int c = 0; c < 4; ++c) cr_assert_not_null(plane[c], "channel %d missing", c);

    /* provenance: what made it, from what, with which parameters and what it found */
    cr_assert(img.has_provenance);
    cr_assert_str_eq(img.prov.tool, "dermis-bake-thin");
    cr_assert(strncmp(img.prov.input_hash, "xxh3-128:", 9) == 0, "%s", img.prov.input_hash);
    cr_assert_eq(prov_int(&img, "width"), N);
    cr_assert_eq(prov_int(&img, "height"), H);
    cr_assert_eq(prov_double(&img, "mm_per_unit"), 50.0);
    double reach = dm_seam_map_reach_mm(GEMS3_WIDEST_MM2);
    cr_assert_eq(prov_double(&img, "reach_mm"), reach);
    cr_assert_eq(prov_double(&img, "largest_variance_mm2"), GEMS3_WIDEST_MM2);
    cr_assert_str_eq(prov_string(&img, "profile"), "gems3-skin");
    cr_assert_str_eq(prov_string(&img, "profile_hash"), "builtin");

    /* the library's bake, texel for texel (the flag is stored as half: 0 and 1 are exact) */
    dm_thin_map map;
    dm_thin_map_stats st;
    bake_head(reach, &map, &st);
    cr_assert_gt(st.one_candidate_texels, 100);
    int64_t with = 0;
    for (size_t x = 0; x < (size_t)N * H; ++x) {
        for (int c = 0; c < 4; ++c)
            cr_assert_eq(plane[c][x], map.texels[4 * x + (size_t)c], "texel %zu channel %d: %g, the bake has %g", x, c,
                         plane[c][x], map.texels[4 * x + (size_t)c]);
        with += plane[3][x] == 1.0f;
    }
    cr_assert_eq(with, st.one_candidate_texels + 2 * st.two_candidate_texels);
    cr_assert_eq(prov_int(&img, "covered_texels"), st.covered_texels);
    cr_assert_eq(prov_int(&img, "one_candidate_texels"), st.one_candidate_texels);
    cr_assert_eq(prov_int(&img, "two_candidate_texels"), st.two_candidate_texels);
    cr_assert_eq(prov_int(&img, "dropped_texels"), st.dropped_texels);
    cr_assert_eq(prov_double(&img, "dropped_weight_sum"), st.dropped_weight_sum);
    cr_assert_eq(prov_double(&img, "max_distance_mm"), st.max_distance_mm);
    dm_thin_map_free(&map);
    dm_exr_free(&img);
}

/* Each --report line that counts something states the library's count for the same bake. */
Test(thin_tool, report_states_the_bakes_counts, .init = setup, .timeout = 120)
{
    test_expect_tool(dir, 60, TOOL " " HEAD " -o s.exr --size 256 --report", 0, "size            256x512", NULL);
    char *text = test_slurp(test_path_in(dir, "log.txt"));
    cr_assert_not_null(text);
    dm_thin_map map;
    dm_thin_map_stats st;
    double reach = dm_seam_map_reach_mm(GEMS3_WIDEST_MM2);
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
    cr_expect(strstr(text, "mesh            " HEAD ": "), "%s", text);
    cr_expect(strstr(text, "time            load "), "%s", text);
    cr_expect(st.max_distance_mm > 0 && st.max_distance_mm <= reach, "max %g mm, reach %g", st.max_distance_mm, reach);
    free(text);
}

/* The reach: --reach-mm as given, else 3 sigma of the profile's widest Gaussian; a shorter
 * reach finds fewer surfaces and none farther than it. */
Test(thin_tool, reach_from_the_option_or_the_profile, .init = setup, .timeout = 120)
{
    FILE *f = fopen(test_path_in(dir, "narrow.json"), "w");
    cr_assert_not_null(f);
    fputs("{\"format\": \"dermis-profile\", \"version\": 1, \"name\": \"narrow\", \"gaussians\": ["
          "{\"variance_mm2\": 0.25, \"weights\": [0.5, 0.5, 0.5]}, {\"variance_mm2\": 1.0, \"weights\": [0.5, 0.5, 0.5]}]}\n",
          f);
    fclose(f);
    test_expect_tool(dir, 60,
                     TOOL " " HEAD " -o p.exr --size 256 --profile narrow.json --quiet && " TOOL " " HEAD
                          " -o r.exr --size 256 --reach-mm 3 --quiet && " TOOL " " HEAD " -o d.exr --size 256 --quiet",
                     0, NULL, NULL);
    dm_exr_image p, r, d;
    read_exr("p.exr", &p), read_exr("r.exr", &r), read_exr("d.exr", &d);
    cr_expect_eq(prov_double(&p, "reach_mm"), 3.0); /* 3·√1 */
    cr_expect_str_eq(prov_string(&p, "profile"), "narrow");
    cr_expect(strncmp(prov_string(&p, "profile_hash"), "xxh3-128:", 9) == 0);
    cr_expect_eq(prov_double(&r, "reach_mm"), 3.0);
    cr_expect_str_eq(prov_string(&r, "profile"), ""); /* the profile played no part */
    cr_expect_null(dm_prov_find(&r.prov, "largest_variance_mm2"));
    for (int c = 0; c < 4; ++c)
        cr_expect_eq(memcmp(p.planes[c], r.planes[c], sizeof(float) * N * H), 0, "channel %s differs", p.names[c]);
    cr_expect_lt(prov_int(&r, "one_candidate_texels") + prov_int(&r, "two_candidate_texels"),
                 prov_int(&d, "one_candidate_texels") + prov_int(&d, "two_candidate_texels"));
    cr_expect_leq(prov_double(&r, "max_distance_mm"), 3.0);
    dm_exr_free(&p), dm_exr_free(&r), dm_exr_free(&d);
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
