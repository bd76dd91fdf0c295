/* dermis-bake-stretch — mesh → UV stretch map, its blurred chain and the chart mask (EXR). */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_bake_cli.h"
#include "image/dm_exr.h"
#include "mesh/dm_mesh.h"
#include "mesh/dm_mesh_plausible.h"
#include "bake/dm_stretch.h"
#include "core/dm_cli.h"
#include "core/dm_hash.h"
#include "core/dm_profile.h"
#include "core/dm_prov.h"
#include "core/dm_version.h"

#define TOOL "dermis-bake-stretch"

typedef struct args {
    dm_bake_cli c; /* the shared options (bake/dm_bake_cli.h) */
    int64_t levels;
} args;

static void usage(FILE *f)
{
    fprintf(f,
            "Usage: " TOOL " MESH -o OUT.exr [--size N] [--mm-per-unit MM] [--levels N] [--profile FILE]\n"
            "                           [--mesh NAME] [--report] [--threads N] [-v | --quiet]\n"
            "Bakes the UV stretch map of MESH (OBJ, PLY, OFF, STL, OM, glTF 2.0 .gltf/.glb; with UVs):\n"
            "s_u = 1/|dP/du| and s_v = 1/|dP/dv| in UV units per mm from the exact per-triangle Jacobian, gutters filled\n"
            "from the nearest chart texel, then blurred through the profile's Gaussian chain (level k\n"
            "from level k-1 by v_k - v_(k-1) mm^2, taps scaled by the stretch), as one float EXR with\n"
            "channels stretch<k>.u, stretch<k>.v (k = 0 .. levels-1) and mask (1 chart, 0 gutter).\n"
            "\n"
            "Options:\n"
            "  -o, --output FILE    output EXR (required)\n"
            "  --size N             texture width and height in texels (default %d, range 16..%d)\n"
            "  --mm-per-unit MM     millimetres per mesh unit (default %g, the Lee Perry-Smith head;\n"
            "                       range 1e-6..1e6)\n"
            "  --levels N           maps to write: the base plus N-1 blurred levels (default: one per\n"
            "                       Gaussian of the profile, 6 for gems3-skin; range 1..profile's count)\n"
            "  --profile FILE       Gaussian chain from a dermis profile JSON (default: built-in\n"
            "                       gems3-skin, variances 0.0064 0.0484 0.187 0.567 1.99 7.41 mm^2)\n"
            "  --mesh NAME          glTF: bake only the meshes of this name (default: every mesh of\n"
            "                       the default scene, merged, node transforms applied)\n"
            "  --report             print coverage, stretch percentiles, degenerate triangles, UV\n"
            "                       islands and timings on stdout\n"
            "  --threads N          worker threads (default 0 = all cores, range 0..64)\n"
            "  -v, --verbose        stage timings on stderr\n"
            "  --quiet              print nothing but errors (conflicts with -v and --report)\n"
            "  -h, --help           this text\n"
            "\n"
            "Exit codes: 0 success, 1 usage error, 2 cannot load the mesh or profile,\n"
            "            3 processing failed (e.g. no texel covered), 4 cannot save the output.\n"
            "Example: " TOOL " LeePerrySmith.obj -o stretch.exr --size 2048 --report\n",
            DM_STRETCH_SIZE_DEFAULT, DM_STRETCH_SIZE_MAX, DM_STRETCH_MM_PER_UNIT_DEFAULT);
}

/* Returns -1 to go on, else the exit code. */
static int parse(int argc, char **argv, args *a)
{
    *a = (args){.c = {.size = DM_STRETCH_SIZE_DEFAULT, .mm_per_unit = DM_STRETCH_MM_PER_UNIT_DEFAULT}};
    for (int i = 1; i < argc; ++i) {
        const char *s = argv[i], *v;
        if (dm_cli_version(s, TOOL)) exit(0);
        if (!strcmp(s, "-h") || !strcmp(s, "--help")) {
            usage(stdout);
            return DM_EXIT_OK;
        } else if (!strcmp(s, "--levels")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 1, DM_PROFILE_MAX_GAUSSIANS, &a->levels))
                return DM_EXIT_USAGE;
        } else if (!dm_bake_cli_option(argc, argv, &i, DM_STRETCH_SIZE_MAX, &a->c)) {
            return DM_EXIT_USAGE;
        }
    }
    return dm_bake_cli_finish(&a->c, NULL, usage);
}

static void on_progress(void *ctx, double f) { dm_progress_update(ctx, f); }

static void print_report(const char *mesh_path, const dm_mesh *m, const dm_stretch_map *map, double load_ms,
                         double write_ms)
{
    const dm_stretch_stats *s = &map->stats;
    static const char *const pct[5] = {"p1", "p5", "p50", "p95", "p99"};
    printf("mesh            %s: %d vertices, %d triangles (%lld faces in the file), normals %s\n", mesh_path,
           m->vertex_count, m->triangle_count, (long long)m->polygon_count,
           m->normals_from_file ? "from the file" : "computed");
    printf("size            %dx%d, %d levels\n", map->width, map->height, map->level_count);
    printf("coverage        %.3f %% (%lld texels), %lld gutter texels filled, farthest %.1f texels\n",
           100.0 * s->coverage, (long long)s->covered_texels, (long long)s->gutter_texels,
           s->fill_distance_max_texels);
    printf("overlaps        %lld texels claimed by more than one triangle\n", (long long)s->overlap_texels);
    printf("uv islands      %d\n", s->uv_islands);
    printf("degenerate      %d of zero UV area, %d of zero surface area: cover no texel, filled from neighbours\n",
           s->zero_uv_area_triangles, s->zero_area_triangles);
    printf("mirrored        %d triangles with mirrored UVs (stretch is orientation-free)\n", s->mirrored_triangles);
    if (s->out_of_range_triangles)
        printf("out of range    %d triangles with UVs beyond 2^20 texels, skipped\n", s->out_of_range_triangles);
    printf("s_u (uv/mm)    ");
    for (int k = 0; k < 5; ++k) printf(" %s %.5g", pct[k], s->s_u_percentile[k]);
    printf(" max %.5g\n", s->s_u_max);
    printf("s_v (uv/mm)    ");
    for (int k = 0; k < 5; ++k) printf(" %s %.5g", pct[k], s->s_v_percentile[k]);
    printf(" max %.5g\n", s->s_v_max);
    printf("texels per mm   median %.2f along u, %.2f along v\n", s->s_u_percentile[2] * map->width,
           s->s_v_percentile[2] * map->height);
    printf("blur reach      %.1f texels at the widest step and largest stretch\n", s->blur_reach_texels);
    printf("time            load %.1f ms, raster %.1f ms, stats %.1f ms, fill %.1f ms, blur %.1f ms, write %.1f ms\n",
           load_ms, s->raster_ms, s->stats_ms, s->fill_ms, s->blur_ms, write_ms);
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
    if (a.levels > profile.count) {
        fprintf(stderr, "error: --levels %lld: profile '%s' has %d Gaussians, expected 1..%d\n", (long long)a.levels,
                profile.name, profile.count, profile.count);
        return DM_EXIT_USAGE;
    }
    char mesh_hash[DM_HASH_HEX_SIZE];
    dm_mesh mesh;
    if (!dm_bake_cli_mesh(&a.c, &mesh, mesh_hash)) return DM_EXIT_LOAD;
    double load_ms = dm_now_ms() - t0;
    char plausible[1024];
    if (dm_mesh_plausible(&mesh, a.c.mm_per_unit, a.c.mesh, plausible, sizeof plausible)) fputs(plausible, stderr);
    if (a.c.verbose)
        fprintf(stderr, "loaded %s: %d triangles in %.1f ms\n", a.c.mesh, mesh.triangle_count, load_ms);

    /* Process. */
    dm_progress bar;
    dm_progress_begin(&bar, "stretch", a.c.quiet || a.c.size < 2048);
    dm_stretch_options opt = {.width = (int)a.c.size,
                              .height = (int)a.c.size,
                              .mm_per_unit = a.c.mm_per_unit,
                              .profile = &profile,
                              .level_count = (int)a.levels,
                              .thread_count = (int)a.c.threads,
                              .progress = on_progress,
                              .progress_ctx = &bar};
    dm_stretch_map map;
    if (dm_stretch_bake(&mesh, &opt, &map, &err) != DM_OK) {
        dm_progress_end(&bar);
        fprintf(stderr, "error: %s: %s\n", a.c.mesh, err.detail);
        dm_mesh_free(&mesh);
        return DM_EXIT_PROCESS;
    }
    dm_progress_end(&bar);
    const dm_stretch_stats *s = &map.stats;
    if (a.c.verbose)
        fprintf(stderr, "baked %dx%d, %d levels: raster %.1f ms, fill %.1f ms, blur %.1f ms\n", map.width, map.height,
                map.level_count, s->raster_ms, s->fill_ms, s->blur_ms);
    if (!a.c.quiet && s->zero_uv_area_triangles + s->zero_area_triangles > 0)
        fprintf(stderr,
                "warning: %s: %d triangles of zero UV area and %d of zero surface area cover no texel "
                "(their texels, if any, are filled from neighbours)\n",
                a.c.mesh, s->zero_uv_area_triangles, s->zero_area_triangles);

    /* Write. */
    t0 = dm_now_ms();
    dm_provenance prov;
    dm_bake_cli_prov(&a.c, TOOL, mesh_hash, &prov);
    dm_prov_add_int(&prov, "levels", map.level_count);
    dm_prov_add_string(&prov, "profile", profile.name);
    dm_prov_add_string(&prov, "profile_hash", profile_hash);
    for (int k = 0; k < map.level_count; ++k) {
        char name[32];
        snprintf(name, sizeof name, "variance_mm2_%d", k);
        dm_prov_add_double(&prov, name, map.variance_mm2[k]);
    }
    dm_prov_add_int(&prov, "blur_taps", DM_STRETCH_TAPS);
    dm_prov_add_string(&prov, "units", "stretch<k>.u/.v: UV units per mm; mask: 1 chart, 0 gutter");
    dm_prov_add_double(&prov, "coverage", s->coverage);
    dm_prov_add_int(&prov, "zero_uv_area_triangles", s->zero_uv_area_triangles);
    dm_prov_add_int(&prov, "zero_area_triangles", s->zero_area_triangles);
    dm_prov_add_int(&prov, "mirrored_triangles", s->mirrored_triangles);

    char names[2 * DM_PROFILE_MAX_GAUSSIANS][32];
    dm_exr_channel ch[2 * DM_PROFILE_MAX_GAUSSIANS + 1];
    int nch = 0;
    for (int k = 0; k < map.level_count; ++k) {
        snprintf(names[2 * k], sizeof names[0], "stretch%d.u", k);
        snprintf(names[2 * k + 1], sizeof names[0], "stretch%d.v", k);
        ch[nch++] = (dm_exr_channel){names[2 * k], map.s_u[k], DM_EXR_FLOAT};
        ch[nch++] = (dm_exr_channel){names[2 * k + 1], map.s_v[k], DM_EXR_FLOAT};
    }
    ch[nch++] = (dm_exr_channel){"mask", map.mask, DM_EXR_HALF}; /* 0 and 1 are exact in half */
    rc = DM_EXIT_OK;
    if (dm_exr_write(a.c.output, map.width, map.height, ch, nch, &prov, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        rc = DM_EXIT_SAVE;
    }
    double write_ms = dm_now_ms() - t0;
    if (rc == DM_EXIT_OK && a.c.report) print_report(a.c.mesh, &mesh, &map, load_ms, write_ms);
    else if (rc == DM_EXIT_OK && !a.c.quiet)
        printf("%s: %dx%d, %d levels, coverage %.2f %%, median %.2f texels/mm, %d mirrored, %d+%d degenerate "
               "triangles\n",
               a.c.output, map.width, map.height, map.level_count, 100.0 * s->coverage,
               s->s_u_percentile[2] * map.width, s->mirrored_triangles, s->zero_uv_area_triangles,
               s->zero_area_triangles);
    dm_stretch_map_free(&map);
    dm_mesh_free(&mesh);
    return rc;
}
