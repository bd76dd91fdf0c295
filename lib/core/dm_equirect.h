/* dm_equirect.h — the one direction convention of every equirectangular (latitude-longitude)
 * environment map in dermis, shared by the bakes and the renderer.
 *
 * World space is Y up, as the head's OBJ (which faces +Z). Texture coordinates follow the
 * image convention of the whole project: u in [0, 1] left to right, v in [0, 1] bottom-up
 * (memory row 0 is v ≈ 0; the top row of the file is v ≈ 1).
 *
 *   u → azimuth:  φ = 2π (u − 0.5)
 *   v → polar:    θ = π (1 − v)          (angle from +Y: v = 1 is straight up, v = 0 down)
 *   d = (sin θ sin φ,  cos θ,  −sin θ cos φ)
 *
 * So the image centre (0.5, 0.5) looks along −Z (behind the head, what a camera in front of
 * the face sees), u = 0.75 is +X, u = 0.25 is −X, and the left/right seam is +Z. Seen from
 * inside the sphere the image is not mirrored. The inverse, as a shader writes it:
 *   u = atan(d.x, −d.z) / 2π + 0.5,   v = 1 − acos(d.y) / π.
 *
 * Rotation: an environment rotated by α about +Y (right-handed) is L'(d) = L(R⁻¹ d); in
 * texture space it samples the source at u + α / 2π (α in radians), v unchanged. A feature
 * at −Z moves towards −X for α > 0.
 *
 * Texel (i, j) of a W × H map covers u in [i/W, (i+1)/W] and v in [j/H, (j+1)/H]; its exact
 * solid angle is (2π/W)(cos θ_top − cos θ_bottom): every texel of a row has the same, and a
 * whole map sums to 4π.
 */
#ifndef DM_EQUIRECT_H
#define DM_EQUIRECT_H

#ifdef __cplusplus
extern "C" {
#endif

/* Unit direction of texture coordinate (u, v); any u (it wraps), v clamped to [0, 1]. */
void dm_equirect_dir(double u, double v, double d[3]);
/* Texture coordinate of direction d (need not be unit length, must not be zero):
 * u in [0, 1), v in [0, 1]. */
void dm_equirect_uv(const double d[3], double *u, double *v);
/* Exact solid angle (sr) of one texel of row j (bottom-up, 0 ≤ j < height) of a
 * width × height map. */
double dm_equirect_texel_solid_angle(int j, int width, int height);

#ifdef __cplusplus
}
#endif
#endif
