/* dm_thin_map.c — the thin-part map's bake. See dm_thin_map.h. */
#include "bake/dm_thin_map.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_parallel.h"
#include "mesh/dm_raycast.h"
#include "mesh/dm_uv_raster.h"

enum { K = DM_THIN_MAP_CANDIDATES, RAYS = DM_THIN_MAP_RAYS };

#define SAME_UV_TEXELS 1.5   /* candidates closer in UV are one surface (and the texel's own) */
#define SAME_PLANE_RATIO 0.25 /* offset along the taken normal / distance: on its tangent plane */
#define SAME_NORMAL_COS 0.70710678118654752 /* normals within 45° */

typedef struct cand {
    double u, v, d, w;
    double q[3], nq[3]; /* the hit (mm) and its triangle's unit normal */
    int ray;
} cand;

typedef struct bake {
    const dm_mesh *m;
    const dm_raycast *rc;
    int n;
    double mm, reach, v_max, eps;
    const int32_t *tri_of;
    const uint8_t *no_uv; /* per triangle: zero UV area */
    float *texels, *dropped;
    int64_t *zero_hits, *lost_hits; /* per row */
} bake;

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static double normalize3(double v[3])
{
    double l = sqrt(dot3(v, v));
    if (l > 0)
        for (int c = 0; c < 3; ++c) v[c] /= l;
    return l;
}

/* Corner c of triangle t in mm. */
static void corner_mm(const bake *b, int32_t t, int c, double p[3])
{
    const float *v = b->m->positions + 3 * (size_t)b->m->indices[3 * (size_t)t + c];
    for (int k = 0; k < 3; ++k) p[k] = (double)v[k] * b->mm;
}

/* The point (mm) and unit normal at barycentrics (b1, b2) of t: the corner normals
 * interpolated, the triangle's own where there are none or they cancel. false: no normal. */
static bool surface_at(const bake *b, int32_t t, double b1, double b2, double p[3], double n[3])
{
    const double w[3] = {1.0 - b1 - b2, b1, b2};
    double c[3][3];
    for (int k = 0; k < 3; ++k) corner_mm(b, t, k, c[k]);
    for (int k = 0; k < 3; ++k) p[k] = w[0] * c[0][k] + w[1] * c[1][k] + w[2] * c[2][k];
    n[0] = n[1] = n[2] = 0;
    if (b->m->normals) {
        const float *cn = b->m->normals + 9 * (size_t)t;
        for (int k = 0; k < 3; ++k) n[k] = w[0] * cn[k] + w[1] * cn[3 + k] + w[2] * cn[6 + k];
    }
    if (normalize3(n) > 1e-6) return true;
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) e1[k] = c[1][k] - c[0][k], e2[k] = c[2][k] - c[0][k];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    return normalize3(n) > 0;
}

/* Ray r's unit direction: −n, +n, then the ring around −n, then the one around +n, each at
 * +t1, −t1, +t2, −t2 of the branchless orthonormal basis (Duff et al. 2017). */
static void ray_dir(const double n[3], int r, double dir[3])
{
    const double s = copysign(1.0, n[2]), a = -1.0 / (s + n[2]), bb = n[0] * n[1] * a;
    const double t1[3] = {1.0 + s * n[0] * n[0] * a, s * bb, -s * n[0]}, t2[3] = {bb, s + n[1] * n[1] * a, -n[1]};
    const double side = r == 0 || (r >= 2 && r < 6) ? -1.0 : 1.0;
    if (r < 2) {
        for (int k = 0; k < 3; ++k) dir[k] = side * n[k];
        return;
    }
    const double tilt = DM_THIN_MAP_TILT_DEG * 3.14159265358979323846 / 180.0, ct = cos(tilt), st = sin(tilt);
    const int az = (r - 2) % 4;
    const double *t = az < 2 ? t1 : t2, sg = az % 2 ? -1.0 : 1.0;
    for (int k = 0; k < 3; ++k) dir[k] = ct * side * n[k] + st * sg * t[k];
}

/* Whether candidate c is a surface already taken as a. */
static bool same_surface(const bake *b, const cand *a, const cand *c)
{
    double du = (a->u - c->u) * b->n, dv = (a->v - c->v) * b->n;
    if (du * du + dv * dv < SAME_UV_TEXELS * SAME_UV_TEXELS) return true;
    double off[3] = {c->q[0] - a->q[0], c->q[1] - a->q[1], c->q[2] - a->q[2]};
    return dot3(a->nq, c->nq) > SAME_NORMAL_COS && fabs(dot3(off, a->nq)) < SAME_PLANE_RATIO * sqrt(dot3(off, off));
}

/* Heaviest first; ties: lower d, then ray order. */
static bool before(const cand *x, const cand *y)
{
    if (x->w != y->w) return x->w > y->w;
    if (x->d != y->d) return x->d < y->d;
    return x->ray < y->ray;
}

/* Ray r's candidate from texel centre (u, v) at p with normal n; false when it gives none. */
static bool cast(const bake *b, size_t row, int r, double u, double v, const double p[3], const double n[3], cand *c)
{
    double dir[3];
    ray_dir(n, r, dir);
    dm_ray_hit h;
    if (!dm_raycast_closest(b->rc, p, dir, b->eps, b->reach, false, &h) || !(dot3(n, h.ng) < 0)) return false;
    if (b->no_uv[h.triangle]) {
        ++b->zero_hits[row];
        return false;
    }
    const double w[3] = {1.0 - (double)h.b1 - (double)h.b2, h.b1, h.b2};
    const float *tuv = b->m->uvs + 6 * (size_t)h.triangle;
    c->u = w[0] * tuv[0] + w[1] * tuv[2] + w[2] * tuv[4];
    c->v = w[0] * tuv[1] + w[1] * tuv[3] + w[2] * tuv[5];
    double fi = floor(c->u * b->n), fj = floor(c->v * b->n);
    if (!(fi >= 0 && fj >= 0 && fi < b->n && fj < b->n) || b->tri_of[(size_t)fj * (size_t)b->n + (size_t)fi] < 0) {
        ++b->lost_hits[row];
        return false;
    }
    double du = (c->u - u) * b->n, dv = (c->v - v) * b->n;
    if (du * du + dv * dv < SAME_UV_TEXELS * SAME_UV_TEXELS) return false; /* its own surface */
    double q[3][3];
    for (int k = 0; k < 3; ++k) corner_mm(b, h.triangle, k, q[k]);
    for (int k = 0; k < 3; ++k) c->q[k] = w[0] * q[0][k] + w[1] * q[1][k] + w[2] * q[2][k], c->nq[k] = h.ng[k];
    double off[3] = {c->q[0] - p[0], c->q[1] - p[1], c->q[2] - p[2]};
    c->d = fmin(sqrt(dot3(off, off)), b->reach); /* ≤ reach up to the float rounding of the ray */
    c->w = exp(-c->d * c->d / (2 * b->v_max));
    c->ray = r;
    return true;
}

static void texel(const bake *b, int i, int j)
{
    const size_t n = (size_t)b->n, x = (size_t)j * n + (size_t)i;
    const int32_t t = b->tri_of[x];
    if (t < 0) return;
    const double u = (i + 0.5) / b->n, v = (j + 0.5) / b->n;
    double b1, b2, p[3], nrm[3];
    dm_uv_raster_barycentrics(b->m, t, u, v, &b1, &b2);
    if (!surface_at(b, t, b1, b2, p, nrm)) return;
    cand c[RAYS];
    int count = 0;
    for (int r = 0; r < RAYS; ++r) {
        cand x1;
        if (!cast(b, (size_t)j, r, u, v, p, nrm, &x1)) continue;
        int at = count++;
        for (; at > 0 && before(&x1, &c[at - 1]); --at) c[at] = c[at - 1]; /* insertion: stable */
        c[at] = x1;
    }
    int taken = 0; /* distinct surfaces, moved to the front of c */
    double dropped = 0;
    for (int k = 0; k < count; ++k) {
        bool dup = false;
        for (int a = 0; a < taken && !dup; ++a) dup = same_surface(b, &c[a], &c[k]);
        if (dup) continue;
        if (taken >= K) dropped += c[k].w;
        c[taken++] = c[k];
    }
    for (int k = 0; k < taken && k < K; ++k) {
        float *o = b->texels + 4 * (((size_t)k * n + (size_t)j) * n + (size_t)i);
        o[0] = (float)c[k].u, o[1] = (float)c[k].v, o[2] = (float)c[k].d, o[3] = 1.0f;
    }
    b->dropped[x] = (float)dropped;
}

static void rows(void *ctx, size_t begin, size_t end)
{
    const bake *b = ctx;
    for (size_t j = begin; j < end; ++j)
        for (int i = 0; i < b->n; ++i) texel(b, i, (int)j);
}

/* The stats from the finished map, in texel order (so the sums never depend on threads). */
static void sum_stats(const bake *b, dm_thin_map_stats *st)
{
    const size_t n = (size_t)b->n, texels = n * n;
    double d_sum = 0;
    int64_t kept = 0;
    for (size_t x = 0; x < texels; ++x) {
        if (b->tri_of[x] < 0) continue;
        ++st->covered_texels;
        int have = 0;
        for (int k = 0; k < K; ++k) {
            const float *o = b->texels + 4 * ((size_t)k * texels + x);
            if (o[3] != 1.0f) continue;
            ++have, ++kept, d_sum += o[2];
            st->max_distance_mm = fmax(st->max_distance_mm, o[2]);
        }
        st->one_candidate_texels += have == 1, st->two_candidate_texels += have == 2;
        if (b->dropped[x] > 0) {
            ++st->dropped_texels, st->dropped_weight_sum += b->dropped[x];
            st->dropped_weight_max = fmax(st->dropped_weight_max, b->dropped[x]);
        }
    }
    for (size_t j = 0; j < n; ++j) st->zero_uv_area_hits += b->zero_hits[j], st->lost_hits += b->lost_hits[j];
    st->mean_distance_mm = kept ? d_sum / (double)kept : 0.0;
}

dm_result dm_thin_map_bake(const dm_mesh *m, const dm_thin_map_options *opt, dm_thin_map *out,
                           dm_thin_map_stats *stats, dm_error *err)
{
    memset(out, 0, sizeof *out);
    if (stats) memset(stats, 0, sizeof *stats);
    if (opt->size < 1 || opt->size > DM_THIN_MAP_SIZE_MAX)
        return dm_fail(err, DM_ERR_RANGE, "thin map: size %d, expected 1..%d", opt->size, DM_THIN_MAP_SIZE_MAX);
    if (!(opt->mm_per_unit > 0) || !isfinite(opt->mm_per_unit) || !(opt->reach_mm > 0) || !isfinite(opt->reach_mm))
        return dm_fail(err, DM_ERR_RANGE, "thin map: mm_per_unit %g and reach_mm %g must be finite and > 0",
                       opt->mm_per_unit, opt->reach_mm);
    if (opt->threads < 0)
        return dm_fail(err, DM_ERR_RANGE, "thin map: threads %d, expected 0 (all cores) or more", opt->threads);
    dm_result rc = dm_mesh_validate(m, "thin map: mesh", err);
    if (rc != DM_OK) return rc;
    const int n = opt->size;
    const size_t texels = (size_t)n * (size_t)n;
    bake b = {m, NULL, n, opt->mm_per_unit, opt->reach_mm, opt->reach_mm * opt->reach_mm / 9.0, 0, NULL, NULL,
              NULL, NULL, NULL, NULL};
    int32_t *tri_of = malloc(sizeof *tri_of * texels);
    uint8_t *no_uv = malloc((size_t)m->triangle_count);
    int64_t *counts = calloc(2 * (size_t)n, sizeof *counts);
    out->texels = calloc(4 * K * texels, sizeof *out->texels);
    out->dropped = calloc(texels, sizeof *out->dropped);
    dm_raycast *ray = NULL;
    rc = tri_of && no_uv && counts && out->texels && out->dropped
             ? DM_OK
             : dm_fail(err, DM_ERR_OUT_OF_MEMORY, "thin map %dx%d: out of memory", n, K * n);
    if (rc == DM_OK) rc = dm_uv_raster(m, NULL, n, n, opt->threads, tri_of, NULL, err);
    if (rc == DM_OK) rc = dm_raycast_create(m, opt->mm_per_unit, &ray, err);
    if (rc == DM_OK) {
        for (int32_t t = 0; t < m->triangle_count; ++t) {
            dm_uv_jacobian J;
            dm_mesh_uv_jacobian(m, t, 1.0, &J);
            no_uv[t] = J.kind == DM_TRIANGLE_ZERO_UV_AREA;
        }
        b.rc = ray, b.eps = dm_raycast_epsilon_mm(ray), b.tri_of = tri_of, b.no_uv = no_uv;
        b.texels = out->texels, b.dropped = out->dropped, b.zero_hits = counts, b.lost_hits = counts + n;
        dm_parallel_for((size_t)n, 1, opt->threads, rows, &b);
        out->size = n;
        if (stats) sum_stats(&b, stats);
    }
    dm_raycast_destroy(ray);
    free(tri_of), free(no_uv), free(counts);
    if (rc != DM_OK) dm_thin_map_free(out);
    return rc;
}

void dm_thin_map_free(dm_thin_map *map)
{
    free(map->texels);
    free(map->dropped);
    memset(map, 0, sizeof *map);
}

void dm_thin_map_stats_prov(const dm_thin_map_stats *s, dm_provenance *p)
{
    dm_prov_add_int(p, "covered_texels", s->covered_texels);
    dm_prov_add_int(p, "one_candidate_texels", s->one_candidate_texels);
    dm_prov_add_int(p, "two_candidate_texels", s->two_candidate_texels);
    dm_prov_add_int(p, "dropped_texels", s->dropped_texels);
    dm_prov_add_double(p, "dropped_weight_sum", s->dropped_weight_sum);
    dm_prov_add_double(p, "dropped_weight_max", s->dropped_weight_max);
    dm_prov_add_int(p, "zero_uv_area_hits", s->zero_uv_area_hits);
    dm_prov_add_int(p, "lost_hits", s->lost_hits);
    dm_prov_add_double(p, "max_distance_mm", s->max_distance_mm);
    dm_prov_add_double(p, "mean_distance_mm", s->mean_distance_mm);
}
