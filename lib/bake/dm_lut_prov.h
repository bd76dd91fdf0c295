/* dm_lut_prov.h — the provenance a baked LUT file carries, and the test that an
 * already-baked file is the table a consumer (dermis-pack) would bake itself.
 *
 * Parameters (all written, all compared):
 *   "table"    "beckmann" | "beckmann_exact" | "rho_dt" | "env_brdf" | "preintegrated"
 *   "width", "height"   texels
 *   "encoding" beckmann: "u8 0.5*D^0.1"; beckmann_exact: "f32 D"; rho_dt: "f32 rho_dt";
 *              env_brdf: "f32 scale,bias"
 *   "f0", "nodes"       directional tables only: Schlick F0, Gauss–Legendre nodes
 *   preintegrated: "encoding" "f32 R,G,B D(N.L, curvature)", "curvature_max_per_mm",
 *              "profile" (name) and "profile_hash" (the profile's content, dm_hash)
 * File forms: Beckmann = 8-bit one-channel PNG; rho_dt = EXR with one channel "rho_dt";
 * env_brdf = EXR with channels "scale" and "bias" (rho = F0·scale + bias). Rows bottom-up.
 */
#ifndef DM_LUT_PROV_H
#define DM_LUT_PROV_H

#include "core/dm_prov.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

void dm_lut_prov_beckmann(dm_provenance *p, const char *tool, int width, int height);
/* The float copy of the exact D (dermis-bake-lut --float): an EXR with one channel "D". */
void dm_lut_prov_beckmann_exact(dm_provenance *p, const char *tool, int width, int height);
/* table: "rho_dt" or "env_brdf". */
void dm_lut_prov_directional(dm_provenance *p, const char *tool, const char *table, int width, int height, double f0,
                             int nodes);

/* The pre-integrated diffuse table (bake/dm_preintegrated.h): EXR channels R, G, B. */
void dm_lut_prov_preintegrated(dm_provenance *p, const char *tool, int width, int height, double curvature_max_per_mm,
                               const char *profile_name, const char *profile_hash);

/* DM_OK when `have` (read from `file`) has the same dermis version and every parameter of
 * `want` with the same value; otherwise DM_ERR_MISMATCH naming the first difference. */
dm_result dm_lut_prov_match(const dm_provenance *have, const dm_provenance *want, const char *file, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
