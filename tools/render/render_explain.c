#include "render_explain.h"

#include <stdio.h>

void render_explain_maps(const dm_renderer *r, const dm_render_assets *a, int irradiance_size)
{
    /* docs/render-quality.md, The blur on the CPU; docs/seam-map.md */
    printf("blur passes: %s\nseam map: %s\n", dm_renderer_blur_on_cpu(r) ? "on the CPU (OpenGL is software)" : "in GL",
           dm_renderer_seam_map(r) ? "the pack's: the irradiance pass also lights the gutter texels a blur reaches, "
                                     "where the surface continues across the UV seam, and the blurs leave out "
                                     "taps that jump to another place of the surface"
           : a->seam.texels ? "the pack's is for another irradiance size: not used, the blurs stop at UV seams"
                            : "none in the pack (or left out: --no-seam-map): the blurs stop at UV seams");
    /* docs/thin-map.md */
    printf("thin-part map: %s\n",
           dm_renderer_thin_map(r) ? "the pack's: the diffusion pass adds the light from across thin parts and "
                                     "folds (up to two points a texel, each level weighted by exp(-d^2/2v))"
           : !a->thin.texels ? "none in the pack: no light reaches across thin parts and folds"
           : !dm_render_assets_thin_map(a, irradiance_size)
               ? "the pack's are for other irradiance sizes (the scene's and half of it): not used"
               : "the pack's is not used: the levels are summed per pixel (reduced levels or "
                 "--diffusion-per-pixel), where it has no texel to read");
    printf("thin gather: %s\n",
           dm_renderer_thin_gather(r) ? "the pack's: near a surface facing away and near a seam, the widest levels are "
                                        "the 3-D sum over the surface's sites (the exact convolution's quadrature) "
                                        "instead of the atlas blur"
           : !a->gather_index.texels && !a->gather_half_index.texels ? "none in the pack: the widest levels come from the atlas blur and the "
                                       "thin-part map"
           : !dm_renderer_thin_map(r) ? "the pack's is not used: it goes with the thin-part map, which is not"
                                      : "the pack's are for other irradiance sizes (the scene's and half of it): not used");
}
