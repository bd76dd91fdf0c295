/* dm_skin_mc.c — MCML-style Monte Carlo of a layered slab (method in dm_skin_mc.h). */
#include "bake/dm_skin_mc.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_math.h"
#include "core/dm_parallel.h"

#define COS_ZERO (1.0 - 1e-12) /* |cos| above this: treat the direction as vertical */
#define COS_90 1e-6            /* cos below this: grazing, reflect whole */

/* ---- random numbers: xoshiro256** seeded by splitmix64 from (seed, batch) ---- */

typedef struct rng {
    uint64_t s[4];
} rng;

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

static uint64_t xoshiro_next(rng *r)
{
    uint64_t *s = r->s, out = rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return out;
}

/* One stream per batch: the batch index is hashed into the seed before expanding it, so
 * neighbouring batches (and neighbouring seeds) start far apart. */
static void rng_seed(rng *r, uint64_t seed, uint64_t batch)
{
    uint64_t x = seed, h = splitmix64(&x);
    x = h ^ (batch * 0xD1B54A32D192ED03ull);
    x = splitmix64(&x);
    for (int i = 0; i < 4; ++i) r->s[i] = splitmix64(&x);
}

/* Uniform in (0, 1]: never 0, so −ln ξ is finite. */
static double rng_uniform(rng *r) { return ((xoshiro_next(r) >> 11) + 1) * 0x1.0p-53; }

/* ---- physics ---- */

double dm_skin_mc_fresnel(double n_i, double n_t, double cos_i)
{
    if (n_i == n_t) return 0.0;
    if (cos_i > COS_ZERO) {
        double r = (n_i - n_t) / (n_i + n_t);
        return r * r;
    }
    if (cos_i < COS_90) return 1.0;
    double sin_i = sqrt(1.0 - cos_i * cos_i), sin_t = n_i / n_t * sin_i;
    if (sin_t >= 1.0) return 1.0; /* total internal reflection */
    double cos_t = sqrt(1.0 - sin_t * sin_t);
    double rs = (n_i * cos_i - n_t * cos_t) / (n_i * cos_i + n_t * cos_t);
    double rp = (n_i * cos_t - n_t * cos_i) / (n_i * cos_t + n_t * cos_i);
    return 0.5 * (rs * rs + rp * rp);
}

/* cos θ from the Henyey–Greenstein phase function by inversion of its CDF. */
static double hg_cos(double g, double xi)
{
    if (fabs(g) < 1e-9) return 2.0 * xi - 1.0;
    double f = (1.0 - g * g) / (1.0 - g + 2.0 * g * xi);
    double c = (1.0 + g * g - f * f) / (2.0 * g);
    if (!(c >= -1.0)) c = -1.0; /* also NaN, for g = −1 and ξ = 1 */
    if (c > 1.0) c = 1.0;
    return c;
}

typedef struct photon {
    double x, y, z, ux, uy, uz, w;
    int layer;
} photon;

/* Turns the direction by polar angle θ (cos_t) and azimuth ψ about the current direction. */
static void spin(photon *p, double cos_t, double psi)
{
    double sin_t = sqrt(fmax(0.0, 1.0 - cos_t * cos_t)), cp = cos(psi), sp = sin(psi);
    if (fabs(p->uz) > COS_ZERO) {
        p->ux = sin_t * cp;
        p->uy = sin_t * sp;
        p->uz = p->uz >= 0 ? cos_t : -cos_t;
        return;
    }
    double t = sqrt(1.0 - p->uz * p->uz);
    double ux = sin_t * (p->ux * p->uz * cp - p->uy * sp) / t + p->ux * cos_t;
    double uy = sin_t * (p->uy * p->uz * cp + p->ux * sp) / t + p->uy * cos_t;
    double uz = -sin_t * cp * t + p->uz * cos_t;
    double norm = 1.0 / sqrt(ux * ux + uy * uy + uz * uz); /* keeps rounding from piling up */
    p->ux = ux * norm;
    p->uy = uy * norm;
    p->uz = uz * norm;
}

/* The stack as the walk sees it. */
typedef struct stack {
    int layers;
    double z_top[DM_SKIN_MC_LAYERS_MAX], z_bottom[DM_SKIN_MC_LAYERS_MAX];
    double mu_a[DM_SKIN_MC_LAYERS_MAX], mu_t[DM_SKIN_MC_LAYERS_MAX], g[DM_SKIN_MC_LAYERS_MAX];
    double n[DM_SKIN_MC_LAYERS_MAX + 2]; /* n[0] above, n[i + 1] layer i, n[layers + 1] below */
    double specular;
    int bins;
    double dr;
    uint32_t step_limit;
} stack;

/* Slots of one batch's tally (doubles): Rd, Tt, unfinished weight, unfinished count,
 * beyond bins, then absorbed per layer, then the radial bins. */
enum { T_RD, T_TT, T_UNF_W, T_UNF_N, T_BEYOND, T_ABS };

static size_t tally_size(const stack *s) { return (size_t)T_ABS + (size_t)s->layers + (size_t)s->bins; }

/* The packet meets the interface it is heading for; reflects, or refracts into the next
 * layer, or leaves (tallied). Returns 0 when the packet has left. */
static int cross(const stack *s, photon *p, rng *r, double *t)
{
    int down = p->uz > 0;
    int next = p->layer + (down ? 1 : -1); /* −1: above, layers: below */
    double n_i = s->n[p->layer + 1], n_t = s->n[next + 1], cos_i = fabs(p->uz);
    double refl = dm_skin_mc_fresnel(n_i, n_t, cos_i);
    if (refl >= 1.0 || (refl > 0.0 && rng_uniform(r) <= refl)) {
        p->uz = -p->uz;
        return 1;
    }
    if (next < 0 || next >= s->layers) {
        if (next < 0) {
            t[T_RD] += p->w;
            double rr = sqrt(p->x * p->x + p->y * p->y);
            double bin = s->bins ? rr / s->dr : 0.0;
            if (bin < s->bins) t[T_ABS + s->layers + (int)bin] += p->w;
            else t[T_BEYOND] += p->w;
        } else {
            t[T_TT] += p->w;
        }
        return 0;
    }
    if (n_i != n_t) {
        double ratio = n_i / n_t, sin2_t = ratio * ratio * (1.0 - cos_i * cos_i);
        double cos_t = sqrt(fmax(0.0, 1.0 - sin2_t));
        p->ux *= ratio;
        p->uy *= ratio;
        p->uz = down ? cos_t : -cos_t;
    }
    p->layer = next;
    return 1;
}

/* One photon packet from launch to its end, tallied into t. */
static void run_photon(const stack *s, rng *r, double *t)
{
    photon p = {.uz = 1.0, .w = 1.0 - s->specular};
    double s_left = 0.0; /* remaining free path, in mean free paths */
    for (uint32_t step = 0;; ++step) {
        if (step >= s->step_limit) {
            t[T_UNF_W] += p.w;
            t[T_UNF_N] += 1.0;
            return;
        }
        int l = p.layer;
        double mu_t = s->mu_t[l];
        if (s_left <= 0.0) s_left = -log(rng_uniform(r));
        double path = mu_t > 0.0 ? s_left / mu_t : INFINITY;
        double to_edge = p.uz > 0 ? (s->z_bottom[l] - p.z) / p.uz : p.uz < 0 ? (s->z_top[l] - p.z) / p.uz : INFINITY;
        if (to_edge <= path) {
            if (isinf(to_edge)) { /* a clear semi-infinite layer, heading down: never returns */
                t[T_UNF_W] += p.w;
                t[T_UNF_N] += 1.0;
                return;
            }
            p.x += to_edge * p.ux;
            p.y += to_edge * p.uy;
            p.z = p.uz > 0 ? s->z_bottom[l] : s->z_top[l];
            s_left = mu_t > 0.0 ? fmax(0.0, s_left - to_edge * mu_t) : s_left;
            if (!cross(s, &p, r, t)) return;
            /* the remainder is in mean free paths, so it carries into the next layer as is */
            continue;
        }
        p.x += path * p.ux;
        p.y += path * p.uy;
        p.z += path * p.uz;
        s_left = 0.0;
        double dw = p.w * s->mu_a[l] / mu_t;
        t[T_ABS + l] += dw;
        p.w -= dw;
        if (s->mu_a[l] < mu_t) spin(&p, hg_cos(s->g[l], rng_uniform(r)), DM_2PI * rng_uniform(r));
        if (p.w < DM_SKIN_MC_ROULETTE_WEIGHT) {
            if (p.w > 0.0 && rng_uniform(r) <= DM_SKIN_MC_ROULETTE_CHANCE) p.w /= DM_SKIN_MC_ROULETTE_CHANCE;
            else return;
        }
    }
}

/* ---- batches over the thread pool ---- */

typedef struct job {
    const stack *s;
    uint64_t photons, seed;
    uint64_t batch_photons;
    double *tallies; /* batch_count × tally_size */
} job;

static void run_batches(void *ctx, size_t begin, size_t end)
{
    const job *j = ctx;
    size_t size = tally_size(j->s);
    for (size_t b = begin; b < end; ++b) {
        double *t = j->tallies + b * size;
        memset(t, 0, size * sizeof *t);
        rng r;
        rng_seed(&r, j->seed, b);
        uint64_t first = b * j->batch_photons;
        uint64_t count = j->photons - first < j->batch_photons ? j->photons - first : j->batch_photons;
        for (uint64_t i = 0; i < count; ++i) run_photon(j->s, &r, t);
    }
}

static int finite_nonneg(double v) { return isfinite(v) && v >= 0.0; }

dm_result dm_skin_mc_validate(const dm_skin_mc_desc *d, const char *what, dm_error *err)
{
    if (!what) what = "dm_skin_mc";
    if (!d || !d->layers || d->layer_count < 1 || d->layer_count > DM_SKIN_MC_LAYERS_MAX)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: layer_count %d, expected 1..%d layers", what,
                       d ? d->layer_count : 0, DM_SKIN_MC_LAYERS_MAX);
    for (int i = 0; i < d->layer_count; ++i) {
        const dm_skin_mc_layer *L = &d->layers[i];
        if (!(L->n >= 1.0 && L->n <= DM_SKIN_MC_INDEX_MAX))
            return dm_fail(err, DM_ERR_RANGE, "%s: layer %d: n = %g, expected [1, %g]", what, i, L->n,
                           DM_SKIN_MC_INDEX_MAX);
        if (!finite_nonneg(L->mu_a_per_mm))
            return dm_fail(err, DM_ERR_RANGE, "%s: layer %d: mu_a = %g mm^-1, expected finite and >= 0", what, i,
                           L->mu_a_per_mm);
        if (!finite_nonneg(L->mu_s_per_mm))
            return dm_fail(err, DM_ERR_RANGE, "%s: layer %d: mu_s = %g mm^-1, expected finite and >= 0", what, i,
                           L->mu_s_per_mm);
        if (!(L->g >= -1.0 && L->g <= 1.0))
            return dm_fail(err, DM_ERR_RANGE, "%s: layer %d: g = %g, expected [-1, 1]", what, i, L->g);
        int last = i == d->layer_count - 1;
        if (!(L->thickness_mm > 0.0) || (isinf(L->thickness_mm) && !last))
            return dm_fail(err, DM_ERR_RANGE, "%s: layer %d: thickness = %g mm, expected > 0 (infinite for the last "
                           "layer only)", what, i, L->thickness_mm);
    }
    double ambient[2] = {d->n_above, d->n_below};
    for (int k = 0; k < 2; ++k)
        if (!(ambient[k] == 0.0 || (ambient[k] >= 1.0 && ambient[k] <= DM_SKIN_MC_INDEX_MAX)))
            return dm_fail(err, DM_ERR_RANGE, "%s: %s = %g, expected 0 (= 1.0) or [1, %g]", what,
                           k ? "n_below" : "n_above", ambient[k], DM_SKIN_MC_INDEX_MAX);
    if (d->photon_count < 1) return dm_fail(err, DM_ERR_EMPTY, "%s: photon_count is 0, expected >= 1", what);
    if (d->batch_photon_count < 0)
        return dm_fail(err, DM_ERR_RANGE, "%s: batch_photon_count = %d, expected >= 0", what, d->batch_photon_count);
    if (d->radial_bin_count < 0 || d->radial_bin_count > DM_SKIN_MC_RADIAL_BINS_MAX)
        return dm_fail(err, DM_ERR_RANGE, "%s: radial_bin_count = %d, expected 0..%d", what, d->radial_bin_count,
                       DM_SKIN_MC_RADIAL_BINS_MAX);
    if (d->radial_bin_count > 0 && !(d->dr_mm > 0.0 && isfinite(d->dr_mm)))
        return dm_fail(err, DM_ERR_RANGE, "%s: dr = %g mm, expected finite and > 0", what, d->dr_mm);
    return DM_OK;
}

/* Mean of per-photon values from batch sums, and the standard error from the spread of the
 * batch means (weighted by batch size; the last batch may be short). */
static void mean_se(const double *tallies, size_t stride, size_t slot, uint64_t batches, uint64_t batch_photons,
                    uint64_t photons, double scale, double *mean, double *se)
{
    double sum = 0.0;
    for (uint64_t b = 0; b < batches; ++b) sum += tallies[b * stride + slot];
    double m = sum / (double)photons;
    double var = 0.0;
    for (uint64_t b = 0; b < batches; ++b) {
        double n_b = (double)(b + 1 < batches ? batch_photons : photons - b * batch_photons);
        double dev = tallies[b * stride + slot] - n_b * m; /* n_b (x̄_b − x̄) */
        var += dev * dev;
    }
    var = batches > 1 ? var * (double)batches / ((double)(batches - 1) * (double)photons * (double)photons) : 0.0;
    *mean = m * scale;
    if (se) *se = sqrt(var) * scale;
}

dm_result dm_skin_mc_run(const dm_skin_mc_desc *d, dm_skin_mc_result *out, dm_error *err)
{
    dm_result rc = dm_skin_mc_validate(d, "dm_skin_mc_run", err);
    if (rc != DM_OK) return rc;
    stack s = {.layers = d->layer_count, .bins = d->radial_bin_count, .dr = d->dr_mm};
    s.step_limit = d->step_limit ? d->step_limit : DM_SKIN_MC_STEP_LIMIT_DEFAULT;
    s.n[0] = d->n_above > 0.0 ? d->n_above : 1.0;
    s.n[s.layers + 1] = d->n_below > 0.0 ? d->n_below : 1.0;
    double z = 0.0;
    for (int i = 0; i < s.layers; ++i) {
        const dm_skin_mc_layer *L = &d->layers[i];
        s.z_top[i] = z;
        z += L->thickness_mm;
        s.z_bottom[i] = z;
        s.mu_a[i] = L->mu_a_per_mm;
        s.mu_t[i] = L->mu_a_per_mm + L->mu_s_per_mm;
        s.g[i] = L->g;
        s.n[i + 1] = L->n;
    }
    s.specular = dm_skin_mc_fresnel(s.n[0], s.n[1], 1.0);

    uint64_t batch = d->batch_photon_count > 0 ? (uint64_t)d->batch_photon_count : DM_SKIN_MC_BATCH_DEFAULT;
    uint64_t batches = (d->photon_count + batch - 1) / batch;
    size_t stride = tally_size(&s);
    double *tallies = malloc(batches * stride * sizeof *tallies);
    if (!tallies)
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "dm_skin_mc_run: %llu batches x %zu tallies",
                       (unsigned long long)batches, stride);
    job j = {.s = &s, .photons = d->photon_count, .seed = d->seed, .batch_photons = batch, .tallies = tallies};
    dm_parallel_for((size_t)batches, 1, d->thread_count, run_batches, &j);

    double *rd_r = out->rd_r_per_mm2, *rd_r_se = out->rd_r_se_per_mm2;
    memset(out, 0, sizeof *out);
    out->rd_r_per_mm2 = rd_r;
    out->rd_r_se_per_mm2 = rd_r_se;
    out->specular = s.specular;
    out->batch_count = batches;
    uint64_t N = d->photon_count;
    mean_se(tallies, stride, T_RD, batches, batch, N, 1.0, &out->diffuse_reflectance, &out->diffuse_reflectance_se);
    mean_se(tallies, stride, T_TT, batches, batch, N, 1.0, &out->transmittance, &out->transmittance_se);
    mean_se(tallies, stride, T_UNF_W, batches, batch, N, 1.0, &out->unfinished, NULL);
    mean_se(tallies, stride, T_BEYOND, batches, batch, N, 1.0, &out->reflectance_beyond_bins, NULL);
    double unfinished_n = 0.0;
    for (uint64_t b = 0; b < batches; ++b) unfinished_n += tallies[b * stride + T_UNF_N];
    out->unfinished_photon_count = (uint64_t)unfinished_n;
    for (int i = 0; i < s.layers; ++i)
        mean_se(tallies, stride, T_ABS + (size_t)i, batches, batch, N, 1.0, &out->absorbed[i], &out->absorbed_se[i]);
    for (int i = 0; i < s.bins; ++i) {
        double area = DM_PI * s.dr * s.dr * (2.0 * i + 1.0); /* π((i+1)² − i²) dr² */
        double m, se;
        mean_se(tallies, stride, T_ABS + (size_t)s.layers + (size_t)i, batches, batch, N, 1.0 / area, &m, &se);
        if (rd_r) rd_r[i] = m;
        if (rd_r_se) rd_r_se[i] = se;
    }
    free(tallies);
    return DM_OK;
}
