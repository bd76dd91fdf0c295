/* dm_bake_cli.c — the mesh bake tools' shared command line (dm_bake_cli.h). */
#include "bake/dm_bake_cli.h"

#include <stdio.h>
#include <string.h>

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

void dm_bake_cli_prov(const dm_bake_cli *a, const char *tool, const char mesh_hash[DM_HASH_HEX_SIZE],
                      dm_provenance *prov)
{
    dm_prov_init(prov, tool);
    snprintf(prov->input_hash, sizeof prov->input_hash, "%s", mesh_hash);
    if (a->mesh_name) dm_prov_add_string(prov, "mesh_name", a->mesh_name);
    dm_prov_add_int(prov, "width", (int)a->size);
    dm_prov_add_int(prov, "height", (int)a->size);
    dm_prov_add_double(prov, "mm_per_unit", a->mm_per_unit);
}
