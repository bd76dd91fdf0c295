/* The curvature smoothing's scale, pinned by an analytic case (issue #31: the smoothing radius
 * could double with every test green).
 *
 * A height field z = A sin(kx) (k = 2π/λ) on a fine grid, mm units. Its mean curvature, with
 * the normal up (convex crests positive, bake/dm_curvature.h), is
 *   H(x) = −z''/(2 (1 + z'²)^{3/2}) = ½ A k² sin(kx) (1 + O((Ak)²)),
 * a sinusoid of amplitude ½ A k² to 0.1 % at A k = 0.05. Smoothing it with the baker's kernel
 * (a 2-D Gaussian of σ = smooth_mm over the vertices within 3σ, weighted by area: uniform on
 * this grid) multiplies that amplitude by
 *   f(σ) = ∫∫_{r<3σ} e^{−r²/2σ²} cos(kx) / ∫∫_{r<3σ} e^{−r²/2σ²}   (≈ e^{−k²σ²/2}),
 * computed here by quadrature over the disk. With kσ = 1.5 the factor is steep:
 * d ln f / d ln σ ≈ −(kσ)² = −2.25, so σ × 1.05 (or 0.95) moves the amplitude by ~11 %.
 *
 * Tolerances, derived: the baked smoothed amplitude over the unsmoothed one (the cotangent
 * Laplacian's own discretisation error, (kh)²/12 = 0.3 % at h = 0.125 mm, cancels) must equal
 * f(σ) within 1.5 %: the grid samples the Gaussian at σ/h = 8 (aliasing e^{−2π²(σ/h)²}: none),
 * the 3-D distances differ from the plane's by (Ak)² relative (0.25 %), the float positions
 * add 1e-6 mm noise, and the least-squares fit over ~20,000 interior vertices averages it; the
 * vertices within 3σ + 2h of the patch's border (whose smoothing reads the boundary rings) are
 * left out. The unsmoothed amplitude must equal ½ A k² within 2 % (the Laplacian's 0.3 % and
 * the slope's 0.1 %). The pack's radius, the profile's RMS radius, is pinned beside it. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "../common/grid_mesh.h"
#include "bake/dm_curvature.h"
#include "core/dm_math.h"
#include "core/dm_profile.h"

enum { CELLS = 160 };          /* per side */
#define HALF_MM 10.0           /* the patch is [−10, 10]² mm, h = 0.125 mm */
#define SIGMA_MM 1.0           /* smooth_mm */
#define K_PER_MM 1.5           /* k: λ = 4.19 mm, kσ = 1.5 */
#define AMP_MM (0.05 / K_PER_MM) /* A: slope A k = 0.05 */

static void bump_pos(double s, double t, double p[3])
{
    p[0] = HALF_MM * (2.0 * s - 1.0);
    p[1] = HALF_MM * (2.0 * t - 1.0);
    p[2] = AMP_MM * sin(K_PER_MM * p[0]);
}
static void bump_uv(double s, double t, double q[3])
{
    q[0] = s, q[1] = t, q[2] = 0.0;
}

/* The amplitude of the sinusoid of wavenumber k in h over the vertices at least `margin` mm
 * inside the patch: least squares h ≈ a sin(kx) + b cos(kx) + c, √(a² + b²). */
static double amplitude(const dm_mesh *m, const double *h, double margin)
{
    double N[3][3] = {{0}}, r[3] = {0};
    for (int v = 0; v < m->vertex_count; ++v) {
        double x = m->positions[3 * v], y = m->positions[3 * v + 1];
        if (fabs(x) > HALF_MM - margin || fabs(y) > HALF_MM - margin) continue;
        double f[3] = {sin(K_PER_MM * x), cos(K_PER_MM * x), 1.0};
        for (int i = 0; i < 3; ++i) {
            r[i] += f[i] * h[v];
            for (int j = 0; j < 3; ++j) N[i][j] += f[i] * f[j];
        }
    }
    /* 3x3 solve by Cramer's rule */
    double det = N[0][0] * (N[1][1] * N[2][2] - N[1][2] * N[2][1]) - N[0][1] * (N[1][0] * N[2][2] - N[1][2] * N[2][0]) +
                 N[0][2] * (N[1][0] * N[2][1] - N[1][1] * N[2][0]);
    double a = (r[0] * (N[1][1] * N[2][2] - N[1][2] * N[2][1]) - N[0][1] * (r[1] * N[2][2] - N[1][2] * r[2]) +
                N[0][2] * (r[1] * N[2][1] - N[1][1] * r[2])) / det;
    double b = (N[0][0] * (r[1] * N[2][2] - N[1][2] * r[2]) - r[0] * (N[1][0] * N[2][2] - N[1][2] * N[2][0]) +
                N[0][2] * (N[1][0] * r[2] - r[1] * N[2][0])) / det;
    return sqrt(a * a + b * b);
}

/* f(σ): the truncated Gaussian's attenuation of cos(kx), polar quadrature over r < 3σ
 * (midpoint rule, 2000 x 720: relative error < 1e-7). */
static double attenuation(double sigma, double k)
{
    const int NR = 2000, NT = 720;
    double num = 0.0, den = 0.0, R = 3.0 * sigma;
    for (int i = 0; i < NR; ++i) {
        double r = (i + 0.5) * R / NR, g = exp(-r * r / (2.0 * sigma * sigma)) * r;
        den += g * NT;
        for (int j = 0; j < NT; ++j) num += g * cos(k * r * cos((j + 0.5) * DM_2PI / NT));
    }
    return num / den;
}

Test(curvature_smoothing, sinusoid_attenuated_by_the_gaussian_of_sigma, .timeout = 120)
{
    dm_mesh m;
    grid_mesh(CELLS, CELLS, bump_pos, bump_uv, &m);
    double *h0 = malloc(sizeof *h0 * (size_t)m.vertex_count), *h1 = malloc(sizeof *h1 * (size_t)m.vertex_count);
    cr_assert(h0 && h1);
    dm_error err = {0};
    cr_assert_eq(dm_curvature_vertices(&m, 1.0, 0.0, 0, h0, NULL, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_curvature_vertices(&m, 1.0, SIGMA_MM, 0, h1, NULL, &err), DM_OK, "%s", err.detail);
    const double cell = 2.0 * HALF_MM / CELLS, margin = 3.0 * SIGMA_MM + 2.0 * cell;
    double a0 = amplitude(&m, h0, margin), a1 = amplitude(&m, h1, margin);
    double analytic = 0.5 * AMP_MM * K_PER_MM * K_PER_MM;
    double f = attenuation(SIGMA_MM, K_PER_MM);
    cr_expect(fabs(a0 / analytic - 1.0) < 0.02, "unsmoothed amplitude %.6g /mm, analytic ½Ak² = %.6g (%.2f %%)", a0,
              analytic, 100.0 * (a0 / analytic - 1.0));
    /* the factor's own check: close to e^{−k²σ²/2} (the 3σ cut keeps 98.9 % of the mass) */
    cr_expect(fabs(f / exp(-0.5 * K_PER_MM * K_PER_MM * SIGMA_MM * SIGMA_MM) - 1.0) < 0.02, "f = %.6f", f);
    double ratio = a1 / a0;
    cr_expect(fabs(ratio / f - 1.0) < 0.015,
              "smoothed / unsmoothed amplitude %.5f, the Gaussian of sigma %.2f mm gives %.5f (%.2f %%); "
              "sigma x 0.95 would give %.5f, x 1.05 %.5f",
              ratio, SIGMA_MM, f, 100.0 * (ratio / f - 1.0), attenuation(0.95 * SIGMA_MM, K_PER_MM),
              attenuation(1.05 * SIGMA_MM, K_PER_MM));
    /* the test separates ±5 %: both neighbours lie outside the tolerance */
    cr_expect(fabs(attenuation(0.95 * SIGMA_MM, K_PER_MM) / f - 1.0) > 0.05);
    cr_expect(fabs(attenuation(1.05 * SIGMA_MM, K_PER_MM) / f - 1.0) > 0.05);
    free(h0);
    free(h1);
    dm_mesh_free(&m);
}

/* The radius dermis-pack smooths with (packer/dm_pack_build_bake.c) is the profile's RMS radius
 * per axis, √(Σ_c Σ_k w_kc v_k / Σ_c Σ_k w_kc): from DESIGN.md's gems3-skin table here,
 * independently of lib/core's copy: 0.7014 mm; a 5 % change fails. */
Test(curvature_smoothing, pack_radius_is_the_profiles_rms_radius)
{
    static const double v[6] = {0.0064, 0.0484, 0.187, 0.567, 1.99, 7.41};
    static const double w[6][3] = {{0.233, 0.455, 0.649}, {0.100, 0.336, 0.344}, {0.118, 0.198, 0},
                                   {0.113, 0.007, 0.007}, {0.358, 0.004, 0},     {0.078, 0, 0}};
    double num = 0.0, den = 0.0;
    for (int k = 0; k < 6; ++k)
        for (int c = 0; c < 3; ++c) num += w[k][c] * v[k], den += w[k][c];
    double want = sqrt(num / den);
    dm_profile p;
    dm_profile_gems3_skin(&p);
    double got = dm_curvature_profile_scale_mm(&p);
    cr_expect(fabs(got / want - 1.0) < 1e-3, "profile scale %.6f mm, expected %.6f mm", got, want);
    cr_expect(fabs(want - 0.7014) < 5e-4, "%.6f", want);
}
