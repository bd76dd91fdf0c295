/* dm_skin_layers.c — multipole slabs in the frequency domain and their stacking
 * (dm_skin_layers.h). */
#include "bake/dm_skin_layers.h"

#include <assert.h>
#include <math.h>

#include "bake/dm_skin_mc.h"
#include "core/dm_diffusion.h"

/* 0 below lo, 1 above hi, C¹ smoothstep between. */
static double ramp(double x, double lo, double hi)
{
    double t = (x - lo) / (hi - lo);
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    return t * t * (3.0 - 2.0 * t);
}

double dm_skin_layer_diffusion_weight(const dm_skin_layer *l)
{
    double sigma_t = l->sigma_a + l->sigma_s_prime;
    return ramp(l->sigma_s_prime / sigma_t, DM_SKIN_ALBEDO_FALLBACK, DM_SKIN_ALBEDO_DIFFUSIVE) *
           ramp(l->thickness_mm * sigma_t, DM_SKIN_DEPTH_FALLBACK, DM_SKIN_DEPTH_DIFFUSIVE);
}

int dm_skin_layer_diffusive(const dm_skin_layer *l)
{
    return dm_skin_layer_diffusion_weight(l) == 1.0;
}

/* Gauss–Legendre, 16 nodes on [0, 1] (half-nodes and weights of the [−1, 1] rule). */
static const double gl_x[8] = {0.0950125098376374, 0.2816035507792589, 0.4580167776572274, 0.6178762444026438,
                               0.7554044083550030, 0.8656312023878318, 0.9445750230732326, 0.9894009349916499};
static const double gl_w[8] = {0.1894506104550685, 0.1826034150449236, 0.1691565193950025, 0.1495959888165767,
                               0.1246289712555339, 0.0951585116824928, 0.0622535239386479, 0.0271524594117541};

double dm_skin_single_scatter_reflectance(double albedo, double optical_depth, double eta)
{
    /* below the critical cosine μc = √(1 − 1/η²) nothing leaves (total internal reflection):
     * integrate over [μc, 1] only, where the integrand is smooth */
    double mu_c = sqrt(fmax(0.0, 1.0 - 1.0 / (eta * eta))), half = 0.5 * (1.0 - mu_c), acc = 0.0;
    for (int i = 0; i < 8; ++i)
        for (int side = -1; side <= 1; side += 2) {
            double mu = mu_c + half * (1.0 + side * gl_x[i]);
            double escape = isinf(optical_depth) ? 1.0 : 1.0 - exp(-optical_depth * (1.0 + 1.0 / mu));
            acc += half * gl_w[i] * mu / (1.0 + mu) * escape * (1.0 - dm_skin_mc_fresnel(eta, 1.0, mu));
        }
    return 0.5 * albedo * acc;
}

void dm_skin_exit_coefficients(double eta, double *c_phi, double *c_e)
{
    /* R = 1 below the critical cosine μc: ∫₀^μc μ dμ = μc²/2, ∫₀^μc μ² dμ = μc³/3. Above it
     * R(μ) has a square-root edge at μc: μ = μc + (1 − μc) t² makes the integrand smooth in t. */
    double mu_c = sqrt(fmax(0.0, 1.0 - 1.0 / (eta * eta))), c1 = 0.5 * mu_c * mu_c, c2 = mu_c * mu_c * mu_c / 3.0;
    if (eta > 1.0)
        for (int i = 0; i < 8; ++i)
            for (int side = -1; side <= 1; side += 2) {
                double t = 0.5 * (1.0 + side * gl_x[i]), mu = mu_c + (1.0 - mu_c) * t * t;
                double w = 0.5 * gl_w[i] * 2.0 * (1.0 - mu_c) * t * dm_skin_mc_fresnel(eta, 1.0, mu);
                c1 += w * mu;
                c2 += w * mu * mu;
            }
    *c_phi = 0.25 * (1.0 - 2.0 * c1);
    *c_e = 0.5 * (1.0 - 3.0 * c2);
}

/* The strongly absorbing or optically thin slab in closed form (dm_skin_layers.h): single
 * scattering back, Beer–Lambert through, no lateral spread. */
static void absorber(const dm_skin_layer *l, dm_skin_slab *out)
{
    double sigma_t = l->sigma_a + l->sigma_s_prime, d = l->thickness_mm;
    double albedo = l->sigma_s_prime / sigma_t;
    double r = dm_skin_single_scatter_reflectance(albedo, sigma_t * d, l->eta_top);
    *out = (dm_skin_slab){{r, 0}, {0, 0}, {0, 0}, {0, 0}};
    if (isinf(d)) return;
    out->r_up.v = dm_skin_single_scatter_reflectance(albedo, sigma_t * d, l->eta_bottom);
    out->t.v = fmax(0.0, exp(-l->sigma_a * d) - r);
    out->t_up.v = fmax(0.0, exp(-2.0 * l->sigma_a * d) - out->r_up.v);
}

/* Extrapolation distance z_b = 2AD of a face with index ratio eta. */
static double extrapolation(double eta, double sigma_t)
{
    double fdr = dm_fresnel_diffuse_reflectance(eta);
    return 2.0 * (1.0 + fdr) / (1.0 - fdr) / (3.0 * sigma_t);
}

/* sgn(z) e^(−|z| q) and its derivative in s² (∂q/∂s² = 1/2q), added to acc with sign. */
static void pole(double z, double q, double sign, dm_skin_dual *acc)
{
    double e = copysign(exp(-fabs(z) * q), z) * sign;
    acc->v += e;
    acc->d += e * (q > 0.0 ? -fabs(z) / (2.0 * q) : -INFINITY);
}

/* The fluence of a real pole at a and its image at b (a, b ≥ 0, their distances to the face),
 * times 2D: (e^(−a q) − e^(−b q))/q, and its derivative in s², added to acc. The pair is
 * finite at q = 0 (b − a: a non-absorbing medium), where each pole alone is not. */
static void fluence_pair(double a, double b, double q, dm_skin_dual *acc)
{
    /* (e^(−a q) − e^(−b q))/q directly where the two differ by more than a thousandth (rounding
     * 1e-13 relative); else e^(−lo q) (1 − e^(−Δ q))/q with lo the nearer pole, Δ = |b − a| */
    double ea = exp(-a * q), eb = exp(-b * q), gap = fabs(b - a), x = gap * q;
    if (x > 1e-3)
        acc->v += (ea - eb) / q;
    else
        acc->v += copysign(exp(-fmin(a, b) * q) * gap * (x == 0.0 ? 1.0 : -expm1(-x) / x), b - a);
    /* ∂/∂s² = (1/2q) ∂/∂q */
    acc->d += q > 0.0 ? ((b * eb - a * ea) / q - (ea - eb) / (q * q)) / (2.0 * q) : -INFINITY;
}

/* Where a face's light leaves: the flux, or the Fresnel-weighted partial current
 * C_φ φ + C_E E (dm_skin_layers.h). Per unit source a pole's flux is sgn(z) e^(−|z|q)/2 and
 * its fluence e^(−|z|q)/2Dq, so with the sums of pole() and fluence_pair() the response is
 * α′/2 (C_E Σflux + C_φ/D Σfluence), D = 1/(3σt′). */
typedef struct face {
    double c_e, c_phi_over_d;
} face;

static face exit_face(const dm_skin_layer *l, double eta, double sigma_t)
{
    if (l->exit == DM_SKIN_EXIT_FLUX) return (face){1.0, 0.0};
    double c_phi, c_e;
    dm_skin_exit_coefficients(eta, &c_phi, &c_e);
    return (face){c_e, c_phi * 3.0 * sigma_t};
}

/* The responses of a diffusive slab, lit from the face whose extrapolation is zb_lit (the
 * other zb_far), the light leaving through the lit face (r) and the far one (t). */
static void multipole(double alpha_p, double l, double d, double zb_lit, double zb_far, int n, double q, face lit,
                      face far, dm_skin_dual *r, dm_skin_dual *t)
{
    dm_skin_dual er = {0, 0}, et = {0, 0}, fr = {0, 0}, ft = {0, 0}; /* flux, fluence·D */
    if (isinf(d)) { /* the dipole: real source at l, its image at −l − 2 z_b */
        pole(l, q, 1.0, &er);
        pole(-l - 2.0 * zb_lit, q, -1.0, &er);
        if (lit.c_phi_over_d != 0.0) fluence_pair(l, l + 2.0 * zb_lit, q, &fr);
    } else {
        double period = 2.0 * (d + zb_lit + zb_far);
        for (int a = n; a >= 0; --a) /* the far, small images first */
            for (int sgn = (a ? -1 : 1); sgn <= 1; sgn += 2) {
                double zr = sgn * a * period + l, zv = sgn * a * period - l - 2.0 * zb_lit;
                pole(zr, q, 1.0, &er);
                pole(zv, q, -1.0, &er);
                if (lit.c_phi_over_d != 0.0) fluence_pair(fabs(zr), fabs(zv), q, &fr);
                if (t) {
                    pole(d - zr, q, 1.0, &et);
                    pole(d - zv, q, -1.0, &et);
                    if (far.c_phi_over_d != 0.0) fluence_pair(fabs(d - zr), fabs(d - zv), q, &ft);
                }
            }
    }
    double k = 0.5 * alpha_p;
    *r = (dm_skin_dual){k * (lit.c_e * er.v + lit.c_phi_over_d * fr.v), k * (lit.c_e * er.d + lit.c_phi_over_d * fr.d)};
    if (t)
        *t = (dm_skin_dual){k * (far.c_e * et.v + far.c_phi_over_d * ft.v),
                            k * (far.c_e * et.d + far.c_phi_over_d * ft.d)};
}

/* The multipole slab (diffusion; dm_skin_layers.h). */
static void diffusion(const dm_skin_layer *l, int pairs, double s_per_mm, dm_skin_slab *out)
{
    double d = l->thickness_mm;
    int n = pairs > 0 ? pairs : DM_MULTIPOLE_PAIRS_DEFAULT;
    double sigma_t = l->sigma_a + l->sigma_s_prime, alpha_p = l->sigma_s_prime / sigma_t;
    double sigma_tr2 = 3.0 * l->sigma_a * sigma_t, q = sqrt(sigma_tr2 + s_per_mm * s_per_mm);
    double zb_top = extrapolation(l->eta_top, sigma_t), zb_bottom = extrapolation(l->eta_bottom, sigma_t);
    face top = exit_face(l, l->eta_top, sigma_t), bottom = exit_face(l, l->eta_bottom, sigma_t);
    multipole(alpha_p, 1.0 / sigma_t, d, zb_top, zb_bottom, n, q, top, bottom, &out->r, isinf(d) ? NULL : &out->t);
    if (isinf(d)) {
        out->t = out->r_up = out->t_up = (dm_skin_dual){0, 0};
        return;
    }
    multipole(alpha_p, 1.0 / sigma_t, d, zb_bottom, zb_top, n, q, bottom, top, &out->r_up, &out->t_up);
}

static dm_skin_dual blend(double w, dm_skin_dual a, dm_skin_dual b)
{
    return (dm_skin_dual){w * a.v + (1.0 - w) * b.v, w * a.d + (1.0 - w) * b.d};
}

void dm_skin_layer_transform(const dm_skin_layer *l, int pairs, double s_per_mm, dm_skin_slab *out)
{
    double w = dm_skin_layer_diffusion_weight(l);
    if (w == 1.0) {
        diffusion(l, pairs, s_per_mm, out);
        return;
    }
    absorber(l, out);
    if (w == 0.0) return;
    dm_skin_slab dif, abs = *out;
    diffusion(l, pairs, s_per_mm, &dif);
    out->r = blend(w, dif.r, abs.r), out->r_up = blend(w, dif.r_up, abs.r_up);
    out->t = blend(w, dif.t, abs.t), out->t_up = blend(w, dif.t_up, abs.t_up);
}

/* a·b and a/b on duals. */
static dm_skin_dual mul(dm_skin_dual a, dm_skin_dual b)
{
    return (dm_skin_dual){a.v * b.v, a.d * b.v + a.v * b.d};
}

static dm_skin_dual quot(dm_skin_dual a, dm_skin_dual b)
{
    return (dm_skin_dual){a.v / b.v, (a.d * b.v - a.v * b.d) / (b.v * b.v)};
}

void dm_skin_stack_transform(const dm_skin_layer *layers, int layer_count, int pairs, double s_per_mm, dm_skin_dual *r,
                             dm_skin_dual *t)
{
    assert(layer_count >= 1 && layer_count <= DM_SKIN_LAYERS_MAX);
    dm_skin_slab below;
    dm_skin_layer_transform(&layers[layer_count - 1], pairs, s_per_mm, &below);
    dm_skin_dual rs = below.r, ts = below.t;
    for (int i = layer_count - 2; i >= 0; --i) { /* fold from the bottom up */
        dm_skin_slab top;
        dm_skin_layer_transform(&layers[i], pairs, s_per_mm, &top);
        dm_skin_dual one_minus = mul(top.r_up, rs);
        one_minus = (dm_skin_dual){1.0 - one_minus.v, -one_minus.d};
        dm_skin_dual bounce = quot(mul(mul(top.t, rs), top.t_up), one_minus);
        ts = quot(mul(top.t, ts), one_minus);
        rs = (dm_skin_dual){top.r.v + bounce.v, top.r.d + bounce.d};
    }
    *r = rs;
    if (t) *t = ts;
}

void dm_skin_layers_at(const dm_skin_params *p, int lambda_index, dm_skin_layer layers[2])
{
    dm_skin_optics o;
    dm_skin_optics_at(p, lambda_index, &o);
    layers[0] = (dm_skin_layer){o.epidermis_sigma_a, o.epidermis_sigma_s_prime, p->epidermis_mm, p->eta, 1.0,
                                DM_SKIN_EXIT_PARTIAL_CURRENT};
    layers[1] = (dm_skin_layer){o.dermis_sigma_a, o.dermis_sigma_s_prime, p->dermis_mm > 0.0 ? p->dermis_mm : INFINITY,
                                1.0, p->eta, DM_SKIN_EXIT_PARTIAL_CURRENT};
}

void dm_skin_reflectance_at(const dm_skin_params *p, int lambda_index, int pairs, double s_per_mm, dm_skin_dual *r,
                            unsigned *invalid)
{
    dm_skin_layer layers[2];
    dm_skin_layers_at(p, lambda_index, layers);
    if (invalid)
        *invalid = (dm_skin_layer_diffusive(&layers[0]) ? 0u : DM_SKIN_INVALID_EPIDERMIS) |
                   (dm_skin_layer_diffusive(&layers[1]) ? 0u : DM_SKIN_INVALID_DERMIS);
    dm_skin_stack_transform(layers, 2, pairs, s_per_mm, r, NULL);
}
