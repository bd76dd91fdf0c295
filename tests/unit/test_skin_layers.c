/* Layered slabs in the frequency domain (bake/dm_skin_layers.h): one layer against the
 * single-medium dipole / multipole of core/dm_diffusion.h (closed forms at s = 0, a
 * brute-force Hankel transform of R(r) at s > 0), the stacking's limits, the fallback. */
#define _XOPEN_SOURCE 700 /* j0 */
#include <criterion/criterion.h>
#include <math.h>

#include "bake/dm_skin_layers.h"
#include "bake/dm_skin_mc.h"
#include "core/dm_diffusion.h"
#include "core/dm_math.h"

/* ∫ 2πr J0(s r) f(r) dr by Simpson in u = ln r over [1e-8, 300] mm, 400000 intervals
 * (h ≈ 8e-5: at r = 300 a step is 0.026 mm, 1/120 of J0's period at s = 10; the integrand
 * r²f is smooth on that scale), plus the disc below 1e-8 (negligible). Independent of the
 * closed-form pole transforms under test. */
static double hankel(double s, double sa, double ss, double eta, double d)
{
    const int n = 400000;
    double u0 = log(1e-8), h = (log(300.0) - u0) / n, acc = 0.0;
    for (int i = 0; i <= n; ++i) {
        double r = exp(u0 + i * h);
        double f = isinf(d) ? dm_dipole(sa, ss, eta, r) : dm_multipole(sa, ss, eta, d, 0, r);
        acc += (i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0) * DM_2PI * r * r * j0(s * r) * f;
    }
    return acc * h / 3.0;
}

Test(skin_layers, one_layer_is_the_dipole_and_multipole_at_s0)
{
    const double sa[3] = {0.01, 0.3, 2.0}, ss[3] = {1.0, 4.8, 9.2};
    for (int k = 0; k < 3; ++k) {
        dm_skin_layer semi = {sa[k], ss[k], INFINITY, 1.4, 1.0, DM_SKIN_EXIT_FLUX}, slab = {sa[k], ss[k], 2.0, 1.4, 1.4, DM_SKIN_EXIT_FLUX}; /* ≥ l */
        dm_skin_dual r;
        dm_skin_stack_transform(&semi, 1, 0, 0.0, &r, NULL);
        double ref = dm_dipole_total(sa[k], ss[k], 1.4);
        cr_assert(fabs(r.v - ref) < 1e-13, "dipole %d: %.15g vs %.15g", k, r.v, ref);
        dm_skin_stack_transform(&slab, 1, 0, 0.0, &r, NULL);
        ref = dm_multipole_total(sa[k], ss[k], 1.4, 2.0, 0);
        cr_assert(fabs(r.v - ref) < 1e-13, "multipole %d: %.15g vs %.15g", k, r.v, ref);
    }
}

/* The closed-form transform at s > 0 against brute force: 1e-6 relative (the quadrature's
 * own error is ~1e-9; the multipole's own truncation is the same on both sides). */
Test(skin_layers, one_layer_matches_hankel_transform_of_r)
{
    const double s[3] = {0.5, 2.0, 10.0};
    const double depth[2] = {INFINITY, 0.7};
    for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 3; ++k) {
            dm_skin_layer l = {0.05, 2.5, depth[j], 1.4, 1.4, DM_SKIN_EXIT_FLUX};
            dm_skin_dual r;
            dm_skin_stack_transform(&l, 1, 0, s[k], &r, NULL);
            double ref = hankel(s[k], 0.05, 2.5, 1.4, depth[j]);
            cr_assert(fabs(r.v - ref) < 1e-6 * fabs(ref), "d %g s %g: %.12g vs %.12g", depth[j], s[k], r.v, ref);
        }
}

/* ∂R̃/∂s² at 0 is −⟨r²⟩/4 · total: against ∫ 2πr r² R dr by brute force (Simpson in ln r to
 * 2000 mm; σtr = 0.6 mm⁻¹ leaves e^−1200 beyond), 1e-7 relative. */
Test(skin_layers, derivative_is_the_second_moment)
{
    double sa = 0.05, ss = 2.5, eta = 1.4;
    const int n = 400000;
    double u0 = log(1e-8), h = (log(2000.0) - u0) / n, m2 = 0.0;
    for (int i = 0; i <= n; ++i) {
        double r = exp(u0 + i * h);
        m2 += (i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0) * DM_2PI * r * r * r * r * dm_dipole(sa, ss, eta, r);
    }
    m2 *= h / 3.0;
    dm_skin_layer l = {sa, ss, INFINITY, eta, 1.0, DM_SKIN_EXIT_FLUX};
    dm_skin_dual r;
    dm_skin_stack_transform(&l, 1, 0, 0.0, &r, NULL);
    cr_assert(fabs(-4.0 * r.d - m2) < 1e-7 * m2, "%.12g vs %.12g", -4.0 * r.d, m2);
    /* the same through a stack: a finite difference in s² (step 1e-6 mm⁻²: error ~1e-6) */
    dm_skin_layer two[2] = {{2.0, 9.0, 0.25, 1.4, 1.0, DM_SKIN_EXIT_FLUX}, {0.1, 3.0, INFINITY, 1.0, 1.4, DM_SKIN_EXIT_FLUX}};
    dm_skin_dual a, b;
    dm_skin_stack_transform(two, 2, 0, 1e-3, &a, NULL);
    dm_skin_stack_transform(two, 2, 0, sqrt(1e-6 + 1e-6), &b, NULL);
    double fd = (b.v - a.v) / 1e-6;
    cr_assert(fabs(fd - 0.5 * (a.d + b.d)) < 1e-5 * fabs(fd), "fd %.9g vs %.9g", fd, a.d);
}

/* A top layer 40 transport lengths deep (σtr d = 40 at the least absorbing): nothing of the
 * bottom shows; the stack is the top layer alone, semi-infinite, to e^−40·2. */
Test(skin_layers, thick_top_layer_hides_the_bottom)
{
    double sa = 0.1, ss = 3.0, d = 40.0 / sqrt(3.0 * sa * (sa + ss));
    dm_skin_layer two[2] = {{sa, ss, d, 1.4, 1.0, DM_SKIN_EXIT_FLUX}, {0.01, 1.0, INFINITY, 1.0, 1.4, DM_SKIN_EXIT_FLUX}}, one = {sa, ss, INFINITY, 1.4, 1.0, DM_SKIN_EXIT_FLUX};
    for (double s = 0.0; s < 20.0; s = s * 3 + 0.1) {
        dm_skin_dual a, b;
        dm_skin_stack_transform(two, 2, 0, s, &a, NULL);
        dm_skin_stack_transform(&one, 1, 0, s, &b, NULL);
        cr_assert(fabs(a.v - b.v) < 1e-12 && fabs(a.d - b.d) < 1e-10 * fabs(b.d) + 1e-14, "s %g: %.15g vs %.15g", s,
                  a.v, b.v);
    }
}

/* One medium cut in two (index-matched, the top at least 2 transport lengths thick) stays
 * itself within 2 %: DJ2005's combination is approximate (each layer re-launches its light
 * at depth l, and Fdr(1) = 0.0016, not 0), so this is the approximation's size, measured. */
Test(skin_layers, one_medium_cut_in_two)
{
    double sa = 0.05, ss = 2.5, l = 1.0 / (sa + ss);
    double whole = dm_dipole_total(sa, ss, 1.4);
    for (double f = 2.0; f < 40.0; f *= 1.5) {
        dm_skin_layer two[2] = {{sa, ss, f * l, 1.4, 1.0, DM_SKIN_EXIT_FLUX}, {sa, ss, INFINITY, 1.0, 1.4, DM_SKIN_EXIT_FLUX}};
        dm_skin_dual r;
        dm_skin_stack_transform(two, 2, 0, 0.0, &r, NULL);
        cr_assert(fabs(r.v - whole) < 0.02 * whole, "d = %g l: %.5f vs %.5f", f, r.v, whole);
    }
}

/* Every response of a slab at least one transport length thick (the multipole alone from
 * 1.1 l, blended with the closed form over 1–1.1 l) is in [0, 1] at every frequency, the
 * transmittances fall with s (they spread), and R + T ≤ 1 at s = 0. */
Test(skin_layers, responses_bounded)
{
    const double sa[3] = {0.02, 0.5, 4.0};
    for (int k = 0; k < 3; ++k)
        for (double f = 1.0; f < 50.0; f *= 1.3) {
            dm_skin_layer l = {sa[k], 5.0, f / (sa[k] + 5.0), 1.4, 1.0, DM_SKIN_EXIT_FLUX};
            cr_assert(dm_skin_layer_diffusive(&l) == (f >= DM_SKIN_DEPTH_DIFFUSIVE));
            double prev_t = 2.0;
            for (double s = 0.0; s < 100.0; s = s * 2 + 0.05) {
                dm_skin_slab o;
                dm_skin_layer_transform(&l, 0, s, &o);
                double v[4] = {o.r.v, o.r_up.v, o.t.v, o.t_up.v};
                for (int j = 0; j < 4; ++j)
                    cr_assert(v[j] >= 0.0 && v[j] <= 1.0, "sa %g d %g l s %g: response %d = %g", sa[k], f, s, j, v[j]);
                if (s == 0.0) cr_assert(o.r.v + o.t.v <= 1.0);
                cr_assert(o.t.v <= prev_t + 1e-15);
                prev_t = o.t.v;
            }
        }
}

/* ∫₀¹ μ/(1+μ)(1 − e^(−τ(1+1/μ)))(1 − F(μ)) dμ by Simpson on 200000 intervals: the
 * independent reference of the closed form's Gauss–Legendre sum. */
static double single_scatter_ref(double albedo, double tau, double eta)
{
    const int n = 200000;
    double acc = 0.0;
    for (int i = 1; i <= n; ++i) { /* the integrand is 0 at μ = 0 */
        double mu = (double)i / n, f = mu / (1.0 + mu) * (isinf(tau) ? 1.0 : 1.0 - exp(-tau * (1.0 + 1.0 / mu)));
        acc += (i == n ? 1.0 : i % 2 ? 4.0 : 2.0) * f * (1.0 - dm_skin_mc_fresnel(eta, 1.0, mu));
    }
    return 0.5 * albedo * acc / (3.0 * n);
}

/* The single-scattering closed form: α′(1 − ln 2)/2 for a semi-infinite index-matched slab
 * (exact), τ(α′/2) for a very thin one (first order in τ: ∫ μ/(1+μ)·τ(1+1/μ) dμ = τ), and
 * Simpson's rule elsewhere (5e-4 relative: measured 1.3e-4 at worst; the Fresnel transmittance
 * rises as √(μ − μc) from the critical angle, which a 16-node Gauss sum follows only so far). */
Test(skin_layers, single_scatter_closed_form)
{
    cr_assert(fabs(dm_skin_single_scatter_reflectance(0.8, INFINITY, 1.0) - 0.4 * (1.0 - log(2.0))) < 1e-12);
    double thin = dm_skin_single_scatter_reflectance(0.6, 1e-6, 1.0);
    cr_assert(fabs(thin - 0.3e-6) < 1e-11, "%.12g", thin);
    const double tau[4] = {0.05, 0.5, 2.0, 20.0}, eta[2] = {1.0, 1.4};
    for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 4; ++k) {
            double r = dm_skin_single_scatter_reflectance(0.7, tau[k], eta[j]), ref = single_scatter_ref(0.7, tau[k], eta[j]);
            cr_assert(fabs(r - ref) < 5e-4 * ref, "τ %g η %g: %.8f vs %.8f", tau[k], eta[j], r, ref);
        }
}

/* The documented fallback: thinner than one transport length, or σa > 1.5 σs′ (α′ < 0.4):
 * the closed form alone. */
Test(skin_layers, closed_form_fallback)
{
    dm_skin_layer thin = {0.5, 9.0, 0.05, 1.4, 1.0, DM_SKIN_EXIT_FLUX}, dark = {20.0, 6.0, 0.25, 1.4, 1.0, DM_SKIN_EXIT_FLUX};
    dm_skin_layer at = {0.5, 9.0, DM_SKIN_DEPTH_DIFFUSIVE / 9.5, 1.4, 1.0, DM_SKIN_EXIT_FLUX};
    cr_assert(!dm_skin_layer_diffusive(&thin) && dm_skin_layer_diffusion_weight(&thin) == 0.0);
    cr_assert(!dm_skin_layer_diffusive(&dark) && dm_skin_layer_diffusion_weight(&dark) == 0.0);
    cr_assert(dm_skin_layer_diffusive(&at));
    dm_skin_slab o;
    dm_skin_layer_transform(&dark, 0, 3.0, &o);
    double a = 6.0 / 26.0, r = dm_skin_single_scatter_reflectance(a, 26.0 * 0.25, 1.4),
           r_up = dm_skin_single_scatter_reflectance(a, 26.0 * 0.25, 1.0);
    cr_assert(o.r.v == r && o.r_up.v == r_up && o.r.d == 0.0 && o.t.d == 0.0);
    cr_assert(fabs(o.t.v - fmax(0.0, exp(-5.0) - r)) < 1e-15 && fabs(o.t_up.v - fmax(0.0, exp(-10.0) - r_up)) < 1e-15);
    dm_skin_layer semi_dark = {20.0, 6.0, INFINITY, 1.4, 1.0, DM_SKIN_EXIT_FLUX};
    dm_skin_layer_transform(&semi_dark, 0, 0.0, &o);
    cr_assert(o.r.v == dm_skin_single_scatter_reflectance(a, INFINITY, 1.4) && o.t.v == 0.0);
    /* over a diffusive bottom: DJ2005's sum with the closed form's R, T */
    dm_skin_layer two[2] = {thin, {0.05, 2.5, INFINITY, 1.0, 1.4, DM_SKIN_EXIT_FLUX}};
    dm_skin_dual rs;
    dm_skin_stack_transform(two, 2, 0, 0.0, &rs, NULL);
    double r1 = dm_skin_single_scatter_reflectance(9.0 / 9.5, 9.5 * 0.05, 1.4);
    double r1u = dm_skin_single_scatter_reflectance(9.0 / 9.5, 9.5 * 0.05, 1.0);
    double t = exp(-0.025) - r1, tu = exp(-0.05) - r1u, r2 = dm_dipole_total(0.05, 2.5, 1.0);
    double want = r1 + t * r2 * tu / (1.0 - r1u * r2);
    cr_assert(fabs(rs.v - want) < 1e-14, "%.15g vs %.15g", rs.v, want);
}

/* The switch is continuous: across each ramp the weight goes 0 → 1 with no step, and the
 * responses of a slab swept through it (depth through 1–1.1 l; albedo through 0.4–0.5)
 * change by no more than 0.01 between neighbours 1/2000 of the sweep apart (the old step
 * switch jumped by 0.1–0.3 here). */
Test(skin_layers, switch_is_continuous)
{
    double prev[2][4] = {{-1}, {-1}};
    for (int i = 0; i <= 2000; ++i) {
        double x = (double)i / 2000;
        dm_skin_layer thick = {0.5, 9.0, (0.9 + 0.3 * x) / 9.5, 1.4, 1.0, DM_SKIN_EXIT_FLUX};           /* d: 0.9 → 1.2 l */
        double sa = 1.0 / (0.35 + 0.2 * x) * 6.0 - 6.0;                              /* α′: 0.35 → 0.55 */
        dm_skin_layer dark = {sa, 6.0, 0.25, 1.4, 1.0, DM_SKIN_EXIT_FLUX};
        const dm_skin_layer *ls[2] = {&thick, &dark};
        for (int k = 0; k < 2; ++k) {
            dm_skin_slab o;
            dm_skin_layer_transform(ls[k], 0, 0.0, &o);
            double v[4] = {o.r.v, o.r_up.v, o.t.v, o.t_up.v};
            for (int j = 0; j < 4; ++j) {
                cr_assert(v[j] >= 0.0 && v[j] <= 1.0, "sweep %d at %g: response %d = %g", k, x, j, v[j]);
                if (i) cr_assert(fabs(v[j] - prev[k][j]) < 0.01, "sweep %d at %g: response %d jumps %g → %g", k, x, j,
                                 prev[k][j], v[j]);
                prev[k][j] = v[j];
            }
        }
    }
}

/* The partial-current readout's coefficients (Kienle & Patterson 1997): C_φ = (1 − 2C₁)/4,
 * C_E = (1 − 3C₂)/2 from the Fresnel moments. A matched face (η = 1) lets out the plain
 * partial current φ/4 + E/2; at η 1.4 they give the moment boundary A = (1 + 3C₂)/(1 − 2C₁)
 * = 2.95 that docs/skin-model.md quotes for Haskell et al. 1994 (C_φ 0.1178, C_E 0.3056). */
Test(skin_layers, partial_current_coefficients)
{
    double c_phi, c_e;
    dm_skin_exit_coefficients(1.0, &c_phi, &c_e);
    cr_assert(c_phi == 0.25 && c_e == 0.5, "%.17g %.17g", c_phi, c_e);
    dm_skin_exit_coefficients(1.4, &c_phi, &c_e);
    double two_c1 = 1.0 - 4.0 * c_phi, three_c2 = 1.0 - 2.0 * c_e, a = (1.0 + three_c2) / (1.0 - two_c1);
    cr_assert(fabs(c_phi - 0.1178) < 5e-5 && fabs(c_e - 0.3056) < 5e-5, "%.6f %.6f", c_phi, c_e);
    cr_assert(fabs(a - 2.95) < 0.005, "A %.4f", a);
}
