/* dm_bake_cli.h — what the mesh bake tools (dermis-bake-stretch, dermis-bake-curvature,
 * dermis-bake-seams, dermis-bake-thin) share on their command line: the operand MESH and the
 * options -o, --size, --mm-per-unit, --profile, --mesh, --threads, --report, -v, --quiet;
 * their checks; the loading of the profile and the mesh with their content hashes; the
 * provenance entries they all write; the reach of the two maps that reach across the surface
 * (--reach-mm, or 3 sigma of the profile's widest Gaussian), the bake's outcome, a reach
 * map's provenance and --report's mesh and time lines; the EXR planes of an interleaved map.
 * Each tool keeps its own --help text and its own options
 * (dermis-bake-seams refuses --threads before this parser sees it: its bake is one pass). */
#ifndef DM_BAKE_CLI_H
#define DM_BAKE_CLI_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "mesh/dm_mesh.h"
#include "core/dm_hash.h"
#include "core/dm_profile.h"
#include "core/dm_prov.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_bake_cli {
    const char *mesh, *output, *profile, *mesh_name;
    int64_t size, threads;
    double mm_per_unit;
    bool report, verbose, quiet;
} dm_bake_cli;

/* Takes argv[*i] (and its value, advancing *i) when it is a shared option or the MESH
 * operand: true. False, said on stderr, for a bad value, an unknown option or a second
 * MESH. Tools test their own options first. --size takes 16..size_max. */
bool dm_bake_cli_option(int argc, char **argv, int *i, int64_t size_max, dm_bake_cli *a);
/* After the options: what is missing or conflicting (no MESH, no output, --quiet with -v
 * or --report), or NULL. */
const char *dm_bake_cli_check(const dm_bake_cli *a);
/* The end of a bake tool's parse: dm_bake_cli_check, else `conflict` (NULL, or the tool's own
 * rule the options broke), said on stderr with the usage. -1 to go on, else DM_EXIT_USAGE. */
int dm_bake_cli_finish(const dm_bake_cli *a, const char *conflict, void (*usage)(FILE *out));

/* The output (-o) against core/dm_output.h's rules: an .exr name (any case), not the mesh
 * or the profile, in a writable folder. 0 when fine, else the exit code (said on stderr).
 * Called right after the options, before anything is loaded. */
int dm_bake_cli_output(const dm_bake_cli *a);

/* The profile: --profile's file or gems3-skin (hash "builtin"). The mesh: MESH (--mesh
 * picks glTF meshes). Each with its content hash; failures said on stderr as
 * "error: ...", the mesh freed. */
bool dm_bake_cli_profile(const dm_bake_cli *a, dm_profile *profile, char hash[DM_HASH_HEX_SIZE]);
bool dm_bake_cli_mesh(const dm_bake_cli *a, dm_mesh *mesh, char hash[DM_HASH_HEX_SIZE]);

/* Provenance for tool: input_hash the mesh's, then mesh_name (when given), width, height
 * (size, or the given height) and mm_per_unit; the tool adds its own after. */
void dm_bake_cli_prov(const dm_bake_cli *a, const char *tool, const char mesh_hash[DM_HASH_HEX_SIZE],
                      dm_provenance *prov);
void dm_bake_cli_prov_height(const dm_bake_cli *a, const char *tool, const char mesh_hash[DM_HASH_HEX_SIZE],
                             int64_t height, dm_provenance *prov);

/* --- the reach (dermis-bake-seams, dermis-bake-thin) ------------------------------------ */

#define DM_BAKE_CLI_REACH_MIN_MM 1e-3
#define DM_BAKE_CLI_REACH_MAX_MM 1e3
/* Whether argv[*i] is --reach-mm; then its value (advancing *i) into *reach_mm, *ok false for
 * a bad one (said on stderr). */
bool dm_bake_cli_reach_option(int argc, char **argv, int *i, double *reach_mm, bool *ok);
/* The whole command line of a reach tool: -h/--help (usage on stdout: DM_EXIT_OK), --version
 * (prints and exits 0), --reach-mm, --threads refused when the bake is one pass (!threads),
 * the shared options, then dm_bake_cli_finish with the reach's conflict. a gets the defaults
 * first (size_default, the stretch map's mm per unit: the maps are baked for the same scene),
 * *reach_opt −1 (from the profile). -1 to go on, else the exit code. */
int dm_bake_cli_parse_reach(int argc, char **argv, const char *tool, int64_t size_default, int64_t size_max,
                            bool threads, void (*usage)(FILE *out), dm_bake_cli *a, double *reach_opt);
/* "--reach-mm and --profile exclude each other" when both are given (reach_opt ≥ 0), else NULL. */
const char *dm_bake_cli_reach_conflict(const dm_bake_cli *a, double reach_opt);
/* reach_opt when ≥ 0, else 3 σ of the profile's widest Gaussian (dm_seam_map_reach_mm);
 * from[from_size] says which, for --report. */
double dm_bake_cli_reach(double reach_opt, const dm_profile *profile, char *from, size_t from_size);
/* reach_mm, profile and profile_hash ("" when --reach-mm gave it) and, from the profile,
 * largest_variance_mm2. */
void dm_bake_cli_reach_prov(double reach_opt, double reach_mm, const dm_profile *profile, const char *profile_hash,
                            dm_provenance *prov);

/* What a reach tool loads: the profile, the reach from it (or --reach-mm) and what set it, the
 * mesh, each with its content hash, and how long it took. */
typedef struct dm_bake_cli_inputs {
    dm_profile profile;
    char profile_hash[DM_HASH_HEX_SIZE];
    double reach_mm;
    char reach_from[128];
    dm_mesh mesh;
    char mesh_hash[DM_HASH_HEX_SIZE];
    double load_ms;
} dm_bake_cli_inputs;
/* Loads them (dm_bake_cli_profile, dm_bake_cli_reach, dm_bake_cli_mesh), says on stderr what
 * dm_mesh_plausible finds and, with -v, the load time. DM_EXIT_OK (free in->mesh with
 * dm_mesh_free) or DM_EXIT_LOAD (said on stderr, nothing to free). */
int dm_bake_cli_load_reach(const dm_bake_cli *a, double reach_opt, dm_bake_cli_inputs *in);

/* The bake's outcome: r's failure (err's message) or a texel that is not finite (of
 * texels[0..float_count), `what` naming the map), said on stderr with the mesh's name.
 * DM_EXIT_OK or DM_EXIT_PROCESS. texels is not read when r is not DM_OK. */
int dm_bake_cli_baked(const dm_bake_cli *a, dm_result r, const dm_error *err, const float *texels, size_t float_count,
                      const char *what);
/* The provenance of a reach map whose EXR is height rows high: dm_bake_cli_prov_height's
 * entries, dm_bake_cli_reach_prov's from in, the bake's method and its channels' units; the
 * tool adds its bake's counts after. */
void dm_bake_cli_reach_map_prov(const dm_bake_cli *a, const char *tool, const dm_bake_cli_inputs *in, double reach_opt,
                                int64_t height, const char *method, const char *units, dm_provenance *prov);

/* A reach tool's times, ms, for --report. */
typedef struct dm_bake_cli_times {
    double load_ms, bake_ms, write_ms;
} dm_bake_cli_times;
/* --report's first line (the mesh: path, vertices, triangles, faces in the file) and its last
 * (the times), on stdout; the tool prints its own lines between them. */
void dm_bake_cli_report_mesh(const char *path, const dm_mesh *m);
void dm_bake_cli_report_times(const dm_bake_cli_times *t);

/* Writes w × h interleaved RGBA texels (rows bottom-up) as an EXR of four channels named
 * names[0..3], float but those whose bit is set in half_mask (flags whose 0 and 1 half holds
 * exactly), with prov, through a temporary renamed into place. DM_EXIT_OK, or DM_EXIT_SAVE
 * said on stderr naming output (out of memory, or the write failed). */
int dm_bake_cli_write_rgba(const char *output, const float *texels, int w, int h, const char *const names[4],
                           unsigned half_mask, const dm_provenance *prov);

#ifdef __cplusplus
}
#endif
#endif
