#include "bake/dm_env_prefilter.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_brdf.h"
#include "core/dm_cli.h"
#include "core/dm_equirect.h"
#include "core/dm_math.h"
#include "core/dm_parallel.h"

int dm_env_level_width(double m, int max_width, int source_width)
{
    double want = 4.0 * DM_PI / (m > DM_ENV_M_MIN ? m : DM_ENV_M_MIN);
    int w = 16;
    while (w < want && w < (1 << 20)) w *= 2;
    if (w > max_width) w = max_width;
    if (w > source_width) w = source_width;
    if (w < 4) w = 4;
    return w & ~1;
}

void dm_env_hammersley(unsigned i, unsigned n, double xi[2])
{
    unsigned b = i;
    b = (b << 16) | (b >> 16);
    b = ((b & 0x55555555u) << 1) | ((b & 0xAAAAAAAAu) >> 1);
    b = ((b & 0x33333333u) << 2) | ((b & 0xCCCCCCCCu) >> 2);
    b = ((b & 0x0F0F0F0Fu) << 4) | ((b & 0xF0F0F0F0u) >> 4);
    b = ((b & 0x00FF00FFu) << 8) | ((b & 0xFF00FF00u) >> 8);
    xi[0] = (i + 0.5) / n;
    xi[1] = b * 2.3283064365386963e-10; /* 2⁻³² */
}

/* Orthonormal basis around unit n (Duff et al. 2017, branchless and stable). */
static void onb(const double n[3], double t[3], double b[3])
{
    double sign = copysign(1.0, n[2]);
    double a = -1.0 / (sign + n[2]);
    double c = n[0] * n[1] * a;
    t[0] = 1.0 + sign * n[0] * n[0] * a;
    t[1] = sign * c;
    t[2] = -sign * n[0];
    b[0] = c;
    b[1] = sign + n[1] * n[1] * a;
    b[2] = -n[1];
}

typedef struct lobe_sample {
    double l[3];    /* direction in the frame of r (z = r) */
    double w;       /* r·l */
    double log2_sa; /* log2 of the solid angle the sample stands for */
} lobe_sample;

typedef struct prefilter_job {
    const dm_envmap *map;
    const lobe_sample *s;
    int count;
    double u_shift;
    int width, height;
    float *out;
} prefilter_job;

typedef struct row_sample {
    double u, v, lod, w;
} row_sample;

static void prefilter_rows(void *ctx, size_t begin, size_t end)
{
    const prefilter_job *job = ctx;
    const dm_envmap *map = job->map;
    /* Level-0 texel solid angle at polar angle θ is (2π/W)(π/H) sin θ; sin θ is floored at
     * half a row so the pole rows do not ask for an infinite lod. */
    const double log2_texel = log2(DM_2PI / map->width * DM_PI / map->height);
    const double sin_min = sin(0.5 * DM_PI / map->height);
    row_sample *rs = malloc((size_t)job->count * sizeof *rs);
    if (!rs) { /* no memory for a row's table: mark the rows, the bake's finiteness check refuses them */
        for (size_t k = begin * job->width * 3; k < end * job->width * 3; ++k) job->out[k] = NAN;
        return;
    }
    for (size_t j = begin; j < end; ++j) {
        /* Every texel of a row is the row's first texel rotated about +Y, which only shifts
         * u: the samples' (u, v, lod) are computed once per row, then shifted by i / W. */
        double r[3], t[3], b[3];
        dm_equirect_dir(0.5 / job->width + job->u_shift, (j + 0.5) / job->height, r);
        onb(r, t, b);
        for (int k = 0; k < job->count; ++k) {
            const lobe_sample *s = &job->s[k];
            double l[3];
            for (int q = 0; q < 3; ++q) l[q] = s->l[0] * t[q] + s->l[1] * b[q] + s->l[2] * r[q];
            dm_equirect_uv(l, &rs[k].u, &rs[k].v);
            double ly = dm_clamp(l[1], -1.0, 1.0);
            double sin_t = sqrt(1.0 - ly * ly);
            if (sin_t < sin_min) sin_t = sin_min;
            rs[k].lod = 0.5 * (s->log2_sa - log2_texel - log2(sin_t)) + DM_ENV_LOD_BIAS;
            rs[k].w = s->w;
        }
        for (int i = 0; i < job->width; ++i) {
            double du = (double)i / job->width;
            double acc[3] = {0, 0, 0}, wsum = 0.0;
            for (int k = 0; k < job->count; ++k) {
                double rgb[3];
                dm_envmap_sample(map, rs[k].u + du, rs[k].v, rs[k].lod, rgb);
                for (int c = 0; c < 3; ++c) acc[c] += rs[k].w * rgb[c];
                wsum += rs[k].w;
            }
            float *o = job->out + ((size_t)j * job->width + i) * 3;
            for (int c = 0; c < 3; ++c) o[c] = (float)(wsum > 0.0 ? acc[c] / wsum : 0.0);
        }
    }
    free(rs);
}

dm_result dm_env_prefilter(const dm_envmap *map, double m, int samples, double rotate_deg, int width, int threads,
                           float *out_rgb, dm_error *err)
{
    assert(map && map->level[0] && out_rgb);
    if (!(m >= DM_ENV_M_MIN && m <= DM_ENV_M_MAX))
        return dm_fail(err, DM_ERR_RANGE, "prefilter roughness m = %g: expected %g..%g", m, DM_ENV_M_MIN,
                       DM_ENV_M_MAX);
    if (samples < 1 || samples > DM_ENV_SAMPLES_MAX)
        return dm_fail(err, DM_ERR_RANGE, "prefilter sample count %d: expected 1..%d", samples, DM_ENV_SAMPLES_MAX);
    if (width < 4 || width % 2 || width > DM_ENVMAP_SIZE_MAX)
        return dm_fail(err, DM_ERR_RANGE, "prefilter level width %d: expected an even number in 4..%d", width,
                       DM_ENVMAP_SIZE_MAX);
    lobe_sample *s = malloc((size_t)samples * sizeof *s);
    if (!s) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "prefilter: out of memory for %d samples", samples);
    int count = 0;
    for (int k = 0; k < samples; ++k) {
        double xi[2];
        dm_env_hammersley((unsigned)k, (unsigned)samples, xi);
        /* Beckmann: tan² θh = −m² ln(1 − ξ1) samples D (n·h)/π exactly. */
        double tan2 = -m * m * log1p(-xi[0]);
        double c = 1.0 / sqrt(1.0 + tan2), sn = sqrt(tan2) * c;
        double phi = DM_2PI * xi[1];
        double h[3] = {sn * cos(phi), sn * sin(phi), c};
        double nl = 2.0 * c * c - 1.0;
        if (nl <= 0.0) continue; /* reflected below the horizon: weight 0 */
        double d = dm_beckmann(c, m);
        lobe_sample *q = &s[count++];
        q->l[0] = 2.0 * c * h[0];
        q->l[1] = 2.0 * c * h[1];
        q->l[2] = nl;
        q->w = nl;
        q->log2_sa = log2(4.0 * DM_PI / ((double)samples * d));
    }
    prefilter_job job = {map, s, count, rotate_deg / 360.0, width, width / 2, out_rgb};
    dm_parallel_for((size_t)(width / 2), 1, threads, prefilter_rows, &job);
    free(s);
    return DM_OK;
}

static int reference_level(const dm_envmap *map, double m)
{
    int best = 0;
    for (int l = 1; l < map->level_count; ++l)
        if (DM_PI / map->level_height[l] <= m / 16.0) best = l;
    return best;
}

void dm_env_prefilter_reference(const dm_envmap *map, double m, double rotate_deg, double u, double v,
                                double rgb[3])
{
    assert(map && rgb);
    double r[3];
    dm_equirect_dir(u + rotate_deg / 360.0, v, r);
    int lvl = reference_level(map, m);
    const int w = map->level_width[lvl], h = map->level_height[lvl];
    const float *px = map->level[lvl];
    double *cs = malloc((size_t)w * 2 * sizeof *cs); /* sin φ, cos φ per column */
    if (!cs) {
        rgb[0] = rgb[1] = rgb[2] = NAN;
        return;
    }
    for (int i = 0; i < w; ++i) {
        double phi = DM_2PI * ((i + 0.5) / w - 0.5);
        cs[2 * i] = sin(phi);
        cs[2 * i + 1] = cos(phi);
    }
    double acc[3] = {0, 0, 0}, wsum = 0.0;
    for (int j = 0; j < h; ++j) {
        double theta = DM_PI * (1.0 - (j + 0.5) / h);
        double st = sin(theta), ct = cos(theta);
        double sa = dm_equirect_texel_solid_angle(j, w, h);
        double row[3] = {0, 0, 0}, rw = 0.0;
        for (int i = 0; i < w; ++i) {
            /* d = (sin θ sin φ, cos θ, −sin θ cos φ); h = (d + r)/|d + r| gives
             * N·H = r·h = √((1 + r·d)/2) for unit r and d. */
            double rl = st * (r[0] * cs[2 * i] - r[2] * cs[2 * i + 1]) + r[1] * ct;
            if (rl <= 0.0) continue;
            double wt = dm_beckmann(sqrt(0.5 * (1.0 + rl)), m) * rl;
            if (wt <= 0.0) continue;
            const float *p = px + ((size_t)j * w + i) * 3;
            for (int q = 0; q < 3; ++q) row[q] += wt * p[q];
            rw += wt;
        }
        for (int q = 0; q < 3; ++q) acc[q] += sa * row[q];
        wsum += sa * rw;
    }
    free(cs);
    for (int q = 0; q < 3; ++q) rgb[q] = wsum > 0.0 ? acc[q] / wsum : 0.0;
}

typedef struct error_job {
    const dm_envmap *map;
    double m, rotate_deg;
    const float *level;
    int width, height, count;
    double *err, *ecu, *ecv;
} error_job;

static void error_items(void *ctx, size_t begin, size_t end)
{
    const error_job *job = ctx;
    for (size_t k = begin; k < end; ++k) {
        /* A 2-D Hammersley spread: column from k, row from its radical inverse. */
        double xi[2];
        dm_env_hammersley((unsigned)k, (unsigned)job->count, xi);
        int i = (int)(xi[0] * job->width), j = (int)(xi[1] * job->height);
        size_t idx = (size_t)j * job->width + i;
        double u = (i + 0.5) / job->width, v = (j + 0.5) / job->height;
        double ref[3];
        dm_env_prefilter_reference(job->map, job->m, job->rotate_deg, u, v, ref);
        const float *got = job->level + idx * 3;
        double big = fmax(ref[0], fmax(ref[1], ref[2])), e = 0.0;
        for (int c = 0; c < 3; ++c) e = fmax(e, fabs(got[c] - ref[c]));
        job->err[k] = big > 0.0 ? e / big : (e > 0.0 ? 1.0 : 0.0);
        job->ecu[k] = u;
        job->ecv[k] = v;
    }
}

void dm_env_prefilter_error(const dm_envmap *map, double m, double rotate_deg, const float *level_rgb, int width,
                            int texel_count, int threads, dm_env_error *out)
{
    assert(map && level_rgb && out && texel_count >= 1);
    memset(out, 0, sizeof *out);
    double t0 = dm_now_ms();
    int height = width / 2;
    if ((size_t)texel_count > (size_t)width * height) texel_count = width * height;
    double *e = malloc((size_t)texel_count * 3 * sizeof *e);
    if (!e) return;
    error_job job = {map, m, rotate_deg, level_rgb, width, height, texel_count, e, e + texel_count, e + 2 * texel_count};
    dm_parallel_for((size_t)texel_count, 1, threads, error_items, &job);
    double sq = 0.0;
    for (int k = 0; k < texel_count; ++k) {
        sq += e[k] * e[k];
        if (e[k] > out->max_rel || k == 0) {
            out->max_rel = e[k];
            out->worst_u = job.ecu[k];
            out->worst_v = job.ecv[k];
        }
    }
    out->texels = texel_count;
    out->rms_rel = sqrt(sq / texel_count);
    free(e);
    out->ms = dm_now_ms() - t0;
}
