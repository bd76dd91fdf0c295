/* dm_render_estimate.h — what create resolves before any GL: the sizes from the assets and
 * options, where the blurs run, whether the diffusion pass sums the levels, and the memory
 * estimate's count (dm_render_memory.h states its formula). No GL. */
#ifndef DM_RENDER_ESTIMATE_H
#define DM_RENDER_ESTIMATE_H

#include <stdbool.h>

#include "render/dm_render.h"
#include "render/dm_render_memory.h"

/* The sizes dm_renderer_create resolves from the assets and options (zero: the scene's or the
 * defaults): output, irradiance, shadow map, each level's edge under blur_reduce_from (the
 * automatic resolution is dmr_auto_level_edges, once the stretch is checked). Texture sizes
 * are edges: an N-texel edge is an N × N texture. */
typedef struct dmr_sizes {
    int width, height, irr_edge, shadow_edge;
    int level_edge[DM_PROFILE_MAX_GAUSSIANS];
} dmr_sizes;
void dmr_resolve_sizes(const dm_render_assets *a, const dm_render_desc *d, dmr_sizes *s);
/* Whether the texture-space blurs (and the glow's) run on the CPU (dm_render_desc.blur_path):
 * the one predicate create and the estimate share. */
bool dmr_blur_cpu_wanted(const dm_render_desc *d, bool software_gl);
/* Whether the diffusion pass sums the levels per texel (not per pixel in the final pass). */
bool dmr_diffusion_summed(const dm_render_plan *p, const dm_render_desc *d);
/* Whether the thin gather is used at irradiance size n: the levels summed per texel, the
 * thin-part map and a gather baked for n, its header of this layout (create checks the rest:
 * core/dm_level_sum.h). */
bool dmr_gather_wanted(const dm_render_assets *a, int n, bool diffusion_sum);
/* What the estimate counts, as create resolved it. */
typedef struct dmr_memory_in {
    const dm_render_assets *a;
    const dm_render_plan *plan;
    const dmr_sizes *sizes;
    const dm_render_desc *desc;
    bool half_levels, diffusion_sum, software_gl;
    bool cpu_blur, cpu_glow; /* the texture-space blurs, the glow's, on the CPU */
} dmr_memory_in;
void dmr_memory_count(const dmr_memory_in *in, dm_render_memory *out);

#endif
