/* dm_sh.h — order-2 real spherical harmonics (9 coefficients) and the irradiance they give.
 *
 * Basis: the standard real SH written literally in world coordinates (x, y, z) of a unit
 * direction d (Sloan's ordering, as in Ramamoorthi & Hanrahan 2001):
 *   k: 0 Y00 = 0.282095              1 Y1−1 = 0.488603 y       2 Y10 = 0.488603 z
 *      3 Y11 = 0.488603 x            4 Y2−2 = 1.092548 xy      5 Y2−1 = 1.092548 yz
 *      6 Y20 = 0.315392 (3z² − 1)    7 Y21 = 1.092548 xz       8 Y22 = 0.546274 (x² − y²)
 * (exact constants: 1/(2√π), √(3/4π), √(15/4π), √(5/16π), √(15/16π)). The basis is
 * orthonormal over the sphere whatever axis is "up"; dermis's world is Y up and its maps
 * follow core/dm_equirect.h.
 *
 * Stored coefficients are the radiance projection L_k = ∫ L(ω) Y_k(ω) dω (W·sr⁻¹·m⁻²·sr,
 * i.e. in the map's radiance units times sr). Irradiance on a surface of normal n follows
 * Ramamoorthi & Hanrahan's convolution with the clamped cosine:
 *   E(n) = Σ_k A_l(k) L_k Y_k(n),  A0 = π, A1 = 2π/3, A2 = π/4,
 * so a uniform environment of radiance L gives E = π L (L00 = 2√π L). Lambertian outgoing
 * radiance is albedo/π · E. The order-2 truncation of the clamped cosine is within 3 % of
 * the exact irradiance for smooth environments (R&H), not for a single sun-like texel.
 */
#ifndef DM_SH_H
#define DM_SH_H

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_SH9_COUNT = 9 };

#define DM_SH_A0 3.14159265358979323846  /* π */
#define DM_SH_A1 2.09439510239319549231  /* 2π/3 */
#define DM_SH_A2 0.785398163397448309616 /* π/4 */

/* The 9 basis values at unit direction d. */
void dm_sh9_basis(const double d[3], double y[DM_SH9_COUNT]);
/* Irradiance E(n) per channel (RGB) from radiance coefficients sh[k][c]; n unit. */
void dm_sh9_irradiance(const double sh[DM_SH9_COUNT][3], const double n[3], double e[3]);

#ifdef __cplusplus
}
#endif
#endif
