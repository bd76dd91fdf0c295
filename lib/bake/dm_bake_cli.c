/* dm_bake_cli.c — the mesh bake tools' shared command line (dm_bake_cli.h). */
#include "bake/dm_bake_cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_seam_map.h"
#include "bake/dm_stretch.h"
#include "image/dm_exr.h"
#include "mesh/dm_mesh_plausible.h"

#include "core/dm_cli.h"
#include "core/dm_output.h"

bool dm_bake_cli_option(int argc, char **argv, int *i, int64_t size_max, dm_bake_cli *a)
{
    const char *s = argv[*i], *v;
    if (!strcmp(s, "-o") || !strcmp(s, "--output"))
        return (a->output = dm_cli_value(argc, argv, i)) != NULL;
    if (!strcmp(s, "--size"))
        return (v = dm_cli_value(argc, argv, i)) && dm_cli_int(s, v, 16, size_max, &a->size);
    if (!strcmp(s, "--mm-per-unit"))
        return (v = dm_cli_value(argc, argv, i)) && dm_cli_double(s, v, 1e-6, 1e6, &a->mm_per_unit);
    if (!strcmp(s, "--profile")) return (a->profile = dm_cli_value(argc, argv, i)) != NULL;
    if (!strcmp(s, "--mesh")) return (a->mesh_name = dm_cli_value(argc, argv, i)) != NULL;
    if (!strcmp(s, "--threads")) return (v = dm_cli_value(argc, argv, i)) && dm_cli_int(s, v, 0, 64, &a->threads);
    if (!strcmp(s, "--report")) return a->report = true;
    if (!strcmp(s, "-v") || !strcmp(s, "--verbose")) return a->verbose = true;
    if (!strcmp(s, "--quiet")) return a->quiet = true;
    if (s[0] == '-' && s[1]) {
        fprintf(stderr, "error: unknown option '%s' (see --help)\n", s);
        return false;
    }
    if (a->mesh) {
        fprintf(stderr, "error: one mesh expected, got '%s' and '%s'\n", a->mesh, s);
        return false;
    }
    a->mesh = s;
    return true;
}

const char *dm_bake_cli_check(const dm_bake_cli *a)
{
    if (!a->mesh) return "no MESH given";
    if (!a->output) return "no output given (-o OUT.exr)";
    if (a->quiet && a->verbose) return "--quiet conflicts with -v";
    if (a->quiet && a->report) return "--quiet conflicts with --report";
    return NULL;
}

int dm_bake_cli_finish(const dm_bake_cli *a, const char *conflict, void (*usage)(FILE *out))
{
    const char *why = dm_bake_cli_check(a);
    if (!why) why = conflict;
    if (!why) return -1;
    fprintf(stderr, "error: %s\n", why);
    usage(stderr);
    return DM_EXIT_USAGE;
}

int dm_bake_cli_output(const dm_bake_cli *a)
{
    return dm_output_check_cli("-o", a->output, (const char *const[]){".exr", NULL},
                               (const char *const[]){a->mesh, a->profile}, 2, NULL);
}

bool dm_bake_cli_profile(const dm_bake_cli *a, dm_profile *profile, char hash[DM_HASH_HEX_SIZE])
{
    dm_error err = {0};
    snprintf(hash, DM_HASH_HEX_SIZE, "builtin");
    dm_profile_gems3_skin(profile);
    if (a->profile && (dm_profile_read(a->profile, profile, &err) != DM_OK ||
                       dm_hash_file_hex(a->profile, hash, &err) != DM_OK)) {
        fprintf(stderr, "error: %s\n", err.detail);
        return false;
    }
    return true;
}

bool dm_bake_cli_mesh(const dm_bake_cli *a, dm_mesh *mesh, char hash[DM_HASH_HEX_SIZE])
{
    dm_error err = {0};
    dm_mesh_load_options load_opt = {.mesh_name = a->mesh_name};
    if (dm_mesh_load(a->mesh, &load_opt, mesh, &err) != DM_OK || dm_hash_file_hex(a->mesh, hash, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_mesh_free(mesh);
        return false;
    }
    return true;
}

void dm_bake_cli_prov_height(const dm_bake_cli *a, const char *tool, const char mesh_hash[DM_HASH_HEX_SIZE],
                             int64_t height, dm_provenance *prov)
{
    dm_prov_init(prov, tool);
    snprintf(prov->input_hash, sizeof prov->input_hash, "%s", mesh_hash);
    if (a->mesh_name) dm_prov_add_string(prov, "mesh_name", a->mesh_name);
    dm_prov_add_int(prov, "width", (int)a->size);
    dm_prov_add_int(prov, "height", height);
    dm_prov_add_double(prov, "mm_per_unit", a->mm_per_unit);
}

void dm_bake_cli_prov(const dm_bake_cli *a, const char *tool, const char mesh_hash[DM_HASH_HEX_SIZE],
                      dm_provenance *prov)
{
    dm_bake_cli_prov_height(a, tool, mesh_hash, a->size, prov);
}

bool dm_bake_cli_reach_option(int argc, char **argv, int *i, double *reach_mm, bool *ok)
{
    const char *s = argv[*i], *v;
    if (strcmp(s, "--reach-mm") != 0) return false;
    *ok = (v = dm_cli_value(argc, argv, i)) &&
          dm_cli_double(s, v, DM_BAKE_CLI_REACH_MIN_MM, DM_BAKE_CLI_REACH_MAX_MM, reach_mm);
    return true;
}

const char *dm_bake_cli_reach_conflict(const dm_bake_cli *a, double reach_opt)
{
    return a->profile && reach_opt >= 0.0 ? "--reach-mm and --profile exclude each other" : NULL;
}

double dm_bake_cli_reach(double reach_opt, const dm_profile *profile, char *from, size_t from_size)
{
    const double v = profile->variance_mm2[profile->count - 1];
    if (reach_opt >= 0.0) {
        snprintf(from, from_size, "--reach-mm");
        return reach_opt;
    }
    snprintf(from, from_size, "3 sigma of %s's widest Gaussian, %g mm^2", profile->name, v);
    return dm_seam_map_reach_mm(v);
}

void dm_bake_cli_reach_prov(double reach_opt, double reach_mm, const dm_profile *profile, const char *profile_hash,
                            dm_provenance *prov)
{
    const bool from_profile = reach_opt < 0.0;
    dm_prov_add_double(prov, "reach_mm", reach_mm);
    dm_prov_add_string(prov, "profile", from_profile ? profile->name : "");
    dm_prov_add_string(prov, "profile_hash", from_profile ? profile_hash : "");
    if (from_profile) dm_prov_add_double(prov, "largest_variance_mm2", profile->variance_mm2[profile->count - 1]);
}

int dm_bake_cli_write_rgba(const char *output, const float *texels, int w, int h, const char *const names[4],
                           unsigned half_mask, const dm_provenance *prov)
{
    size_t count = (size_t)w * (size_t)h;
    float *all = malloc(4 * count * sizeof *all);
    if (!all) {
        fprintf(stderr, "error: %s: out of memory for the %zu-texel planes\n", output, count);
        return DM_EXIT_SAVE;
    }
    dm_exr_channel ch[4];
    for (int c = 0; c < 4; ++c) {
        float *plane = all + (size_t)c * count;
        for (size_t x = 0; x < count; ++x) plane[x] = texels[4 * x + (size_t)c];
        ch[c] = (dm_exr_channel){names[c], plane, half_mask >> c & 1u ? DM_EXR_HALF : DM_EXR_FLOAT};
    }
    dm_error err = {0};
    int rc = DM_EXIT_OK;
    if (dm_exr_write(output, w, h, ch, 4, prov, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        rc = DM_EXIT_SAVE;
    }
    free(all);
    return rc;
}

int dm_bake_cli_load_reach(const dm_bake_cli *a, double reach_opt, dm_bake_cli_inputs *in)
{
    double t0 = dm_now_ms();
    if (!dm_bake_cli_profile(a, &in->profile, in->profile_hash)) return DM_EXIT_LOAD;
    in->reach_mm = dm_bake_cli_reach(reach_opt, &in->profile, in->reach_from, sizeof in->reach_from);
    if (!dm_bake_cli_mesh(a, &in->mesh, in->mesh_hash)) return DM_EXIT_LOAD;
    in->load_ms = dm_now_ms() - t0;
    char plausible[1024];
    if (dm_mesh_plausible(&in->mesh, a->mm_per_unit, a->mesh, plausible, sizeof plausible)) fputs(plausible, stderr);
    if (a->verbose)
        fprintf(stderr, "loaded %s: %d triangles in %.1f ms\n", a->mesh, in->mesh.triangle_count, in->load_ms);
    return DM_EXIT_OK;
}

int dm_bake_cli_baked(const dm_bake_cli *a, dm_result r, const dm_error *err, const float *texels, size_t float_count,
                      const char *what)
{
    if (r != DM_OK) {
        fprintf(stderr, "error: %s: %s\n", a->mesh, err->detail);
        return DM_EXIT_PROCESS;
    }
    return dm_cli_finite(texels, float_count, what) ? DM_EXIT_OK : DM_EXIT_PROCESS;
}

void dm_bake_cli_reach_map_prov(const dm_bake_cli *a, const char *tool, const dm_bake_cli_inputs *in, double reach_opt,
                                int64_t height, const char *method, const char *units, dm_provenance *prov)
{
    dm_bake_cli_prov_height(a, tool, in->mesh_hash, height, prov);
    dm_bake_cli_reach_prov(reach_opt, in->reach_mm, &in->profile, in->profile_hash, prov);
    dm_prov_add_string(prov, "method", method);
    dm_prov_add_string(prov, "units", units);
}

void dm_bake_cli_report_mesh(const char *path, const dm_mesh *m)
{
    printf("mesh            %s: %d vertices, %d triangles (%lld faces in the file)\n", path, m->vertex_count,
           m->triangle_count, (long long)m->polygon_count);
}

void dm_bake_cli_report_times(const dm_bake_cli_times *t)
{
    printf("time            load %.1f ms, bake %.1f ms, write %.1f ms\n", t->load_ms, t->bake_ms, t->write_ms);
}

int dm_bake_cli_parse_reach(int argc, char **argv, const char *tool, int64_t size_default, int64_t size_max,
                            bool threads, void (*usage)(FILE *out), dm_bake_cli *a, double *reach_opt)
{
    *a = (dm_bake_cli){.size = size_default, .mm_per_unit = DM_STRETCH_MM_PER_UNIT_DEFAULT};
    *reach_opt = -1.0;
    for (int i = 1; i < argc; ++i) {
        const char *s = argv[i];
        bool ok = true;
        if (dm_cli_version(s, tool)) exit(0);
        if (!strcmp(s, "-h") || !strcmp(s, "--help")) {
            usage(stdout);
            return DM_EXIT_OK;
        } else if (dm_bake_cli_reach_option(argc, argv, &i, reach_opt, &ok)) {
            if (!ok) return DM_EXIT_USAGE;
        } else if (!threads && !strcmp(s, "--threads")) { /* shared by the other bakers */
            fprintf(stderr, "error: --threads: %s bakes on one thread (see --help)\n", tool);
            return DM_EXIT_USAGE;
        } else if (!dm_bake_cli_option(argc, argv, &i, size_max, a)) {
            return DM_EXIT_USAGE;
        }
    }
    return dm_bake_cli_finish(a, dm_bake_cli_reach_conflict(a, *reach_opt), usage);
}
