/* render_explain.h — dermis-render --explain's lines on the texture-space maps: where the blurs
 * run, and whether the pack's seam map, thin-part map and thin gather are used, and why not. */
#ifndef RENDER_EXPLAIN_H
#define RENDER_EXPLAIN_H

#include "render/dm_render.h"

/* Prints the lines to stdout; irradiance_size: the size the renderer was made at. */
void render_explain_maps(const dm_renderer *r, const dm_render_assets *a, int irradiance_size);

#endif
