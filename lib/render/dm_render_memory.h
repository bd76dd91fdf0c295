/* dm_render_memory.h — the renderer's memory by its options, before anything is made, and the
 * sizes this OpenGL can make. dm_renderer_create refuses, before its first allocation, a
 * renderer whose estimate exceeds the memory available (core/dm_memory.h) or whose targets
 * exceed the context's limits; tools and embedders may ask the same questions first.
 *
 * THE ESTIMATE (bytes; W x H the output, N the irradiance size, n_k level k's edge, S the
 * shadow map size; "x 4/3" for textures with mip levels). With software OpenGL (llvmpipe,
 * softpipe) every texture and target lives in this process's memory and is counted; with a
 * GPU only the CPU side is (the GPU's own memory is its driver's to refuse: GL_OUT_OF_MEMORY).
 *   driver      DM_RENDER_MEMORY_DRIVER_SIZE: the software OpenGL itself (LLVM, shader code,
 *               the rasteriser's bins and tiles), measured on the synthetic sphere at the
 *               smallest sizes; 0 with a GPU
 *   inputs      Σ the assets' texel and mesh bytes the plan reads (a pack's mapped pages are
 *               resident once create has read them)
 *   uploads     the same textures as GL copies (albedo, normal, specular, roughness with mip
 *               levels x 4/3; the environment levels twice: per level and as one array)
 *   shadow      shadow maps x S² x 4
 *   texture     Σ_k n_k² x 16 (RGBA32F levels; 8 with blur_half_float) + one U target per
 *   space       distinct size (n_k x n_(k-1) x 16) + the diffusion sum N² x 16 (when summed
 *               per texel) + the surface G-buffer 4 x N² x 16 + its depth N² x 4
 *   screen      W x H x (16 screen + 4 depth [+ 64 G-buffer when deferred] [+ 56 screen-space
 *               diffuse, aux, specular, tmp] [+ 4 display when tonemapped]) + glow
 *               (W/2 x H/2 x 32) + the texture views' target, at the largest texture a view
 *               shows (N², S², the stretch or curvature map) x 16
 *   CPU blur    when the blurs run on the CPU: 3 padded level buffers (N+4)² x 16, the
 *               stretch per texel Σ_k (n_k n_(k-1) + n_k²) x 4, the diffusion sum N² x 16, the
 *               glow's two images W/2 x H/2 x 32; with the thin-part map its candidates
 *               (16 each, 8 a texel that has any, (N+1) x 4), with the gather its compact copy
 *               (8 a tap, 24 a site, 12 a gathering texel, (N+1) x 4: core/dm_level_sum.h);
 *               with the seam map (used at the size it was baked for) its points and cuts N² x 24
 *   read-back   one read of the output at full precision by the caller and the renderer:
 *               W x H x (16 + 16 + 4 + 4), and a texture view's W_v x H_v x 16
 * Not counted: a texture view's target and its read-back (2 x 16 bytes a texel of the texture
 * shown). Measured against the peak resident set of dermis-render: 0.96..1.11 of it from
 * irradiance 64 to 4096 and outputs up to 2048² (docs/dermis-render.md, Memory and sizes);
 * tests/render/test_render_memory.c holds it to 0.8..1.5. */
#ifndef DM_RENDER_MEMORY_H
#define DM_RENDER_MEMORY_H

#include <stdbool.h>
#include <stdint.h>

#include "core/dm_result.h"
#include "render/dm_render.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What the software OpenGL (llvmpipe here: Mesa 22.3, LLVM 15) keeps itself: the peak RSS of
 * dermis-render on the synthetic quad at 64x36 and irradiance 64 less what the estimate counts
 * there. */
#define DM_RENDER_MEMORY_DRIVER_SIZE ((uint64_t)96 << 20)

typedef struct dm_render_memory {
    uint64_t driver_size, inputs_size, uploads_size, shadow_size, texture_space_size, screen_size, cpu_blur_size,
        readback_size;
    uint64_t total_size;   /* the sum */
    bool gl_host_memory;   /* software OpenGL: GL's textures and targets counted */
} dm_render_memory;

/* The estimate above for a renderer made from these assets and options (the same defaults and
 * plan as dm_renderer_create). software_gl: count GL's textures and targets as this process's
 * memory (true for OSMesa/llvmpipe; dm_renderer_create knows it from GL_RENDERER). Fails as
 * the plan does (DM_ERR_INVALID_ARGUMENT for a scene it cannot plan). */
dm_result dm_render_memory_estimate(const dm_render_assets *a, const dm_render_desc *desc, bool software_gl,
                                    dm_render_memory *out, dm_error *err);

/* The same for a renderer over a pack's assets (render/dm_render_pack.h). */
dm_result dm_render_memory_estimate_pack(const dm_pack *pack, const dm_render_desc *desc, bool software_gl,
                                         dm_render_memory *out, dm_error *err);

/* The estimate's parts, largest first, as one line: "texture space 12.2 GiB, blur on the CPU
 * 6.5 GiB, ..." (parts of 0 bytes left out). */
void dm_render_memory_text(const dm_render_memory *m, char *out, size_t out_size);

/* The current context's limits (GL_MAX_TEXTURE_SIZE, GL_MAX_RENDERBUFFER_SIZE,
 * GL_MAX_VIEWPORT_DIMS) and whether it makes one w x h texture of `internal` format
 * (GL_RGBA32F, ...): a proxy texture, which on llvmpipe also says no to a texture of more
 * bytes than it holds in one (here, Mesa 22.3 on a 24 GiB machine: an RGBA32F texture of
 * up to 1.5 GiB, 10032x10032 or 16384x6140). Needs a current context. */
typedef struct dm_render_gl_limits {
    int max_texture_size, max_renderbuffer_size, max_viewport[2];
} dm_render_gl_limits;
void dm_render_gl_limits_get(dm_render_gl_limits *out);
bool dm_render_gl_can_make(unsigned int internal_format, int width, int height);
/* The largest edge e <= max_edge with an e x e texture of that format (by halving and proxy tests; 0 if none). */
int dm_render_gl_largest_square(unsigned int internal_format, int max_edge);

#ifdef __cplusplus
}
#endif
#endif
