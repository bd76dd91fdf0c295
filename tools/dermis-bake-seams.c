/* dermis-bake-seams — mesh → seam map (EXR): per gutter texel, the UV where the surface
 * continues across the UV seam (bake/dm_seam_map.h), for texture-space diffusion to blur
 * across seams (issue #29 point 1). Pipeline: parse → load → bake → write. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_bake_cli.h"
#include "bake/dm_seam_map.h"
#include "bake/dm_stretch.h"
#include "image/dm_exr.h"
#include "mesh/dm_mesh.h"
#include "core/dm_cli.h"
#include "core/dm_hash.h"
#include "core/dm_profile.h"
#include "core/dm_prov.h"

#define TOOL "dermis-bake-seams"

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
            "                         [--mesh NAME] [--report] [-v | --quiet]\n"
            "Bakes the seam map of MESH (OBJ, PLY, OFF, STL, OM, glTF 2.0 .gltf/.glb; with UVs): for every\n"
            "gutter texel within reach of a UV chart, the point of the surface it stands for, found by\n"
            "extending the chart across its nearest seam edge and unfolding onto the triangle on the other\n"
            "side, looked up in that triangle's UVs; texture-space diffusion reads there so light crosses\n"
            "UV seams. Beyond a boundary edge the surface ends and the texel stays empty. One float EXR\n"
            "with channels seam.u, seam.v (the continued UV), seam.continued (1, or 0: empty) and seam.mm\n"
            "(distance beyond the edge in mm); chart texels and empty ones are all 0.\n"
            "\n"
            "Options:\n"
            "  -o, --output FILE    output EXR (required)\n"
            "  --size N             texture width and height in texels (default %d, range 16..%d)\n"
            "  --mm-per-unit MM     millimetres per mesh unit (default %g, the Lee Perry-Smith head;\n"
            "                       range 1e-6..1e6)\n"
            "  --reach-mm MM        how far beyond an edge to continue the surface (default: 3 sigma of the\n"
            "                       profile's widest Gaussian, %.3g for gems3-skin; range %g..%g)\n"
            "  --profile FILE       profile JSON whose widest Gaussian sets --reach-mm (default built-in\n"
            "                       gems3-skin, widest variance %g mm^2)\n"
            "  --mesh NAME          glTF: bake only the meshes of this name (default: every mesh of\n"
            "                       the default scene, merged, node transforms applied)\n"
            "  --report             print seam edges, degenerate sides, continued / lost / ended gutter\n"
            "                       texels, the farthest continuation and timings on stdout\n"
            "  -v, --verbose        stage timings on stderr\n"
            "  --quiet              print nothing but errors (conflicts with -v and --report)\n"
            "  -h, --help           this text\n"
            "\n"
            "Exit codes: 0 success, 1 usage error, 2 cannot load the mesh or profile,\n"
            "            3 processing failed, 4 cannot save the output.\n"
            "Example: " TOOL " LeePerrySmith.obj -o seams.exr --size 1024 --report\n",
            DM_SEAM_MAP_SIZE_DEFAULT, DM_SEAM_MAP_SIZE_MAX, DM_STRETCH_MM_PER_UNIT_DEFAULT, dm_seam_map_reach_mm(v),
            DM_BAKE_CLI_REACH_MIN_MM, DM_BAKE_CLI_REACH_MAX_MM, v);
}

static void print_report(const dm_bake_cli *c, const dm_bake_cli_inputs *in, const dm_seam_map *map,
                         const dm_seam_map_stats *s, const dm_bake_cli_times *t)
{
    dm_bake_cli_report_mesh(c->mesh, &in->mesh);
    printf("size            %dx%d\n", map->size, map->size);
    printf("reach           %.3f mm beyond an edge (%s)\n", in->reach_mm, in->reach_from);
    printf("seam edges      %lld: %lld cut (two sides), %lld boundary, %lld non-manifold\n", (long long)s->seam_edges,
           (long long)s->cut_edges, (long long)s->boundary_edges, (long long)s->nonmanifold_edges);
    printf("degenerate      %lld edge sides of zero UV area (or none across): no continuation from them\n",
           (long long)s->degenerate_sides);
    printf("gutter texels   %lld continued, %lld lost (left the mesh or landed off the charts), %lld ended (the surface "
           "ends: boundary)\n",
           (long long)s->continued_texels, (long long)s->lost_texels, (long long)s->ended_texels);
    printf("max distance    %.3f mm beyond the edge\n", s->max_distance_mm);
    dm_bake_cli_report_times(t);
}

static int write_map(const args *a, const dm_bake_cli_inputs *in, const dm_seam_map *map, const dm_seam_map_stats *s)
{
    dm_provenance prov;
    dm_bake_cli_reach_map_prov(&a->c, TOOL, in, a->reach_mm, map->size,
                               "nearest seam edge, chart extended and unfolded onto the other side",
                               "seam.u/.v: continued UV; seam.continued: 1 or 0 (empty); seam.mm: mm beyond the edge",
                               &prov);
    dm_seam_map_stats_prov(s, &prov);

    static const char *const names[4] = {"seam.u", "seam.v", "seam.continued", "seam.mm"};
    return dm_bake_cli_write_rgba(a->c.output, map->texels, map->size, map->size, names, 1u << 2, &prov); /* the flag in half */
}

int main(int argc, char **argv)
{
    args a;
    int rc = dm_bake_cli_parse_reach(argc, argv, TOOL, DM_SEAM_MAP_SIZE_DEFAULT, DM_SEAM_MAP_SIZE_MAX, false, usage, &a.c,
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
    dm_seam_map_options opt = {.size = (int)a.c.size, .mm_per_unit = a.c.mm_per_unit, .reach_mm = in.reach_mm};
    dm_seam_map map;
    dm_seam_map_stats s;
    dm_result r = dm_seam_map_bake(&in.mesh, &opt, &map, &s, &err);
    t.bake_ms = dm_now_ms() - t0;
    if ((rc = dm_bake_cli_baked(&a.c, r, &err, map.texels, 4 * (size_t)map.size * (size_t)map.size, "seam map"))) {
        dm_seam_map_free(&map);
        dm_mesh_free(&in.mesh);
        return rc;
    }
    if (a.c.verbose)
        fprintf(stderr, "baked %dx%d, reach %.3f mm: %lld seam edges, %lld texels continued in %.1f ms\n", map.size,
                map.size, in.reach_mm, (long long)s.seam_edges, (long long)s.continued_texels, t.bake_ms);
    if (!a.c.quiet && s.degenerate_sides > 0)
        fprintf(stderr, "warning: %s: %lld seam edge sides touch a triangle of zero UV area: no continuation from them\n",
                a.c.mesh, (long long)s.degenerate_sides);

    /* Write. */
    t0 = dm_now_ms();
    rc = write_map(&a, &in, &map, &s);
    t.write_ms = dm_now_ms() - t0;
    if (rc == DM_EXIT_OK && a.c.report) print_report(&a.c, &in, &map, &s, &t);
    else if (rc == DM_EXIT_OK && !a.c.quiet)
        printf("%s: %dx%d, reach %.3f mm, %lld seam edges (%lld cut, %lld boundary), %lld gutter texels continued, "
               "%lld lost, %lld ended, farthest %.3f mm\n",
               a.c.output, map.size, map.size, in.reach_mm, (long long)s.seam_edges, (long long)s.cut_edges,
               (long long)s.boundary_edges, (long long)s.continued_texels, (long long)s.lost_texels,
               (long long)s.ended_texels, s.max_distance_mm);
    dm_seam_map_free(&map);
    dm_mesh_free(&in.mesh);
    return rc;
}
