#include "bake/dm_profile_fit.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_lsq.h"
#include "core/dm_math.h"

enum { NMAX = DM_PROFILE_MAX_GAUSSIANS };

/* ---- sources ------------------------------------------------------------------------ */

dm_result dm_profile_source_validate(const dm_profile_source *s, const char *what, dm_error *err)
{
    if (s->kind == DM_SOURCE_GAUSSIANS) return dm_profile_validate(&s->gaussians, what, err);
    if (s->kind == DM_SOURCE_MEDIUM) return dm_medium_validate(&s->medium, what, err);
    if (s->kind == DM_SOURCE_BURLEY) return dm_burley_validate(&s->burley, what, err);
    if (s->kind == DM_SOURCE_SKIN) return dm_skin_params_validate(&s->skin, what, err);
    return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: source kind %d, expected Gaussians, a medium, Burley or a skin",
                   what, (int)s->kind);
}

dm_result dm_profile_source_skin(const dm_skin_params *p, dm_profile_source *out, dm_error *err)
{
    memset(out, 0, sizeof *out);
    out->kind = DM_SOURCE_SKIN;
    out->skin = *p;
    dm_skin_report rep;
    dm_result r = dm_skin_physics_report(p, 0, &rep, err);
    if (r == DM_OK) memcpy(out->skin_total_rgb, rep.total_rgb, sizeof out->skin_total_rgb);
    return r == DM_OK ? dm_skin_dense_profile(p, 0, &out->skin_dense, err) : r;
}

void dm_profile_source_eval(const dm_profile_source *s, double r_mm, double rgb[3])
{
    if (s->kind == DM_SOURCE_GAUSSIANS)
        dm_profile_eval(&s->gaussians, r_mm, rgb);
    else if (s->kind == DM_SOURCE_BURLEY)
        dm_burley_eval(&s->burley, r_mm, rgb);
    else if (s->kind == DM_SOURCE_SKIN)
        dm_skin_dense_eval(&s->skin_dense, r_mm, rgb);
    else
        dm_medium_eval(&s->medium, r_mm, rgb);
}

void dm_profile_source_total(const dm_profile_source *s, double rgb[3])
{
    if (s->kind == DM_SOURCE_GAUSSIANS)
        dm_profile_channel_sums(&s->gaussians, rgb);
    else if (s->kind == DM_SOURCE_BURLEY)
        dm_burley_total(&s->burley, rgb);
    else if (s->kind == DM_SOURCE_SKIN)
        memcpy(rgb, s->skin_total_rgb, sizeof s->skin_total_rgb);
    else
        dm_medium_total(&s->medium, rgb);
}

/* Smallest and largest length scales of the source, mm: the Gaussians' σ, the medium's
 * real and virtual source depths, or Burley's d/10 (so that r_min = 1e-4 d resolves the
 * 1/r spike) and 3d (the slow exponential) over the channels with A > 0. */
static void source_scales(const dm_profile_source *s, double *lo, double *hi)
{
    if (s->kind == DM_SOURCE_BURLEY) {
        *lo = INFINITY;
        *hi = 0.0;
        for (int k = 0; k < 4; ++k) {
            int c = k % 3; /* k = 3: every albedo is 0, take channel R's scale */
            if (k == 3 ? *hi > 0.0 : s->burley.albedo[c] == 0.0) continue;
            double d = dm_burley_scale_mm(s->burley.albedo[c], s->burley.mfp_mm[c]);
            *lo = fmin(*lo, 0.1 * d);
            *hi = fmax(*hi, 3.0 * d);
        }
        return;
    }
    if (s->kind == DM_SOURCE_SKIN) { /* the dense Gaussians that carry weight (grid_init's cap
                                      * follows hi: lo may be 4 µm, a closed-form layer's spike) */
        const dm_skin_dense *d = &s->skin_dense;
        *lo = INFINITY;
        *hi = 0.0;
        for (int k = 0; k < DM_SKIN_DENSE_GAUSSIANS; ++k)
            if (d->weight[k][0] != 0.0 || d->weight[k][1] != 0.0 || d->weight[k][2] != 0.0) {
                *lo = fmin(*lo, sqrt(d->variance_mm2[k]));
                *hi = fmax(*hi, sqrt(d->variance_mm2[k]));
            }
        if (*hi == 0.0) *lo = *hi = 1.0; /* all-zero: the fit reports DM_ERR_EMPTY */
        return;
    }
    if (s->kind == DM_SOURCE_GAUSSIANS) {
        *lo = sqrt(s->gaussians.variance_mm2[0]);
        *hi = sqrt(s->gaussians.variance_mm2[s->gaussians.count - 1]);
        return;
    }
    const dm_medium *m = &s->medium;
    double fdr = dm_fresnel_diffuse_reflectance(m->eta), a = (1.0 + fdr) / (1.0 - fdr);
    *lo = INFINITY;
    *hi = 0.0;
    for (int c = 0; c < 3; ++c) {
        double zr = 1.0 / (m->sigma_a_per_mm[c] + m->sigma_s_prime_per_mm[c]);
        double zv = zr * (1.0 + 4.0 * a / 3.0);
        *lo = fmin(*lo, zr);
        *hi = fmax(*hi, zv);
    }
}

/* ---- quadrature grid ----------------------------------------------------------------- */

typedef struct grid {
    int m;
    double r_min, r_max;
    double *r;         /* m radii, log-spaced */
    double *q;         /* ∫ r f dr ≈ Σ q_i f(r_i) */
    double *sq;        /* √q_i */
    double *b[3];      /* √q_i R_c(r_i) */
    double energy[3];  /* E_c = Σ q_i R_c(r_i)² ≈ ∫ r R_c² dr */
    double *mem;
} grid;

static void grid_free(grid *g)
{
    free(g->mem);
    memset(g, 0, sizeof *g);
}

static double peak_r2(const dm_profile_source *s, double r)
{
    double v[3];
    dm_profile_source_eval(s, r, v);
    return r * r * fmax(v[0], fmax(v[1], v[2]));
}

static dm_result grid_init(grid *g, const dm_profile_source *s, int m, dm_error *err)
{
    memset(g, 0, sizeof *g);
    double lo, hi;
    source_scales(s, &lo, &hi);
    /* Burley: r_min = 1e-6 d, so that the disc [0, r_min], where r R ≈ A s/4π and r G → 0,
     * holds ~1e-6 of the norm; the cap then follows the widest scale instead. */
    int burley = s->kind == DM_SOURCE_BURLEY;
    g->r_min = (burley ? 1e-5 : 1e-3) * lo;
    /* r_max: walk out by √2 until r²R(r) (the profile's mass per unit ln r) has fallen
     * below 1e-10 of its peak, past the widest scale; at most 1e6·r_min (Burley and the
     * skin, whose scales span more: 1e3·hi). */
    double cap = burley || s->kind == DM_SOURCE_SKIN ? 1e3 * hi : 1e6 * g->r_min, peak = 0.0, r = g->r_min;
    for (;;) {
        double p = peak_r2(s, r);
        if (!isfinite(p)) return dm_fail(err, DM_ERR_NON_FINITE, "profile source: R(%g mm) is not finite", r);
        peak = fmax(peak, p);
        if ((r >= 3.0 * hi && p <= 1e-10 * peak) || r >= cap) break;
        r *= DM_SQRT2;
    }
    g->r_max = fmin(r, cap);
    g->m = m;
    g->mem = malloc(sizeof(double) * (size_t)m * 6);
    if (!g->mem) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "profile fit: %d quadrature nodes", m);
    g->r = g->mem;
    g->q = g->r + m;
    g->sq = g->q + m;
    for (int c = 0; c < 3; ++c) g->b[c] = g->sq + (size_t)m * (1 + c);
    double u0 = log(g->r_min), h = (log(g->r_max) - u0) / (m - 1);
    for (int i = 0; i < m; ++i) {
        double ri = i == m - 1 ? g->r_max : exp(u0 + i * h);
        double coef = (i == 0 || i == m - 1) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        g->r[i] = ri;
        /* dr = r du, and the weight r (r² for Burley: see dm_profile_fit.h) */
        g->q[i] = coef * h / 3.0 * ri * ri * (s->kind == DM_SOURCE_BURLEY ? ri : 1.0);
    }
    /* the disc [0, r_min]: f taken as f(r_min); for Burley r²f is taken as r_min² f(r_min)
     * (exact for the 1/r² of (R − G)² there) */
    g->q[0] += s->kind == DM_SOURCE_BURLEY ? g->r_min * g->r_min * g->r_min : 0.5 * g->r_min * g->r_min;
    for (int c = 0; c < 3; ++c) g->energy[c] = 0.0;
    for (int i = 0; i < m; ++i) {
        double v[3];
        dm_profile_source_eval(s, g->r[i], v);
        g->sq[i] = sqrt(g->q[i]);
        for (int c = 0; c < 3; ++c) {
            if (!isfinite(v[c]))
                return dm_fail(err, DM_ERR_NON_FINITE, "profile source: R[%d](%g mm) = %g, expected finite", c, g->r[i],
                               v[c]);
            g->b[c][i] = g->sq[i] * v[c];
            g->energy[c] += g->q[i] * v[c] * v[c];
        }
    }
    return DM_OK;
}

/* ---- variable projection ------------------------------------------------------------- */

typedef struct state {
    double x[NMAX];   /* ln v, ascending */
    double w[3][NMAX];
    double f;         /* Σ_c e_c / E_c */
    double fc[3];     /* e_c */
    double *res[3];   /* m each: A w_c − b_c */
    double *a, *d;    /* m × n: √q G and √q ∂G/∂ln v */
} state;

typedef struct fitter {
    const grid *g;
    int n;
    double x_lo, x_hi, gap;
    double *qrbuf, *ybuf, *jbuf; /* m × NMAX, m, m × NMAX scratch */
    double cap[3];               /* the most each channel's weights may sum to: 1 (cap_channel) */
    double *capbuf;              /* (m + 1) × (2 NMAX + 2) scratch of cap_channel */
    int capping;                 /* evaluate holds the sums to cap[] */
    int evaluations, iterations;
} fitter;

/* A fit returns at most the light it receives: where a channel's weights sum to more than 1
 * (the shape fit alone can overshoot a source whose total is 1: gems3-skin with 3 Gaussians
 * summed 1.036 in green, over dm_profile_validate's limit; a source of less total, such as a
 * dipole's, is left as the shape fit makes it, which the tools normalise), the weights are
 * solved again with Σ_k w_kc = cap: NNLS with the sum as one more row weighted 1e4 times the
 * largest column, then scaled onto the cap exactly (the row leaves it ~1e-8 off). The search
 * runs free first (the Kaufman Jacobian is the free projection's, and a cap met at the optimum
 * would slow it there: gems3-skin's own six Gaussians sum to exactly 1); only when its best
 * overshoots is it polished again with the cap inside evaluate, so the variances are found
 * for the capped weights. */
static void cap_channel(fitter *ft, state *st, int c)
{
    int m = ft->g->m, n = ft->n, rows = m + 1;
    double sum = 0.0, cap = ft->cap[c];
    for (int k = 0; k < n; ++k) sum += st->w[c][k];
    if (!(sum > cap * (1.0 + 1e-9)) || !(cap > 0.0)) return;
    double *a = ft->capbuf, *y = a + (size_t)rows * NMAX, *scratch = y + rows, norm = 0.0;
    for (int k = 0; k < n; ++k) {
        double q = 0.0;
        for (int i = 0; i < m; ++i) q += st->a[(size_t)k * m + i] * st->a[(size_t)k * m + i];
        norm = fmax(norm, sqrt(q));
    }
    double lambda = 1e4 * norm;
    for (int k = 0; k < n; ++k) {
        memcpy(a + (size_t)k * rows, st->a + (size_t)k * m, sizeof(double) * (size_t)m);
        a[(size_t)k * rows + m] = lambda;
    }
    memcpy(y, ft->g->b[c], sizeof(double) * (size_t)m);
    y[m] = lambda * cap;
    dm_lsq_nnls_shared(a, rows, n, y, 1, scratch, st->w[c]);
    sum = 0.0;
    for (int k = 0; k < n; ++k) sum += st->w[c][k];
    for (int k = 0; k < n && sum > 0.0; ++k) st->w[c][k] *= cap / sum;
}

static void evaluate(fitter *ft, state *st)
{
    const grid *g = ft->g;
    int m = g->m, n = ft->n;
    ++ft->evaluations;
    for (int k = 0; k < n; ++k) {
        double v = exp(st->x[k]);
        double *ak = st->a + (size_t)k * m, *dk = st->d + (size_t)k * m;
        for (int i = 0; i < m; ++i) {
            double r = g->r[i];
            double gi = g->sq[i] * dm_gaussian(v, r);
            ak[i] = gi;
            dk[i] = gi * (r * r / (2.0 * v) - 1.0);
        }
    }
    double beta[NMAX], rd[NMAX], rm[NMAX * NMAX];
    memcpy(ft->qrbuf, st->a, sizeof(double) * (size_t)m * n);
    dm_lsq_qr(ft->qrbuf, m, n, beta, rd);
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < n; ++i)
            rm[(size_t)k * n + i] = i < k ? ft->qrbuf[(size_t)k * m + i] : i == k ? rd[k] : 0.0;
    st->f = 0.0;
    for (int c = 0; c < 3; ++c) {
        memcpy(ft->ybuf, g->b[c], sizeof(double) * (size_t)m);
        dm_lsq_qr_apply(ft->qrbuf, m, n, beta, ft->ybuf);
        dm_lsq_nnls(rm, n, ft->ybuf, st->w[c]);
        if (ft->capping) cap_channel(ft, st, c);
        double e = 0.0;
        for (int i = 0; i < m; ++i) {
            double s = -g->b[c][i];
            for (int k = 0; k < n; ++k) s += st->a[(size_t)k * m + i] * st->w[c][k];
            st->res[c][i] = s;
            e += s * s;
        }
        st->fc[c] = e;
        if (g->energy[c] > 0.0) st->f += e / g->energy[c];
    }
}

/* Keeps the log-variances sorted, inside [x_lo, x_hi] and at least gap apart. */
static void project(const fitter *ft, double *x)
{
    int n = ft->n;
    for (int k = 0; k < n; ++k) x[k] = dm_clamp(x[k], ft->x_lo, ft->x_hi);
    for (int k = 1; k < n; ++k) /* insertion sort: n ≤ 8, deterministic */
        for (int j = k; j > 0 && x[j] < x[j - 1]; --j) {
            double t = x[j];
            x[j] = x[j - 1];
            x[j - 1] = t;
        }
    for (int k = 1; k < n; ++k) x[k] = fmax(x[k], x[k - 1] + ft->gap);
    if (x[n - 1] > ft->x_hi) {
        x[n - 1] = ft->x_hi;
        for (int k = n - 2; k >= 0; --k) x[k] = fmin(x[k], x[k + 1] - ft->gap);
    }
}

static void copy_state(const fitter *ft, state *dst, const state *src)
{
    size_t m = (size_t)ft->g->m, n = (size_t)NMAX;
    memcpy(dst->x, src->x, sizeof src->x);
    memcpy(dst->w, src->w, sizeof src->w);
    memcpy(dst->fc, src->fc, sizeof src->fc);
    dst->f = src->f;
    for (int c = 0; c < 3; ++c) memcpy(dst->res[c], src->res[c], sizeof(double) * m);
    memcpy(dst->a, src->a, sizeof(double) * m * n);
    memcpy(dst->d, src->d, sizeof(double) * m * n);
}

/* Levenberg–Marquardt on the log-variances from cur (evaluated); trial is scratch. */
static void levenberg_marquardt(fitter *ft, state *cur, state *trial, int iterations)
{
    const grid *g = ft->g;
    int m = g->m, n = ft->n;
    double lambda = 1e-3;
    int stalled = 0;
    for (int it = 0; it < iterations && cur->f > 1e-30; ++it) {
        /* Kaufman's Jacobian of the variable-projection residual: for channel c,
         * J_c,k = w_kc P⊥_c D_k, P⊥_c the projector off the span of the columns of A in
         * that channel's passive set (w > 0). The gradient Jᵀr needs no projector (r is
         * already orthogonal to that span). Scaled by 1/E_c like the objective. */
        double jtj[NMAX * NMAX] = {0}, jtr[NMAX] = {0};
        for (int c = 0; c < 3; ++c) {
            if (!(g->energy[c] > 0.0)) continue;
            int idx[NMAX], p = 0;
            for (int k = 0; k < n; ++k)
                if (cur->w[c][k] > 0.0) {
                    memcpy(ft->qrbuf + (size_t)p * m, cur->a + (size_t)k * m, sizeof(double) * (size_t)m);
                    idx[p++] = k;
                }
            if (p == 0) continue;
            double beta[NMAX], rd[NMAX];
            dm_lsq_qr(ft->qrbuf, m, p, beta, rd);
            for (int t = 0; t < p; ++t) {
                int k = idx[t];
                double *jk = ft->jbuf + (size_t)t * m;
                const double *dk = cur->d + (size_t)k * m;
                for (int i = 0; i < m; ++i) jk[i] = cur->w[c][k] * dk[i];
                dm_lsq_qr_apply(ft->qrbuf, m, p, beta, jk);
                for (int i = 0; i < p; ++i) jk[i] = 0.0;
                dm_lsq_qr_apply_q(ft->qrbuf, m, p, beta, jk);
                double s = 0.0;
                for (int i = 0; i < m; ++i) s += dk[i] * cur->res[c][i];
                jtr[k] += cur->w[c][k] * s / g->energy[c];
            }
            for (int t = 0; t < p; ++t)
                for (int u = 0; u <= t; ++u) {
                    const double *jt = ft->jbuf + (size_t)t * m, *ju = ft->jbuf + (size_t)u * m;
                    double s = 0.0;
                    for (int i = 0; i < m; ++i) s += jt[i] * ju[i];
                    s /= g->energy[c];
                    jtj[idx[t] * n + idx[u]] += s;
                    if (u != t) jtj[idx[u] * n + idx[t]] += s;
                }
        }
        double trace = 0.0;
        for (int k = 0; k < n; ++k) trace += jtj[k * n + k];
        double floor_diag = 1e-9 * trace / n + 1e-300;
        int accepted = 0;
        while (lambda < 1e12) {
            double sys[NMAX * NMAX], rhs[NMAX], step[NMAX];
            memcpy(sys, jtj, sizeof sys);
            for (int k = 0; k < n; ++k) {
                sys[k * n + k] += lambda * fmax(jtj[k * n + k], floor_diag);
                rhs[k] = -jtr[k];
            }
            if (!dm_lsq_cholesky_solve(sys, n, rhs, step)) {
                lambda *= 4.0;
                continue;
            }
            for (int k = 0; k < n; ++k) trial->x[k] = cur->x[k] + dm_clamp(step[k], -2.0, 2.0);
            project(ft, trial->x);
            evaluate(ft, trial);
            if (trial->f < cur->f) {
                double gain = (cur->f - trial->f) / cur->f;
                state t = *cur;
                *cur = *trial;
                *trial = t;
                lambda = fmax(lambda / 3.0, 1e-9);
                accepted = 1;
                ++ft->iterations;
                stalled = gain < 1e-10 ? stalled + 1 : 0;
                break;
            }
            lambda *= 4.0;
        }
        if (!accepted || stalled >= 3) break;
    }
}

static int state_alloc(state *st, int m, int n, double *mem)
{
    for (int c = 0; c < 3; ++c) st->res[c] = mem + (size_t)m * c;
    st->a = mem + (size_t)m * 3;
    st->d = st->a + (size_t)m * n;
    return 3 * m + 2 * m * n;
}

static dm_result check_options(const dm_fit_options *opt, int *n, int *m, int *iters, dm_error *err)
{
    dm_fit_options o = {0};
    if (opt) o = *opt;
    *n = o.gaussian_count ? o.gaussian_count : DM_FIT_GAUSSIANS_DEFAULT;
    *m = o.node_count ? o.node_count : DM_FIT_NODES_DEFAULT;
    *iters = o.iterations ? o.iterations : DM_FIT_ITERATIONS_DEFAULT;
    if (*n < 1 || *n > NMAX)
        return dm_fail(err, DM_ERR_RANGE, "profile fit: %d Gaussians, expected 1..%d", *n, NMAX);
    if (*m < DM_FIT_NODES_MIN || *m > DM_FIT_NODES_MAX || *m % 2 == 0)
        return dm_fail(err, DM_ERR_RANGE, "profile fit: %d quadrature nodes, expected an odd count in %d..%d", *m,
                       DM_FIT_NODES_MIN, DM_FIT_NODES_MAX);
    if (*iters < 1 || *iters > 10000)
        return dm_fail(err, DM_ERR_RANGE, "profile fit: %d iterations, expected 1..10000", *iters);
    return DM_OK;
}

dm_result dm_profile_fit(const dm_profile_source *s, const dm_fit_options *opt, const char *name,
                         dm_fit_result *out, dm_error *err)
{
    memset(out, 0, sizeof *out);
    int n, m, iters;
    dm_result r = check_options(opt, &n, &m, &iters, err);
    if (r == DM_OK) r = dm_profile_source_validate(s, "profile source", err);
    if (r != DM_OK) return r;
    grid g;
    if ((r = grid_init(&g, s, m, err)) != DM_OK) {
        grid_free(&g);
        return r;
    }
    if (!(g.energy[0] > 0.0 || g.energy[1] > 0.0 || g.energy[2] > 0.0)) {
        grid_free(&g);
        return dm_fail(err, DM_ERR_EMPTY, "profile source: R(r) is zero in every channel, nothing to fit");
    }

    /* Seeds: the narrowest scale from R(0) (a Gaussian has v = Rd / (2π R(0))), the widest
     * from the second moment (a Gaussian has ∫ 2πr r² G dr / Rd = 2v). */
    double seed_lo = INFINITY, seed_hi = 0.0;
    for (int c = 0; c < 3; ++c) {
        double t = 0.0, m2 = 0.0, r0 = g.b[c][0] / g.sq[0];
        for (int i = 0; i < m; ++i) {
            double ri = g.b[c][i] / g.sq[i];
            t += g.q[i] * ri;
            m2 += g.q[i] * g.r[i] * g.r[i] * ri;
        }
        if (!(t > 0.0) || !(r0 > 0.0)) continue;
        seed_lo = fmin(seed_lo, t / (DM_2PI * r0));
        seed_hi = fmax(seed_hi, m2 / (2.0 * t));
    }
    if (!(seed_lo < INFINITY)) seed_lo = g.r_min * g.r_min * 100.0; /* a channel with R(0) = 0 only */
    if (!(seed_hi > seed_lo)) seed_hi = seed_lo * 10.0;

    fitter ft = {.g = &g, .n = n};
    ft.x_lo = log(100.0 * g.r_min * g.r_min);
    ft.x_hi = log(g.r_max * g.r_max / 16.0);
    ft.gap = log(DM_FIT_MIN_RATIO);
    size_t per_state = (size_t)(3 * m + 2 * m * NMAX);
    size_t cap_size = (size_t)(m + 1) * (2 * NMAX + 2);
    double *mem = malloc(sizeof(double) * (per_state * 4 + (size_t)m * NMAX * 2 + (size_t)m + cap_size));
    if (!mem) {
        grid_free(&g);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "profile fit: %d nodes x %d Gaussians", m, n);
    }
    state cur, trial, best, level;
    double *p = mem;
    p += state_alloc(&cur, m, NMAX, p);
    p += state_alloc(&trial, m, NMAX, p);
    p += state_alloc(&best, m, NMAX, p);
    p += state_alloc(&level, m, NMAX, p);
    ft.qrbuf = p;
    ft.ybuf = p + (size_t)m * NMAX;
    ft.jbuf = ft.ybuf + m;
    ft.capbuf = ft.jbuf + (size_t)m * NMAX;
    for (int c = 0; c < 3; ++c) ft.cap[c] = 1.0;

    /* Continuation in the count: the best fit with k − 1 Gaussians plus one new Gaussian
     * tried in every gap and beyond either end; the best of those seeds k. At k = n the
     * geometric starts compete as well, and the winner is polished. */
    static const double spread[DM_FIT_STARTS][2] = {{1.0, 1.0}, {0.25, 4.0}, {1.0 / 16.0, 2.0}, {0.5, 16.0}};
    double prev[NMAX];
    for (int k = 1; k <= n; ++k) {
        ft.n = k;
        level.f = INFINITY;
        int cands = k == 1 ? 0 : k;
        for (int j = 0; j < cands; ++j) {
            int t = 0;
            for (int i = 0; i < k - 1; ++i) {
                if (i == j) cur.x[t++] = i == 0 ? prev[0] - 1.5 : 0.5 * (prev[i - 1] + prev[i]);
                cur.x[t++] = prev[i];
            }
            if (j == k - 1) cur.x[t++] = prev[k - 2] + 1.5;
            project(&ft, cur.x);
            evaluate(&ft, &cur);
            levenberg_marquardt(&ft, &cur, &trial, iters / 2 + 1);
            if (cur.f < level.f) copy_state(&ft, &level, &cur);
        }
        if (k == 1 || k == n) {
            for (int st = 0; st < DM_FIT_STARTS; ++st) {
                double a = log(seed_lo * spread[st][0]), b = log(seed_hi * spread[st][1]);
                for (int i = 0; i < k; ++i) cur.x[i] = a + (i + 0.5) / k * (b - a);
                project(&ft, cur.x);
                evaluate(&ft, &cur);
                levenberg_marquardt(&ft, &cur, &trial, iters / 2 + 1);
                if (cur.f < level.f) copy_state(&ft, &level, &cur);
            }
        }
        if (k == n) {
            copy_state(&ft, &best, &level);
            levenberg_marquardt(&ft, &best, &trial, iters);
        }
        memcpy(prev, level.x, sizeof prev);
    }
    for (int c = 0; c < 3; ++c) {
        double sum = 0.0;
        for (int k = 0; k < n; ++k) sum += best.w[c][k];
        if (sum > ft.cap[c] * (1.0 + 1e-9)) ft.capping = 1;
    }
    if (ft.capping) {
        evaluate(&ft, &best);
        levenberg_marquardt(&ft, &best, &trial, iters);
    }

    dm_profile *pf = &out->profile;
    snprintf(pf->name, sizeof pf->name, "%s", name ? name : "");
    pf->count = n;
    for (int k = 0; k < n; ++k) {
        pf->variance_mm2[k] = exp(best.x[k]);
        for (int c = 0; c < 3; ++c) pf->weight[k][c] = best.w[c][k];
    }
    for (int c = 0; c < 3; ++c) {
        out->error_relative[c] = g.energy[c] > 0.0 ? sqrt(best.fc[c] / g.energy[c]) : 0.0;
        out->error_relative_max = fmax(out->error_relative_max, out->error_relative[c]);
    }
    out->r_min_mm = g.r_min;
    out->r_max_mm = g.r_max;
    out->iterations = ft.iterations;
    out->evaluations = ft.evaluations;
    free(mem);
    grid_free(&g);
    return dm_profile_validate(pf, "profile fit result", err);
}

dm_result dm_profile_fit_error(const dm_profile_source *s, const dm_profile *p, const dm_fit_options *opt,
                               double error_relative[3], dm_error *err)
{
    int n, m, iters;
    dm_result r = check_options(opt, &n, &m, &iters, err);
    if (r == DM_OK) r = dm_profile_source_validate(s, "profile source", err);
    if (r == DM_OK) r = dm_profile_validate(p, "profile", err);
    if (r != DM_OK) return r;
    grid g;
    if ((r = grid_init(&g, s, m, err)) == DM_OK) {
        for (int c = 0; c < 3; ++c) {
            double e = 0.0;
            for (int i = 0; i < m; ++i) {
                double v[3];
                dm_profile_eval(p, g.r[i], v);
                double d = g.b[c][i] - g.sq[i] * v[c];
                e += d * d;
            }
            error_relative[c] = g.energy[c] > 0.0 ? sqrt(e / g.energy[c]) : 0.0;
        }
    }
    grid_free(&g);
    return r;
}

/* ---- a dense representation ----------------------------------------------------------- */

dm_result dm_profile_represent(const dm_profile_source *s, int gaussian_count, double *variance_mm2,
                               double (*weight)[3], double rel_error[3], dm_error *err)
{
    const int n = gaussian_count, m = DM_FIT_NODES_DEFAULT;
    if (n < 2 || n > DM_PROFILE_REPRESENT_MAX)
        return dm_fail(err, DM_ERR_RANGE, "profile representation: %d Gaussians, expected 2..%d", n,
                       DM_PROFILE_REPRESENT_MAX);
    dm_result r = dm_profile_source_validate(s, "profile source", err);
    if (r != DM_OK) return r;
    grid g;
    if ((r = grid_init(&g, s, m, err)) != DM_OK) {
        grid_free(&g);
        return r;
    }
    /* scales: from a quarter of the narrowest source scale to a third of the radius that
     * holds all but 1e-4 of the widest channel's mass */
    double lo, hi, total[3] = {0, 0, 0}, cum[3] = {0, 0, 0}, r_mass = g.r_max;
    source_scales(s, &lo, &hi);
    for (int i = 0; i < m; ++i)
        for (int c = 0; c < 3; ++c) total[c] += g.q[i] * g.b[c][i] / g.sq[i];
    for (int i = 0, done = 0; i < m && !done; ++i) {
        done = 1;
        for (int c = 0; c < 3; ++c) {
            cum[c] += g.q[i] * g.b[c][i] / g.sq[i];
            done &= !(total[c] > 0.0) || cum[c] >= (1.0 - 1e-4) * total[c];
        }
        r_mass = g.r[i];
    }
    double s_lo = 0.25 * lo, s_hi = fmax(r_mass / 3.0, 2.0 * s_lo);
    for (int k = 0; k < n; ++k) {
        double sk = s_lo * pow(s_hi / s_lo, (double)k / (n - 1));
        variance_mm2[k] = sk * sk;
    }
    /* a (m × n), the scratch of dm_lsq_nnls_shared (m × (n + 1)), the three channels as
     * right-hand sides (m × 3) and their weights (n × 3) */
    double *a = malloc(sizeof(double) * ((size_t)m * (2 * n + 4) + 3 * (size_t)n));
    if (!a) {
        grid_free(&g);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "profile representation");
    }
    double *scratch = a + (size_t)m * n, *y = scratch + (size_t)m * (n + 1), *w = y + 3 * (size_t)m;
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < m; ++i) a[(size_t)k * m + i] = g.sq[i] * dm_gaussian(variance_mm2[k], g.r[i]);
    for (int c = 0; c < 3; ++c) memcpy(y + (size_t)c * m, g.b[c], sizeof(double) * (size_t)m);
    dm_lsq_nnls_shared(a, m, n, y, 3, scratch, w);
    for (int c = 0; c < 3; ++c) {
        double e = 0.0;
        for (int i = 0; i < m; ++i) {
            double d = -g.b[c][i];
            for (int k = 0; k < n; ++k) d += a[(size_t)k * m + i] * w[(size_t)c * n + k];
            e += d * d;
        }
        for (int k = 0; k < n; ++k) weight[k][c] = w[(size_t)c * n + k];
        rel_error[c] = g.energy[c] > 0.0 ? sqrt(e / g.energy[c]) : 0.0;
    }
    free(a);
    grid_free(&g);
    return DM_OK;
}

dm_result dm_profile_source_parse(const char *spec, bool burley, bool multipole, double thickness_mm, int pair_count,
                                  const char *what, dm_profile_source *out, dm_error *err)
{
    *out = (dm_profile_source){.kind = burley ? DM_SOURCE_BURLEY : DM_SOURCE_MEDIUM};
    if (!burley)
        return dm_medium_parse(spec, multipole ? DM_MODEL_MULTIPOLE : DM_MODEL_DIPOLE, thickness_mm, pair_count, what,
                               &out->medium, err);
    const char *slash = strchr(spec, '/');
    if (!slash)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: '%s': expected ALBEDO/MFP, e.g. 0.8,0.6,0.4/1,0.5,0.25", what,
                       spec);
    char albedo[256];
    snprintf(albedo, sizeof albedo, "%.*s", (int)(slash - spec), spec);
    return dm_burley_parse(albedo, slash + 1, what, &out->burley, err);
}
