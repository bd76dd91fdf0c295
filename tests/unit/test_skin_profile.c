/* The physical skin as a profile (bake/dm_skin_profile.h, bake/dm_skin_optics.h): the
 * parameter check, the exemplars against the NIST forearm cohort, the RMS radii against
 * GPU Gems 3, the fit, the hard cases and a sweep, and a pin on every parameter. */
#define _XOPEN_SOURCE 700 /* j0 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bake/dm_skin_ad.h"
#include "bake/dm_skin_freq.h"
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

/* The model's total diffuse reflectance (adding-doubling; the profile is normalised to it). */
static double total_at(const dm_skin_params *p, double nm)
{
    return dm_skin_ad_total_at(p, dm_skin_data_index(nm), 0);
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
 * percentile, by 0.009 (measured 0.334; diffusion alone said 0.355): held here so a change
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

/* The Fitzpatrick gallery (our own mapping, dm_skin_optics.c) against the cohort, issue #30's
 * check: every type inside the 5–95 % band at 450, 550 and 650 nm, each darker than the one
 * before at every wavelength, type I near the top (the band's top quarter at 450 and 550 nm,
 * its upper half at 650: measured 0.316 / 0.358 / 0.551) and type VI near the bottom (its
 * bottom quarter at all three: 0.138 / 0.221 / 0.396); and the line between them — melanin
 * 0.006 to 0.042 in steps of 0.0005, the gallery's epidermis and blood — inside the band
 * everywhere. Melanin −20 % at the light end or ±20 % at the dark end, or DJ2006's 0.25 mm
 * epidermis, fails it. */
Test(skin_profile, gallery_spans_the_nist_cohort, .timeout = 60)
{
    double prev[3] = {1, 1, 1};
    for (int i = 1; i <= 6; ++i) {
        char name[32];
        snprintf(name, sizeof name, "fitzpatrick-%d", i);
        dm_skin_params p = preset(name);
        for (int k = 0; k < 3; ++k) {
            double r = total_at(&p, nist_nm[k]), q = (r - nist_lo[k]) / (nist_hi[k] - nist_lo[k]);
            printf("%s %g nm: %.3f (%.0f %% up the band)\n", name, nist_nm[k], r, 100 * q);
            cr_assert(r >= nist_lo[k] && r <= nist_hi[k], "%s %g nm: %.3f", name, nist_nm[k], r);
            cr_assert(r < prev[k], "%s %g nm: %.3f, not darker than %.3f", name, nist_nm[k], r, prev[k]);
            if (i == 1) cr_assert(q >= (k < 2 ? 0.75 : 0.5), "%s %g nm: %.2f up", name, nist_nm[k], q);
            if (i == 6) cr_assert(q <= 0.25, "%s %g nm: %.2f up", name, nist_nm[k], q);
            prev[k] = r;
        }
    }
    dm_skin_params lo = preset("fitzpatrick-1"), hi = preset("fitzpatrick-6");
    for (double cm = lo.melanin_fraction; cm <= hi.melanin_fraction + 1e-12; cm += 0.0005) {
        dm_skin_params p = lo;
        p.melanin_fraction = cm;
        for (int k = 0; k < 3; ++k) {
            double r = total_at(&p, nist_nm[k]);
            cr_assert(r >= nist_lo[k] && r <= nist_hi[k], "Cm %g, %g nm: %.3f", cm, nist_nm[k], r);
        }
    }
}

/* The gallery's totals at 450 nm, today's, pinned so that a change of a preset shows: melanin
 * 5 % off moves them by 0.0028–0.0053, the epidermis 5 % off by 0.0011–0.0038 from type 2 on;
 * held to 0.001. */
Test(skin_profile, gallery_totals_pinned)
{
    static const double want[6] = {0.3162, 0.2903, 0.2606, 0.2243, 0.1828, 0.1377};
    for (int i = 1; i <= 6; ++i) {
        char name[32];
        snprintf(name, sizeof name, "fitzpatrick-%d", i);
        dm_skin_params p = preset(name);
        double r = total_at(&p, 450);
        cr_expect(fabs(r - want[i - 1]) <= 0.001, "%s at 450 nm: %.4f, pinned %.4f", name, r, want[i - 1]);
    }
}

/* The darker exemplars are darker at every wavelength (Caucasian > Asian > African). Not
 * held to the cohort: DJ2006's melanin spread evenly through a 0.25 mm epidermis absorbs
 * more than the cohort's darkest skins (measured: Asian 0.029 / 0.055 / 0.121, African
 * 0.0055 / 0.0080 / 0.0123 at 450 / 550 / 650 nm, under the 5th percentiles 0.116 / 0.190 /
 * 0.386; diffusion with its closed form said 0.050 / 0.099 / 0.169 and 0.011 / 0.014 /
 * 0.018). The Monte Carlo of the same layers agrees (below): it is the parameters, not the
 * transport (docs/skin-model.md). Printed here so the numbers show. */
Test(skin_profile, darker_exemplars_are_darker)
{
    dm_skin_params c = preset("caucasian"), a = preset("asian"), f = preset("african");
    for (int k = 0; k < 3; ++k) {
        double rc = total_at(&c, nist_nm[k]), ra = total_at(&a, nist_nm[k]), rf = total_at(&f, nist_nm[k]);
        printf("%g nm: asian %.3f african %.4f (NIST 5 %% %.3f)\n", nist_nm[k], ra, rf, nist_lo[k]);
        cr_assert(rc > ra && ra >= rf && rf >= 0, "%g nm: %.3f %.3f %.4f", nist_nm[k], rc, ra, rf);
    }
    /* today's value, pinned so that a change to the model or the preset shows (adding-doubling:
     * 0.121; it was diffusion's 0.169) */
    cr_assert(fabs(total_at(&a, 650) - 0.121) < 0.02, "asian at 650 nm: %.3f", total_at(&a, 650));
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
    /* adding-doubling's totals and the partial-current shape (diffusion's flux totals were
     * 0.17338332 0.209353133 0.295271512, red RMS radius 0.723295197) */
    const double want[4] = {0.121131196, 0.161008586, 0.251458508, 0.761856425};
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
 * An exemplar's two layers as an MCML-style stack: n 1.4 both, air above, Henyey–Greenstein
 * g = DM_SKIN_ANISOTROPY (0.8) with μs = σs′/(1 − g), semi-infinite dermis. Like for like:
 * the MC's Rd is per incident power, the model's total per entering power (the renderer
 * applies the entry Fresnel itself), so the MC side is Rd/(1 − Rsp). */
static dm_skin_mc_result mc_of(const dm_skin_params *p, int li, uint64_t photons, uint64_t seed, double *rd,
                               double *se, int bins)
{
    dm_skin_layer L[2];
    dm_skin_layers_at(p, li, L);
    dm_skin_mc_layer m[2];
    for (int j = 0; j < 2; ++j)
        m[j] = (dm_skin_mc_layer){p->eta, L[j].sigma_a, L[j].sigma_s_prime / (1.0 - DM_SKIN_ANISOTROPY),
                                  DM_SKIN_ANISOTROPY, L[j].thickness_mm};
    dm_skin_mc_desc d = {.layers = m, .layer_count = 2, .photon_count = photons, .seed = seed, .thread_count = 0,
                         .dr_mm = 0.1, .radial_bin_count = bins};
    dm_skin_mc_result res = {.rd_r_per_mm2 = rd, .rd_r_se_per_mm2 = se};
    dm_error err = {0};
    cr_assert_eq(dm_skin_mc_run(&d, &res, &err), DM_OK, "%s", err.detail);
    return res;
}

/* Issue #30: the total diffuse reflectance the profile carries (the report's total_spectral,
 * adding-doubling's) against the MC of the same slab, within 2 % + 2 SE, every exemplar at
 * 450/550/650 nm (4·10⁴ photons: SE 0.3–0.5 % on the light skins, 2–7 % on the African, whose
 * Rd is 0.006–0.012). 2 % is the issue's; the MC's own noise is added because the model is
 * exact in what both describe (adding-doubling solves the MC's transport equation: 16
 * streams are within 1e-3 of 32, test_skin_ad.c), and at 2 SE the seeds fixed here leave it
 * deterministic. Measured (docs/skin-model.md): within ±1.3 %, most within 0.5 %. Before,
 * diffusion's total was +6.8 / +2.6 / +1.1 % (Caucasian), +21 / +12 / +7 % (Fitzpatrick 1)
 * like for like, and 1.4–2× on the dark exemplars. */
Test(skin_profile, totals_against_monte_carlo, .timeout = 120)
{
    const char *names[4] = {"caucasian", "fitzpatrick-1", "asian", "african"};
    for (int e = 0; e < 4; ++e) {
        dm_skin_params p = preset(names[e]);
        dm_profile prof;
        dm_skin_report rep;
        cr_assert_eq(dm_skin_profile_fit(&p, NULL, names[e], &prof, &rep, NULL), DM_OK);
        for (int k = 0; k < 3; ++k) {
            int li = dm_skin_data_index(nist_nm[k]);
            dm_skin_mc_result res = mc_of(&p, li, 40000, 30 + 3 * e + k, NULL, NULL, 0);
            double mc = res.diffuse_reflectance / (1.0 - res.specular), se = res.diffuse_reflectance_se / (1.0 - res.specular);
            double model = rep.total_spectral[li];
            printf("%s %g nm: model %.4f (diffusion %.4f), MC %.4f ± %.4f (%+.2f %%)\n", names[e], nist_nm[k], model,
                   rep.diffusion_total_spectral[li], mc, se, 100.0 * (model / mc - 1.0));
            cr_assert(fabs(model - mc) < 0.02 * mc + 2.0 * se, "%s %g nm: model %.4f, MC %.4f ± %.4f", names[e],
                      nist_nm[k], model, mc, se);
        }
    }
}

/* The darker exemplars' shortfall against the cohort is not the model's: the Monte Carlo of
 * the same layers (as above, 10⁴ photons) is below the NIST 5th percentile at 450/550/650 nm
 * too (measured Asian 0.029 / 0.054 / 0.117, African 0.006 / 0.008 / 0.012 against 0.116 /
 * 0.190 / 0.386; SE < 0.002), and so is the model, which agrees with it (above).
 * docs/skin-model.md, "Measured". */
Test(skin_profile, dark_exemplars_below_the_cohort_in_the_monte_carlo_too, .timeout = 60)
{
    const char *names[2] = {"asian", "african"};
    for (int e = 0; e < 2; ++e) {
        dm_skin_params p = preset(names[e]);
        for (int k = 0; k < 3; ++k) {
            dm_skin_mc_result res = mc_of(&p, dm_skin_data_index(nist_nm[k]), 10000, 32, NULL, NULL, 0);
            double mc = res.diffuse_reflectance, model = total_at(&p, nist_nm[k]);
            printf("%s %g nm: Monte Carlo %.4f ± %.4f, model %.4f, NIST 5 %% %.3f\n", names[e], nist_nm[k], mc,
                   res.diffuse_reflectance_se, model, nist_lo[k]);
            cr_assert(mc + 4.0 * res.diffuse_reflectance_se < nist_lo[k], "%s %g nm: %.4f", names[e], nist_nm[k], mc);
            cr_assert(model < nist_lo[k], "%s %g nm: model %.4f", names[e], nist_nm[k], model);
        }
    }
}

/* R_λ(r) of the model by the inverse transform (1/2π) ∫ s J0(s r) R̃(s) ds, trapezoid with
 * Δs = 0.005 mm⁻¹ to 400 mm⁻¹ (R̃ falls as e^(−l s), l ≈ 0.1 mm: e^−40 there; at r = 5 mm
 * J0's period 1.26 mm⁻¹ holds 250 steps), times the normalisation to adding-doubling's total
 * (dm_skin_freq_totals), as the profile takes it. Independent of the Gaussian fit. */
static double model_r(const dm_skin_params *p, int li, double scale, double r)
{
    const double ds = 0.005;
    double acc = 0.0;
    for (int i = 1; i <= 80000; ++i) {
        double s = i * ds;
        dm_skin_dual f;
        dm_skin_reflectance_at(p, li, 0, s, &f, NULL);
        acc += (i == 80000 ? 0.5 : 1.0) * s * j0(s * r) * f.v;
    }
    return scale * acc * ds / DM_2PI;
}

/* R(r) of the Caucasian exemplar at 650 nm (dermis l′ = 0.41 mm, epidermis 0.25 mm = 1.1 of
 * its own l) against the Monte Carlo's annuli (g 0.8, 4·10⁴ photons, 0.1 mm bins) over
 * 0.2–5 mm, like for like (MC/(1 − Rsp)): the shape is diffusion's read out as the
 * Fresnel-weighted partial current, the total adding-doubling's. Measured model/MC: 1.14 at
 * 0.25 mm, 1.00–1.09 over 0.35–0.95 mm, 0.91–1.10 over 1–4.5 mm (the flux readout, normalised
 * the same way: 1.37, 0.75–0.87, 0.88–1.01). Diffusion's known accuracy — a single dipole
 * against the same MC, docs/skin-mc.md: 0.92–1.18 over 0.4–5 l′ — is what is held: 20 % +
 * 4 SE per annulus under 1 mm (0.5–2.4 l′), 15 % + 4 SE beyond. */
Test(skin_profile, radial_profile_against_monte_carlo, .timeout = 120)
{
    dm_skin_params p = preset("caucasian");
    int li = dm_skin_data_index(650);
    double rd[60], se[60], scale[DM_SKIN_LAMBDA_COUNT];
    dm_skin_mc_result res = mc_of(&p, li, 40000, 31, rd, se, 60);
    dm_skin_freq_totals(&p, 0, 0, NULL, scale);
    for (int i = 2; i < 50; i += (i < 10 ? 1 : 5)) {
        double r = (i + 0.5) * 0.1, model = model_r(&p, li, scale[li], r);
        double mc = rd[i] / (1.0 - res.specular), mc_se = se[i] / (1.0 - res.specular);
        printf("r %.2f mm: model %.5f MC %.5f ± %.5f (ratio %.3f)\n", r, model, mc, mc_se, model / mc);
        double tol = r < 1.0 ? 0.2 : 0.15;
        cr_assert(fabs(model - mc) < tol * mc + 4.0 * mc_se, "r %.2f: %.5f vs %.5f", r, model, mc);
    }
}
