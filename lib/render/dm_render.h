/* dm_render.h — the real-time skin renderer on OpenGL 3.3 core: subsurface scattering by
 * texture-space diffusion (GPU Gems 3 ch. 14) or screen-space separable SSS (Jimenez et al.
 * 2015), as the scene's effects.subsurface.technique says, and translucency. No window or context code: the caller makes a GL 3.3+ core context
 * current (lib/host/dm_osmesa.h headless, a GLFW window in the viewer) and keeps it
 * current for every call below.
 *
 *   dm_render_assets a = {...};                 // GPU-ready arrays + the scene
 *   dm_renderer *r;
 *   if (dm_renderer_create(&a, &(dm_render_desc){0}, &r, &err) != DM_OK) ...;
 *   dm_render_frame(r, &(dm_frame_options){0}, &err);
 *   dm_renderer_read_display(r, rgba8);         // width*height*4 bytes, bottom-up
 *   dm_renderer_blit_display(r, fbo, 0, 0, w, h, &err); // or into your framebuffer
 *   dm_renderer_destroy(r);
 *
 * Inputs are exactly what a pack holds (DESIGN.md: the runtime maps and uploads, it does
 * not bake). Every array is read during dm_renderer_create only (uploaded, not kept):
 * the caller may free it afterwards. A pointer may be NULL (an absent texture has
 * texels == NULL) when no enabled effect needs it; create fails with DM_ERR_MISMATCH,
 * naming the missing input and the effect that needs it, otherwise.
 *
 * Pass graph (dm_render_plan.h): built from the scene's effects; a pass runs only when an
 * enabled effect needs it. Units: mesh units for positions (scene->mm_per_unit converts),
 * mm² for profile variances, UV units per mm for stretch.
 *
 * Light units (as in the chapter's shaders): a light of colour C and intensity I gives a
 * white Lambertian surface facing it the radiance C·I; specular radiance is
 * C·I·(N·L)·rho_s·f_KS. The environment's SH holds radiance; its diffuse radiance is
 * albedo·E(N)/π with E the SH irradiance.
 */
#ifndef DM_RENDER_H
#define DM_RENDER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "pack/dm_pack.h"
#include "core/dm_profile.h"
#include "core/dm_result.h"
#include "core/dm_scene.h"
#include "render/dm_render_plan.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Interleaved vertex: 12 float32 (48 bytes), the pack's layout (pack/dm_pack.h,
 * DM_PACK_VERTEX_*), so a pack's vertex blob uploads as it is:
 *   [0..2]  position, mesh units
 *   [3..5]  normal, unit
 *   [6..7]  uv, v = 0 at the bottom of the maps (OBJ/OpenGL convention)
 *   [8..10] tangent, unit, along +u in the surface
 *   [11]    handedness ±1: bitangent B = handedness · cross(N, T), along +v
 * Vertices are split at UV seams (one vertex per distinct position/normal/uv). */
enum { DM_VERTEX_FLOATS = DM_PACK_VERTEX_STRIDE / 4, DM_VERTEX_STRIDE = DM_PACK_VERTEX_STRIDE };
enum {
    DM_VERTEX_POSITION = DM_PACK_VERTEX_POSITION / 4,
    DM_VERTEX_NORMAL = DM_PACK_VERTEX_NORMAL / 4,
    DM_VERTEX_UV = DM_PACK_VERTEX_UV / 4,
    DM_VERTEX_TANGENT = DM_PACK_VERTEX_TANGENT / 4
};

/* Texel formats are the pack's (pack/dm_pack.h: dm_tex_format, dm_tex_format_get): rows
 * bottom-up, texels tightly packed, "16f" formats hold IEEE half floats (uint16_t). */

typedef struct dm_texture {
    dm_tex_format format;
    int width, height;  /* texels, 1..16384 */
    const void *texels; /* width*height texels, bottom-up; NULL = absent */
} dm_texture;

enum { DM_RENDER_ENV_LEVELS_MAX = 6, DM_RENDER_SH_COUNT = 9 };

typedef struct dm_render_assets {
    const dm_scene *scene; /* effects, lights, camera, profile, sizes; never NULL */

    /* mesh */
    const float *vertices; /* vertex_count * DM_VERTEX_FLOATS */
    int vertex_count;
    const uint32_t *indices; /* index_count, triangles, counter-clockwise = front */
    int index_count;

    /* maps (all optional: absent albedo is white, absent normal map is (0,0,1), absent
     * specular map is 1, absent roughness map uses scene->roughness) */
    dm_texture albedo;        /* RGBA8_SRGB */
    dm_texture normal_map;    /* RGBA8 (or RGBA16F/32F holding −1..1 already: not supported) */
    dm_texture specular_map;  /* R8 or RGBA8 (red channel) */
    dm_texture roughness_map; /* R8, m in [0, 1] */

    /* specular tables (dm_lut.h layout: s = cosine, t = m, texel centres) */
    dm_texture beckmann;       /* R8, 0.5·D^0.1; needed by specular */
    dm_texture rho_dt;         /* R32F; needed by energy_conservation (with specular) */
    dm_texture env_brdf;       /* RG32F: F0·R + G = ∫ f_KS cos (split sum; R = scale, G = bias);
                                * needed by environment_lighting (with specular) */

    /* subsurface: stretch chain, UV units per mm along u (R) and v (G). Level k is the
     * stretch blurred like irradiance level k; the blur that makes level k reads stretch
     * level k−1. One level is accepted (used for every blur). RG32F or RG16F. */
    int stretch_level_count; /* 1..DM_PROFILE_MAX_GAUSSIANS */
    dm_texture stretch[DM_PROFILE_MAX_GAUSSIANS];
    dm_texture stretch_mask; /* R8 chart coverage; optional (coverage is also rasterized) */
    /* the seam map (bake/dm_seam_map.h): RGBA32F, per gutter texel the UV where the surface
     * continues beyond the chart (u', v', 1, mm beyond the edge), else 0; optional. With it the
     * irradiance pass lights those texels at that point, so the blurs cross UV seams; used only
     * when its size is the irradiance size (dm_renderer_seam_map says whether it is used). */
    dm_texture seam;
    /* the thin-part map (bake/dm_thin_map.h): RGBA32F, N × 2N, two layers of N rows: per texel
     * up to two points across a thin part or a fold (u', v', mm apart, 1), else 0; optional.
     * With it the diffusion pass adds Σ_k w_k exp(−d²/2v_k) L_k(u', v') per candidate (exact for
     * parallel sheets); used only when N is the irradiance size and the levels are summed per
     * texel (dm_renderer_thin_map says whether it is used). */
    dm_texture thin;
    /* the thin-part map baked at half the size (the pack's "thin.half", N/2 × N): a renderer
     * at half the scene's irradiance size (dermis-view's default) uses it, one at the scene's
     * size the one above (dm_render_assets_thin_map); optional. (No half-size seam map: at
     * 512² on the head it made the seam region worse, docs/seam-map.md.) */
    dm_texture thin_half;
    /* the thin gather (bake/dm_thin_gather.h): "gather.index" RGBA32F N × N and "gather.taps"
     * RG32F: the profile's widest levels as a 3-D sum over the surface's sites where a surface
     * facing away or a UV seam is near; optional. Used with the thin-part map, when N is the irradiance size and the
     * levels are summed per texel (dm_renderer_thin_gather says whether it is used). */
    dm_texture gather_index, gather_taps;
    /* the thin gather baked at half the size ("gather.half.index", "gather.half.taps"): what a
     * renderer at N/2 reads, as thin_half (dm_render_assets_gather); optional. */
    dm_texture gather_half_index, gather_half_taps;
    const dm_profile *profile; /* NULL: scene->profile */

    /* screen-space subsurface: the separable kernels dermis-pack fitted to the profile, one row
     * per size of pixel (core/dm_ssss_kernel.h layout: ss_kernel_taps × ss_kernel_rows RGBA
     * float32 texels, rgb = weights, a = offset in pixels at the row's size; the pack entry's
     * t_range, the first and last row's mm per pixel, in ss_kernel_mm_per_px, NULL for a pack
     * made before the rows: one row, offsets in mm). NULL: fitted at create from the profile
     * with scene->screen_taps taps (the same function, so the same kernels). */
    const float *ss_kernel;
    int ss_kernel_taps, ss_kernel_rows;
    const float *ss_kernel_mm_per_px;

    /* pre-integrated subsurface (Penner 2011; bake/dm_preintegrated.h layout): the table
     * D(N.L, curvature), RGBA32F/16F (rgb), s = N.L at texel centres, row j = curvature
     * preint_curvature_max_per_mm·j/(height − 1); and the mean curvature per texel of the
     * mesh (R32F, 1/mm, bake/dm_curvature.h; negative = concave, read as flat). Both needed by
     * the technique; preint_curvature_max_per_mm 0 = 1. */
    dm_texture preintegrated;
    dm_texture curvature;
    float preint_curvature_max_per_mm;

    /* environment (mesh space; equirect: u = 0.5 + atan2(d.x, −d.z)/2π, v = 0.5 + asin(d.y)/π,
     * so v = 1 is straight up; scene->env_rotation_deg turns it about +Y) */
    bool has_env_sh;
    float env_sh[DM_RENDER_SH_COUNT][3]; /* radiance SH, real basis, order (0,0) (1,−1) (1,0)
                                          * (1,1) (2,−2) (2,−1) (2,0) (2,1) (2,2), RGB */
    int env_level_count;                 /* prefiltered specular levels, 0..6 */
    float env_level_m[DM_RENDER_ENV_LEVELS_MAX]; /* Beckmann m of each level, ascending */
    dm_texture env_levels[DM_RENDER_ENV_LEVELS_MAX]; /* RGBA16F/32F equirect radiance */
    dm_texture env_background;                       /* RGBA16F/32F equirect radiance */
} dm_render_assets;

/* Texels (of its reduced grid) a level's total Gaussian σ keeps under the automatic
 * blur resolution (dm_render_desc.blur_auto_resolution). */
#define DM_BLUR_AUTO_SIGMA 1.2

/* Where the texture-space blur passes run. AUTO: on the CPU (core/dm_level_blur.h) when the
 * OpenGL renders on the CPU too (llvmpipe, softpipe) and the levels are RGBA32F, in GL
 * (shaders/blur.glsl) otherwise. The glow's two blur passes follow it (core/dm_glow_blur.h;
 * its targets are always RGBA32F; on the CPU its intermediate target glow_b is not written).
 * The two give the same sums to float rounding. */
typedef enum dm_blur_path { DM_BLUR_PATH_AUTO = 0, DM_BLUR_PATH_GL, DM_BLUR_PATH_CPU } dm_blur_path;

/* The shadow map's default size. The normal offset is 1.5 of its texels, and where a cast
 * shadow's edge falls moves with it: on the eyes close up (docs/crevices.md) the frame's mean
 * error against the ray-cast truth is 3.77 / 6.47 / 5.81 % at 1024, 2.31 / 3.66 / 3.48 % at
 * 2048 (+3 ms of shadow pass on llvmpipe at 1280x720) and 1.66 / 2.07 / 2.03 % at 4096. */
enum { DM_RENDER_SHADOW_SIZE_DEFAULT = 2048 };

/* The seam map (N × N) of a baked for irradiance size n, or the thin-part map (N × 2N) — the
 * pack's own or its half-size one — or NULL when none is. */
const dm_texture *dm_render_assets_seam_map(const dm_render_assets *a, int n);
const dm_texture *dm_render_assets_thin_map(const dm_render_assets *a, int n);
/* The thin gather's index (n × n) baked for irradiance size n, its taps in *taps; NULL when the
 * pack has none at that size. */
const dm_texture *dm_render_assets_gather(const dm_render_assets *a, int n, const dm_texture **taps);

/* Options of the renderer itself; zero means default. */
typedef struct dm_render_desc {
    const char *shader_dir; /* load shaders/<pass>.glsl from here; NULL = embedded copies */
    int width, height;      /* output size; 0 = scene's */
    int irradiance_size;    /* texture-space size; 0 = scene's irradiance_size */
    int shadow_size;        /* shadow map size, 16..8192; 0 = DM_RENDER_SHADOW_SIZE_DEFAULT */
    bool timings_cpu;       /* with timings on a software renderer: process CPU time (every
                             * llvmpipe thread summed) instead of wall time per pass */
    bool timings;           /* time every pass (CPU clock around glFinish on software
                             * renderers, GL_TIME_ELAPSED queries elsewhere) */

    /* Speed/accuracy settings (DESIGN.md promise 1: bench/results/render.md gives each one's
     * time and its error against the exact path). Zero is the default everywhere, and the
     * default is the exact path or equal to it to float rounding. */
    int shadow_pcf_taps;      /* 0 = 4: the 3x3 PCF filter (4x4 texels, bilinear compares)
                               * taken with 4 taps, equal to 9 taps to float rounding;
                               * 9: the same filter with 9 taps (reference); 1: one bilinear
                               * compare (2x2 texels, harder shadow edges) */
    int blur_reduce_from;     /* 0 = off. k in 1..(Gaussians − 1): blur levels k and wider are
                               * rendered and stored at irradiance_size >> blur_reduce_shift
                               * (the wide Gaussians span many texels; the final pass
                               * upsamples them bilinearly) */
    int blur_reduce_shift;    /* 0 = 1 (half resolution); 1..3 */
    bool blur_auto_resolution; /* (without blur_reduce_from) each level k stored at
                               * irradiance_size >> j, the largest j <= 3 that keeps its total
                               * Gaussian at least DM_BLUR_AUTO_SIGMA texels wide there (at the
                               * stretch map's median along the coarser axis), never finer than
                               * level k−1: on the head at 1024, levels 4, 5 at 1/2, 1/4. Not the
                               * default: where the atlas is sparser than its median (back of the
                               * head, neck, seams) the area-weighted error against the ground
                               * truth grows (bench/results/accuracy.md) */
    bool blur_half_float;     /* irradiance and blur targets in RGBA16F instead of RGBA32F
                               * (11-bit mantissa: relative rounding 4.9e-4 per pass). Halves
                               * memory and bandwidth on GPUs; on llvmpipe it is slower (the
                               * half-float conversions cost more than the bytes saved) */
    dm_blur_path blur_path;   /* where the blur passes run (above); CPU with blur_half_float
                               * is refused */
    bool diffusion_per_pixel; /* the final pass samples every level per pixel and sums them
                               * (DM_LEVELS bilinear fetches), as before the diffusion pass;
                               * default: the diffusion pass sums them once per texel and the
                               * final pass reads that sum (one fetch). The two differ in the
                               * texel ring at chart edges, where bilinear sampling mixes
                               * covered and uncovered texels (bench/results/accuracy.md).
                               * Reduced levels (blur_reduce_from, blur_auto_resolution) are
                               * always summed per pixel: a per-texel sum would interpolate
                               * them twice */
    uint64_t memory_available_size; /* what create may count on: it refuses (DM_ERR_OUT_OF_MEMORY,
                               * with both numbers) when its estimate (render/dm_render_memory.h)
                               * exceeds it; 0 = what the machine has available now
                               * (core/dm_memory.h: DERMIS_MEM_AVAILABLE_MB, a cgroup's limit,
                               * MemAvailable); UINT64_MAX = no check */
    bool reuse_texture_space; /* skip shadow maps, irradiance and the blur chain when nothing
                               * they depend on (the scene: dm_renderer_set_scene; the light
                               * rotation; blur and roughness scales) changed since the last
                               * frame that made them: exact; their timings read 0 then */
} dm_render_desc;

typedef struct dm_renderer dm_renderer;

/* Median stretch over the charts (stretch mask > 0, else s_u > 0) of level 0: s_u and s_v in
 * UV units per mm (the automatic blur resolution's texel density). False when there is none. */
bool dm_render_stretch_median(const dm_render_assets *a, float med[2]);

/* Builds the pass plan, checks the assets against it, compiles the shaders and uploads
 * everything. Needs a current GL 3.3+ core context. Free with dm_renderer_destroy.
 * Before it makes anything it refuses, with a message naming the size, the limit and the
 * largest size that fits: a target beyond this OpenGL's limits (GL_MAX_TEXTURE_SIZE,
 * GL_MAX_RENDERBUFFER_SIZE, GL_MAX_VIEWPORT_DIMS, and a proxy texture of the target's format
 * and size: llvmpipe caps one texture's bytes) with DM_ERR_RANGE, and a renderer whose memory
 * estimate exceeds what is available (desc.memory_available_size) with DM_ERR_OUT_OF_MEMORY. */
dm_result dm_renderer_create(const dm_render_assets *assets, const dm_render_desc *desc, dm_renderer **out,
                             dm_error *err);
void dm_renderer_destroy(dm_renderer *r);

/* Whether the texture-space blur passes run on the CPU (dm_render_desc.blur_path). */
bool dm_renderer_blur_on_cpu(const dm_renderer *r);
/* Whether texture space reads the pack's seam map (its irradiance pass lights the gutter
 * texels a blur reaches where the surface continues across a UV seam). */
bool dm_renderer_seam_map(const dm_renderer *r);
/* Whether texture space reads the pack's thin-part map (its diffusion pass adds the light
 * from across thin parts and folds). */
bool dm_renderer_thin_map(const dm_renderer *r);
/* Whether the blur on the CPU gathers the widest levels in 3-D (the pack's thin gather). */
bool dm_renderer_thin_gather(const dm_renderer *r);

/* Replaces the scene's values that no pass, target or upload depends on: camera, light
 * directions, positions, colours and intensities, material constants, environment
 * intensity and rotation, mix, exposure, glow settings (the interactive viewer moves
 * these every frame). Output size and irradiance size stay those of create; the profile
 * stays the one given at create. Fails with DM_ERR_INVALID_ARGUMENT, naming the field,
 * when the scene changes the pass list or the uploads (effects, light count, a light's
 * type or shadow casting, environment background, blur taps): recreate the renderer then. */
dm_result dm_renderer_set_scene(dm_renderer *r, const dm_scene *scene, dm_error *err);

/* The largest scale_rgb of dm_renderer_set_profile_weights. */
#define DM_PROFILE_SCALE_MAX 100.0

/* Replaces the profile's weights and keeps its variances: the blur chain and the stretch maps
 * depend on the variances only, so nothing is re-created or uploaded again (the viewer's
 * live skin sliders over bake/dm_skin_weights.h). p must pass dm_profile_validate
 * (DM_ERR_RANGE) and have the renderer's Gaussian count and variances, bit for bit
 * (DM_ERR_INVALID_ARGUMENT naming the first that differs: recreate the renderer then). As at
 * create, each channel's weights are divided by their sum (the colour comes from the albedo
 * map); scale_rgb (NULL: 1, 1, 1; each in [0, DM_PROFILE_SCALE_MAX]) then multiplies channel
 * c's diffused light: a caller whose new skin is darker or lighter than the one the albedo
 * map shows passes the ratio of their totals. The texture-space levels and translucency's
 * T(d) take the weights at the next frame; the screen-space kernel and the pre-integrated
 * table are made from the profile at create (or packed), so with subsurface on in those
 * techniques it is refused (DM_ERR_INVALID_ARGUMENT). The create profile with NULL gives
 * the create frame, byte for byte. */
dm_result dm_renderer_set_profile_weights(dm_renderer *r, const dm_profile *p, const double scale_rgb[3], dm_error *err);

/* Per-frame options; zero means the final picture. */
typedef struct dm_frame_options {
    dm_view view;
    int view_index;           /* blur/stretch level, shadow light */
    float view_scale;         /* multiplies debug texture views; 0 = 1 */
    float light_rotation_deg; /* turns every light about +Y (mesh space) */
    float blur_scale;         /* multiplies every profile variance (the blur width: σ grows
                               * as its square root); 0 = 1, > 0. The level weights and the
                               * plan's explain text stay those of the profile. */
    float roughness_scale;    /* multiplies the Beckmann m (roughness map or constant) before
                               * the lookups, clamped to at most 1; 0 = 1, > 0 */
} dm_frame_options;

/* Renders one frame. Fails with DM_ERR_INVALID_ARGUMENT when the view is not available
 * for this scene (e.g. the irradiance view with subsurface off) and DM_ERR_GL on a GL
 * error (the message names the pass). */
dm_result dm_render_frame(dm_renderer *r, const dm_frame_options *opt, dm_error *err);

/* The plan of the last frame (or of the final view before any frame). */
const dm_render_plan *dm_renderer_plan(const dm_renderer *r);
/* Milliseconds per pass of the last frame (plan order), and the frame total; zeros when
 * desc.timings was false. pass_ms holds dm_renderer_plan(r)->pass_count values. */
void dm_renderer_last_timings(const dm_renderer *r, double *pass_ms, double *frame_ms);
/* The GL_RENDERER string and whether timings use the CPU clock (software renderer). */
const char *dm_renderer_gl_name(const dm_renderer *r);
bool dm_renderer_timing_on_cpu(const dm_renderer *r);

void dm_renderer_size(const dm_renderer *r, int *width, int *height, int *irradiance_size);

/* The output of the last frame, bottom-up. Display: 8-bit sRGB RGBA (tonemapped when the
 * tonemap effect is on and the view is a shaded one; otherwise the linear values clamped
 * to [0, 1] and sRGB-encoded on the CPU; alpha 255). Linear: the float32 radiance before
 * tonemapping (or the debug view's values stretched over the screen), alpha = coverage:
 * 1 where the head is drawn, 0 on the background. Buffers hold width*height*4 values. */
dm_result dm_renderer_read_display(dm_renderer *r, uint8_t *rgba, dm_error *err);
dm_result dm_renderer_read_linear(dm_renderer *r, float *rgba, dm_error *err);

/* Puts the last frame's display picture (the very bytes dm_renderer_read_display returns)
 * into the caller's framebuffer object `framebuffer` (0: the default framebuffer), in each of
 * its draw buffers, at the rectangle of width x height pixels whose lower-left corner is
 * (x, y): an exact copy when that is the output size (dm_renderer_size), else scaled with
 * linear filtering (glBlitFramebuffer; what falls outside the framebuffer is clipped). The
 * bytes land as they are, sRGB-encoded: the target should be 8-bit RGBA, single-sampled.
 * The scissor test and GL_FRAMEBUFFER_SRGB are off during the blit.
 * A tonemapped frame is blitted from the renderer's display target; any other is built on
 * the CPU as dm_renderer_read_display does and uploaded to an RGBA8 texture the renderer
 * owns (made on the first such call, freed by dm_renderer_destroy); that path expects the
 * pixel-store defaults and no pixel buffer bound, as the read-back calls do.
 * On return the caller's GL_READ_FRAMEBUFFER and GL_DRAW_FRAMEBUFFER bindings, scissor test
 * and GL_FRAMEBUFFER_SRGB are as they were (the active unit's 2D texture and the pixel-store
 * alignments may change, as with the renderer's other calls).
 * Fails with DM_ERR_INVALID_ARGUMENT, naming the value, for width or height < 1, a rectangle
 * ending past INT_MAX, a name that is not a framebuffer object, an incomplete framebuffer,
 * or before the first dm_render_frame; DM_ERR_GL on a GL error (an integer or multisampled
 * target). Nothing is written then. */
dm_result dm_renderer_blit_display(dm_renderer *r, unsigned int framebuffer, int x, int y, int width, int height,
                                   dm_error *err);

/* The last frame's view at full precision (float32, bottom-up, RGBA). Texture views
 * (dm_view_is_texture) are read from the "view" target at the source texture's own size,
 * one value per texel, nothing resampled: irradiance, blurK and diffusion are
 * coverage-normalised (rgb / alpha of the level) times view_scale with alpha = chart
 * coverage (the irradiance alpha, 0 or 1; reduced levels take the fine texel under their
 * centre); irradiance at view_scale 1 equals the "irradiance" target bit for bit wherever
 * it is covered. diffusion is dm_diffusion of shaders/common.glsl, the very sum the final
 * pass samples, at the texel centres. stretchK: u, v, mask with alpha = mask (1 without
 * one); shadowK: depth, alpha 1. Other views: the screen, as dm_renderer_read_linear.
 * dm_renderer_view_size gives the size the buffer needs (width*height*4 floats). */
void dm_renderer_view_size(const dm_renderer *r, int *width, int *height);
/* The colour scale of the last frame's stretch or curvature view (its picture maps lo..hi
 * through the turbo colour scale, dm_render_turbo): the 1st and 99th percentiles of what it
 * shows over the charts, and that quantity's name ("mm per texel": 1 / (map width ·
 * sqrt(s_u s_v)); "mean curvature, 1/mm"). lo = hi = 0, quantity NULL for other views. */
void dm_renderer_view_scale(const dm_renderer *r, float *lo, float *hi, const char **quantity);
/* The gain the last frame's specular view applied to the head (its 99th percentile to near
 * display white; the background keeps the scene's exposure); 1 for other views. */
float dm_renderer_view_gain(const dm_renderer *r);
/* A stretch or curvature view's display picture (*px, w x *h RGBA8, bottom-up, malloc'd)
 * with its colour scale's legend in a strip below (*px replaced, *h grown); other views
 * unchanged. */
dm_result dm_render_view_with_legend(const dm_renderer *r, void **px, int w, int *h, dm_error *err);
dm_result dm_renderer_read_view(dm_renderer *r, float *rgba, dm_error *err);
/* The last line of defence before a picture of the last frame is written (dermis-render,
 * dermis-view's screenshot): DM_ERR_NON_FINITE when its view (what dm_renderer_read_view
 * returns) holds a NaN or infinite value, the message naming the view, how many values, the
 * first pixel, and every target of the frame holding such values, in the order the renderer
 * made them ("irradiance", "blur3", "screen": where they arose). DM_OK otherwise. */
dm_result dm_renderer_check_finite(dm_renderer *r, dm_error *err);

/* Every intermediate render target, for inspection (tests scan them for NaN/Inf). */
typedef struct dm_target_info {
    const char *name; /* "irradiance", "blur3", "blur_tmp", "shadow0", "screen", "view", ... */
    int width, height;
    int channels; /* values per texel read back: 4, or 1 for depth */
} dm_target_info;
int dm_renderer_target_count(const dm_renderer *r);
void dm_renderer_target_info(const dm_renderer *r, int index, dm_target_info *info);
/* Reads target `index` as float, width*height*channels values, bottom-up. */
dm_result dm_renderer_read_target(dm_renderer *r, int index, float *out, dm_error *err);
/* The index of the target with that name, or −1. */
int dm_renderer_find_target(const dm_renderer *r, const char *name);

/* The discrete blur kernel the renderer uses for `taps` taps (odd, 3..63): offsets in
 * standard deviations over ±3σ, weights the Gaussian integrated over each tap's bin with
 * the tails folded into the end taps (7 taps give the chapter's 0.006, 0.061, 0.242,
 * 0.382). offsets/weights hold `taps` values. Returns the kernel's variance in σ² (1.08
 * for 7 taps): the blur of variance v really blurs by v times this. */
double dm_render_blur_kernel(int taps, float *offsets_sigma, float *weights);

#ifdef __cplusplus
}
#endif
#endif
