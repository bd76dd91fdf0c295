/* dm_ref_shade.h — CPU shading for the ground truth: the renderer's irradiance, specular and
 * environment terms evaluated exactly at points of a dm_ref_surface, and the irradiance
 * atlas that the exact convolution (dm_reference.h) diffuses.
 *
 * The same quantities as shaders/irradiance.glsl and shaders/final.glsl (+ common.glsl),
 * term by term, with three differences, all towards the truth:
 * - Shadows are hard shadows of the true geometry: a ray (dm_raycast_occluded) from the
 *   point lifted onto the smooth surface the vertex normals describe
 *   (dm_ref_surface_smooth_point: no terminator band where a facet turns from a light its
 *   normals still face), offset by s->eps_mm along the triangle's geometric front normal,
 *   towards the light (to the point light's position, or to infinity). The renderer
 *   filters a shadow map (3×3 PCF, normal offset): its edges are soft and shifted by up to
 *   a few shadow texels. Only lights with casts_shadow, with the shadows effect on, are
 *   tested, as in the renderer.
 * - ρdt and the split-sum factor come from the exact BRDF integral (dm_ref_surface.h), the
 *   Beckmann D from dm_beckmann in double, not from the 8-bit LUT.
 * - Maps are sampled bilinearly at level 0 (dm_ref_texture.h), no mipmaps.
 * The SH irradiance is dm_sh9_irradiance (the same order-2 Ramamoorthi–Hanrahan formula
 * the shader writes with rounded constants), clamped at 0 per channel, × env intensity / π.
 * Every result is finite for finite inputs (light intensities up to 1e6 and beyond, N·L or
 * N·H → 0, m → 0): see the tests.
 */
#ifndef DM_REF_SHADE_H
#define DM_REF_SHADE_H

#include <stdint.h>

#include "reference/dm_ref_surface.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 1 when light i reaches p (or casts no shadow), 0 when the geometry blocks it. */
double dm_ref_shade_visibility(const dm_ref_surface *s, const dm_ref_point *p, int light);

/* Unit direction from p towards light i (the renderer's dm_light_dir). */
void dm_ref_shade_light_dir(const dm_ref_surface *s, const dm_ref_point *p, int light, double L[3]);

/* The light arriving at p as the irradiance pass sums it, before albedo:
 *   Σ_i color_i · max(N·L, 0) · visibility · max(1 − ρs·ρdt(N·L, m), 0)   [energy term]
 *   + env_intensity · max(E_SH(rotated N), 0) / π                           [env_diffuse]
 * (a white sky of radiance L alone gives L). */
void dm_ref_shade_irradiance(const dm_ref_surface *s, const dm_ref_point *p, double e[3]);

/* The specular radiance towards the eye at p for view direction V (unit, towards the eye):
 * Σ_i color_i · visibility · (N·L) ρs max(D F / |h|², 0) over lights with N·L > 0, plus,
 * with env_specular, env_intensity · ρs · ρdt(N·V, m) · prefiltered(reflect(−V, N), m)
 * (the levels interpolated in m as final.glsl's env_specular does). 0 without specular. */
void dm_ref_shade_specular(const dm_ref_surface *s, const dm_ref_point *p, const double V[3], double spec[3]);

/* Environment radiance (background, or a prefiltered level) along direction d, turned by
 * the scene's rotation, as dm_equirect_uv in common.glsl: bilinear, u repeats. */
void dm_ref_shade_env_lookup(const dm_ref_surface *s, const dm_ref_texture *t, const double d[3], double rgb[3]);

typedef struct dm_ref_atlas_stats {
    int64_t covered_texels;
    double ms;
} dm_ref_atlas_stats;

/* The irradiance atlas: for every texel of size × size whose centre a triangle covers
 * (dm_uv_raster), the point at that centre (barycentrics from the UVs), and
 *   rgb = dm_ref_shade_irradiance × albedo^mix, alpha = 1;
 * rgb = alpha = 0 elsewhere (the renderer's irradiance target, cleared to 0). Rows
 * bottom-up; rgba is size·size·4 floats, caller-owned. size in [1, DM_UV_RASTER_SIZE_MAX];
 * thread_count 0 = all cores; byte-identical for any thread count. stats may be NULL.
 * progress (may be NULL) is called from the calling thread with the fraction done. */
dm_result dm_ref_shade_atlas(const dm_ref_surface *s, int size, int thread_count, float *rgba,
                             dm_ref_atlas_stats *stats, void (*progress)(void *user, double fraction),
                             void *progress_user, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
