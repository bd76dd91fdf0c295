/* dm_env_sh.h — projection of an equirectangular environment onto order-2 spherical
 * harmonics (core/dm_sh.h basis, core/dm_equirect.h directions).
 *
 * Exact for the map as a piecewise-constant function: each texel's radiance is constant
 * over its spherical rectangle, and every basis function is integrated over that rectangle
 * analytically (the basis is a sum of products f(θ)·g(φ), so each texel's integral is a
 * product of a row integral, sin θ included, and a column integral). A uniform map
 * therefore gives L00 = 2√π L and the other 8 coefficients 0 up to rounding, at any size.
 * Rotation about +Y is exact too: it only shifts the column intervals in φ.
 *
 * Numerics: everything in double. Each row is summed over its columns (at most 16384
 * terms: error below 16384 · 2⁻⁵³ ≈ 2e-12 of the sum of magnitudes), rows are summed with
 * Kahan compensation, so a 1e6 sun beside unit sky loses nothing that float output keeps.
 * Rows are processed in parallel and summed in a fixed order: results are bit-identical
 * for any thread count.
 */
#ifndef DM_ENV_SH_H
#define DM_ENV_SH_H

#include "bake/dm_envmap.h"
#include "core/dm_result.h"
#include "core/dm_sh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* sh[k][c] = ∫ L'(ω) Y_k(ω) dω for the map rotated by rotate_deg about +Y. threads: 0 =
 * all cores. Fails only for lack of memory. */
dm_result dm_env_project_sh9(const dm_envmap *map, double rotate_deg, int threads, double sh[DM_SH9_COUNT][3],
                             dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
