#include "core/dm_brdf.h"

#include <assert.h>
#include <math.h>

#include "core/dm_math.h"

static const double LN_D_MAX = 46.051701859880914; /* ln(1e20) */

double dm_beckmann(double c, double m)
{
    if (!(c > 0.0)) return 0.0; /* also catches NaN */
    if (c > 1.0) c = 1.0;
    if (!(m > 0.0)) return c >= 1.0 ? DM_BECKMANN_D_MAX : 0.0;
    /* ln D = (c² − 1)/(c² m²) − 2 ln m − 4 ln c, evaluated so that nothing overflows:
     * the exponent is ≤ 0, −inf when c² m² underflows (D → 0), and 0 at c = 1. */
    double c2 = c * c;
    double e = c >= 1.0 ? 0.0 : ((c - 1.0) * (c + 1.0)) / c2 / m / m;
    double ln_d = e - 2.0 * log(m) - 4.0 * log(c);
    if (ln_d > LN_D_MAX) return DM_BECKMANN_D_MAX;
    return exp(ln_d);
}

float dm_beckmann_f(float c, float m)
{
    if (!(c > 0.0f)) return 0.0f;
    if (c > 1.0f) c = 1.0f;
    if (!(m > 0.0f)) return c >= 1.0f ? (float)DM_BECKMANN_D_MAX : 0.0f;
    float c2 = c * c;
    float e = c >= 1.0f ? 0.0f : ((c - 1.0f) * (c + 1.0f)) / c2 / m / m;
    float ln_d = e - 2.0f * logf(m) - 4.0f * logf(c);
    if (ln_d > (float)LN_D_MAX) return (float)DM_BECKMANN_D_MAX;
    return expf(ln_d);
}

double dm_fresnel_schlick(double cos_theta, double f0)
{
    double x = 1.0 - (cos_theta > 1.0 ? 1.0 : cos_theta > 0.0 ? cos_theta : 0.0);
    double x2 = x * x;
    return f0 + (1.0 - f0) * x2 * x2 * x;
}

float dm_fresnel_schlick_f(float cos_theta, float f0)
{
    float x = 1.0f - (cos_theta > 1.0f ? 1.0f : cos_theta > 0.0f ? cos_theta : 0.0f);
    float x2 = x * x;
    return f0 + (1.0f - f0) * x2 * x2 * x;
}

double dm_ks_specular(const double n[3], const double l[3], const double v[3], double m, double rho_s, double f0)
{
    double ndotl = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
    if (!(ndotl > 0.0)) return 0.0;
    double h[3] = {l[0] + v[0], l[1] + v[1], l[2] + v[2]};
    double hh = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
    if (!(hh > 1e-12)) return 0.0; /* V = −L: no half vector, no reflection */
    double inv = 1.0 / sqrt(hh);
    double ndoth = (n[0] * h[0] + n[1] * h[1] + n[2] * h[2]) * inv;
    double vdoth = (v[0] * h[0] + v[1] * h[1] + v[2] * h[2]) * inv;
    double f = dm_beckmann(ndoth, m) * dm_fresnel_schlick(vdoth, f0) / hh;
    return ndotl * rho_s * (f > 0.0 ? f : 0.0);
}

float dm_ks_specular_f(const float n[3], const float l[3], const float v[3], float m, float rho_s, float f0)
{
    float ndotl = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
    if (!(ndotl > 0.0f)) return 0.0f;
    float h[3] = {l[0] + v[0], l[1] + v[1], l[2] + v[2]};
    float hh = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
    if (!(hh > 1e-12f)) return 0.0f;
    float inv = 1.0f / sqrtf(hh);
    float ndoth = (n[0] * h[0] + n[1] * h[1] + n[2] * h[2]) * inv;
    float vdoth = (v[0] * h[0] + v[1] * h[1] + v[2] * h[2]) * inv;
    float f = dm_beckmann_f(ndoth, m) * dm_fresnel_schlick_f(vdoth, f0) / hh;
    return ndotl * rho_s * (f > 0.0f ? f : 0.0f);
}

/* Gauss–Legendre nodes and weights on [0, 1], computed once per node count by Newton
 * iteration on P_n (Golub-free, exact to double rounding for n ≤ 128). */
enum { GL_MAX = 128 };
static void gauss_legendre01(int n, double *x, double *w)
{
    for (int i = 0; i < (n + 1) / 2; ++i) {
        double z = cos(DM_PI * (i + 0.75) / (n + 0.5)), pp = 0.0;
        for (int it = 0; it < 100; ++it) {
            double p1 = 1.0, p2 = 0.0;
            for (int j = 1; j <= n; ++j) {
                double p3 = p2;
                p2 = p1;
                p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
            }
            pp = n * (z * p1 - p2) / (z * z - 1.0);
            double dz = p1 / pp;
            z -= dz;
            if (fabs(dz) < 1e-16) break;
        }
        x[i] = 0.5 * (1.0 - z);
        x[n - 1 - i] = 0.5 * (1.0 + z);
        w[i] = w[n - 1 - i] = 1.0 / ((1.0 - z * z) * pp * pp);
    }
}

/* θ_h as a function of s ∈ [0, 1): u = −ln(1 − s), tan θ_h = m √u. And back. */
static double theta_of_s(double s, double m)
{
    return atan(m * sqrt(-log1p(-s)));
}
static double s_of_theta(double theta, double m)
{
    double t = tan(theta) / m;
    return -expm1(-t * t);
}

void dm_ks_directional(double c, double m, int nodes, double *scale, double *bias)
{
    assert(scale && bias);
    if (!(c >= 0.0)) c = 0.0; /* NaN too */
    if (c > 1.0) c = 1.0;
    if (nodes < 4) nodes = 4;
    if (nodes > GL_MAX) nodes = GL_MAX;
    if (!(m > 1e-7)) {
        /* m → 0: H = N, V is the mirror direction; ∫ D cos dω_h = π. */
        double x = 1.0 - c, x5 = x * x * x * x * x;
        *scale = c > 0.0 ? DM_PI * (1.0 - x5) : 0.0;
        *bias = c > 0.0 ? DM_PI * x5 : 0.0;
        return;
    }
    double xs[GL_MAX], ws[GL_MAX];
    gauss_legendre01(nodes, xs, ws);

    double sl = sqrt(1.0 - c * c), theta_l = acos(c);
    /* Breakpoints in θ_h where the horizon cut N·V = 0 starts or stops cutting φ:
     * all φ valid below (π/2 − θ_L)/2, none above (π/2 + θ_L)/2. */
    double t_lo = 0.5 * (DM_PI_2 - theta_l), t_hi = 0.5 * (DM_PI_2 + theta_l);
    double cuts[4] = {0.0, s_of_theta(t_lo, m), s_of_theta(t_hi, m), 1.0};
    if (!(cuts[1] > 0.0)) cuts[1] = 0.0;
    if (!(cuts[2] < 1.0) || !isfinite(cuts[2])) cuts[2] = 1.0;

    double acc_scale = 0.0, acc_bias = 0.0;
    for (int piece = 0; piece < 3; ++piece) {
        double a = cuts[piece], b = cuts[piece + 1];
        if (!(b > a)) continue;
        for (int i = 0; i < nodes; ++i) {
            double s = a + (b - a) * xs[i];
            double th = theta_of_s(s, m);
            double st = sin(th), ct = cos(th);
            /* valid φ: cos φ > κ, κ = −c cos 2θ / (sin θ_L sin 2θ) */
            double denom = sl * 2.0 * st * ct;
            double num = -c * (ct * ct - st * st);
            double phi_max;
            if (denom <= 0.0) phi_max = num < 0.0 ? DM_PI : 0.0;
            else {
                double kappa = num / denom;
                phi_max = kappa <= -1.0 ? DM_PI : kappa >= 1.0 ? 0.0 : acos(kappa);
            }
            if (phi_max <= 0.0) continue;
            double row_scale = 0.0, row_bias = 0.0;
            for (int j = 0; j < nodes; ++j) {
                double phi = phi_max * xs[j];
                double ldoth = sl * st * cos(phi) + c * ct;
                double ndotv = 2.0 * ldoth * ct - c;
                if (!(ndotv > 0.0) || !(ldoth > 0.0)) continue;
                double x = 1.0 - ldoth, x5 = x * x * x * x * x;
                double g = ndotv / (ldoth * ct);
                row_scale += ws[j] * g * (1.0 - x5);
                row_bias += ws[j] * g * x5;
            }
            /* φ ∈ [−φmax, φmax]: symmetric, so 2 φmax; the ½ of e^{−u}du/2 cancels it. */
            acc_scale += (b - a) * ws[i] * phi_max * row_scale;
            acc_bias += (b - a) * ws[i] * phi_max * row_bias;
        }
    }
    *scale = acc_scale;
    *bias = acc_bias;
}

double dm_rho_dt(double c, double m, double f0, int nodes)
{
    double s, b;
    dm_ks_directional(c, m, nodes, &s, &b);
    return f0 * s + b;
}

uint8_t dm_beckmann_encode8(double d)
{
    if (!(d > 0.0)) return 0;
    if (d >= DM_BECKMANN_LUT_D_MAX) return 255;
    double v = 255.0 * 0.5 * pow(d, 0.1);
    long r = lround(v);
    return (uint8_t)(r > 255 ? 255 : r < 0 ? 0 : r);
}

double dm_beckmann_decode8(double v_over_255)
{
    return pow(2.0 * v_over_255, 10.0);
}
