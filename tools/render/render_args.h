/* render_args.h — dermis-render's command line: the options (render_args), --help, and the
 * parse that checks them against each other. */
#ifndef DM_TOOL_RENDER_ARGS_H
#define DM_TOOL_RENDER_ARGS_H

#include <stdbool.h>
#include <stdio.h>

#include "render/dm_render.h"

typedef struct render_args {
    const char *pack, *out, *synthetic, *shader_dir, *view_text, *reference;
    double error_scale;
    bool view_given;
    int width, height, irradiance, frames, view_index;
    dm_view view;
    double view_scale, light_azimuth;
    bool view_scale_given;
    bool timings, explain, verbose, quiet, compare_exact, no_seam_map, no_thin_map, no_thin_gather;
    dm_render_desc speed; /* the speed/accuracy fields only */
} render_args;

/* --help's text. */
void render_usage(FILE *f);
/* Fills o from the command line: −1 to go on, else the exit code (0 after --help or
 * --version, DM_EXIT_USAGE with the error printed). */
int render_parse(int argc, char **argv, render_args *o);

#endif
