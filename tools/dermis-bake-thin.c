/* dermis-bake-thin — mesh → thin-part map (EXR, N × 2N): per covered texel, up to two points
 * of the surface across a thin part or a fold (bake/dm_thin_map.h), for texture-space
 * diffusion to carry light through ears and across lips (issue #29 point 2).
 * Pipeline: parse → load → bake → write. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_bake_cli.h"
#include "bake/dm_seam_map.h"
#include "bake/dm_stretch.h"
#include "bake/dm_thin_map.h"
#include "image/dm_exr.h"
#include "mesh/dm_mesh.h"
#include "core/dm_cli.h"
#include "core/dm_hash.h"
#include "core/dm_profile.h"
#include "core/dm_prov.h"

#define TOOL "dermis-bake-thin"

typedef struct args {
    dm_bake_cli c;   /* the shared options (bake/dm_bake_cli.h) */
    double reach_mm; /* < 0: from the profile */
} args;

static void usage(FILE *f)
{
    dm_profile gems3;
    dm_profile_gems3_skin(&gems3);
    double v = gems3.variance_mm2[gems3.count - 1];
    fprintf(f,
            "Usage: " TOOL " MESH -o OUT.exr [--size N] [--mm-per-unit MM] [--reach-mm MM | --profile FILE]\n"
            "                        [--mesh NAME] [--threads N] [--report] [-v | --quiet]\n"
            "Bakes the thin-part map of MESH (OBJ, PLY, OFF, STL, OM, glTF 2.0 .gltf/.glb; with UVs): for every\n"
            "covered texel, rays from its surface point through the part (-n) and across a fold (+n), with a\n"
            "ring of four tilted 30 degrees around each, find the surfaces facing back within reach; the two\n"
            "heaviest distinct ones (weight exp(-d^2 / (2 v_max))) are kept, so texture-space diffusion can\n"
            "add the light that crosses ears, nostril walls, eyelids and lips. One float EXR of N x 2N:\n"
            "candidate k of texel (i, j) in row k*N + j, channels thin.u, thin.v (the UV across), thin.mm (the\n"
            "distance in mm) and thin.candidate (1, or 0: none, every channel 0).\n"
            "\n"
            "Options:\n"
            "  -o, --output FILE    output EXR (required)\n"
            "  --size N             texels along u and v, N (default %d, range 16..%d); the EXR is N x 2N\n"
            "  --mm-per-unit MM     millimetres per mesh unit (default %g, the Lee Perry-Smith head;\n"
            "                       range 1e-6..1e6)\n"
            "  --reach-mm MM        how far the rays reach (default: 3 sigma of the profile's widest Gaussian,\n"
            "                       %.3g for gems3-skin; range %g..%g)\n"
            "  --profile FILE       profile JSON whose widest Gaussian sets --reach-mm (default built-in\n"
            "                       gems3-skin, widest variance %g mm^2)\n"
            "  --mesh NAME          glTF: bake only the meshes of this name (default: every mesh of\n"
            "                       the default scene, merged, node transforms applied)\n"
            "  --threads N          bake threads (default 0 = all cores, range 0..64); the output is the\n"
            "                       same for any N\n"
            "  --report             print covered texels, texels with one and two candidates, the weight\n"
            "                       dropped, zero-UV-area and lost hits, distances and timings on stdout\n"
            "  -v, --verbose        stage timings on stderr\n"
            "  --quiet              print nothing but errors (conflicts with -v and --report)\n"
            "  -h, --help           this text\n"
            "\n"
            "Exit codes: 0 success, 1 usage error, 2 cannot load the mesh or profile,\n"
            "            3 processing failed, 4 cannot save the output.\n"
            "Example: " TOOL " LeePerrySmith.obj -o thin.exr --size 1024 --report\n",
            DM_THIN_MAP_SIZE_DEFAULT, DM_THIN_MAP_SIZE_MAX, DM_STRETCH_MM_PER_UNIT_DEFAULT, dm_seam_map_reach_mm(v),
            DM_BAKE_CLI_REACH_MIN_MM, DM_BAKE_CLI_REACH_MAX_MM, v);
}

static void print_report(const dm_bake_cli *c, const dm_bake_cli_inputs *in, const dm_thin_map *map,
                         const dm_thin_map_stats *s, const dm_bake_cli_times *t)
{
    dm_bake_cli_report_mesh(c->mesh, &in->mesh);
    printf("size            %dx%d (%d candidates per texel, one above the other)\n", map->size,
           DM_THIN_MAP_CANDIDATES * map->size, DM_THIN_MAP_CANDIDATES);
    printf("reach           %.3f mm (%s)\n", in->reach_mm, in->reach_from);
    printf("covered texels  %lld: %lld with one candidate, %lld with two\n", (long long)s->covered_texels,
           (long long)s->one_candidate_texels, (long long)s->two_candidate_texels);
    printf("dropped         %lld texels had more surfaces across: weight %.4f in all, %.4f at most\n",
           (long long)s->dropped_texels, s->dropped_weight_sum, s->dropped_weight_max);
    printf("hits            %lld on zero-UV-area triangles, %lld lost (landed on no covered texel)\n",
           (long long)s->zero_uv_area_hits, (long long)s->lost_hits);
    printf("distance        %.3f mm at most, %.3f mm mean\n", s->max_distance_mm, s->mean_distance_mm);
    dm_bake_cli_report_times(t);
}

static int write_map(const args *a, const dm_bake_cli_inputs *in, const dm_thin_map *map, const dm_thin_map_stats *s)
{
    const int w = map->size, h = DM_THIN_MAP_CANDIDATES * map->size;
    dm_provenance prov;
    dm_bake_cli_reach_map_prov(&a->c, TOOL, in, a->reach_mm, h,
                               "rays along -n, +n and a 30-degree ring of 4 around each; the two heaviest distinct "
                               "surfaces facing back",
                               "thin.u/.v: UV across; thin.mm: distance mm; thin.candidate: 1 or 0 (none); candidate k "
                               "in rows k*N..(k+1)*N-1",
                               &prov);
    dm_thin_map_stats_prov(s, &prov);

    static const char *const names[4] = {"thin.u", "thin.v", "thin.mm", "thin.candidate"};
    return dm_bake_cli_write_rgba(a->c.output, map->texels, w, h, names, 1u << 3, &prov); /* the flag in half */
}

int main(int argc, char **argv)
{
    args a;
    int rc = dm_bake_cli_parse_reach(argc, argv, TOOL, DM_THIN_MAP_SIZE_DEFAULT, DM_THIN_MAP_SIZE_MAX, true, usage, &a.c,
                                     &a.reach_mm);
    if (rc >= 0) return rc;
    if ((rc = dm_bake_cli_output(&a.c))) return rc; /* before any work (core/dm_output.h) */

    /* Load. */
    dm_bake_cli_inputs in;
    if ((rc = dm_bake_cli_load_reach(&a.c, a.reach_mm, &in)) != DM_EXIT_OK) return rc;
    dm_bake_cli_times t = {.load_ms = in.load_ms};

    /* Process. */
    dm_error err = {0};
    double t0 = dm_now_ms();
    dm_thin_map_options opt = {.size = (int)a.c.size, .mm_per_unit = a.c.mm_per_unit, .reach_mm = in.reach_mm,
                               .threads = (int)a.c.threads};
    dm_thin_map map;
    dm_thin_map_stats s;
    dm_result r = dm_thin_map_bake(&in.mesh, &opt, &map, &s, &err);
    t.bake_ms = dm_now_ms() - t0;
    if ((rc = dm_bake_cli_baked(&a.c, r, &err, map.texels,
                                4 * DM_THIN_MAP_CANDIDATES * (size_t)map.size * (size_t)map.size, "thin map"))) {
        dm_thin_map_free(&map);
        dm_mesh_free(&in.mesh);
        return rc;
    }
    if (a.c.verbose)
        fprintf(stderr, "baked %dx%d, reach %.3f mm: %lld texels with a candidate in %.1f ms\n", map.size,
                DM_THIN_MAP_CANDIDATES * map.size, in.reach_mm, (long long)(s.one_candidate_texels + s.two_candidate_texels),
                t.bake_ms);
    if (!a.c.quiet && s.zero_uv_area_hits > 0)
        fprintf(stderr, "warning: %s: %lld rays met a triangle of zero UV area: no candidate from them\n", a.c.mesh,
                (long long)s.zero_uv_area_hits);

    /* Write. */
    t0 = dm_now_ms();
    rc = write_map(&a, &in, &map, &s);
    t.write_ms = dm_now_ms() - t0;
    if (rc == DM_EXIT_OK && a.c.report) print_report(&a.c, &in, &map, &s, &t);
    else if (rc == DM_EXIT_OK && !a.c.quiet)
        printf("%s: %dx%d, reach %.3f mm, %lld covered texels: %lld with one candidate, %lld with two, %lld dropped "
               "more (weight %.3f), farthest %.3f mm\n",
               a.c.output, map.size, DM_THIN_MAP_CANDIDATES * map.size, in.reach_mm, (long long)s.covered_texels,
               (long long)s.one_candidate_texels, (long long)s.two_candidate_texels, (long long)s.dropped_texels,
               s.dropped_weight_sum, s.max_distance_mm);
    dm_thin_map_free(&map);
    dm_mesh_free(&in.mesh);
    return rc;
}
