/* ref_args.h — dermis-reference's command line: the options (ref_args), --help, and the
 * parse that checks them against each other. */
#ifndef DM_TOOL_REF_ARGS_H
#define DM_TOOL_REF_ARGS_H

#include <stdbool.h>
#include <stdio.h>

#include "reference/dm_reference.h"

enum { MERGE_MAX = 4096 };

typedef struct ref_args {
    const char *pack, *out, *irradiance, *medium;
    const char *skin, *skin_preset; /* --skin SPEC, --skin-preset NAME */
    bool multipole, burley; /* burley: medium is "ALBEDO/MFP" */
    double thickness_mm;
    int pairs, radial_gaussians;
    const char *merge[MERGE_MAX];
    int merge_count;
    int size, width, height, atlas, tile_index, tile_count, threads, atlas_samples, pixel_samples, refine;
    bool frame, levels, verbose, quiet, at_centre;
    bool no_albedo, no_normal_map, no_shadows, no_subsurface; /* --without */
    const char *without;
    dm_reference_options ropt;
} ref_args;

/* --help's text. */
void ref_usage(FILE *f);
/* Fills a from the command line: −1 to go on, else the exit code (0 after --help or
 * --version, DM_EXIT_USAGE with the error printed). */
int ref_parse(int argc, char **argv, ref_args *a);
/* A radial profile replaces the pack's Gaussians: a medium, Burley or the physical skin. */
bool ref_radial(const ref_args *a);

#endif
