/* dm_env_prefilter.h — specular prefiltering of an environment for the Beckmann lobe of
 * core/dm_brdf.h, the radiance half of the split sum.
 *
 * What a level holds. For reflection direction r and roughness m, with the split-sum
 * assumption N = V = R:
 *   P(r, m) = ∫ L(l) D(h) (r·l)⁺ dl / ∫ D(h) (r·l)⁺ dl,   h = (l + r)/|l + r|,
 * a weighted AVERAGE of radiance (weights sum to 1: a uniform environment L gives P = L).
 * D is dermis's Beckmann (∫ D (N·H) dω_h = π), so D(h)(n·h)/π is a pdf over half vectors
 * and D/4π the pdf of l = reflect(−r, h) when n = v = r. The renderer combines a level
 * with the env-BRDF table of dermis-bake-lut (bake/dm_lut.h, dm_lut_bake_directional:
 * F0·scale + bias = ∫ f_KS (N·L) dω) as
 *   specular radiance ≈ P(R, m) · (F0 · scale(N·V, m) + bias(N·V, m)) · rho_s,
 * interpolating P between the two levels whose m bracket the surface's m.
 *
 * How. Filtered importance sampling (Křivánek & Colbert 2008): `samples` half vectors
 * from the pdf above, placed by a deterministic Hammersley set (ξ1 = (i + 0.5)/N,
 * ξ2 = radical inverse of i in base 2), the same set for every texel; each sample reads
 * the source pyramid (bake/dm_envmap.h) trilinearly at the level whose texel matches its
 * share of the lobe, lod = ½ log2(Ω_sample / Ω_texel) + DM_ENV_LOD_BIAS with
 * Ω_sample = 4π / (N D), and is weighted by r·l (Karis's estimator: Σ L w / Σ w).
 * Deterministic: byte-identical for any thread count.
 *
 * Error. dm_env_prefilter_error compares a level, texel by texel on a spread subset,
 * against the definition above evaluated by exact quadrature over the source texels
 * (every texel, its exact solid angle, D at the texel centre), on the coarsest pyramid
 * level whose texel is at most m/16 rad high (level 0 when none is that fine).
 *
 * Resolution. A level of roughness m is dm_env_level_width(m, …) wide, the power of two
 * ≥ 4π/m (the reflected lobe's standard deviation, about √2·m rad, spans ≥ 2.8 texels),
 * clamped to [16, max_width] and to the source width; height = width / 2.
 */
#ifndef DM_ENV_PREFILTER_H
#define DM_ENV_PREFILTER_H

#include "bake/dm_envmap.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define DM_ENV_LOD_BIAS 0.0 /* measured: 0 beats Colbert's +1 (bench: 2-3x lower error at 256-1024 samples) */
#define DM_ENV_M_MIN 0.01
#define DM_ENV_M_MAX 2.0
enum { DM_ENV_SAMPLES_MAX = 65536 };

/* Width of the level for roughness m (see the header comment). */
int dm_env_level_width(double m, int max_width, int source_width);

/* Point i of an n-point Hammersley set in [0, 1)², as used here. */
void dm_env_hammersley(unsigned i, unsigned n, double xi[2]);

/* Prefilters `map` rotated by rotate_deg about +Y for roughness m in [DM_ENV_M_MIN,
 * DM_ENV_M_MAX] into out_rgb (width × width/2 texels, RGB interleaved, rows bottom-up,
 * caller-owned). samples in [1, DM_ENV_SAMPLES_MAX]; width even, ≥ 4. threads: 0 = all. */
dm_result dm_env_prefilter(const dm_envmap *map, double m, int samples, double rotate_deg, int width, int threads,
                           float *out_rgb, dm_error *err);

/* P(r, m) of the header comment by exact quadrature, for texture coordinate (u, v) of the
 * rotated map. Slow: one pass over a pyramid level. */
void dm_env_prefilter_reference(const dm_envmap *map, double m, double rotate_deg, double u, double v,
                                double rgb[3]);

typedef struct dm_env_error {
    int texels;     /* texels compared */
    double rms_rel; /* root mean square of the per-texel error */
    double max_rel; /* largest per-texel error; per texel: max over R, G, B of |P − P_ref|
                     * divided by the reference's largest channel */
    double worst_u, worst_v;
    double ms;
} dm_env_error;

/* Compares texel_count texels of a level (spread by a 2-D Hammersley set) with
 * dm_env_prefilter_reference. texel_count ≥ 1 (capped at the level's texel count). */
void dm_env_prefilter_error(const dm_envmap *map, double m, double rotate_deg, const float *level_rgb, int width,
                            int texel_count, int threads, dm_env_error *out);

#ifdef __cplusplus
}
#endif
#endif
