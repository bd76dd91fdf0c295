/* Physical diffusion profiles (core/dm_diffusion.h): dipole and multipole, their closed
 * forms against brute-force radial integrals, and every hard case. */
#include <criterion/criterion.h>
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/dm_diffusion.h"
#include "core/dm_math.h"

typedef struct chan {
    double sa, ss, eta, d;
    int pairs; /* 0: dipole */
} chan;

static double r_of(const chan *c, double r)
{
    return c->pairs ? dm_multipole(c->sa, c->ss, c->eta, c->d, c->pairs, r) : dm_dipole(c->sa, c->ss, c->eta, r);
}

/* ∫₀^∞ 2πr R(r) dr by brute force: Simpson in u = ln r over [1e-9, 1e5] mm with 200000
 * intervals (h ≈ 1.6e-4: the integrand r²R is smooth on that scale), plus the disc
 * [0, 1e-9] as π r² R(0). Independent of the closed forms under test. */
static double radial_total(const chan *c)
{
    const int n = 200000;
    double u0 = log(1e-9), u1 = log(1e5), h = (u1 - u0) / n, s = 0.0;
    for (int i = 0; i <= n; ++i) {
        double r = exp(u0 + i * h);
        double f = DM_2PI * r * r * r_of(c, r);
        s += (i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0) * f;
    }
    return s * h / 3.0 + DM_PI * 1e-18 * r_of(c, 0.0);
}

Test(diffusion, dipole_total_matches_closed_form)
{
    const char *names[] = {"skin1", "skin2", "marble"};
    for (int p = 0; p < 3; ++p) {
        dm_medium m;
        cr_assert_eq(dm_medium_preset(names[p], &m, NULL), DM_OK);
        for (int c = 0; c < 3; ++c) {
            chan ch = {m.sigma_a_per_mm[c], m.sigma_s_prime_per_mm[c], m.eta, 0, 0};
            double num = radial_total(&ch), ref = dm_dipole_total(ch.sa, ch.ss, ch.eta);
            /* Quadrature error ~1e-12; tails beyond 1e5 mm are below e^-1000. */
            cr_assert(fabs(num - ref) < 1e-8 * ref, "%s[%d]: integral %.12g vs closed form %.12g", names[p], c, num,
                      ref);
        }
    }
}

Test(diffusion, dipole_by_hand)
{
    /* σa = 0.1, σs′ = 0.9, η = 1.3 at r = 0.5, evaluated step by step from Jensen 2001. */
    double sa = 0.1, ss = 0.9, eta = 1.3, r = 0.5;
    double st = sa + ss, ap = ss / st, str = sqrt(3 * sa * st);
    double fdr = -1.44 / (eta * eta) + 0.71 / eta + 0.668 + 0.0636 * eta, A = (1 + fdr) / (1 - fdr);
    double zr = 1 / st, zv = zr + 4 * A / (3 * st);
    double dr = sqrt(r * r + zr * zr), dv = sqrt(r * r + zv * zv);
    double ref = ap / (4 * DM_PI) *
                 (zr * (str * dr + 1) * exp(-str * dr) / (dr * dr * dr) + zv * (str * dv + 1) * exp(-str * dv) / (dv * dv * dv));
    double got = dm_dipole(sa, ss, eta, r);
    cr_assert(fabs(got - ref) < 1e-14 * ref, "%.17g vs %.17g", got, ref);
}

Test(diffusion, r_zero_is_finite)
{
    dm_medium m;
    dm_medium_preset("skin1", &m, NULL);
    double rgb[3];
    dm_medium_eval(&m, 0.0, rgb);
    for (int c = 0; c < 3; ++c) cr_assert(isfinite(rgb[c]) && rgb[c] > 0.0, "R(0)[%d] = %g", c, rgb[c]);
    m.model = DM_MODEL_MULTIPOLE;
    m.thickness_mm = 0.2;
    dm_medium_eval(&m, 0.0, rgb);
    for (int c = 0; c < 3; ++c) cr_assert(isfinite(rgb[c]) && rgb[c] > 0.0, "multipole R(0)[%d] = %g", c, rgb[c]);
}

Test(diffusion, r_huge_underflows_to_zero_not_nan)
{
    const double rs[] = {1e4, 1e10, 1e103, 1e155, 1e200, 1e308, DBL_MAX, INFINITY};
    const double sas[] = {0.032, 0.0, 5.0};
    for (size_t i = 0; i < sizeof rs / sizeof rs[0]; ++i)
        for (int a = 0; a < 3; ++a) {
            double d = dm_dipole(sas[a], 0.74, 1.3, rs[i]);
            double mp = dm_multipole(sas[a], 0.74, 1.3, 0.5, 0, rs[i]);
            cr_assert(isfinite(d) && d >= 0.0, "dipole(σa %g, r %g) = %g", sas[a], rs[i], d);
            cr_assert(isfinite(mp), "multipole(σa %g, r %g) = %g", sas[a], rs[i], mp);
            if (rs[i] >= 1e103 || sas[a] > 0.0) cr_assert(d < 1e-300, "dipole(σa %g, r %g) = %g", sas[a], rs[i], d);
        }
}

Test(diffusion, sigma_a_zero_gives_white_and_an_inverse_cube_tail)
{
    double eta = 1.3, ss = 1.0;
    /* α′ = 1, σtr = 0: the closed form gives (1/2)(1 + 1)·1 = 1 exactly. */
    cr_assert_eq(dm_dipole_total(0.0, ss, eta), 1.0);
    double fdr = dm_fresnel_diffuse_reflectance(eta), A = (1 + fdr) / (1 - fdr);
    double zr = 1.0 / ss, zv = zr * (1 + 4 * A / 3);
    double r = 1e5 * zv;
    /* With σtr = 0 each source gives z/d³ → z/r³: r³R → (zr + zv)/4π, to (z/r)² ~ 1e-10. */
    double tail = r * r * r * dm_dipole(0.0, ss, eta, r), ref = (zr + zv) / (4 * DM_PI);
    cr_assert(fabs(tail - ref) < 1e-8 * ref, "%.12g vs %.12g", tail, ref);
    /* σa → 0 is continuous. */
    double a = dm_dipole(0.0, ss, eta, 0.7), b = dm_dipole(1e-12, ss, eta, 0.7);
    cr_assert(fabs(a - b) < 1e-9 * a, "%.17g vs %.17g", a, b);
    cr_assert(fabs(dm_dipole_total(1e-12, ss, eta) - 1.0) < 1e-5);
}

Test(diffusion, eta_one)
{
    /* Fdr(1) = −1.44 + 0.71 + 0.668 + 0.0636 = 0.0016: almost no internal reflection. */
    cr_assert(fabs(dm_fresnel_diffuse_reflectance(1.0) - 0.0016) < 1e-12);
    chan ch = {0.05, 1.2, 1.0, 0, 0};
    double num = radial_total(&ch), ref = dm_dipole_total(ch.sa, ch.ss, ch.eta);
    cr_assert(isfinite(ref) && ref > 0.0 && ref < 1.0);
    cr_assert(fabs(num - ref) < 1e-8 * ref, "%.12g vs %.12g", num, ref);
    /* A larger η traps more light inside, raising the boundary's A and Rd's spread. */
    cr_assert(dm_dipole(0.05, 1.2, 1.0, 0.0) > dm_dipole(0.05, 1.2, 1.4, 0.0));
}

Test(diffusion, thick_slab_is_the_dipole)
{
    dm_medium m;
    dm_medium_preset("skin1", &m, NULL);
    const double rs[] = {0.0, 0.1, 1.0, 10.0};
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 4; ++i) {
            double sa = m.sigma_a_per_mm[c], ss = m.sigma_s_prime_per_mm[c];
            double d = dm_dipole(sa, ss, m.eta, rs[i]);
            double mp = dm_multipole(sa, ss, m.eta, 1000.0, 0, rs[i]);
            /* The first image pair sits 2000 mm away: its terms are below e^-500. */
            cr_assert(fabs(mp - d) <= 1e-12 * d, "[%d] r %g: multipole %.17g vs dipole %.17g", c, rs[i], mp, d);
        }
    cr_assert(fabs(dm_multipole_total(0.032, 0.74, 1.3, 1000.0, 0) - dm_dipole_total(0.032, 0.74, 1.3)) < 1e-12);
}

Test(diffusion, thin_slab_reflects_less)
{
    double prev = 0.0;
    const double ds[] = {1e-4, 1e-3, 0.01, 0.1, 1.0, 10.0};
    for (int i = 0; i < 6; ++i) {
        double t = dm_multipole_total(0.032, 0.74, 1.3, ds[i], 0);
        double r0 = dm_multipole(0.032, 0.74, 1.3, ds[i], 0, 0.0);
        cr_assert(isfinite(t) && isfinite(r0), "d %g: total %g R(0) %g", ds[i], t, r0);
        cr_assert(t >= 0.0 && t > prev, "d %g: total %.12g not above the thinner slab's %.12g", ds[i], t, prev);
        cr_assert(t <= dm_dipole_total(0.032, 0.74, 1.3) + 1e-12);
        prev = t;
    }
    /* The model keeps its source at depth 1/σt′ (1.3 mm here) however thin the slab, so as
     * d → 0 it tends to a finite limit (0.193 for skin1 red), not to 0: diffusion is not
     * valid for d σt′ ≪ 1 (dm_diffusion.h says so). What must hold is a smooth limit. */
    double t4 = dm_multipole_total(0.032, 0.74, 1.3, 1e-4, 0), t3 = dm_multipole_total(0.032, 0.74, 1.3, 1e-3, 0);
    cr_assert(fabs(t3 - t4) < 1e-3 * t4, "d 1e-4: %.9g, d 1e-3: %.9g", t4, t3);
}

Test(diffusion, multipole_total_matches_integral)
{
    const double ds[] = {0.1, 0.5, 3.0};
    for (int i = 0; i < 3; ++i) {
        chan ch = {0.032, 0.74, 1.3, ds[i], DM_MULTIPOLE_PAIRS_DEFAULT};
        double num = radial_total(&ch), ref = dm_multipole_total(ch.sa, ch.ss, ch.eta, ch.d, ch.pairs);
        cr_assert(fabs(num - ref) < 1e-7 * ref, "d %g: integral %.12g vs term-wise %.12g", ds[i], num, ref);
    }
}

Test(diffusion, presets_are_jensen_2001)
{
    dm_medium m;
    cr_assert_eq(dm_medium_preset("skin1", &m, NULL), DM_OK);
    cr_assert(m.sigma_a_per_mm[0] == 0.032 && m.sigma_s_prime_per_mm[2] == 1.01 && m.eta == 1.3);
    cr_assert_eq(dm_medium_validate(&m, "skin1", NULL), DM_OK);
    dm_error err = {0};
    cr_assert_eq(dm_medium_preset("skin3", &m, &err), DM_ERR_INVALID_ARGUMENT);
    cr_assert(strstr(err.detail, "skin3") && strstr(err.detail, "skin2"), "%s", err.detail);
    for (const char *const *n = dm_medium_preset_names(); *n; ++n) {
        cr_assert_eq(dm_medium_preset(*n, &m, NULL), DM_OK);
        cr_assert_eq(dm_medium_validate(&m, *n, NULL), DM_OK);
    }
}

static dm_medium good(void)
{
    dm_medium m;
    dm_medium_preset("skin2", &m, NULL);
    return m;
}

static void refused(const dm_medium *m, const char *field)
{
    dm_error err = {0};
    dm_result r = dm_medium_validate(m, "test", &err);
    cr_assert(r == DM_ERR_RANGE || r == DM_ERR_NON_FINITE, "accepted (%s)", field);
    cr_assert(strstr(err.detail, field) != NULL, "message '%s' does not name %s", err.detail, field);
    cr_assert(strstr(err.detail, "expected") != NULL, "message '%s' does not say what was expected", err.detail);
}

Test(diffusion, refuses_negative_sigma_a)
{
    dm_medium m = good();
    m.sigma_a_per_mm[1] = -0.01;
    refused(&m, "sigma_a_per_mm[G]");
}

Test(diffusion, refuses_nan_sigma_s_prime)
{
    dm_medium m = good();
    m.sigma_s_prime_per_mm[0] = NAN;
    refused(&m, "sigma_s_prime_per_mm[R]");
}

Test(diffusion, refuses_zero_sigma_s_prime)
{
    dm_medium m = good();
    m.sigma_s_prime_per_mm[2] = 0.0;
    refused(&m, "sigma_s_prime_per_mm[B]");
}

Test(diffusion, refuses_infinite_sigma_a)
{
    dm_medium m = good();
    m.sigma_a_per_mm[0] = INFINITY;
    refused(&m, "sigma_a_per_mm[R]");
}

Test(diffusion, refuses_eta_below_one_and_nan)
{
    dm_medium m = good();
    m.eta = 0.9;
    refused(&m, "eta");
    m.eta = NAN;
    refused(&m, "eta");
}

Test(diffusion, refuses_bad_thickness)
{
    dm_medium m = good();
    m.model = DM_MODEL_MULTIPOLE;
    m.thickness_mm = 0.0;
    refused(&m, "thickness_mm");
    m.thickness_mm = -1.0;
    refused(&m, "thickness_mm");
    m.thickness_mm = NAN;
    refused(&m, "thickness_mm");
    m.thickness_mm = 1.0;
    m.pair_count = -3;
    dm_error err = {0};
    cr_assert_eq(dm_medium_validate(&m, "test", &err), DM_ERR_RANGE);
    cr_assert(strstr(err.detail, "pair_count"), "%s", err.detail);
}
