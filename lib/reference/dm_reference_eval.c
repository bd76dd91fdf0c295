/* dm_reference_eval.c — evaluating the surface convolution at targets (dm_reference.h
 * "THE QUADRATURE"): narrow groups by on-the-fly subdivision of the triangles near the
 * target, the wide group over texel elements, plus the mass beyond the cut. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reference/dm_reference_impl.h"
#include "core/dm_math.h"
#include "core/dm_parallel.h"

/* Sub-triangles one triangle may contribute to one target (slivers beyond it are
 * subdivided more coarsely: their area, and so their weight, is tiny). */
#define SUBPOINTS_MAX 4.0e6

typedef struct gauss {
    double inv_2v, norm, r2; /* 1/2v, 1/2πv, (cut σ)² */
} gauss;

typedef struct eval_ctx {
    const dm_reference *ref;
    const dm_reference_target *targets;
    float *rgb, *levels;
    gauss g[DM_REFERENCE_GAUSSIANS_MAX];
    volatile int out_of_memory; /* set by a worker that could not get its scratch */
} eval_ctx;

typedef struct scratch {
    uint32_t *stamp; /* per triangle: the visit number that last saw it */
    uint32_t visit;
} scratch;

static void target_point(const dm_reference *ref, const dm_reference_target *tg, double p[3], double uv[2])
{
    const dm_mesh *m = ref->mesh;
    size_t t = (size_t)tg->triangle;
    double b1 = tg->b1, b2 = tg->b2, b0 = 1.0 - b1 - b2;
    for (int a = 0; a < 3; ++a)
        p[a] = b0 * ref->pos_mm[3 * (size_t)m->indices[3 * t] + a] + b1 * ref->pos_mm[3 * (size_t)m->indices[3 * t + 1] + a] +
               b2 * ref->pos_mm[3 * (size_t)m->indices[3 * t + 2] + a];
    const float *u = m->uvs + 6 * t;
    uv[0] = b0 * u[0] + b1 * u[2] + b2 * u[4];
    uv[1] = b0 * u[1] + b1 * u[3] + b2 * u[5];
}

static void accumulate(const gauss *g, int first, int count, double d2, const double flux[3], double S[][3])
{
    for (int k = first; k < first + count; ++k) {
        if (!(d2 < g[k].r2)) continue;
        double w = exp(-d2 * g[k].inv_2v) * g[k].norm;
        S[k][0] += flux[0] * w;
        S[k][1] += flux[1] * w;
        S[k][2] += flux[2] * w;
    }
}

static void wide_group(const eval_ctx *ctx, const dm_ref_group *grp, const double p[3], double S[][3])
{
    const dm_reference *ref = ctx->ref;
    const dm_ref_grid *g = &ref->element_grid;
    double r2 = grp->radius_mm * grp->radius_mm;
    int lo[3], hi[3];
    dm_ref_grid_range(g, p, grp->radius_mm, lo, hi);
    for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y) {
            int64_t row = ((int64_t)z * g->dim[1] + y) * g->dim[0];
            for (int64_t e = g->start[row + lo[0]]; e < g->start[row + hi[0] + 1]; ++e) {
                const dm_ref_element *el = &ref->element[e];
                double dx = el->pos[0] - p[0], dy = el->pos[1] - p[1], dz = el->pos[2] - p[2];
                double d2 = dx * dx + dy * dy + dz * dz;
                if (!(d2 < r2)) continue;
                double flux[3] = {el->flux[0], el->flux[1], el->flux[2]};
                accumulate(ctx->g, grp->first, grp->count, d2, flux, S);
            }
        }
}

/* One triangle's sub-triangles within the group's radius of p. */
static void narrow_triangle(const eval_ctx *ctx, const dm_ref_group *grp, int32_t t, const double p[3], double S[][3])
{
    const dm_reference *ref = ctx->ref;
    const dm_mesh *m = ref->mesh;
    double A = ref->tri_area[t];
    if (!(A > 0.0)) return;
    const double *P0 = ref->pos_mm + 3 * (size_t)m->indices[3 * (size_t)t];
    const double *P1 = ref->pos_mm + 3 * (size_t)m->indices[3 * (size_t)t + 1];
    const double *P2 = ref->pos_mm + 3 * (size_t)m->indices[3 * (size_t)t + 2];
    double e1[3], e2[3], d[3];
    for (int a = 0; a < 3; ++a) {
        e1[a] = P1[a] - P0[a];
        e2[a] = P2[a] - P0[a];
        d[a] = p[a] - P0[a];
    }
    double R = grp->radius_mm, R2 = R * R;
    /* quick reject: the triangle's bounding sphere about its centroid */
    double c2 = 0.0, rad = 0.0;
    for (int a = 0; a < 3; ++a) {
        double c = (e1[a] + e2[a]) / 3.0 - d[a];
        c2 += c * c;
    }
    for (int v = 0; v < 3; ++v) {
        double s = 0.0;
        for (int a = 0; a < 3; ++a) {
            double q = (v == 1 ? e1[a] : v == 2 ? e2[a] : 0.0) - (e1[a] + e2[a]) / 3.0;
            s += q * q;
        }
        rad = fmax(rad, sqrt(s));
    }
    if (sqrt(c2) - rad > R) return;
    /* p's projection on the plane in (s, t), and the disk's extent in s and t */
    double a11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
    double a22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    double a12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    double r1 = e1[0] * d[0] + e1[1] * d[1] + e1[2] * d[2];
    double r2 = e2[0] * d[0] + e2[1] * d[1] + e2[2] * d[2];
    double det = 4.0 * A * A; /* = a11 a22 − a12² */
    double s0 = (a22 * r1 - a12 * r2) / det, t0 = (a11 * r2 - a12 * r1) / det;
    double ds = R * sqrt(a22) / (2.0 * A), dt = R * sqrt(a11) / (2.0 * A);
    double n = ceil(ref->tri_edge[t] / grp->spacing_mm);
    if (!(n >= 1.0)) n = 1.0;
    double span = (fmin(1.0, s0 + ds) - fmax(0.0, s0 - ds)) * (fmin(1.0, t0 + dt) - fmax(0.0, t0 - dt));
    if (!(span > 0.0)) return;
    if (span * n * n > SUBPOINTS_MAX) n = floor(sqrt(SUBPOINTS_MAX / span));
    if (n > 1e9) n = 1e9;
    int64_t N = (int64_t)n;
    int64_t i0 = (int64_t)fmax(0.0, floor((s0 - ds) * n) - 1.0), i1 = (int64_t)fmin(n - 1.0, ceil((s0 + ds) * n));
    int64_t j0 = (int64_t)fmax(0.0, floor((t0 - dt) * n) - 1.0), j1 = (int64_t)fmin(n - 1.0, ceil((t0 + dt) * n));
    const float *uv = m->uvs + 6 * (size_t)t;
    double du1 = uv[2] - uv[0], dv1 = uv[3] - uv[1], du2 = uv[4] - uv[0], dv2 = uv[5] - uv[1];
    double sub_area = A / (n * n), inv_n = 1.0 / n;
    /* p's squared distance off the plane, then per row of s the t-interval of the disk:
     * a22 (t − t0)² + 2 a12 (s − s0)(t − t0) + a11 (s − s0)² + z² ≤ R² */
    double z2 = 0.0;
    for (int a = 0; a < 3; ++a) {
        double q = d[a] - s0 * e1[a] - t0 * e2[a];
        z2 += q * q;
    }
    for (int64_t i = i0; i <= i1; ++i)
        for (int down = 0; down < 2; ++down) {
            double off = down ? 2.0 / 3.0 : 1.0 / 3.0;
            double s = (i + off) * inv_n, ds_ = s - s0;
            double b = a12 * ds_, disc = b * b - a22 * (a11 * ds_ * ds_ + z2 - R2);
            if (!(disc >= 0.0)) continue;
            double root = sqrt(disc), tlo = t0 + (-b - root) / a22, thi = t0 + (-b + root) / a22;
            /* centroids at t = (j + off)/n; one extra on each side against rounding */
            int64_t jlo = (int64_t)fmax((double)j0, ceil(tlo * n - off) - 1.0);
            int64_t jhi = (int64_t)fmin((double)j1, floor(thi * n - off) + 1.0);
            int64_t jmax = N - 1 - i - down; /* up: i + j ≤ N − 1; down: i + j ≤ N − 2 */
            if (jhi > jmax) jhi = jmax;
            if (jlo > jhi) continue;
            /* along the row d² is quadratic in t, so each exp(−d²/2v) follows from the last by
             * two products (E ← E·R, R ← R·Q): no exp per point */
            /* from the offset vector itself (no expanded quadratic: its terms cancel
             * catastrophically on large triangles) */
            double t_first = (jlo + off) * inv_n, d2 = 0.0, qe = 0.0;
            for (int a = 0; a < 3; ++a) {
                double q = s * e1[a] + t_first * e2[a] - d[a];
                d2 += q * q;
                qe += q * e2[a];
            }
            double step = inv_n * (2.0 * qe + a22 * inv_n); /* d²(j+1) − d²(j) */
            double step2 = 2.0 * a22 * inv_n * inv_n;
            double E[DM_REFERENCE_GAUSSIANS_MAX], Rk[DM_REFERENCE_GAUSSIANS_MAX], Qk[DM_REFERENCE_GAUSSIANS_MAX];
            const gauss *g = ctx->g + grp->first;
            for (int k = 0; k < grp->count; ++k) {
                E[k] = exp(-d2 * g[k].inv_2v) * g[k].norm;
                Rk[k] = exp(-step * g[k].inv_2v);
                Qk[k] = exp(-step2 * g[k].inv_2v);
            }
            double us = uv[0] + s * du1 + t_first * du2, vs = uv[1] + s * dv1 + t_first * dv2;
            double dus = du2 * inv_n, dvs = dv2 * inv_n;
            for (int64_t j = jlo; j <= jhi; ++j) {
                if (d2 < R2) {
                    double rgb[3];
                    dm_ref_sample(&ref->lookup, us, vs, rgb);
                    for (int k = 0; k < grp->count; ++k) {
                        if (!(d2 < g[k].r2)) continue;
                        double w = E[k] * sub_area;
                        S[grp->first + k][0] += rgb[0] * w;
                        S[grp->first + k][1] += rgb[1] * w;
                        S[grp->first + k][2] += rgb[2] * w;
                    }
                }
                for (int k = 0; k < grp->count; ++k) {
                    E[k] *= Rk[k];
                    Rk[k] *= Qk[k];
                }
                d2 += step;
                step += step2;
                us += dus;
                vs += dvs;
            }
        }
}

static void narrow_group(const eval_ctx *ctx, const dm_ref_group *grp, const double p[3], scratch *sc, double S[][3])
{
    const dm_ref_grid *g = &ctx->ref->tri_grid;
    int lo[3], hi[3];
    dm_ref_grid_range(g, p, grp->radius_mm, lo, hi);
    if (++sc->visit == 0) { /* wrapped: clear */
        memset(sc->stamp, 0, sizeof *sc->stamp * (size_t)ctx->ref->mesh->triangle_count);
        sc->visit = 1;
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
            for (int x = lo[0]; x <= hi[0]; ++x) {
                int64_t c = ((int64_t)z * g->dim[1] + y) * g->dim[0] + x;
                for (int64_t k = g->start[c]; k < g->start[c + 1]; ++k) {
                    int32_t t = g->item[k];
                    if (sc->stamp[t] == sc->visit) continue;
                    sc->stamp[t] = sc->visit;
                    narrow_triangle(ctx, grp, t, p, S);
                }
            }
}

static void eval_range(void *vctx, size_t begin, size_t end)
{
    eval_ctx *ctx = vctx;
    const dm_reference *ref = ctx->ref;
    const dm_reference_kernel *K = &ref->kernel;
    scratch sc = {calloc((size_t)ref->mesh->triangle_count, sizeof(uint32_t)), 0};
    if (!sc.stamp) { /* no partial answer: the call fails */
        ctx->out_of_memory = 1;
        return;
    }
    for (size_t i = begin; i < end; ++i) {
        double S[DM_REFERENCE_GAUSSIANS_MAX][3] = {{0}};
        double p[3], uv[2], Ix[3];
        target_point(ref, &ctx->targets[i], p, uv);
        dm_ref_sample(&ref->lookup, uv[0], uv[1], Ix);
        for (int gi = 0; gi < ref->group_count; ++gi) {
            const dm_ref_group *grp = &ref->group[gi];
            if (gi == ref->wide_group) wide_group(ctx, grp, p, S);
            else narrow_group(ctx, grp, p, &sc, S);
        }
        double D[3] = {0, 0, 0};
        for (int k = 0; k < K->count; ++k)
            for (int c = 0; c < 3; ++c) {
                S[k][c] += ref->tail_fraction * Ix[c]; /* the mass beyond the cut */
                if (!isfinite(S[k][c])) S[k][c] = S[k][c] > 0.0 ? FLT_MAX : 0.0;
                S[k][c] = fmin(S[k][c], FLT_MAX);
                D[c] += K->weight[k][c] * S[k][c];
                if (ctx->levels) ctx->levels[(i * (size_t)K->count + (size_t)k) * 3 + (size_t)c] = (float)S[k][c];
            }
        for (int c = 0; c < 3; ++c) ctx->rgb[i * 3 + (size_t)c] = (float)fmin(D[c], FLT_MAX);
    }
    free(sc.stamp);
}

dm_result dm_reference_eval(const dm_reference *ref, const dm_reference_target *targets, size_t target_count,
                            float *rgb, float *levels, dm_error *err)
{
    for (size_t i = 0; i < target_count; ++i)
        if (targets[i].triangle < 0 || targets[i].triangle >= ref->mesh->triangle_count ||
            !isfinite(targets[i].b1) || !isfinite(targets[i].b2))
            return dm_fail(err, DM_ERR_RANGE, "reference: target %zu: triangle %d (of %d) or barycentrics (%g, %g) invalid",
                           i, targets[i].triangle, ref->mesh->triangle_count, targets[i].b1, targets[i].b2);
    eval_ctx ctx = {.ref = ref, .targets = targets, .rgb = rgb, .levels = levels};
    for (int k = 0; k < ref->kernel.count; ++k) {
        double v = ref->kernel.variance_mm2[k];
        ctx.g[k].inv_2v = 0.5 / v;
        ctx.g[k].norm = 1.0 / (DM_2PI * v);
        ctx.g[k].r2 = ref->cut_sigma * ref->cut_sigma * v;
    }
    /* batches, so progress is reported from this thread; each target on its own */
    size_t batch = target_count / 100 + 1;
    if (batch < 256) batch = 256;
    for (size_t b = 0; b < target_count; b += batch) {
        size_t n = target_count - b < batch ? target_count - b : batch;
        eval_ctx sub = ctx;
        sub.targets = targets + b;
        sub.rgb = rgb + 3 * b;
        sub.levels = levels ? levels + 3 * b * (size_t)ref->kernel.count : NULL;
        dm_parallel_for(n, 16, ref->opt.thread_count, eval_range, &sub);
        if (sub.out_of_memory)
            return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference: no scratch for %d triangles",
                           ref->mesh->triangle_count);
        if (ref->opt.progress) ref->opt.progress(ref->opt.progress_user, (double)(b + n) / (double)target_count);
    }
    return DM_OK;
}
