/* dm_pass_diffusion.h — the diffusion pass in GL: the levels' weighted sum at each texel of
 * the irradiance grid, for the final pass and the diffusion view. No state of its own. */
#ifndef DM_PASS_DIFFUSION_H
#define DM_PASS_DIFFUSION_H

#include "render/frame/dm_frame_pass.h"

/* Uploads the pack's thin gather where the thin-part map is used and the blur runs in GL (the
 * blur on the CPU gathers from the pack's texels itself), and its index for the "gather" debug
 * view wherever texture space runs at its size. After the blur on the CPU's setup. */
dm_result dmr_diffusion_setup(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err);
bool dmr_diffusion_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out);
void dmr_diffusion_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt);

#endif
