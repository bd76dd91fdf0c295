/* The physical skin as a profile (bake/dm_skin_profile.h, bake/dm_skin_optics.h): the
 * parameter check, the exemplars against the NIST forearm cohort, the RMS radii against
 * GPU Gems 3, the fit, the hard cases and a sweep, and a pin on every parameter. */
#define _XOPEN_SOURCE 700 /* j0 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bake/dm_skin_layers.h"
#include "bake/dm_skin_mc.h"
#include "bake/dm_skin_profile.h"
#include "core/dm_math.h"

static dm_skin_params preset(const char *name)
{
    dm_skin_params p;
    cr_assert_eq(dm_skin_preset(name, &p, NULL), DM_OK);
    return p;
}

static double total_at(const dm_skin_params *p, double nm)
{
    dm_skin_dual r;
    dm_skin_reflectance_at(p, dm_skin_data_index(nm), 0, 0.0, &r, NULL);
    return r.v;
}

/* ---- the parameter check ---- */

static void refused(dm_skin_params p, const char *field, dm_result code)
{
    dm_error err = {0};
    cr_assert_eq(dm_skin_params_validate(&p, "skin", &err), code, "%s: %s", field, err.detail);
    cr_assert(strstr(err.detail, field) && strstr(err.detail, "expected"), "message '%s' should name %s", err.detail,
              field);
    dm_profile prof;
    cr_assert_eq(dm_skin_profile_fit(&p, NULL, "x", &prof, NULL, &err), code);
}

Test(skin_profile, out_of_range_refused_by_name)
{
    dm_skin_params d = dm_skin_params_default(), p;
    cr_assert_eq(dm_skin_params_validate(&d, "skin", NULL), DM_OK);
    p = d, p.melanin_fraction = 0.51, refused(p, "melanin_fraction", DM_ERR_RANGE);
    p = d, p.melanin_fraction = -0.01, refused(p, "melanin_fraction", DM_ERR_RANGE);
    p = d, p.eumelanin_blend = 1.1, refused(p, "eumelanin_blend", DM_ERR_RANGE);
    p = d, p.blood_fraction = 0.11, refused(p, "blood_fraction", DM_ERR_RANGE);
    p = d, p.blood_fraction = NAN, refused(p, "blood_fraction", DM_ERR_NON_FINITE);
    p = d, p.oxygenation = -0.1, refused(p, "oxygenation", DM_ERR_RANGE);
    p = d, p.epidermis_mm = 0.0, refused(p, "epidermis_mm", DM_ERR_RANGE);
    p = d, p.epidermis_mm = INFINITY, refused(p, "epidermis_mm", DM_ERR_NON_FINITE);
    p = d, p.dermis_mm = 0.05, refused(p, "dermis_mm", DM_ERR_RANGE);
    p = d, p.eta = 0.9, refused(p, "eta", DM_ERR_RANGE);
    dm_error err = {0};
    cr_assert_eq(dm_skin_preset("martian", &p, &err), DM_ERR_INVALID_ARGUMENT);
    cr_assert(strstr(err.detail, "martian") && strstr(err.detail, "caucasian"));
    dm_skin_profile_options opt = {.gaussian_count = 2, .variance_mm2 = {1.0, 0.5}};
    dm_profile prof;
    cr_assert_eq(dm_skin_profile_fit(&d, &opt, "x", &prof, NULL, &err), DM_ERR_RANGE);
    cr_assert(strstr(err.detail, "variance_mm2[1]"), "%s", err.detail);
}

/* ---- the NIST forearm cohort (100 subjects, SKIN-MODEL.md): 5 %, median, 95 % ---- */

static const double nist_nm[3] = {450, 550, 650}; /* the cohort's rows are 451, 550, 652 nm */
static const double nist_lo[3] = {0.116, 0.190, 0.386}, nist_med[3] = {0.269, 0.327, 0.577},
                    nist_hi[3] = {0.325, 0.391, 0.658};

/* The light exemplar (DJ2006's Caucasian, Cm 0.005) is inside the bands at 550 and 650 nm,
 * above the median at 550 (light near the top); at 450 nm it is brighter than the 95th
 * percentile, by 0.03 (measured 0.355): the model's known excess, held here so a change
 * shows, and reported in docs/skin-model.md. */
Test(skin_profile, caucasian_against_nist)
{
    dm_skin_params p = preset("caucasian");
    for (int k = 0; k < 3; ++k) printf("caucasian %g nm: %.3f (NIST %.3f..%.3f)\n", nist_nm[k], total_at(&p, nist_nm[k]), nist_lo[k], nist_hi[k]);
    for (int k = 1; k < 3; ++k) {
        double r = total_at(&p, nist_nm[k]);
        cr_assert(r >= nist_lo[k] && r <= nist_hi[k], "%g nm: %.3f", nist_nm[k], r);
    }
    cr_assert(total_at(&p, 550) > nist_med[1]);
    double r450 = total_at(&p, 450);
    cr_assert(r450 > nist_hi[0] && r450 < nist_hi[0] + 0.05, "450 nm: %.3f", r450);
}

/* Jacques' light adults (melanosome fraction 1.3–6.3 %): at Cm 0.013 (and blood 0.2–2 %)
 * all three wavelengths land inside the bands. */
Test(skin_profile, light_skin_inside_nist_bands)
{
    const double ch[3] = {0.002, 0.005, 0.02};
    for (int j = 0; j < 3; ++j) {
        dm_skin_params p = dm_skin_params_default();
        p.melanin_fraction = 0.013, p.blood_fraction = ch[j];
        for (int k = 0; k < 3; ++k) {
            double r = total_at(&p, nist_nm[k]);
            cr_assert(r >= nist_lo[k] && r <= nist_hi[k], "Ch %g, %g nm: %.3f", ch[j], nist_nm[k], r);
        }
    }
}

/* The darker exemplars are darker at every wavelength (Caucasian > Asian > African). Not
 * held to the cohort: DJ2006's melanin spread evenly through a 0.25 mm epidermis absorbs
 * more than the cohort's darkest skins (measured: Asian 0.050 / 0.099 / 0.169, African
 * 0.011 / 0.014 / 0.018 at 450 / 550 / 650 nm, under the 5th percentiles 0.116 / 0.190 /
 * 0.386). The Monte Carlo of the same layers agrees that they are that dark (Asian 0.03 /
 * 0.05 / 0.12, African 0.006 / 0.007 / 0.012 at g 0.8): it is the parameters, not the
 * diffusion (docs/skin-model.md). Printed here so the numbers show. */
Test(skin_profile, darker_exemplars_are_darker)
{
    dm_skin_params c = preset("caucasian"), a = preset("asian"), f = preset("african");
    for (int k = 0; k < 3; ++k) {
        double rc = total_at(&c, nist_nm[k]), ra = total_at(&a, nist_nm[k]), rf = total_at(&f, nist_nm[k]);
        printf("%g nm: asian %.3f african %.4f (NIST 5 %% %.3f)\n", nist_nm[k], ra, rf, nist_lo[k]);
        cr_assert(rc > ra && ra >= rf && rf >= 0, "%g nm: %.3f %.3f %.4f", nist_nm[k], rc, ra, rf);
    }
    /* today's value, pinned so that a change to the model or the preset shows */
    cr_assert(fabs(total_at(&a, 650) - 0.169) < 0.02, "asian at 650 nm: %.3f", total_at(&a, 650));
}

/* ---- the switch to the closed form where diffusion fails ---- */

/* Melanin swept over [0.01, 0.5] in steps of 0.0005 at every wavelength, for both melanin
 * types: no step of the total larger than 0.01. The largest step is the physics' own
 * slope where melanin starts to tell (measured 0.0058, at Cm 0.01); the old switch jumped
 * by 0.074 (Cm 0.10 → 0.12 at 450 nm took the total from 0.075 to 0). */
Test(skin_profile, melanin_sweep_is_continuous)
{
    const double beta[2] = {0.0, 0.7};
    double worst = 0.0;
    for (int b = 0; b < 2; ++b)
        for (int l = 0; l < DM_SKIN_LAMBDA_COUNT; ++l) {
            dm_skin_params p = dm_skin_params_default();
            p.eumelanin_blend = beta[b];
            double prev = -1.0;
            for (int i = 20; i <= 1000; ++i) {
                p.melanin_fraction = i * 0.0005;
                dm_skin_dual r;
                dm_skin_reflectance_at(&p, l, 0, 0.0, &r, NULL);
                cr_assert(isfinite(r.v) && r.v >= 0.0);
                if (prev >= 0.0) {
                    worst = fmax(worst, fabs(r.v - prev));
                    cr_assert(fabs(r.v - prev) < 0.01, "βm %g row %d Cm %g: %.4f → %.4f", beta[b], l,
                              p.melanin_fraction, prev, r.v);
                }
                prev = r.v;
            }
        }
    printf("melanin sweep: largest step %.4f\n", worst);
}

/* ---- the profile ---- */

/* GPU Gems 3's RMS radii 1.66 / 0.37 / 0.22 mm were fitted to another skin (DJ2005's
 * three-layer model with other parameters): within a factor of 2 of each, red > green >
 * blue. Measured: 1.47 / 0.63 / 0.26 mm. */
Test(skin_profile, caucasian_rms_radius_vs_gems3)
{
    dm_skin_params p = preset("caucasian");
    dm_profile prof;
    dm_skin_report rep;
    cr_assert_eq(dm_skin_profile_fit(&p, NULL, "caucasian", &prof, &rep, NULL), DM_OK);
    const double gems[3] = {1.66, 0.37, 0.22};
    for (int c = 0; c < 3; ++c) {
        printf("RMS radius %c: %.3f mm (GPU Gems 3 %.2f, ratio %.2f)\n", "RGB"[c], rep.rms_radius_mm[c], gems[c],
               rep.rms_radius_mm[c] / gems[c]);
        cr_assert(rep.rms_radius_mm[c] > gems[c] / 2 && rep.rms_radius_mm[c] < gems[c] * 2);
    }
    cr_assert(rep.rms_radius_mm[0] > rep.rms_radius_mm[1] && rep.rms_radius_mm[1] > rep.rms_radius_mm[2]);
}

/* The six GPU Gems variances fit the Caucasian profile to 8 / 7 / 12 % (relative L2, as
 * dm_profile_fit measures): held under 15 %; the fit's weight sums keep each channel's total
 * within 0.01; the profile passes dm_profile_validate; the dense representation is exact
 * to 1e-5 and integrates (by brute force in r) to the colorimetric totals. */
Test(skin_profile, caucasian_fit)
{
    dm_skin_params p = preset("caucasian");
    dm_profile prof;
    dm_skin_report rep;
    cr_assert_eq(dm_skin_profile_fit(&p, NULL, "caucasian", &prof, &rep, NULL), DM_OK);
    cr_assert_eq(dm_profile_validate(&prof, "caucasian", NULL), DM_OK);
    cr_assert_eq(rep.epidermis_invalid_count + rep.dermis_invalid_count, 0);
    for (int c = 0; c < 3; ++c) {
        printf("channel %c: total %.4f, fit total %.4f, fit error %.4f\n", "RGB"[c], rep.total_rgb[c],
               rep.fit_total_rgb[c], rep.fit_error_relative[c]);
        cr_assert(rep.fit_error_relative[c] < 0.15);
        cr_assert(fabs(rep.fit_total_rgb[c] - rep.total_rgb[c]) < 0.01);
    }
    dm_skin_dense d;
    cr_assert_eq(dm_skin_dense_profile(&p, 0, &d, NULL), DM_OK);
    cr_assert(d.error_relative_max < 1e-5, "%g", d.error_relative_max);
    double tot[3] = {0, 0, 0};
    const double h = 1e-3; /* midpoint rule to 60 mm: the widest Gaussian (σ 16 mm) holds e^−7 beyond */
    for (int i = 0; i < 60000; ++i) {
        double r = (i + 0.5) * h, v[3];
        dm_skin_dense_eval(&d, r, v);
        for (int c = 0; c < 3; ++c) tot[c] += DM_2PI * r * v[c] * h;
    }
    for (int c = 0; c < 3; ++c) cr_assert(fabs(tot[c] - rep.total_rgb[c]) < 1e-3, "%c %.5f vs %.5f", "RGB"[c], tot[c], rep.total_rgb[c]);
}

/* ---- hard cases and a sweep ---- */

static void sane(const dm_skin_params *p, const char *what, dm_skin_report *rep)
{
    dm_profile prof;
    dm_error err = {0};
    cr_assert_eq(dm_skin_profile_fit(p, NULL, what, &prof, rep, &err), DM_OK, "%s: %s", what, err.detail);
    cr_assert_eq(dm_profile_validate(&prof, what, &err), DM_OK, "%s: %s", what, err.detail);
    for (int k = 0; k < prof.count; ++k)
        for (int c = 0; c < 3; ++c) cr_assert(isfinite(prof.weight[k][c]) && prof.weight[k][c] >= 0.0, "%s", what);
    for (int c = 0; c < 3; ++c)
        cr_assert(isfinite(rep->total_rgb[c]) && isfinite(rep->rms_radius_mm[c]) && isfinite(rep->fit_error_relative[c]),
                  "%s", what);
    for (int l = 0; l < DM_SKIN_LAMBDA_COUNT; ++l)
        cr_assert(rep->total_spectral[l] >= 0.0 && rep->total_spectral[l] <= 1.0, "%s: λ row %d: %g", what, l,
                  rep->total_spectral[l]);
}

Test(skin_profile, hard_cases)
{
    dm_skin_report rep;
    dm_skin_params p = dm_skin_params_default();
    p.melanin_fraction = 0.0;
    sane(&p, "no melanin", &rep);
    cr_assert_eq(rep.epidermis_invalid_count, 0);
    p = dm_skin_params_default(), p.melanin_fraction = 0.5;
    sane(&p, "melanin 0.5", &rep);
    /* a dark epidermis fails diffusion at short wavelengths: expected, counted, reported */
    printf("melanin 0.5: epidermis falls back at %d of %d wavelengths\n", rep.epidermis_invalid_count,
           DM_SKIN_LAMBDA_COUNT);
    cr_assert(rep.epidermis_invalid_count > 0 && (rep.invalid[0] & DM_SKIN_INVALID_EPIDERMIS));
    p = dm_skin_params_default(), p.blood_fraction = 0.0;
    sane(&p, "no blood", &rep);
    double bloodless = rep.total_rgb[0];
    p.blood_fraction = 0.001;
    sane(&p, "blood 0.001", &rep);
    cr_assert(rep.total_rgb[0] < bloodless);
    p = dm_skin_params_default(), p.epidermis_mm = 0.01; /* under one transport length (≥ 0.1 mm) everywhere */
    sane(&p, "epidermis 0.01 mm", &rep);
    cr_assert_eq(rep.epidermis_invalid_count, DM_SKIN_LAMBDA_COUNT);
    p = dm_skin_params_default(), p.blood_fraction = 0.1;
    sane(&p, "blood 0.1", &rep);
    cr_assert(rep.dermis_invalid_count > 0, "blood-rich dermis in the Soret band");
}

Test(skin_profile, sweep_whole_range, .timeout = 120)
{
    const double cm[3] = {0.0, 0.2, 0.5}, beta[2] = {0.0, 1.0}, ch[3] = {0.0, 0.01, 0.1}, gam[2] = {0.0, 1.0};
    const double epi[3] = {0.001, 0.25, 2.0}, der[2] = {0.0, 0.1};
    int count = 0;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 3; ++c)
                for (int g = 0; g < 2; ++g)
                    for (int e = 0; e < 3; ++e)
                        for (int d = 0; d < 2; ++d) {
                            if ((b + g + d) % 2) continue; /* half the grid: each pair of levels still meets */
                            dm_skin_params p = {cm[a], beta[b], ch[c], gam[g], epi[e], der[d], 1.4};
                            char what[128];
                            snprintf(what, sizeof what, "Cm %g βm %g Ch %g γ %g epi %g dermis %g", cm[a], beta[b],
                                     ch[c], gam[g], epi[e], der[d]);
                            dm_skin_report rep;
                            sane(&p, what, &rep);
                            ++count;
                        }
    cr_assert_eq(count, 108);
}

/* ---- every parameter pinned ----
 * A point where every parameter matters (dermis finite, all chromophores present); the
 * totals at 450/550/650 nm and the red RMS radius as this code computed them (a regression
 * pin, 1e-6 relative: the code is deterministic). Each parameter changed by 5 % moves one of
 * them by far more than that, so a change in any law or parameter handling fails here. */
static const dm_skin_params pin_point = {0.03, 0.6, 0.02, 0.7, 0.3, 1.5, 1.4};

static void pin_values(const dm_skin_params *p, double v[4])
{
    for (int k = 0; k < 3; ++k) v[k] = total_at(p, nist_nm[k]);
    dm_profile prof;
    dm_skin_report rep;
    cr_assert_eq(dm_skin_profile_fit(p, NULL, "pin", &prof, &rep, NULL), DM_OK);
    v[3] = rep.rms_radius_mm[0];
}

static int differs(const double a[4], const double b[4])
{
    for (int k = 0; k < 4; ++k)
        if (fabs(a[k] - b[k]) > 1e-6 * fabs(b[k])) return 1;
    return 0;
}

Test(skin_profile, every_parameter_pinned)
{
    const double want[4] = {0.17338332, 0.209353133, 0.295271512, 0.723295197};
    double v[4];
    pin_values(&pin_point, v);
    printf("pin: %.9g %.9g %.9g %.9g\n", v[0], v[1], v[2], v[3]);
    cr_assert(!differs(v, want), "pinned values moved: %.9g %.9g %.9g %.9g", v[0], v[1], v[2], v[3]);
    for (int f = 0; f < 7; ++f) {
        dm_skin_params p = pin_point;
        double *field[7] = {&p.melanin_fraction, &p.eumelanin_blend, &p.blood_fraction, &p.oxygenation,
                            &p.epidermis_mm,     &p.dermis_mm,       &p.eta};
        *field[f] *= 1.05;
        double w[4];
        pin_values(&p, w);
        cr_assert(differs(w, want), "parameter %d changed by 5 %% and the pin did not notice", f);
    }
}

/* ---- against the Monte Carlo (bake/dm_skin_mc.h) ----
 * The Caucasian exemplar's two layers as an MCML-style stack (n 1.4 both, air above,
 * Henyey–Greenstein g 0.8 with μs = σs′/(1 − g), semi-infinite dermis), 2·10⁴ photons
 * (SE ≈ 0.7 %). Diffusion theory with DJ2005's layering overestimates it: measured +9.8 %,
 * +4.6 %, +4.5 % at 450/550/650 nm. Of that, 2.8 points are normalisation (the MC's Rd is per
 * incident power, the model's per entering power, 1 − Rsp = 0.972), and most of the rest is
 * the flux-only dipole at the dermis' albedo (0.94 at 450 nm): the semi-infinite dermis alone
 * is +9 / +6 / −1 % like for like (docs/skin-model.md, "Diffusion against the Monte Carlo"). Held
 * at what is measured, with 4 SE of room: the 2 % the issue asks for is not met
 * (docs/skin-model.md). */
Test(skin_profile, caucasian_against_monte_carlo, .timeout = 60)
{
    dm_skin_params p = preset("caucasian");
    const double high[3] = {0.13, 0.075, 0.075};
    for (int k = 0; k < 3; ++k) {
        int li = dm_skin_data_index(nist_nm[k]);
        dm_skin_layer L[2];
        dm_skin_layers_at(&p, li, L);
        const double g = 0.8;
        dm_skin_mc_layer m[2];
        for (int j = 0; j < 2; ++j)
            m[j] = (dm_skin_mc_layer){1.4, L[j].sigma_a, L[j].sigma_s_prime / (1.0 - g), g, L[j].thickness_mm};
        dm_skin_mc_desc d = {.layers = m, .layer_count = 2, .photon_count = 20000, .seed = 30, .thread_count = 1};
        dm_skin_mc_result res = {0};
        dm_error err = {0};
        cr_assert_eq(dm_skin_mc_run(&d, &res, &err), DM_OK, "%s", err.detail);
        double model = total_at(&p, nist_nm[k]), rel = model / res.diffuse_reflectance - 1.0;
        double se = res.diffuse_reflectance_se / res.diffuse_reflectance;
        printf("%g nm: model %.4f, Monte Carlo %.4f ± %.4f (%+.1f %%)\n", nist_nm[k], model, res.diffuse_reflectance,
               res.diffuse_reflectance_se, 100.0 * rel);
        cr_assert(rel > -4.0 * se && rel < high[k] + 4.0 * se, "%g nm: %+.3f", nist_nm[k], rel);
    }
}

/* The darker exemplars' shortfall against the cohort is not diffusion's: the Monte Carlo of
 * the same layers (as above, 10⁴ photons) is below the NIST 5th percentile at 450/550/650 nm
 * too (measured Asian 0.028 / 0.054 / 0.117, African 0.006 / 0.007 / 0.012 against 0.116 /
 * 0.190 / 0.386; SE < 0.002), and below the layered model (whose closed form and diffusion
 * both overestimate a strongly absorbing epidermis). docs/skin-model.md, "Measured". */
Test(skin_profile, dark_exemplars_below_the_cohort_in_the_monte_carlo_too, .timeout = 60)
{
    const char *names[2] = {"asian", "african"};
    for (int e = 0; e < 2; ++e) {
        dm_skin_params p = preset(names[e]);
        for (int k = 0; k < 3; ++k) {
            dm_skin_layer L[2];
            dm_skin_layers_at(&p, dm_skin_data_index(nist_nm[k]), L);
            const double g = 0.8;
            dm_skin_mc_layer m[2];
            for (int j = 0; j < 2; ++j)
                m[j] = (dm_skin_mc_layer){1.4, L[j].sigma_a, L[j].sigma_s_prime / (1.0 - g), g, L[j].thickness_mm};
            dm_skin_mc_desc d = {.layers = m, .layer_count = 2, .photon_count = 10000, .seed = 32, .thread_count = 1};
            dm_skin_mc_result res = {0};
            cr_assert_eq(dm_skin_mc_run(&d, &res, NULL), DM_OK);
            double mc = res.diffuse_reflectance, model = total_at(&p, nist_nm[k]);
            printf("%s %g nm: Monte Carlo %.4f ± %.4f, model %.4f, NIST 5 %% %.3f\n", names[e], nist_nm[k], mc,
                   res.diffuse_reflectance_se, model, nist_lo[k]);
            cr_assert(mc + 4.0 * res.diffuse_reflectance_se < nist_lo[k], "%s %g nm: %.4f", names[e], nist_nm[k], mc);
            cr_assert(mc < model, "%s %g nm: MC %.4f, model %.4f", names[e], nist_nm[k], mc, model);
        }
    }
}

/* R_λ(r) of the model by the inverse transform (1/2π) ∫ s J0(s r) R̃(s) ds, trapezoid with
 * Δs = 0.005 mm⁻¹ to 400 mm⁻¹ (R̃ falls as e^(−l s), l ≈ 0.1 mm: e^−40 there; at r = 5 mm
 * J0's period 1.26 mm⁻¹ holds 250 steps). Independent of the Gaussian fit. */
static double model_r(const dm_skin_params *p, int li, double r)
{
    const double ds = 0.005;
    double acc = 0.0;
    for (int i = 1; i <= 80000; ++i) {
        double s = i * ds;
        dm_skin_dual f;
        dm_skin_reflectance_at(p, li, 0, s, &f, NULL);
        acc += (i == 80000 ? 0.5 : 1.0) * s * j0(s * r) * f.v;
    }
    return acc * ds / DM_2PI;
}

/* R(r) of the Caucasian exemplar at 650 nm (dermis l′ = 0.41 mm, epidermis 0.25 mm = 1.1 of
 * its own l) against the Monte Carlo's annuli (g 0.8, 4·10⁴ photons, 0.1 mm bins) over
 * 0.2–5 mm. Measured model/MC: 1.43 at 0.25 mm, 0.78–0.83 over 0.5–1 mm, 0.91–1.05 over
 * 1–4.5 mm: the layered diffusion puts too much light next to the beam (its total is +3.6 %)
 * and too little at 1–2 l′, and agrees beyond. Diffusion's known accuracy (a single layer's
 * dipole against the same MC, docs/skin-mc.md: 0.37–0.62 under 0.25 l′, 0.92–1.18 over
 * 0.4–5 l′) is kept beyond 1 mm (≥ 2.4 l′): 15 % + 4 SE per annulus; under it the layering
 * is worse than one dipole, held at what is measured: 50 % + 4 SE. */
Test(skin_profile, radial_profile_against_monte_carlo, .timeout = 120)
{
    dm_skin_params p = preset("caucasian");
    int li = dm_skin_data_index(650);
    dm_skin_layer L[2];
    dm_skin_layers_at(&p, li, L);
    const double g = 0.8, dr = 0.1;
    dm_skin_mc_layer m[2];
    for (int j = 0; j < 2; ++j)
        m[j] = (dm_skin_mc_layer){1.4, L[j].sigma_a, L[j].sigma_s_prime / (1.0 - g), g, L[j].thickness_mm};
    double rd[60], se[60];
    dm_skin_mc_desc d = {.layers = m, .layer_count = 2, .photon_count = 40000, .seed = 31, .thread_count = 0,
                         .dr_mm = dr, .radial_bin_count = 60};
    dm_skin_mc_result res = {.rd_r_per_mm2 = rd, .rd_r_se_per_mm2 = se};
    dm_error err = {0};
    cr_assert_eq(dm_skin_mc_run(&d, &res, &err), DM_OK, "%s", err.detail);
    for (int i = 2; i < 50; i += (i < 10 ? 1 : 5)) {
        double r = (i + 0.5) * dr, model = model_r(&p, li, r);
        printf("r %.2f mm: model %.5f MC %.5f ± %.5f (ratio %.3f)\n", r, model, rd[i], se[i], model / rd[i]);
        double tol = r < 1.0 ? 0.5 : 0.15;
        cr_assert(fabs(model - rd[i]) < tol * rd[i] + 4.0 * se[i], "r %.2f: %.5f vs %.5f", r, model, rd[i]);
    }
}
