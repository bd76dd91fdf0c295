/* dm_skin_ad.c — adding-doubling for a layered slab (dm_skin_ad.h). */
#include "bake/dm_skin_ad.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "bake/dm_skin_layers.h"
#include "bake/dm_skin_mc.h"
#include "core/dm_math.h"

enum { NMAX = DM_SKIN_AD_STREAMS_MAX, DOUBLINGS_MAX = 64 };
#define T_CONVERGED 1e-9
#define INDEX_MAX 10.0

typedef double mat[NMAX * NMAX]; /* row-major, stride n */

/* ---- quadrature ---- */

/* P_n(x) and P_{n−1}(x) by the three-term recurrence (n ≥ 1). */
static void legendre(int n, double x, double *pn, double *pn1)
{
    double p0 = 1.0, p1 = x;
    for (int k = 2; k <= n; ++k) {
        double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1, p1 = p2;
    }
    *pn = p1, *pn1 = p0;
}

/* Gauss (radau = 0): P_n; Radau with the node −1 fixed (radau = 1): P_{n−1} + P_n. */
static double node_function(int n, int radau, double x)
{
    double pn, pn1;
    legendre(n, x, &pn, &pn1);
    return radau ? pn + pn1 : pn;
}

/* The n nodes and weights on [−1, 1], ascending: roots bracketed on a grid uniform in
 * θ = arccos x (the roots' spacing is ~π/n there) and bisected to rounding. */
static void rule(int n, int radau, double *x, double *w)
{
    int count = 0, steps = 64 * n;
    double prev_x = 1.0, prev_f = node_function(n, radau, 1.0);
    for (int k = 1; k < steps && count < n; ++k) { /* θ = π (x = −1) is Radau's fixed node: not searched */
        double xk = cos(DM_PI * k / steps), fk = node_function(n, radau, xk);
        if (fk == 0.0 || (fk < 0.0) != (prev_f < 0.0)) {
            double lo = xk, hi = prev_x;
            for (int it = 0; it < 200 && hi - lo > 0.0; ++it) {
                double mid = 0.5 * (lo + hi);
                if (mid <= lo || mid >= hi) break;
                if ((node_function(n, radau, mid) < 0.0) == (fk < 0.0)) lo = mid;
                else hi = mid;
            }
            x[count++] = 0.5 * (lo + hi);
        }
        prev_x = xk, prev_f = fk;
    }
    if (radau) x[count++] = -1.0;
    assert(count == n);
    for (int i = 0; i < n; ++i) {
        double pn, pn1;
        if (radau) {
            legendre(n - 1 > 0 ? n - 1 : 1, x[i], &pn, &pn1);
            double p = n > 1 ? pn : 1.0; /* P_{n−1}(x) */
            w[i] = x[i] == -1.0 ? 2.0 / ((double)n * n) : (1.0 - x[i]) / ((double)n * n * p * p);
        } else {
            legendre(n, x[i], &pn, &pn1);
            double dp = n * (x[i] * pn - pn1) / (x[i] * x[i] - 1.0);
            w[i] = 2.0 / ((1.0 - x[i] * x[i]) * dp * dp);
        }
    }
}

typedef struct streams {
    int n;
    double mu[NMAX], w[NMAX]; /* ascending; mu[n − 1] = 1 */
    double fresnel[NMAX];     /* reflectance of the face to air, from inside, per stream */
} streams;

/* Maps a rule on [−1, 1] to [a, b] with x = −1 going to b (Radau's node to μ = 1 or μc). */
static void place(int n, int radau, double a, double b, double *mu, double *w)
{
    double x[NMAX], wx[NMAX];
    rule(n, radau, x, wx);
    for (int i = 0; i < n; ++i) { /* x descends from the bisection, so μ ascends */
        mu[i] = a + 0.5 * (b - a) * (1.0 - x[i]);
        w[i] = 0.5 * (b - a) * wx[i];
    }
}

static void make_streams(int n, double index, streams *s)
{
    s->n = n;
    double mu_c = index > 1.0 ? sqrt(1.0 - 1.0 / (index * index)) : 0.0;
    if (mu_c > 0.0) {
        place(n / 2, 0, 0.0, mu_c, s->mu, s->w);
        place(n / 2, 1, mu_c, 1.0, s->mu + n / 2, s->w + n / 2);
    } else {
        place(n, 1, 0.0, 1.0, s->mu, s->w);
    }
    for (int i = 0; i < n; ++i) s->fresnel[i] = index > 1.0 ? dm_skin_mc_fresnel(index, 1.0, s->mu[i]) : 0.0;
}

/* ---- small dense matrices ---- */

static void identity(int n, double *a)
{
    memset(a, 0, sizeof(double) * (size_t)n * n);
    for (int i = 0; i < n; ++i) a[i * n + i] = 1.0;
}

/* c = a b (c distinct from a and b). */
static void mul(int n, const double *a, const double *b, double *c)
{
    for (int i = 0; i < n; ++i) {
        double *ci = c + i * n;
        for (int j = 0; j < n; ++j) ci[j] = 0.0;
        for (int k = 0; k < n; ++k) {
            double aik = a[i * n + k];
            const double *bk = b + k * n;
            for (int j = 0; j < n; ++j) ci[j] += aik * bk[j];
        }
    }
}

/* x = a⁻¹ b by Gaussian elimination with partial pivoting; a and b are overwritten. */
static void solve(int n, double *a, double *b, double *x)
{
    for (int k = 0; k < n; ++k) {
        int p = k;
        for (int i = k + 1; i < n; ++i)
            if (fabs(a[i * n + k]) > fabs(a[p * n + k])) p = i;
        if (p != k)
            for (int j = 0; j < n; ++j) {
                double t = a[k * n + j];
                a[k * n + j] = a[p * n + j], a[p * n + j] = t;
                t = b[k * n + j], b[k * n + j] = b[p * n + j], b[p * n + j] = t;
            }
        for (int i = k + 1; i < n; ++i) {
            double f = a[i * n + k] / a[k * n + k];
            if (f == 0.0) continue;
            for (int j = k; j < n; ++j) a[i * n + j] -= f * a[k * n + j];
            for (int j = 0; j < n; ++j) b[i * n + j] -= f * b[k * n + j];
        }
    }
    for (int k = n - 1; k >= 0; --k)
        for (int j = 0; j < n; ++j) {
            double v = b[k * n + j];
            for (int i = k + 1; i < n; ++i) v -= a[k * n + i] * x[i * n + j];
            x[k * n + j] = v / a[k * n + k];
        }
}

/* z = (I − a b)⁻¹ c. */
static void resolvent(int n, const double *a, const double *b, const double *c, double *z)
{
    mat m, rhs;
    mul(n, a, b, m);
    for (int i = 0; i < n * n; ++i) m[i] = -m[i];
    for (int i = 0; i < n; ++i) m[i * n + i] += 1.0;
    memcpy(rhs, c, sizeof(double) * (size_t)n * n);
    solve(n, m, rhs, z);
}

/* ---- one layer ---- */

/* The diamond-initialised thin layer (radiance form, then similar to the flux form):
 * X = (Δτ/2) M⁻¹ (I − (a/2) H⁺ W), Y = (Δτ/2) M⁻¹ (a/2) H⁻ W,
 * R = (I + X − Y)⁻¹ − (I + X + Y)⁻¹, T = (I + X − Y)⁻¹ + (I + X + Y)⁻¹ − I. */
static void thin_layer(const streams *s, const double *hp, const double *hm, double albedo, double dtau, double *r,
                       double *t)
{
    int n = s->n;
    mat am, ap, im, ip, eye;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double c = 0.5 * dtau / s->mu[i], x = c * ((i == j) - 0.5 * albedo * hp[i * n + j] * s->w[j]);
            double y = c * 0.5 * albedo * hm[i * n + j] * s->w[j];
            am[i * n + j] = (i == j) + x - y;
            ap[i * n + j] = (i == j) + x + y;
        }
    identity(n, eye);
    memcpy(im, eye, sizeof(double) * (size_t)n * n);
    solve(n, am, im, r); /* r holds (I + X − Y)⁻¹ for now */
    memcpy(ip, eye, sizeof(double) * (size_t)n * n);
    solve(n, ap, ip, t); /* t holds (I + X + Y)⁻¹ */
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double dij = 2.0 * s->mu[i] * s->w[i], dj = 2.0 * s->mu[j] * s->w[j]; /* flux = D radiance */
            double a = r[i * n + j], b = t[i * n + j];
            r[i * n + j] = (a - b) * dij / dj;
            t[i * n + j] = (a + b - (i == j)) * dij / dj;
        }
}

/* R, T ← the layer of twice the depth. */
static void double_layer(int n, double *r, double *t)
{
    mat z, tr, trz, tz;
    resolvent(n, r, r, t, z); /* (I − R R)⁻¹ T */
    mul(n, t, r, tr);
    mul(n, tr, z, trz);
    mul(n, t, z, tz);
    for (int i = 0; i < n * n; ++i) r[i] += trz[i];
    memcpy(t, tz, sizeof(double) * (size_t)n * n);
}

static double max_column_sum(int n, const double *a)
{
    double m = 0.0;
    for (int j = 0; j < n; ++j) {
        double c = 0.0;
        for (int i = 0; i < n; ++i) c += a[i * n + j];
        m = fmax(m, c);
    }
    return m;
}

/* The layer's flux operators R and T (δ-M HG; doubled from a thin layer). */
static void layer_operators(const streams *s, const dm_skin_ad_layer *l, double start_depth, double *r, double *t)
{
    int n = s->n;
    double f = pow(l->g, n), mu_s = l->mu_s_per_mm * (1.0 - f), mu_t = l->mu_a_per_mm + mu_s;
    double albedo = mu_t > 0.0 ? mu_s / mu_t : 0.0;
    /* h(μi, ±μj) of the truncated series, each column renormalised */
    mat hp, hm;
    double pi_[NMAX][NMAX]; /* P_k(μ_i), k < n */
    for (int i = 0; i < n; ++i) {
        double p0 = 1.0, p1 = s->mu[i];
        pi_[i][0] = 1.0;
        if (n > 1) pi_[i][1] = p1;
        for (int k = 2; k < n; ++k) {
            double p2 = ((2 * k - 1) * s->mu[i] * p1 - (k - 1) * p0) / k;
            p0 = p1, p1 = p2, pi_[i][k] = p2;
        }
    }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double same = 0.0, opposite = 0.0, gk = 1.0;
            for (int k = 0; k < n; ++k, gk *= l->g) {
                double term = (2 * k + 1) * (gk - f) / (1.0 - f) * pi_[i][k] * pi_[j][k];
                same += term, opposite += k % 2 ? -term : term;
            }
            hp[i * n + j] = same, hm[i * n + j] = opposite;
        }
    for (int j = 0; j < n; ++j) {
        double norm = 0.0;
        for (int i = 0; i < n; ++i) norm += 0.5 * s->w[i] * (hp[i * n + j] + hm[i * n + j]);
        for (int i = 0; i < n; ++i) hp[i * n + j] /= norm, hm[i * n + j] /= norm;
    }
    double tau = mu_t * l->thickness_mm;
    if (isinf(tau)) {
        thin_layer(s, hp, hm, albedo, start_depth, r, t);
        for (int k = 0; k < DOUBLINGS_MAX && max_column_sum(n, t) > T_CONVERGED; ++k) double_layer(n, r, t);
        return;
    }
    int doublings = tau > start_depth ? (int)ceil(log2(tau / start_depth)) : 0;
    thin_layer(s, hp, hm, albedo, ldexp(tau, -doublings), r, t);
    for (int k = 0; k < doublings; ++k) double_layer(n, r, t);
}

/* ---- the stack ---- */

static dm_result check(const dm_skin_ad_layer *layers, int count, double index, const dm_skin_ad_options *opt,
                       dm_error *err)
{
    if (count < 1 || count > DM_SKIN_AD_LAYERS_MAX)
        return dm_fail(err, DM_ERR_RANGE, "adding-doubling: layer_count = %d, expected 1..%d", count,
                       DM_SKIN_AD_LAYERS_MAX);
    if (!isfinite(index)) return dm_fail(err, DM_ERR_NON_FINITE, "adding-doubling: n = %g, expected finite", index);
    if (!(index >= 1.0 && index <= INDEX_MAX))
        return dm_fail(err, DM_ERR_RANGE, "adding-doubling: n = %g, expected 1..%g", index, INDEX_MAX);
    if (opt && (opt->stream_count < 0 || opt->stream_count > NMAX || opt->stream_count % 2 ||
                (opt->stream_count > 0 && opt->stream_count < 2)))
        return dm_fail(err, DM_ERR_RANGE, "adding-doubling: stream_count = %d, expected 0 (%d) or even 2..%d",
                       opt->stream_count, DM_SKIN_AD_STREAMS_DEFAULT, NMAX);
    if (opt && !(opt->start_depth >= 0.0 && opt->start_depth <= 1.0))
        return dm_fail(err, DM_ERR_RANGE, "adding-doubling: start_depth = %g, expected 0 (%g) or (0, 1]",
                       opt->start_depth, DM_SKIN_AD_START_DEPTH);
    for (int i = 0; i < count; ++i) {
        const dm_skin_ad_layer *l = &layers[i];
        const char *field[3] = {"mu_a_per_mm", "mu_s_per_mm", "g"};
        double v[3] = {l->mu_a_per_mm, l->mu_s_per_mm, l->g};
        for (int f = 0; f < 3; ++f)
            if (!isfinite(v[f]))
                return dm_fail(err, DM_ERR_NON_FINITE, "adding-doubling: layer %d: %s = %g, expected finite", i,
                               field[f], v[f]);
        if (!(l->mu_a_per_mm >= 0.0) || !(l->mu_s_per_mm >= 0.0))
            return dm_fail(err, DM_ERR_RANGE, "adding-doubling: layer %d: %s = %g, expected ≥ 0", i,
                           l->mu_a_per_mm < 0.0 ? field[0] : field[1], fmin(l->mu_a_per_mm, l->mu_s_per_mm));
        if (!(fabs(l->g) < 1.0))
            return dm_fail(err, DM_ERR_RANGE, "adding-doubling: layer %d: g = %g, expected in (−1, 1)", i, l->g);
        int last = i == count - 1;
        if (isnan(l->thickness_mm) || !(l->thickness_mm > 0.0) || (isinf(l->thickness_mm) && !last))
            return dm_fail(err, DM_ERR_RANGE,
                           "adding-doubling: layer %d: thickness_mm = %g, expected > 0 (INFINITY for the last only)", i,
                           l->thickness_mm);
        if (isinf(l->thickness_mm) && !(l->mu_a_per_mm > 0.0))
            return dm_fail(err, DM_ERR_RANGE,
                           "adding-doubling: layer %d: mu_a_per_mm = %g, expected > 0 in a semi-infinite layer", i,
                           l->mu_a_per_mm);
    }
    return DM_OK;
}

dm_result dm_skin_ad_run(const dm_skin_ad_layer *layers, int layer_count, double n, const dm_skin_ad_options *opt,
                         dm_skin_ad_result *out, dm_error *err)
{
    dm_result rc = check(layers, layer_count, n, opt, err);
    if (rc != DM_OK) return rc;
    int m = opt && opt->stream_count ? opt->stream_count : DM_SKIN_AD_STREAMS_DEFAULT;
    double start = opt && opt->start_depth > 0.0 ? opt->start_depth : DM_SKIN_AD_START_DEPTH;
    streams s;
    make_streams(m, n, &s);
    /* below a plane: S (down-going flux → up-going), u (down-going → leaving the bottom) */
    mat sr, r, t, z, ts, tsz, bm;
    double u[NMAX] = {0}, u2[NMAX];
    int top = layer_count - 1;
    if (isinf(layers[top].thickness_mm)) {
        layer_operators(&s, &layers[top], start, sr, t);
        --top;
    } else {
        memset(sr, 0, sizeof sr);
        for (int i = 0; i < m; ++i) sr[i * m + i] = s.fresnel[i], u[i] = 1.0 - s.fresnel[i];
    }
    for (int k = top; k >= 0; --k) {
        layer_operators(&s, &layers[k], start, r, t);
        resolvent(m, r, sr, t, z); /* (I − R S)⁻¹ T */
        mul(m, t, sr, ts);
        mul(m, ts, z, tsz);
        for (int i = 0; i < m * m; ++i) sr[i] = r[i] + tsz[i];
        for (int j = 0; j < m; ++j) {
            u2[j] = 0.0;
            for (int i = 0; i < m; ++i) u2[j] += u[i] * z[i * m + j];
        }
        memcpy(u, u2, sizeof u);
    }
    /* the top face: v = (I − S B)⁻¹ S e, e the unit flux in the stream μ = 1 */
    memset(bm, 0, sizeof bm);
    for (int i = 0; i < m; ++i) bm[i * m + i] = s.fresnel[i];
    resolvent(m, sr, bm, sr, z);
    double refl = 0.0, trans = u[m - 1];
    for (int i = 0; i < m; ++i) {
        double v = z[i * m + (m - 1)];
        refl += (1.0 - s.fresnel[i]) * v;
        trans += u[i] * s.fresnel[i] * v;
    }
    out->reflectance = refl, out->transmittance = trans;
    return DM_OK;
}

double dm_skin_ad_total_at(const dm_skin_params *p, int lambda_index, int stream_count)
{
    dm_skin_layer l[2];
    dm_skin_layers_at(p, lambda_index, l);
    dm_skin_ad_layer a[2];
    for (int i = 0; i < 2; ++i)
        a[i] = (dm_skin_ad_layer){l[i].sigma_a, l[i].sigma_s_prime / (1.0 - DM_SKIN_ANISOTROPY), DM_SKIN_ANISOTROPY,
                                  l[i].thickness_mm};
    dm_skin_ad_options opt = {.stream_count = stream_count};
    dm_skin_ad_result res;
    dm_result rc = dm_skin_ad_run(a, 2, p->eta, &opt, &res, NULL);
    assert(rc == DM_OK);
    (void)rc;
    return res.reflectance;
}
