/* dm_seam_map.c — the seam map's bake. See dm_seam_map.h. */
#include "bake/dm_seam_map.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/dm_seam_edges.h"
#include "mesh/dm_uv_raster.h"

enum { BOX_TEXELS_MAX = 1024 }; /* the band of one edge side: at most this far in texels */

typedef struct side {
    double p0[3], p1[3], p2[3]; /* A's edge ends and third corner, mm */
    double a0[2], a1[2], a2[2]; /* their UVs in A */
    double inv[2][2];           /* (g − a0) → (λ1, λ2), the barycentrics of p1 and p2 */
    int32_t tb;                 /* the other side's triangle B */
    int cb[3];                  /* B's corners at p0 and p1, and its third */
    double nb[3];               /* unit, in B's plane, normal to the edge, pointing into B */
    bool continues;
} side;

typedef struct bake {
    const dm_mesh *m;
    const dm_seam_edges *se;
    double mm, reach;
    int n;
    const int32_t *tri_of;
    double *best; /* per texel: rank (mm) of the winning candidate */
    float *out;
    dm_seam_map_stats st;
} bake;

enum { WALK_STEPS_MAX = 4096 }; /* triangles one walk may cross */

static void corner(const bake *b, int32_t t, int c, double p[3], double uv[2])
{
    uint32_t v = b->m->indices[3 * (size_t)t + c];
    for (int k = 0; k < 3; ++k) p[k] = (double)b->m->positions[3 * (size_t)v + k] * b->mm;
    uv[0] = b->m->uvs[(3 * (size_t)t + c) * 2], uv[1] = b->m->uvs[(3 * (size_t)t + c) * 2 + 1];
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static double uv_area2(const double a[2], const double b[2], const double c[2])
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
}

static bool uv_degenerate(const double a[2], const double b[2], const double c[2])
{
    double l = 0;
    for (int k = 0; k < 2; ++k) l += (b[k] - a[k]) * (b[k] - a[k]) + (c[k] - a[k]) * (c[k] - a[k]);
    return !(fabs(uv_area2(a, b, c)) > 1e-9 * l);
}

static uint32_t welded(const bake *b, int32_t t, int c) { return b->se->weld[b->m->indices[3 * (size_t)t + c]]; }

/* The corner of triangle t at welded position w, or −1. */
static int corner_at(const bake *b, int32_t t, uint32_t w)
{
    for (int c = 0; c < 3; ++c)
        if (welded(b, t, c) == w) return c;
    return -1;
}

/* The unit vector in t's plane normal to the edge a → b (corners of t), pointing to t's third
 * corner; false when t has no height over the edge. */
static bool inward(const bake *b, int32_t t, int ca, int cb, double e_unit[3], double in[3])
{
    double pa[3], pb[3], pc[3], uv[2];
    corner(b, t, ca, pa, uv), corner(b, t, cb, pb, uv), corner(b, t, 3 - ca - cb, pc, uv);
    double e[3], q[3];
    for (int k = 0; k < 3; ++k) e[k] = pb[k] - pa[k], q[k] = pc[k] - pa[k];
    double ee = sqrt(dot3(e, e));
    if (!(ee > 0)) return false;
    for (int k = 0; k < 3; ++k) e_unit[k] = e[k] / ee;
    double kq = dot3(q, e_unit);
    for (int k = 0; k < 3; ++k) in[k] = q[k] - kq * e_unit[k];
    double h = sqrt(dot3(in, in));
    if (!(h > 1e-9 * ee)) return false;
    for (int k = 0; k < 3; ++k) in[k] /= h;
    return true;
}

/* Walks the surface from the point of barycentrics bary in triangle t (on its edge opposite
 * corner `entry`, or −1) along the unit vector dir (3-D, in t's plane) for len mm: a straight
 * line in the unfolded triangles, crossing each edge into the triangle across it
 * (dm_seam_edges.adj) with dir turned about the edge into that triangle's plane — the
 * straightest geodesic, exact on a developable surface. On return t and bary are where it
 * ends; false when it leaves the mesh (a boundary or non-manifold edge), meets a triangle
 * with no area, or crosses more than WALK_STEPS_MAX triangles. */
static bool walk(const bake *b, int32_t *t, double bary[3], int entry, double dir[3], double len)
{
    for (int step = 0; step < WALK_STEPS_MAX; ++step) {
        double p[3][3], uv[2], e1[3], e2[3];
        for (int c = 0; c < 3; ++c) corner(b, *t, c, p[c], uv);
        for (int k = 0; k < 3; ++k) e1[k] = p[1][k] - p[0][k], e2[k] = p[2][k] - p[0][k];
        double g11 = dot3(e1, e1), g12 = dot3(e1, e2), g22 = dot3(e2, e2), det = g11 * g22 - g12 * g12;
        if (!(det > 1e-12 * g11 * g22)) return false;
        double r1 = dot3(dir, e1), r2 = dot3(dir, e2);
        double dl[3];
        dl[1] = (g22 * r1 - g12 * r2) / det, dl[2] = (g11 * r2 - g12 * r1) / det, dl[0] = -dl[1] - dl[2];
        int k_out = -1;
        double s_out = INFINITY;
        for (int k = 0; k < 3; ++k) {
            if (k == entry || !(dl[k] < 0)) continue;
            double s = fmax(bary[k], 0.0) / -dl[k];
            if (s < s_out) s_out = s, k_out = k;
        }
        if (k_out < 0 || s_out >= len) {
            for (int k = 0; k < 3; ++k) bary[k] += len * dl[k];
            return true;
        }
        len -= s_out;
        int ca = (k_out + 1) % 3, cb = (k_out + 2) % 3;
        double tau = bary[cb] + s_out * dl[cb], sum = bary[ca] + s_out * dl[ca] + tau;
        tau = fmin(fmax(tau / sum, 0.0), 1.0);
        int32_t nt = b->se->adj[3 * (size_t)*t + ca];
        if (nt < 0) return false;
        int na = corner_at(b, nt, welded(b, *t, ca)), nb = corner_at(b, nt, welded(b, *t, cb));
        double eu[3], in[3], eu_n[3], in_n[3];
        if (na < 0 || nb < 0 || !inward(b, *t, ca, cb, eu, in) || !inward(b, nt, na, nb, eu_n, in_n)) return false;
        double along = dot3(dir, eu), across = -dot3(dir, in); /* > 0: leaving t */
        for (int k = 0; k < 3; ++k) dir[k] = along * eu[k] + fmax(across, 0.0) * in_n[k];
        double dn = sqrt(dot3(dir, dir));
        if (!(dn > 0)) return false;
        for (int k = 0; k < 3; ++k) dir[k] /= dn;
        *t = nt, entry = 3 - na - nb;
        bary[na] = 1 - tau, bary[nb] = tau, bary[entry] = 0;
    }
    return false;
}

/* Side s of edge e: A = tri[s] from its corner, B = tri[1 − s]. false when A has no UV area
 * (then it is skipped) or B has no height over the edge. */
static bool side_of(const bake *b, const dm_seam_edge *e, int s, side *o)
{
    int32_t ta = e->tri[s];
    int c = e->corner[s];
    corner(b, ta, c, o->p0, o->a0), corner(b, ta, (c + 1) % 3, o->p1, o->a1), corner(b, ta, (c + 2) % 3, o->p2, o->a2);
    if (uv_degenerate(o->a0, o->a1, o->a2)) return false;
    double e1[2] = {o->a1[0] - o->a0[0], o->a1[1] - o->a0[1]}, e2[2] = {o->a2[0] - o->a0[0], o->a2[1] - o->a0[1]};
    double det = e1[0] * e2[1] - e2[0] * e1[1];
    o->inv[0][0] = e2[1] / det, o->inv[0][1] = -e2[0] / det, o->inv[1][0] = -e1[1] / det, o->inv[1][1] = e1[0] / det;
    o->continues = e->sides == 2;
    if (!o->continues) return true;
    o->tb = e->tri[1 - s];
    o->cb[0] = corner_at(b, o->tb, welded(b, ta, c)), o->cb[1] = corner_at(b, o->tb, welded(b, ta, (c + 1) % 3));
    o->cb[2] = 3 - o->cb[0] - o->cb[1];
    double eu[3];
    return o->cb[0] >= 0 && o->cb[1] >= 0 && inward(b, o->tb, o->cb[0], o->cb[1], eu, o->nb);
}

/* UV' across the edge for P_g = p0 + λ1 E + λ2 F (A's plane): P_g's offset from the edge,
 * turned about the edge into B's plane (its part along E kept, its distance d from the edge's
 * line along nb), walked on the surface from the edge point nearest it (the ends kept a hair
 * inside the edge). false when the walk leaves the mesh or ends on a triangle with no UV area. */
static bool unfold(const bake *b, const side *o, double l1, double l2, double *d_mm, double uv[2])
{
    double E[3], F[3], w[3];
    for (int k = 0; k < 3; ++k) E[k] = o->p1[k] - o->p0[k], F[k] = o->p2[k] - o->p0[k];
    double ee = dot3(E, E);
    double t = l1 + l2 * dot3(F, E) / ee; /* P_g − p0 = λ1 E + λ2 F, projected on E */
    for (int k = 0; k < 3; ++k) w[k] = l1 * E[k] + l2 * F[k] - t * E[k];
    double d = sqrt(dot3(w, w)), tc = fmin(fmax(t, 1e-6), 1 - 1e-6), v[3];
    for (int k = 0; k < 3; ++k) v[k] = (t - tc) * E[k] + d * o->nb[k];
    double len = sqrt(dot3(v, v));
    *d_mm = d;
    if (!(len > 0)) return false;
    for (int k = 0; k < 3; ++k) v[k] /= len;
    int32_t t_end = o->tb;
    double bary[3];
    bary[o->cb[0]] = 1 - tc, bary[o->cb[1]] = tc, bary[o->cb[2]] = 0;
    if (!walk(b, &t_end, bary, o->cb[2], v, len)) return false;
    double q[3], u[3][2];
    for (int c = 0; c < 3; ++c) corner(b, t_end, c, q, u[c]);
    if (uv_degenerate(u[0], u[1], u[2])) return false;
    for (int k = 0; k < 2; ++k) uv[k] = bary[0] * u[0][k] + bary[1] * u[1][k] + bary[2] * u[2][k];
    return true;
}

/* The largest UV step a 1 mm step in A's plane makes: 1/σ_min of A's Jacobian UV → 3-D. */
static double uv_per_mm(const side *o)
{
    double E[3], F[3], J[2][3];
    for (int k = 0; k < 3; ++k) E[k] = o->p1[k] - o->p0[k], F[k] = o->p2[k] - o->p0[k];
    for (int k = 0; k < 3; ++k)
        J[0][k] = E[k] * o->inv[0][0] + F[k] * o->inv[1][0], J[1][k] = E[k] * o->inv[0][1] + F[k] * o->inv[1][1];
    double a = dot3(J[0], J[0]), c = dot3(J[1], J[1]), bb = dot3(J[0], J[1]);
    double lmin = 0.5 * (a + c) - sqrt(0.25 * (a - c) * (a - c) + bb * bb);
    return lmin > 0 ? 1 / sqrt(lmin) : INFINITY;
}

static void run_side(bake *b, const side *o)
{
    const int n = b->n;
    double r_uv = b->reach * uv_per_mm(o);
    double lo[2], hi[2];
    for (int k = 0; k < 2; ++k) {
        double m0 = fmin(o->a0[k], o->a1[k]), m1 = fmax(o->a0[k], o->a1[k]);
        lo[k] = fmax(floor((m0 - r_uv) * n), fmax(0.0, floor(m0 * n) - BOX_TEXELS_MAX));
        hi[k] = fmin(ceil((m1 + r_uv) * n), fmin((double)n - 1, ceil(m1 * n) + BOX_TEXELS_MAX));
    }
    double E[3], F[3];
    for (int k = 0; k < 3; ++k) E[k] = o->p1[k] - o->p0[k], F[k] = o->p2[k] - o->p0[k];
    double ee = dot3(E, E), fe = dot3(F, E);
    for (int j = (int)lo[1]; j <= (int)hi[1]; ++j)
        for (int i = (int)lo[0]; i <= (int)hi[0]; ++i) {
            size_t x = (size_t)j * (size_t)n + (size_t)i;
            if (b->tri_of[x] >= 0) continue;
            double g[2] = {(i + 0.5) / n - o->a0[0], (j + 0.5) / n - o->a0[1]};
            double l1 = o->inv[0][0] * g[0] + o->inv[0][1] * g[1], l2 = o->inv[1][0] * g[0] + o->inv[1][1] * g[1];
            if (!(l2 < 0)) continue; /* on A's side of the edge's line */
            double t = l1 + l2 * fe / ee, w[3];
            for (int k = 0; k < 3; ++k) w[k] = l1 * E[k] + l2 * F[k] - t * E[k];
            double along = t < 0 ? -t : t > 1 ? t - 1 : 0;
            double rank = sqrt(dot3(w, w) + along * along * ee);
            /* a tie (beyond a seam's end, where it meets the boundary) goes to the boundary */
            bool wins = rank < b->best[x] || (!o->continues && rank <= b->best[x] * (1 + 1e-9));
            if (!(rank <= b->reach) || !wins) continue;
            b->best[x] = rank;
            float *px = b->out + 4 * x;
            double d = 0, uv[2];
            if (!o->continues || !unfold(b, o, l1, l2, &d, uv)) {
                px[0] = px[1] = px[2] = 0, px[3] = o->continues ? -2.0f : -1.0f; /* lost / ended, resolved below */
                continue;
            }
            double fi = floor(uv[0] * n), fj = floor(uv[1] * n);
            bool lands = fi >= 0 && fj >= 0 && fi < n && fj < n && b->tri_of[(size_t)fj * (size_t)n + (size_t)fi] >= 0;
            px[0] = (float)uv[0], px[1] = (float)uv[1], px[2] = lands ? 1.0f : 0.0f, px[3] = lands ? (float)d : -2.0f;
        }
}

double dm_seam_map_reach_mm(double largest_variance_mm2) { return 3 * sqrt(fmax(largest_variance_mm2, 0)); }

dm_result dm_seam_map_bake(const dm_mesh *m, const dm_seam_map_options *opt, dm_seam_map *out,
                           dm_seam_map_stats *stats, dm_error *err)
{
    memset(out, 0, sizeof *out);
    if (stats) memset(stats, 0, sizeof *stats);
    if (opt->size < 1 || opt->size > DM_SEAM_MAP_SIZE_MAX)
        return dm_fail(err, DM_ERR_RANGE, "seam map: size %d, expected 1..%d", opt->size, DM_SEAM_MAP_SIZE_MAX);
    if (!(opt->mm_per_unit > 0) || !isfinite(opt->mm_per_unit) || !(opt->reach_mm > 0) || !isfinite(opt->reach_mm))
        return dm_fail(err, DM_ERR_RANGE, "seam map: mm_per_unit %g and reach_mm %g must be finite and > 0",
                       opt->mm_per_unit, opt->reach_mm);
    const int n = opt->size;
    size_t texels = (size_t)n * (size_t)n;
    dm_seam_edges se = {0};
    int32_t *tri_of = malloc(sizeof *tri_of * texels);
    double *best = malloc(sizeof *best * texels);
    out->texels = calloc(4 * texels, sizeof *out->texels);
    dm_result rc = tri_of && best && out->texels
                       ? DM_OK
                       : dm_fail(err, DM_ERR_OUT_OF_MEMORY, "seam map %dx%d: out of memory", n, n);
    if (rc == DM_OK) rc = dm_seam_edges_find(m, &se, err);
    if (rc == DM_OK) rc = dm_uv_raster(m, NULL, n, n, 1, tri_of, NULL, err);
    if (rc != DM_OK) {
        free(tri_of), free(best), dm_seam_edges_free(&se), dm_seam_map_free(out);
        return rc;
    }
    bake b = {m, &se, opt->mm_per_unit, opt->reach_mm, n, tri_of, best, out->texels, {0}};
    for (size_t x = 0; x < texels; ++x) best[x] = INFINITY;
    b.st.seam_edges = (int64_t)se.count, b.st.boundary_edges = se.boundary_edges;
    b.st.nonmanifold_edges = se.nonmanifold_edges;
    for (size_t k = 0; k < se.count; ++k) {
        const dm_seam_edge *e = &se.edges[k];
        b.st.cut_edges += e->sides == 2;
        for (int s = 0; s < (e->sides == 2 ? 2 : 1); ++s) {
            side o;
            if (side_of(&b, e, s, &o)) run_side(&b, &o);
            else ++b.st.degenerate_sides;
        }
    }
    for (size_t x = 0; x < texels; ++x) {
        float *px = out->texels + 4 * x;
        if (px[2] > 0) ++b.st.continued_texels, b.st.max_distance_mm = fmax(b.st.max_distance_mm, px[3]);
        else if (px[3] == -1.0f) ++b.st.ended_texels;
        else if (px[3] == -2.0f) ++b.st.lost_texels;
        if (!(px[2] > 0)) px[0] = px[1] = px[2] = px[3] = 0;
    }
    out->size = n;
    if (stats) *stats = b.st;
    free(tri_of), free(best), dm_seam_edges_free(&se);
    return DM_OK;
}

void dm_seam_map_free(dm_seam_map *map)
{
    free(map->texels);
    memset(map, 0, sizeof *map);
}

void dm_seam_map_stats_prov(const dm_seam_map_stats *s, dm_provenance *p)
{
    dm_prov_add_int(p, "seam_edges", s->seam_edges);
    dm_prov_add_int(p, "cut_edges", s->cut_edges);
    dm_prov_add_int(p, "boundary_edges", s->boundary_edges);
    dm_prov_add_int(p, "nonmanifold_edges", s->nonmanifold_edges);
    dm_prov_add_int(p, "degenerate_sides", s->degenerate_sides);
    dm_prov_add_int(p, "continued_texels", s->continued_texels);
    dm_prov_add_int(p, "lost_texels", s->lost_texels);
    dm_prov_add_int(p, "ended_texels", s->ended_texels);
    dm_prov_add_double(p, "max_distance_mm", s->max_distance_mm);
}
