/* dm_pack_semantic.h — what the values of each pack entry may be: the ranges that make
 * physical sense, checked over every value of every entry (nothing sampled) as the last
 * step of dm_pack_open's verification (VERIFIED ON OPEN, pack/dm_pack.h). Every reader of a
 * pack (the renderer, the viewer, the reference, dermis-check) opens it through that one
 * verification, so they take or refuse the same packs; dermis-check adds only its slower
 * re-evaluations (LUT texels against the analytic functions, provenance).
 *
 * Entries are known by name (an environment copy "env<k>.x" as "env.x", dm_pack_needs.h).
 * A known name must have its row's kind and format (whether or not the scene needs it),
 * and its shape and values must be what the renderer takes:
 *   mesh.vertices  the dermis layout (dm_pack_mesh), ≥ 3 vertices; every position
 *                  |x|, |y|, |z| · mm_per_unit ≤ DM_PACK_POSITION_MAX_MM; unit normals and
 *                  tangents (|length − 1| ≤ DM_PACK_UNIT_TOLERANCE), tangent w = ±1.
 *   lut.rho_dt, lut.env_brdf  every value in [0, DM_PACK_DIRECTIONAL_MAX].
 *   stretch        1 level, one layer per Gaussian of the scene's profile; every float of
 *                  the blob (u and v of every texel of every layer) in
 *                  (0, DM_PACK_STRETCH_MAX_PER_MM].
 *   sss.kernel     taps × rows, odd taps in [3, DM_SSSS_MAX_TAPS], 1 to DM_SSSS_MAX_ROWS rows
 *                  with "t_range" (their sizes of pixel, mm), 1 row without (a pack made
 *                  before the rows: offsets in mm), 1 level, 1 layer, and what
 *                  dm_ssss_kernel_from_texels takes (the renderer's own reading).
 *   sss.preintegrated  1 level, 1 layer, height ≥ 2, "t_range" [0, κ_max] with κ_max in
 *                  (0, DM_PACK_CURVATURE_MAX_PER_MM]; every value in [0, DM_PACK_PREINT_MAX].
 *   env.sh         order 2 (9 RGB coefficients); |c| ≤ DM_PACK_SH_MAX, c₀₀ ≥ 0 per channel.
 *   env.specular   1 level, 1..DM_PACK_ENV_LEVELS_MAX layers, "layer_values" (one Beckmann
 *                  m per layer, strictly ascending, in [DM_PACK_ENV_M_MIN, DM_PACK_ENV_M_MAX]);
 *                  every value in [0, DM_PACK_RADIANCE_MAX].
 *   env.background 1 level, 1 layer; every value in [0, DM_PACK_RADIANCE_MAX].
 *   albedo, normal, specular, roughness, lut.beckmann, stretch.mask, sss.curvature
 *                  1 level, 1 layer (8-bit maps hold no absurd value; curvature: any finite
 *                  value, the renderer clamps it to its table's rows).
 *   profile, scene the profile's ranges are dm_profile_validate's (core/dm_profile.h),
 *                  checked when they are parsed.
 * Every other entry: the format checks only (finite floats, indices in range).
 * A refusal is DM_ERR_RANGE (DM_ERR_FORMAT for a shape), naming the file, the entry, where
 * (vertex, texel and layer, coefficient), the value and the range with its reason.
 */
#ifndef DM_PACK_SEMANTIC_H
#define DM_PACK_SEMANTIC_H

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

struct dm_pack;

/* Positions: 10 m from the origin in mm (x · mm_per_unit). A head is ~0.25 m, a whole body
 * 2 m; a bound in mm holds them at every mm_per_unit the scene allows (1e-6..1e6), and a
 * vertex beyond it leaves the rest of the mesh a dot in its own bounds (the shadow map and
 * the camera framing are fitted to them). */
#define DM_PACK_POSITION_MAX_MM 1e4
/* Unit vectors: the packer normalises in double and stores floats (error ~1e-7). */
#define DM_PACK_UNIT_TOLERANCE 1e-3
/* rho_dt = F0·scale + bias and the split-sum scale, bias: each at most π (reached as m → 0,
 * core/dm_brdf.h dm_ks_directional; F0 ≤ 1), + 1e-3 relative for quadrature and storage. */
#define DM_PACK_DIRECTIONAL_MAX (3.14159265358979 * 1.001)
/* Stretch, UV units per mm: above 1e6 the whole atlas would span a nanometre of skin; the
 * stretch baker counts a triangle beyond it as degenerate (bake/dm_stretch.h), so it never
 * writes one. Below: any value > 0 (a huge, flat chart). */
#define DM_PACK_STRETCH_MAX_PER_MM 1e6
/* The pre-integrated table holds averages of max(0, N·L) (bake/dm_preintegrated.h): [0, 1],
 * + 1e-3 for the quadrature. */
#define DM_PACK_PREINT_MAX 1.001
/* The table's last row: curvature of a sphere of 1 µm radius (the renderer's own limit). */
#define DM_PACK_CURVATURE_MAX_PER_MM 1e3
/* Environment radiance: what the environment loader takes (bake/dm_envmap.h; real suns reach
 * ~5e4 in relative HDR maps, 1.6e9 in absolute cd/m²), every prefiltered or resampled value
 * being a weighted mean of those. SH coefficients: |∫ L Y_lm| ≤ max L · ∫|Y_lm| ≤ max L · √(4π). */
#define DM_PACK_RADIANCE_MAX 1e18
#define DM_PACK_SH_MAX (DM_PACK_RADIANCE_MAX * 3.5449077018110318 * 1.001)
/* Beckmann m of prefiltered levels: the environment baker's range (bake/dm_env_prefilter.h). */
#define DM_PACK_ENV_M_MIN 0.01
#define DM_PACK_ENV_M_MAX 2.0
enum { DM_PACK_ENV_LEVELS_MAX = 6 };

/* Checks every entry of an open pack's entries as described above: its data pointers set,
 * its format checks passed and its scene parsed (dm_pack_open calls it last). */
dm_result dm_pack_check_values(const struct dm_pack *pack, dm_error *err);

/* Whether one stretch value is in (0, DM_PACK_STRETCH_MAX_PER_MM] (NaN is not): the one rule
 * for the pack entry and dermis-check's stretch EXR files. */
static inline int dm_pack_stretch_ok(float s)
{
    return s > 0.0f && s <= (float)DM_PACK_STRETCH_MAX_PER_MM;
}

#ifdef __cplusplus
}
#endif
#endif
