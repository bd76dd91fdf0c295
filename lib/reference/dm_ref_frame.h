/* dm_ref_frame.h — the ground-truth frame: what the scene's camera sees, shaded on the CPU
 * independently of the renderer, diffused by the exact surface convolution.
 *
 * STAGES
 * 1. Surface (dm_ref_surface.h): the pack's mesh and maps, an Embree BVH in mm, the exact
 *    ρdt table.
 * 2. Irradiance atlas (dm_ref_shade_atlas): atlas_size² texels, every light of the scene
 *    (shadows by ray casting), the normal map, the SH environment, × albedo^mix.
 * 3. Primary rays: one per pixel centre from the scene camera, exactly the renderer's
 *    projection (lib/core/dm_mat4.h, as the renderer's camera uses them: forward f = target − eye,
 *    right = f × up, up' = right × f; pixel (x, y), rows bottom-up, looks along
 *    f + (2(x+½)/W − 1)·tan(fov/2)·(W/H)·right + (2(y+½)/H − 1)·tan(fov/2)·up'), clipped to
 *    the renderer's near and far planes (view depth in [max(d − 2r, 0.01 r), d + 2r] for the
 *    mesh's bounding sphere at distance d, radius r) and culling back faces as its final
 *    pass does (a ray goes on through a triangle seen from behind).
 * 4. Convolution (dm_reference_eval) at every hit: D = Σ_k w_k ∫ I G_k dA over the whole
 *    mesh, I the atlas, w the profile's weights normalised per channel
 *    (dm_reference_kernel_from_profile). Without the subsurface effect D is not used:
 *    the diffuse is then Lambert at the point, as final.glsl does it.
 * 5. Composition, as final.glsl: diffuse = D · albedo^(1 − mix)
 *    [× max(1 − ρs·ρdt(N·V, m), 0) with energy conservation] + specular (KS per light,
 *    exact Beckmann, shadowed by rays) + environment specular (ρs · ρdt(N·V, m) ·
 *    prefiltered levels from the pack); a ray that hits nothing gets the environment
 *    background (env_intensity × the pack's env.background along the ray) when the
 *    renderer draws one, else black (its clear colour).
 * The subsurface technique a scene names (texture-space, screen-space, ...) does not change
 * the reference: it is the exact diffusion every technique approximates. No separate
 * translucency term is added: the convolution over 3-D distances already carries light
 * to the other side of thin parts (ears, lips, eyelids).
 *
 * OUTPUT. rgba (width·height·4 floats, rows bottom-up, caller-owned): linear radiance
 * before tonemapping, A = 1 on the head ("skin"), 0 on background pixels. It excludes GLOW:
 * the renderer adds its glow (bright pass, blur, add) to the same linear image before
 * tonemapping and its linear read-back includes it; the reference has none (compare with
 * a glow-off render, or only where nothing exceeds the glow threshold). dm_ref_frame_display
 * makes the 8-bit image through the renderer's tonemap (shaders/tonemap.glsl).
 *
 * Determinism: every pixel and texel is computed independently, the BVH is built on one
 * thread: byte-identical output for any thread_count.
 */
#ifndef DM_REF_FRAME_H
#define DM_REF_FRAME_H

#include <stdbool.h>
#include <stdint.h>

#include "reference/dm_ref_surface.h"
#include "reference/dm_reference.h"
#include "pack/dm_pack.h"
#include "core/dm_result.h"
#include "core/dm_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_ref_frame_stats {
    int64_t skin_pixels;     /* pixels whose ray hit the head */
    int64_t refined_pixels;  /* of those, shaded again from refine_samples² rays */
    int64_t covered_texels;  /* atlas texels the mesh covers */
    double setup_ms;         /* surface, BVH, ρdt table */
    double atlas_ms;         /* CPU irradiance atlas */
    double reference_ms;     /* dm_reference_create (texel elements) */
    double rays_ms;          /* primary rays */
    double convolution_ms;   /* dm_reference_eval at the hits */
    double compose_ms;       /* per-pixel shading */
    double total_ms;
} dm_ref_frame_stats;

typedef struct dm_ref_frame_options {
    int width, height; /* 0: the scene's output size; [1, 16384] */
    int atlas_size;    /* CPU irradiance atlas, texels per side; 0 = DM_REF_FRAME_ATLAS_DEFAULT; [16, 8192] */
    int thread_count;  /* 0 = all cores */
    /* Anti-aliasing, per axis (1..8): the atlas texel is the mean irradiance over its area,
     * atlas_samples² points (0 = 4, reduced until atlas_size × it ≤ 8192); a skin pixel is
     * the mean of the surface terms (albedo, normal, specular) over pixel_samples² sub-pixel
     * rays that hit (0 = 3), D taken at each of them (see diffusion_at_centre). The renderer's mipmaps filter the
     * same detail; one point sample per pixel instead leaves ~10 % per-pixel noise against
     * it at 320×180 (the means agree to 0.5 %). */
    int atlas_samples, pixel_samples;
    /* false (default): D is taken at each sub-pixel ray's own hit, as the surface terms are
     * (issue #27); true: at the centre's hit only (cheaper by ~k², the behaviour before #27:
     * kept for the convergence table in docs/dermis-reference.md). */
    bool diffusion_at_centre;
    /* Adaptive: a skin pixel whose sub-pixel rays' mean deviates from its centre ray's value
     * by more than DM_REF_FRAME_REFINE_DEVIATION in a channel (eyelids, lips, nostrils, ears:
     * surfaces of another depth or facing in one pixel; terminators) is shaded again from
     * refine_samples² rays, D at each (0 = off; more than pixel_samples, at most 16). The
     * pixel_samples² rays decide; deterministic. */
    int refine_samples;
    /* quadrature of the convolution (cut, spacing, wide_texels); NULL = its defaults.
     * Its thread_count and progress are replaced by these options'. */
    const dm_reference_options *reference;
    /* what is convolved; NULL = the profile's Gaussians (dm_reference_kernel_from_profile),
     * else e.g. a dipole's dense representation (dm_reference_kernel_from_source) */
    const dm_reference_kernel *kernel;
    /* Called now and then from the calling thread: stage ("setup", "irradiance", "elements",
     * "rays", "convolution", "shading", "refine") and the fraction of that stage done. May be NULL. */
    void (*progress)(void *user, const char *stage, double fraction);
    void *progress_user;
    /* Optional outputs: stats (may be NULL); atlas (may be NULL) receives the irradiance
     * atlas, atlas_size²·4 floats, malloc'd (free it). */
    dm_ref_frame_stats *stats;
    float **atlas;
} dm_ref_frame_options;

/* The converged default atlas (docs/dermis-reference.md, Convergence: on the head at
 * 1280×720 the transport signal moves 8 % from 1024 to 2048 and 2.5 % from 2048 to 4096). */
#define DM_REF_FRAME_ATLAS_DEFAULT 4096

/* The deviation (|mean of a pixel's rays − its centre ray's value| over the mean, in any
 * channel) above which a pixel is refined. A regular k × k grid's error is about that
 * deviation / k² where the radiance is smooth in the pixel (the midpoint rule's h²/24 ∇²f
 * against the centre's h²/24 ∇²f · k²), and the deviation is large where it is not (depth
 * edges, folds): 0.2 % keeps 3² rays' error near 0.02 % of the value, a hundredth of the
 * 2 % signal threshold of the transport comparison (dm_ref_frame_compare.h). */
#define DM_REF_FRAME_REFINE_DEVIATION 0.002

/* The atlas samples per axis a run takes: atlas_samples (0 = 4), reduced until
 * atlas_size × it ≤ 8192 (4096: 2). */
int dm_ref_frame_atlas_samples(int atlas_size, int atlas_samples);

/* Renders the reference frame of `scene` (usually dm_pack_scene of pack; its camera,
 * lights, material, effects, environment) from pack's mesh, maps and environment into
 * rgba_out (width·height·4 floats for the size the options give). opt may be NULL.
 * Fails on a pack without a mesh, sizes out of range, a profile that cannot be
 * normalised (DM_ERR_RANGE), or memory. Always finite output. */
dm_result dm_ref_frame_render(const dm_pack *pack, const dm_scene *scene, const dm_ref_frame_options *opt,
                              float *rgba_out, dm_error *err);

/* The same from a surface description (dm_ref_surface.h; desc->scene gives the camera,
 * lights, effects and the default size): synthetic scenes and tests, no pack needed. */
dm_result dm_ref_frame_render_desc(const dm_ref_surface_desc *desc, const dm_ref_frame_options *opt,
                                   float *rgba_out, dm_error *err);

/* What each pixel's centre ray hits (the frame's stage 3: the same camera, clipping and
 * back-face culling) on the surface s (dm_ref_surface_create of the same description),
 * width·height targets, rows bottom-up, triangle −1 where the ray misses: a caller labels
 * the pixels (dm_ref_regions_classify) or reads the surface there. Deterministic. */
dm_result dm_ref_frame_hits(const dm_ref_surface *s, int width, int height, int thread_count,
                            dm_reference_target *out, dm_error *err);

/* The 8-bit display image of a linear frame, as the renderer makes it: with the tonemap
 * effect, c = max(rgb · 2^exposure, 0), Hable's filmic curve of 2c over that of the white
 * point 11.2, sRGB-encoded; without it, the sRGB encoding of rgb clamped to [0, 1].
 * Rounded to nearest; alpha 255 (the renderer's is opaque). rows bottom-up, out is
 * width·height·4 bytes. */
void dm_ref_frame_display(const dm_scene *scene, const float *rgba, int width, int height, uint8_t *out);

#ifdef __cplusplus
}
#endif
#endif
