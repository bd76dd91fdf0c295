/* dermis-bake-curvature — mesh → per-texel mean curvature (mm⁻¹) and the chart mask (EXR),
 * for the pre-integrated skin technique. Pipeline: parse → load → bake → write. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_curvature.h"
#include "bake/dm_bake_cli.h"
#include "image/dm_exr.h"
#include "mesh/dm_mesh.h"
#include "core/dm_cli.h"
#include "core/dm_hash.h"
#include "core/dm_profile.h"
#include "core/dm_prov.h"
#include "core/dm_version.h"

#define TOOL "dermis-bake-curvature"
#define MM_PER_UNIT_DEFAULT 50.0 /* the Lee Perry-Smith head (DESIGN.md), as dermis-bake-stretch */

typedef struct args {
    dm_bake_cli c; /* the shared options (bake/dm_bake_cli.h) */
    double smooth_mm; /* < 0: from the profile */
} args;

static void usage(FILE *f)
{
    fprintf(f,
            "Usage: " TOOL " MESH -o OUT.exr [--size N] [--mm-per-unit MM] [--smooth MM | --profile FILE]\n"
            "                             [--mesh NAME] [--report] [--threads N] [-v | --quiet]\n"
            "Bakes the mean curvature H of MESH (OBJ, PLY, OFF, STL, OM, glTF 2.0; with UVs) per texel, in 1/mm,\n"
            "for pre-integrated skin: vertices welded by position, the cotangent Laplacian with mixed\n"
            "Voronoi areas (Meyer et al. 2003), H = K.n/2 (positive on convex surfaces: a sphere of radius\n"
            "R gives 1/R, a plane 0), boundary vertices from their interior ring, smoothed by a Gaussian of\n"
            "sigma MM over the surface (3D distance, area-weighted), interpolated per texel inside each\n"
            "UV triangle, gutters filled from the nearest chart texel. Channels: curvature, mask.\n"
            "\n"
            "Options:\n"
            "  -o, --output FILE    output EXR (required)\n"
            "  --size N             texture width and height in texels (default %d, range 16..%d)\n"
            "  --mm-per-unit MM     millimetres per mesh unit (default %g, the Lee Perry-Smith head;\n"
            "                       range 1e-6..1e6)\n"
            "  --smooth MM          smoothing sigma in mm (default: the profile's RMS radius, 0.70 for\n"
            "                       gems3-skin; range 0..%g, 0 = none)\n"
            "  --profile FILE       profile JSON whose scale sets --smooth (default built-in gems3-skin)\n"
            "  --mesh NAME          glTF: bake only the meshes of this name (default: every mesh)\n"
            "  --report             print welding, boundaries, degenerate and mirrored triangles,\n"
            "                       curvature percentiles and timings on stdout\n"
            "  --threads N          worker threads (default 0 = all cores, range 0..64)\n"
            "  -v, --verbose        stage timings on stderr\n"
            "  --quiet              print nothing but errors (conflicts with -v and --report)\n"
            "  -h, --help           this text\n"
            "\n"
            "Exit codes: 0 success, 1 usage error, 2 cannot load the mesh or profile,\n"
            "            3 processing failed (e.g. no texel covered), 4 cannot save the output.\n"
            "Example: " TOOL " LeePerrySmith.obj -o curvature.exr --size 1024 --report\n",
            DM_CURVATURE_SIZE_DEFAULT, DM_CURVATURE_SIZE_MAX, MM_PER_UNIT_DEFAULT, DM_CURVATURE_SMOOTH_MAX_MM);
}

/* Returns -1 to go on, else the exit code. */
static int parse(int argc, char **argv, args *a)
{
    *a = (args){.c = {.size = DM_CURVATURE_SIZE_DEFAULT, .mm_per_unit = MM_PER_UNIT_DEFAULT}, .smooth_mm = -1.0};
    for (int i = 1; i < argc; ++i) {
        const char *s = argv[i], *v;
        if (dm_cli_version(s, TOOL)) exit(0);
        if (!strcmp(s, "-h") || !strcmp(s, "--help")) {
            usage(stdout);
            return DM_EXIT_OK;
        } else if (!strcmp(s, "--smooth")) {
            if (!(v = dm_cli_value(argc, argv, &i)) ||
                !dm_cli_double(s, v, 0.0, DM_CURVATURE_SMOOTH_MAX_MM, &a->smooth_mm))
                return DM_EXIT_USAGE;
        } else if (!dm_bake_cli_option(argc, argv, &i, DM_CURVATURE_SIZE_MAX, &a->c)) {
            return DM_EXIT_USAGE;
        }
    }
    return dm_bake_cli_finish(&a->c, a->c.profile && a->smooth_mm >= 0.0 ? "--smooth and --profile exclude each other" : NULL,
                              usage);
}

static void print_report(const char *path, const dm_mesh *m, const dm_curvature_map *map, double smooth_mm,
                         double load_ms, double write_ms)
{
    const dm_curvature_stats *s = &map->stats;
    static const char *const pct[5] = {"p1", "p5", "p50", "p95", "p99"};
    printf("mesh            %s: %d vertices (%d after welding), %d triangles\n", path, m->vertex_count,
           s->welded_vertices, m->triangle_count);
    printf("size            %dx%d, smoothing sigma %.3g mm\n", map->width, map->height, smooth_mm);
    printf("coverage        %.3f %% (%lld texels), %lld gutter texels filled\n", 100.0 * s->coverage,
           (long long)s->covered_texels, (long long)s->gutter_texels);
    printf("boundary        %d vertices on boundary or non-manifold edges (from their interior ring)\n",
           s->boundary_vertices);
    printf("degenerate      %d triangles skipped by the Laplacian\n", s->degenerate_triangles);
    printf("mirrored        %d triangles with mirrored UVs (curvature is per vertex: unaffected)\n",
           s->mirrored_triangles);
    printf("curvature (1/mm)");
    for (int k = 0; k < 5; ++k) printf(" %s %.4g", pct[k], s->percentile[k]);
    printf(" min %.4g max %.4g\n", s->min, s->max);
    printf("time            load %.1f ms, vertices %.1f ms, smoothing %.1f ms, raster %.1f ms, fill %.1f ms, "
           "write %.1f ms\n",
           load_ms, s->vertex_ms, s->smooth_ms, s->raster_ms, s->fill_ms, write_ms);
}

int main(int argc, char **argv)
{
    args a;
    int rc = parse(argc, argv, &a);
    if (rc >= 0) return rc;
    if ((rc = dm_bake_cli_output(&a.c))) return rc; /* before any work (core/dm_output.h) */

    /* Load. */
    dm_error err = {0};
    double t0 = dm_now_ms();
    dm_profile profile;
    char profile_hash[DM_HASH_HEX_SIZE];
    if (!dm_bake_cli_profile(&a.c, &profile, profile_hash)) return DM_EXIT_LOAD;
    double smooth_mm = a.smooth_mm >= 0.0 ? a.smooth_mm : dm_curvature_profile_scale_mm(&profile);
    char mesh_hash[DM_HASH_HEX_SIZE];
    dm_mesh mesh;
    if (!dm_bake_cli_mesh(&a.c, &mesh, mesh_hash)) return DM_EXIT_LOAD;
    double load_ms = dm_now_ms() - t0;
    if (a.c.verbose) fprintf(stderr, "loaded %s: %d triangles in %.1f ms\n", a.c.mesh, mesh.triangle_count, load_ms);

    /* Process. */
    dm_curvature_options opt = {.width = (int)a.c.size,
                                .height = (int)a.c.size,
                                .mm_per_unit = a.c.mm_per_unit,
                                .smooth_mm = smooth_mm,
                                .thread_count = (int)a.c.threads};
    dm_curvature_map map;
    if (dm_curvature_bake(&mesh, &opt, &map, &err) != DM_OK) {
        fprintf(stderr, "error: %s: %s\n", a.c.mesh, err.detail);
        dm_curvature_map_free(&map);
        dm_mesh_free(&mesh);
        return DM_EXIT_PROCESS;
    }
    const dm_curvature_stats *s = &map.stats;
    if (a.c.verbose)
        fprintf(stderr, "baked %dx%d: vertices %.1f ms, smoothing %.1f ms, raster %.1f ms, fill %.1f ms\n", map.width,
                map.height, s->vertex_ms, s->smooth_ms, s->raster_ms, s->fill_ms);

    /* Write. */
    t0 = dm_now_ms();
    dm_provenance prov;
    dm_bake_cli_prov(&a.c, TOOL, mesh_hash, &prov);
    dm_prov_add_double(&prov, "smooth_mm", smooth_mm);
    dm_prov_add_string(&prov, "profile", a.smooth_mm >= 0.0 ? "" : profile.name);
    dm_prov_add_string(&prov, "profile_hash", a.smooth_mm >= 0.0 ? "" : profile_hash);
    dm_prov_add_string(&prov, "method", "cotangent Laplacian, mixed Voronoi areas (Meyer 2003), H = K.n/2, welded");
    dm_prov_add_string(&prov, "units", "curvature: mean curvature 1/mm, > 0 convex; mask: 1 chart, 0 gutter");
    dm_prov_add_double(&prov, "coverage", s->coverage);
    dm_prov_add_int(&prov, "boundary_vertices", s->boundary_vertices);
    dm_prov_add_int(&prov, "degenerate_triangles", s->degenerate_triangles);
    dm_prov_add_int(&prov, "mirrored_triangles", s->mirrored_triangles);
    dm_exr_channel ch[2] = {{"curvature", map.curvature, DM_EXR_FLOAT},
                            {"mask", map.mask, DM_EXR_HALF}}; /* 0 and 1 are exact in half */
    rc = DM_EXIT_OK;
    if (dm_exr_write(a.c.output, map.width, map.height, ch, 2, &prov, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        rc = DM_EXIT_SAVE;
    }
    double write_ms = dm_now_ms() - t0;
    if (rc == DM_EXIT_OK && a.c.report) print_report(a.c.mesh, &mesh, &map, smooth_mm, load_ms, write_ms);
    else if (rc == DM_EXIT_OK && !a.c.quiet)
        printf("%s: %dx%d, coverage %.2f %%, curvature p5 %.3g p50 %.3g p95 %.3g /mm, smoothing %.3g mm, "
               "%d boundary vertices, %d degenerate, %d mirrored triangles\n",
               a.c.output, map.width, map.height, 100.0 * s->coverage, s->percentile[1], s->percentile[2],
               s->percentile[3], smooth_mm, s->boundary_vertices, s->degenerate_triangles, s->mirrored_triangles);
    dm_curvature_map_free(&map);
    dm_mesh_free(&mesh);
    return rc;
}
