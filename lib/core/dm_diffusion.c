#include "core/dm_diffusion.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_math.h"

/* Jensen, Marschner, Levoy, Hanrahan 2001, Figure 5 (measured, η = 1.3): σs′ then σa,
 * mm⁻¹, RGB. The same table ships in pbrt (GetMediumScatteringProperties). */
typedef struct preset {
    const char *name;
    double sigma_s_prime[3], sigma_a[3];
} preset;
static const preset presets[] = {
    {"skin1", {0.74, 0.88, 1.01}, {0.032, 0.17, 0.48}},
    {"skin2", {1.09, 1.59, 1.79}, {0.013, 0.070, 0.145}},
    {"marble", {2.19, 2.62, 3.00}, {0.0021, 0.0041, 0.0071}},
    {"wholemilk", {2.55, 3.21, 3.77}, {0.0011, 0.0024, 0.014}},
    {"skimmilk", {0.70, 1.22, 1.90}, {0.0014, 0.0025, 0.0142}},
    {"apple", {2.29, 2.39, 1.97}, {0.0030, 0.0034, 0.046}},
    {"ketchup", {0.18, 0.07, 0.03}, {0.061, 0.97, 1.45}},
};
enum { PRESET_COUNT = sizeof presets / sizeof presets[0] };
static const char *const preset_names[PRESET_COUNT + 1] = {"skin1",     "skin2", "marble",  "wholemilk",
                                                           "skimmilk", "apple", "ketchup", NULL};

const char *const *dm_medium_preset_names(void)
{
    return preset_names;
}

dm_result dm_medium_preset(const char *name, dm_medium *m, dm_error *err)
{
    for (int i = 0; i < PRESET_COUNT; ++i) {
        if (strcmp(name, presets[i].name) != 0) continue;
        memset(m, 0, sizeof *m);
        snprintf(m->name, sizeof m->name, "%s", name);
        m->model = DM_MODEL_DIPOLE;
        m->eta = 1.3;
        for (int c = 0; c < 3; ++c) {
            m->sigma_a_per_mm[c] = presets[i].sigma_a[c];
            m->sigma_s_prime_per_mm[c] = presets[i].sigma_s_prime[c];
        }
        return DM_OK;
    }
    char list[256] = "";
    for (int i = 0; i < PRESET_COUNT; ++i) {
        size_t n = strlen(list);
        snprintf(list + n, sizeof list - n, "%s%s", i ? ", " : "", presets[i].name);
    }
    return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "medium preset '%s': unknown, expected one of %s", name, list);
}

static dm_result check(double v, double lo, int lo_open, double hi, const char *what, const char *field, int c,
                       dm_error *err)
{
    if (isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi) return DM_OK;
    char at[16] = "";
    if (c >= 0) snprintf(at, sizeof at, "[%c]", "RGB"[c]);
    return dm_fail(err, isfinite(v) ? DM_ERR_RANGE : DM_ERR_NON_FINITE,
                   "%s: %s%s = %g, expected a finite value in %s%g, %g]", what, field, at, v, lo_open ? "(" : "[",
                   lo, hi);
}

dm_result dm_medium_validate(const dm_medium *m, const char *what, dm_error *err)
{
    dm_result r;
    for (int c = 0; c < 3; ++c) {
        if ((r = check(m->sigma_a_per_mm[c], 0.0, 0, DM_SIGMA_MAX_PER_MM, what, "sigma_a_per_mm", c, err))) return r;
        if ((r = check(m->sigma_s_prime_per_mm[c], 0.0, 1, DM_SIGMA_MAX_PER_MM, what, "sigma_s_prime_per_mm", c,
                       err)))
            return r;
    }
    if ((r = check(m->eta, DM_ETA_MIN, 0, DM_ETA_MAX, what, "eta", -1, err))) return r;
    if (m->model == DM_MODEL_MULTIPOLE) {
        if ((r = check(m->thickness_mm, 0.0, 1, DM_THICKNESS_MAX_MM, what, "thickness_mm", -1, err))) return r;
        if (m->pair_count < 0 || m->pair_count > DM_MULTIPOLE_PAIRS_MAX)
            return dm_fail(err, DM_ERR_RANGE, "%s: pair_count = %d, expected 0 (default %d) or 1..%d", what,
                           m->pair_count, DM_MULTIPOLE_PAIRS_DEFAULT, DM_MULTIPOLE_PAIRS_MAX);
    } else if (m->model != DM_MODEL_DIPOLE) {
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: model %d, expected dipole or multipole", what, (int)m->model);
    }
    return DM_OK;
}

double dm_fresnel_diffuse_reflectance(double eta)
{
    return -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
}

/* Channel constants shared by the dipole and the multipole. */
typedef struct channel {
    double alpha_p, sigma_tr, z_r, z_b;
} channel;

static channel channel_of(double sigma_a, double sigma_s_prime, double eta)
{
    channel ch;
    double sigma_t = sigma_a + sigma_s_prime;
    double fdr = dm_fresnel_diffuse_reflectance(eta);
    double a = (1.0 + fdr) / (1.0 - fdr);
    ch.alpha_p = sigma_s_prime / sigma_t;
    ch.sigma_tr = sqrt(3.0 * sigma_a * sigma_t);
    ch.z_r = 1.0 / sigma_t;
    ch.z_b = 2.0 * a / (3.0 * sigma_t); /* 2AD */
    return ch;
}

/* z (σtr d + 1) e^(−σtr d) / d³ with d = √(r² + z²), written so that nothing overflows:
 * hypot does not square, the d³ is split into (z/d)/d², and an infinite d gives 0. */
static double source_term(double z, double sigma_tr, double r)
{
    double d = hypot(r, z);
    if (isinf(d)) return 0.0;
    double x = sigma_tr * d;
    if (x > 745.0) return 0.0; /* e^(−x) underflows to 0 in double beyond ~745 */
    return (z / d) * ((x + 1.0) * exp(-x)) / (d * d);
}

double dm_dipole(double sigma_a, double sigma_s_prime, double eta, double r_mm)
{
    channel ch = channel_of(sigma_a, sigma_s_prime, eta);
    double z_v = ch.z_r + 2.0 * ch.z_b;
    return ch.alpha_p / (4.0 * DM_PI) *
           (source_term(ch.z_r, ch.sigma_tr, r_mm) + source_term(z_v, ch.sigma_tr, r_mm));
}

double dm_dipole_total(double sigma_a, double sigma_s_prime, double eta)
{
    double sigma_t = sigma_a + sigma_s_prime;
    double alpha_p = sigma_s_prime / sigma_t;
    double fdr = dm_fresnel_diffuse_reflectance(eta);
    double a = (1.0 + fdr) / (1.0 - fdr);
    double s = sqrt(3.0 * (1.0 - alpha_p));
    return 0.5 * alpha_p * (1.0 + exp(-4.0 / 3.0 * a * s)) * exp(-s);
}

static int pairs_or_default(int pairs)
{
    return pairs > 0 ? pairs : DM_MULTIPOLE_PAIRS_DEFAULT;
}

/* Σ over the multipole's image pairs i = −n..n (Donner & Jensen 2005: the real source at
 * i·period + z_r, the virtual one at i·period − z_r − 2 z_b) of term(z_real, z_virtual),
 * the small far images first (from |i| = n inwards) to keep rounding low. */
typedef double (*image_term)(double zr, double zv, double sigma_tr, double r_mm);

static double sum_images(const channel *ch, double thickness_mm, int pairs, image_term term, double r_mm)
{
    int n = pairs_or_default(pairs);
    double period = 2.0 * (thickness_mm + 2.0 * ch->z_b);
    double sum = 0.0;
    for (int a = n; a >= 0; --a) {
        for (int sgn = (a ? -1 : 1); sgn <= 1; sgn += 2) {
            int i = sgn * a;
            double zr = i * period + ch->z_r;
            double zv = i * period - ch->z_r - 2.0 * ch->z_b;
            sum += term(zr, zv, ch->sigma_tr, r_mm);
        }
    }
    return sum;
}

static double radiant_exitance_term(double zr, double zv, double sigma_tr, double r_mm)
{
    return source_term(zr, sigma_tr, r_mm) - source_term(zv, sigma_tr, r_mm);
}

/* ∫ 2πr z(σ d + 1)e^(−σd)/d³ dr = 2π sgn(z) e^(−σ|z|); the 2π meets the 4π. */
static double total_term(double zr, double zv, double sigma_tr, double r_mm)
{
    (void)r_mm;
    return copysign(exp(-sigma_tr * fabs(zr)), zr) - copysign(exp(-sigma_tr * fabs(zv)), zv);
}

double dm_multipole(double sigma_a, double sigma_s_prime, double eta, double thickness_mm, int pairs, double r_mm)
{
    channel ch = channel_of(sigma_a, sigma_s_prime, eta);
    return ch.alpha_p / (4.0 * DM_PI) * sum_images(&ch, thickness_mm, pairs, radiant_exitance_term, r_mm);
}

double dm_multipole_total(double sigma_a, double sigma_s_prime, double eta, double thickness_mm, int pairs)
{
    channel ch = channel_of(sigma_a, sigma_s_prime, eta);
    return 0.5 * ch.alpha_p * sum_images(&ch, thickness_mm, pairs, total_term, 0.0);
}

void dm_medium_eval(const dm_medium *m, double r_mm, double rgb[3])
{
    for (int c = 0; c < 3; ++c)
        rgb[c] = m->model == DM_MODEL_MULTIPOLE
                     ? dm_multipole(m->sigma_a_per_mm[c], m->sigma_s_prime_per_mm[c], m->eta, m->thickness_mm,
                                    m->pair_count, r_mm)
                     : dm_dipole(m->sigma_a_per_mm[c], m->sigma_s_prime_per_mm[c], m->eta, r_mm);
}

void dm_medium_total(const dm_medium *m, double rgb[3])
{
    for (int c = 0; c < 3; ++c)
        rgb[c] = m->model == DM_MODEL_MULTIPOLE
                     ? dm_multipole_total(m->sigma_a_per_mm[c], m->sigma_s_prime_per_mm[c], m->eta,
                                          m->thickness_mm, m->pair_count)
                     : dm_dipole_total(m->sigma_a_per_mm[c], m->sigma_s_prime_per_mm[c], m->eta);
}

dm_result dm_medium_parse(const char *spec, dm_diffusion_model model, double thickness_mm, int pair_count,
                          const char *what, dm_medium *m, dm_error *err)
{
    memset(m, 0, sizeof *m);
    if (!strchr(spec, ',')) { /* a name; numbers always come in 3 or 7 */
        dm_error e = {0};
        dm_result r = dm_medium_preset(spec, m, &e);
        if (r != DM_OK) return dm_fail(err, r, "%s: %s", what, e.detail);
    } else {
        double v[8];
        int count = 0;
        const char *s = spec;
        for (;;) {
            char *end;
            if (count == 8) break;
            v[count++] = strtod(s, &end);
            if (end == s || (*end && *end != ','))
                return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: '%s': item %d is not a number", what, spec, count);
            if (!*end) break;
            s = end + 1;
        }
        if (count != 3 && count != 7)
            return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                           "%s: '%s' has %d numbers, expected 3 (sa,ss,eta) or 7 (saR,saG,saB,ssR,ssG,ssB,eta)", what,
                           spec, count);
        for (int c = 0; c < 3; ++c) {
            m->sigma_a_per_mm[c] = count == 3 ? v[0] : v[c];
            m->sigma_s_prime_per_mm[c] = count == 3 ? v[1] : v[3 + c];
        }
        m->eta = v[count - 1];
    }
    m->model = model;
    m->thickness_mm = thickness_mm;
    m->pair_count = pair_count;
    return dm_medium_validate(m, what, err);
}

/* ---- Burley normalized diffusion (Christensen & Burley 2015) ------------------------- */

dm_result dm_burley_validate(const dm_burley *b, const char *what, dm_error *err)
{
    dm_result r;
    for (int c = 0; c < 3; ++c) {
        if ((r = check(b->albedo[c], 0.0, 0, 1.0, what, "albedo", c, err))) return r;
        if ((r = check(b->mfp_mm[c], 0.0, 1, DM_MFP_MAX_MM, what, "mfp_mm", c, err))) return r;
    }
    return DM_OK;
}

/* 1 or 3 comma-separated numbers into v[3]; 0 on success. */
static int parse_rgb(const char *spec, double v[3])
{
    int count = 0;
    const char *s = spec;
    for (;;) {
        char *end;
        if (count == 3) return -1;
        v[count++] = strtod(s, &end);
        if (end == s || (*end && *end != ',')) return -1;
        if (!*end) break;
        s = end + 1;
    }
    if (count == 1) v[1] = v[2] = v[0];
    return count == 1 || count == 3 ? 0 : -1;
}

dm_result dm_burley_parse(const char *albedo, const char *mfp, const char *what, dm_burley *b, dm_error *err)
{
    memset(b, 0, sizeof *b);
    if (parse_rgb(albedo, b->albedo))
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: albedo '%s', expected 1 number or 3 (R,G,B) in [0, 1]",
                       what, albedo);
    if (parse_rgb(mfp, b->mfp_mm))
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: mean free path '%s', expected 1 number or 3 (R,G,B) in mm",
                       what, mfp);
    return dm_burley_validate(b, what, err);
}

double dm_burley_shape(double albedo)
{
    double t = fabs(albedo - 0.8);
    return 1.85 - albedo + 7.0 * t * t * t;
}

double dm_burley_scale_mm(double albedo, double mfp_mm)
{
    return mfp_mm / dm_burley_shape(albedo);
}

double dm_burley_reflectance(double albedo, double mfp_mm, double r_mm)
{
    if (albedo == 0.0 || isinf(r_mm)) return 0.0;
    double s = 1.0 / dm_burley_scale_mm(albedo, mfp_mm);
    if (r_mm == 0.0) return INFINITY;
    double x = s * r_mm;
    /* exp(−x/3) underflows only beyond x ≈ 2235; then both terms are 0. */
    return albedo * s * (exp(-x) + exp(-x / 3.0)) / (8.0 * DM_PI * r_mm);
}

void dm_burley_eval(const dm_burley *b, double r_mm, double rgb[3])
{
    for (int c = 0; c < 3; ++c) rgb[c] = dm_burley_reflectance(b->albedo[c], b->mfp_mm[c], r_mm);
}

void dm_burley_total(const dm_burley *b, double rgb[3])
{
    for (int c = 0; c < 3; ++c) rgb[c] = b->albedo[c];
}

double dm_burley_mass_within(double albedo, double mfp_mm, double rho_mm)
{
    double x = rho_mm / dm_burley_scale_mm(albedo, mfp_mm);
    /* 1 − e^(−x)/4 − 3e^(−x/3)/4 = (−expm1(−x) + 3·(−expm1(−x/3)))/4: accurate near 0. */
    return albedo * (-expm1(-x) - 3.0 * expm1(-x / 3.0)) / 4.0;
}
