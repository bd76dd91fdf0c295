/* dm_gpu_target.h — render targets: float colour targets with their framebuffers, depth
 * renderbuffers, four-target G-buffers; each named in the registry's target list (read-back
 * and the target queries go by it, in the order made). */
#ifndef DM_GPU_TARGET_H
#define DM_GPU_TARGET_H

#include "render/gpu/dm_gpu.h"

/* Names a target (fbo attached, w x h, channels 4, or 1 for depth) in g's list. */
void dmg_add_target(dmg *g, const char *name, GLuint fbo, int w, int h, int channels);
/* The index of the target named `name`, or −1. */
int dmg_find_target(const dmg *g, const char *name);
/* A w x h colour texture (`internal`, linear filter, `wrap`, border 0) and a framebuffer
 * drawing to it; named `name`. */
dm_result dmg_color_target(dmg *g, const char *name, int w, int h, GLenum internal, GLenum wrap, GLuint *tex,
                           GLuint *fbo, dm_error *err);
/* A w x h DEPTH_COMPONENT24 renderbuffer. */
GLuint dmg_depth_buffer(dmg *g, int w, int h);
/* Attaches the depth renderbuffer to fbo (left bound); `what` names it in the failure. */
dm_result dmg_attach_depth(GLuint fbo, GLuint depth, const char *what, dm_error *err);
/* A G-buffer (deferred shading: a pass rasterises the surface into it, the next shades each
 * pixel or texel once from it, with every SIMD lane on one): four RGBA32F targets named
 * <prefix>0..3, w x h, in one FBO drawing to all four with the depth renderbuffer `depth`,
 * cleared to 0 once (frames write and read only what the surface covers). */
dm_result dmg_gbuffer_targets(dmg *g, const char *prefix, int w, int h, GLuint depth, GLuint tex[4], GLuint *fbo,
                              dm_error *err);
extern const GLenum dmg_draw_buffers[4]; /* colour attachments 0..3, for glDrawBuffers */

#endif
