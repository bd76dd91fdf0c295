/* dm_gather_sites.c — the quadrature's sites. See dm_gather_sites.h. */
#include "bake/dm_gather_sites.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

enum { POLY_MAX = 12, SUBDIVIDE_MAX = 64 };

typedef struct poly {
    int n;
    double x[POLY_MAX], y[POLY_MAX];
} poly;

/* The part of `in` on the side sign · (coordinate − bound) ≥ 0 (axis 0: x, 1: y). The truth
 * (lib/reference/dm_reference_elements.c) clips with its own copy on purpose: it shares no code
 * with what it measures, so that a slip here cannot cancel against the same slip there. */
static void clip(const poly *in, int axis, double bound, double sign, poly *out)
{
    out->n = 0;
    for (int i = 0; i < in->n; ++i) {
        int j = (i + 1) % in->n;
        double a = sign * ((axis ? in->y[i] : in->x[i]) - bound), b = sign * ((axis ? in->y[j] : in->x[j]) - bound);
        if (a >= 0.0) out->x[out->n] = in->x[i], out->y[out->n] = in->y[i], out->n++;
        if ((a >= 0.0) != (b >= 0.0)) {
            double t = a / (a - b);
            out->x[out->n] = in->x[i] + t * (in->x[j] - in->x[i]);
            out->y[out->n] = in->y[i] + t * (in->y[j] - in->y[i]);
            out->n++;
        }
    }
}

/* Signed area (> 0 counter-clockwise) and centroid. Clipping against half-planes keeps the turn. */
static double area_centroid(const poly *p, double *cx, double *cy)
{
    double a = 0.0, x = 0.0, y = 0.0;
    for (int i = 0; i < p->n; ++i) {
        int j = (i + 1) % p->n;
        double c = p->x[i] * p->y[j] - p->x[j] * p->y[i];
        a += c, x += (p->x[i] + p->x[j]) * c, y += (p->y[i] + p->y[j]) * c;
    }
    if (a != 0.0) *cx = x / (3.0 * a), *cy = y / (3.0 * a);
    return 0.5 * a;
}

typedef struct acc { /* a site while it grows */
    double seed[3], a, p[3], nrm[3], uv[2];
    int32_t island, next;
    int64_t first; /* the piece that started it (coarsening: a fine site) */
} acc;

typedef struct build {
    int n, C, m;
    double radius2;
    int32_t *head; /* m × m: each cell's first site, −1 */
    acc *s;
    int64_t count, cap, pieces;
    double tiny; /* mm² of pieces too small to place (clipping's slivers at cell corners) */
    int32_t last; /* the site the last piece joined */
    bool oom;
} build;

/* A piece at (x, y) texels, point p (mm), area a (mm²), normal nrm (unit), of island isl. */
static void add(build *b, double x, double y, const double *p, double a, const double *nrm, int32_t isl)
{
    int cx = (int)floor(x / b->C), cy = (int)floor(y / b->C);
    cx = cx < 0 ? 0 : cx >= b->m ? b->m - 1 : cx;
    cy = cy < 0 ? 0 : cy >= b->m ? b->m - 1 : cy;
    size_t cell = (size_t)cy * b->m + cx;
    int32_t at = b->head[cell], last = -1; /* the cell's list; last: its tail */
    while (at >= 0) {
        const acc *s = &b->s[at];
        double d0 = p[0] - s->seed[0], d1 = p[1] - s->seed[1], d2 = p[2] - s->seed[2];
        if (s->island == isl && d0 * d0 + d1 * d1 + d2 * d2 <= b->radius2) break;
        last = at, at = s->next;
    }
    if (at < 0) {
        if (b->count == b->cap) {
            int64_t cap = b->cap ? 2 * b->cap : 4096;
            acc *g = cap < INT32_MAX ? realloc(b->s, sizeof *g * (size_t)cap) : NULL;
            if (!g) {
                b->oom = true;
                return;
            }
            b->s = g, b->cap = cap;
        }
        at = (int32_t)b->count++;
        acc *s = &b->s[at];
        memset(s, 0, sizeof *s);
        memcpy(s->seed, p, sizeof s->seed);
        s->island = isl, s->next = -1, s->first = b->pieces;
        if (last < 0) b->head[cell] = at;
        else b->s[last].next = at;
    }
    acc *s = &b->s[at];
    b->last = at, ++b->pieces;
    s->a += a;
    for (int d = 0; d < 3; ++d) s->p[d] += a * p[d], s->nrm[d] += a * nrm[d];
    s->uv[0] += a * x, s->uv[1] += a * y;
}

/* Triangle t's pieces. P: its corners in mm; U: in texels. */
static void triangle(build *b, double P[3][3], double U[3][2], double radius, int32_t isl)
{
    double e1[3], e2[3], cr[3];
    for (int d = 0; d < 3; ++d) e1[d] = P[1][d] - P[0][d], e2[d] = P[2][d] - P[0][d];
    cr[0] = e1[1] * e2[2] - e1[2] * e2[1], cr[1] = e1[2] * e2[0] - e1[0] * e2[2], cr[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double twice = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    if (!(twice > 0.0) || !isfinite(twice)) return;
    double nrm[3] = {cr[0] / twice, cr[1] / twice, cr[2] / twice}, edge = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double *q = P[c], *r = P[(c + 1) % 3];
        edge = fmax(edge, sqrt((r[0] - q[0]) * (r[0] - q[0]) + (r[1] - q[1]) * (r[1] - q[1]) + (r[2] - q[2]) * (r[2] - q[2])));
    }
    int s = (int)ceil(edge / radius);
    s = s < 1 ? 1 : s > SUBDIVIDE_MAX ? SUBDIVIDE_MAX : s;
    double ux1 = U[1][0] - U[0][0], uy1 = U[1][1] - U[0][1], ux2 = U[2][0] - U[0][0], uy2 = U[2][1] - U[0][1];
    double det = ux1 * uy2 - ux2 * uy1, sub = 0.5 * twice / ((double)s * s);
    /* a UV image of less than 1e-6 texel² is taken as none: clipping a sliver that thin, the
     * centroid's barycentrics (divided by det) would be rounding, far off the triangle */
    bool flat = fabs(det) > 2e-6;
    double mm2_per_texel2 = flat ? 0.5 * twice / (0.5 * fabs(det)) : 0.0;
    for (int i = 0; i < s; ++i)
        for (int j = 0; i + j < s; ++j)
            for (int up = 0; up < 2; ++up) {
                if (up && i + j > s - 2) continue;
                /* the sub-triangle's corners as barycentrics (b1, b2) · s */
                double bb[3][2] = {{i, j}, {i + 1, j}, {i, j + 1}};
                if (up) bb[0][0] = i + 1, bb[0][1] = j + 1;
                if (!flat) { /* zero UV area: the sub-triangle whole at its UV */
                    double b1 = (bb[0][0] + bb[1][0] + bb[2][0]) / (3.0 * s), b2 = (bb[0][1] + bb[1][1] + bb[2][1]) / (3.0 * s);
                    double p[3];
                    for (int d = 0; d < 3; ++d) p[d] = P[0][d] + b1 * e1[d] + b2 * e2[d];
                    add(b, U[0][0] + b1 * ux1 + b2 * ux2, U[0][1] + b1 * uy1 + b2 * uy2, p, sub, nrm, isl);
                    continue;
                }
                poly tri = {3, {0}, {0}};
                for (int c = 0; c < 3; ++c) {
                    tri.x[c] = U[0][0] + (bb[c][0] * ux1 + bb[c][1] * ux2) / s;
                    tri.y[c] = U[0][1] + (bb[c][0] * uy1 + bb[c][1] * uy2) / s;
                }
                double x0 = fmin(tri.x[0], fmin(tri.x[1], tri.x[2])), x1 = fmax(tri.x[0], fmax(tri.x[1], tri.x[2]));
                double y0 = fmin(tri.y[0], fmin(tri.y[1], tri.y[2])), y1 = fmax(tri.y[0], fmax(tri.y[1], tri.y[2]));
                for (int cy = (int)floor(y0 / b->C); cy <= (int)floor(y1 / b->C); ++cy) {
                    poly lo, row;
                    clip(&tri, 1, (double)cy * b->C, 1.0, &lo);
                    clip(&lo, 1, (double)(cy + 1) * b->C, -1.0, &row);
                    if (row.n < 3) continue;
                    for (int cx = (int)floor(x0 / b->C); cx <= (int)floor(x1 / b->C); ++cx) {
                        poly left, piece;
                        clip(&row, 0, (double)cx * b->C, 1.0, &left);
                        clip(&left, 0, (double)(cx + 1) * b->C, -1.0, &piece);
                        if (piece.n < 3) continue;
                        double x = 0.0, y = 0.0, a = fabs(area_centroid(&piece, &x, &y)) * mm2_per_texel2; /* either turn */
                        if (!(a > 1e-9 * sub)) { /* a sliver of rounding: its centroid means nothing */
                            b->tiny += a > 0.0 ? a : 0.0;
                            continue;
                        }
                        double dx = x - U[0][0], dy = y - U[0][1], b1 = (dx * uy2 - ux2 * dy) / det,
                               b2 = (ux1 * dy - dx * uy1) / det, p[3];
                        b1 = b1 < 0.0 ? 0.0 : b1 > 1.0 ? 1.0 : b1; /* inside the triangle, as it is */
                        b2 = b2 < 0.0 ? 0.0 : b2 > 1.0 - b1 ? 1.0 - b1 : b2;
                        for (int d = 0; d < 3; ++d) p[d] = P[0][d] + b1 * e1[d] + b2 * e2[d];
                        add(b, x, y, p, a, nrm, isl);
                    }
                }
            }
}

/* A covered texel among the 2 × 2 around (x, y) texels; else the centre of the nearest covered
 * one within 2 texels into (x, y); false when none. */
static bool readable(const int32_t *covered, int n, double *x, double *y)
{
    int x0 = (int)floor(*x - 0.5), y0 = (int)floor(*y - 0.5);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            int xx = x0 + i, yy = y0 + j;
            if (xx >= 0 && yy >= 0 && xx < n && yy < n && covered[(size_t)yy * n + xx] >= 0) return true;
        }
    double best = 8.0 + 1e-9, bx = 0, by = 0; /* within 2 texels: distance² ≤ 8 (a 2-texel diagonal step) */
    bool found = false;
    for (int yy = y0 - 2; yy <= y0 + 3; ++yy)
        for (int xx = x0 - 2; xx <= x0 + 3; ++xx) {
            if (xx < 0 || yy < 0 || xx >= n || yy >= n || covered[(size_t)yy * n + xx] < 0) continue;
            double dx = xx + 0.5 - *x, dy = yy + 0.5 - *y, d = dx * dx + dy * dy;
            if (d < best) best = d, bx = xx + 0.5, by = yy + 0.5, found = true;
        }
    if (found) *x = bx, *y = by;
    return found;
}

dm_result dm_gather_sites_build(const dm_mesh *m, const int32_t *covered, int n, double mm_per_unit, int cell,
                                double radius_mm, dm_gather_sites *out, dm_error *err)
{
    memset(out, 0, sizeof *out);
    if (!m || !covered || n < 1 || cell < 1 || cell > n || !(mm_per_unit > 0) || !isfinite(mm_per_unit) ||
        !(radius_mm > 0) || !isfinite(radius_mm))
        return dm_fail(err, DM_ERR_RANGE, "gather sites: size %d, cell %d, mm_per_unit %g, radius %g mm", n, cell,
                       mm_per_unit, radius_mm);
    build b = {n, cell, (n + cell - 1) / cell, radius_mm * radius_mm, NULL, NULL, 0, 0, 0, 0.0, -1, false};
    int32_t *island = malloc(sizeof *island * (size_t)m->triangle_count), islands = 0;
    b.head = malloc(sizeof *b.head * (size_t)b.m * (size_t)b.m);
    if (!island || !b.head) {
        free(island), free(b.head);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "gather sites: out of memory");
    }
    dm_result rc = dm_mesh_uv_islands(m, island, &islands, err);
    for (size_t c = 0; c < (size_t)b.m * b.m; ++c) b.head[c] = -1;
    for (int32_t t = 0; rc == DM_OK && t < m->triangle_count && !b.oom; ++t) {
        double P[3][3], U[3][2];
        for (int c = 0; c < 3; ++c) {
            for (int d = 0; d < 3; ++d) P[c][d] = (double)m->positions[3 * (size_t)m->indices[3 * (size_t)t + c] + d] * mm_per_unit;
            U[c][0] = (double)m->uvs[6 * (size_t)t + 2 * c] * n, U[c][1] = (double)m->uvs[6 * (size_t)t + 2 * c + 1] * n;
        }
        triangle(&b, P, U, radius_mm, island[t]);
    }
    if (rc == DM_OK && b.oom) rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "gather sites: out of memory");
    if (rc == DM_OK) {
        int64_t k = b.count;
        out->p = malloc(sizeof *out->p * 3 * (size_t)(k ? k : 1));
        out->nrm = malloc(sizeof *out->nrm * 3 * (size_t)(k ? k : 1));
        out->area = malloc(sizeof *out->area * (size_t)(k ? k : 1));
        out->uv = malloc(sizeof *out->uv * 2 * (size_t)(k ? k : 1));
        out->island = malloc(sizeof *out->island * (size_t)(k ? k : 1));
        if (!out->p || !out->nrm || !out->area || !out->uv || !out->island) rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "gather sites: out of memory");
    }
    out->dropped_mm2 = b.tiny;
    for (int64_t i = 0; rc == DM_OK && i < b.count; ++i) { /* in creation order: the triangles' order */
        const acc *s = &b.s[i];
        double x = s->uv[0] / s->a, y = s->uv[1] / s->a;
        if (!readable(covered, n, &x, &y)) {
            out->dropped_mm2 += s->a;
            continue;
        }
        int64_t o = out->count++;
        double len = sqrt(s->nrm[0] * s->nrm[0] + s->nrm[1] * s->nrm[1] + s->nrm[2] * s->nrm[2]);
        for (int d = 0; d < 3; ++d) out->p[3 * o + d] = s->p[d] / s->a, out->nrm[3 * o + d] = len > 0 ? s->nrm[d] / len : 0.0;
        out->area[o] = s->a, out->island[o] = s->island;
        out->uv[2 * o] = (float)(x / n), out->uv[2 * o + 1] = (float)(y / n);
    }
    free(island), free(b.head), free(b.s);
    if (rc != DM_OK) dm_gather_sites_free(out);
    return rc;
}

void dm_gather_sites_free(dm_gather_sites *s)
{
    free(s->p), free(s->nrm), free(s->area), free(s->uv), free(s->island);
    memset(s, 0, sizeof *s);
}

dm_result dm_gather_sites_coarsen(const dm_gather_sites *fine, const int32_t *covered, int n, int cell,
                                  double radius_mm, dm_gather_sites *coarse, int32_t **child_first,
                                  int32_t **children, dm_error *err)
{
    memset(coarse, 0, sizeof *coarse);
    *child_first = *children = NULL;
    if (n < 1 || cell < 1 || cell > n || !(radius_mm > 0) || !isfinite(radius_mm))
        return dm_fail(err, DM_ERR_RANGE, "gather sites: coarsen: size %d, cell %d, radius %g mm", n, cell, radius_mm);
    build b = {n, cell, (n + cell - 1) / cell, radius_mm * radius_mm, NULL, NULL, 0, 0, 0, 0.0, -1, false};
    int32_t *parent = malloc(sizeof *parent * (size_t)(fine->count ? fine->count : 1));
    b.head = malloc(sizeof *b.head * (size_t)b.m * (size_t)b.m);
    dm_result rc = parent && b.head ? DM_OK : dm_fail(err, DM_ERR_OUT_OF_MEMORY, "gather sites: out of memory");
    for (size_t c = 0; rc == DM_OK && c < (size_t)b.m * b.m; ++c) b.head[c] = -1;
    for (int64_t f = 0; rc == DM_OK && f < fine->count && !b.oom; ++f) {
        /* the fine site as one piece: its UV in texels, its area-weighted normal */
        add(&b, fine->uv[2 * f] * (double)n, fine->uv[2 * f + 1] * (double)n, fine->p + 3 * f, fine->area[f],
            fine->nrm + 3 * f, fine->island[f]);
        parent[f] = b.last;
    }
    if (rc == DM_OK && b.oom) rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "gather sites: out of memory");
    int64_t k = b.count;
    if (rc == DM_OK) {
        coarse->p = malloc(sizeof *coarse->p * 3 * (size_t)(k ? k : 1));
        coarse->nrm = malloc(sizeof *coarse->nrm * 3 * (size_t)(k ? k : 1));
        coarse->area = malloc(sizeof *coarse->area * (size_t)(k ? k : 1));
        coarse->uv = malloc(sizeof *coarse->uv * 2 * (size_t)(k ? k : 1));
        coarse->island = malloc(sizeof *coarse->island * (size_t)(k ? k : 1));
        *child_first = calloc((size_t)k + 1, sizeof **child_first);
        *children = malloc(sizeof **children * (size_t)(fine->count ? fine->count : 1));
        if (!coarse->p || !coarse->nrm || !coarse->area || !coarse->uv || !coarse->island || !*child_first || !*children)
            rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "gather sites: out of memory");
    }
    if (rc == DM_OK) {
        for (int64_t i = 0; i < k; ++i) { /* every coarse site holds a fine one: all readable */
            const acc *s = &b.s[i];
            double x = s->uv[0] / s->a, y = s->uv[1] / s->a;
            if (!readable(covered, n, &x, &y)) { /* between its fine ones' texels: read at its first's */
                const float *uv0 = fine->uv + 2 * (size_t)s->first;
                x = uv0[0] * (double)n, y = uv0[1] * (double)n;
            }
            double len = sqrt(s->nrm[0] * s->nrm[0] + s->nrm[1] * s->nrm[1] + s->nrm[2] * s->nrm[2]);
            for (int d = 0; d < 3; ++d) coarse->p[3 * i + d] = s->p[d] / s->a, coarse->nrm[3 * i + d] = len > 0 ? s->nrm[d] / len : 0.0;
            coarse->area[i] = s->a, coarse->island[i] = s->island;
            coarse->uv[2 * i] = (float)(x / n), coarse->uv[2 * i + 1] = (float)(y / n);
        }
        coarse->count = k;
        for (int64_t f = 0; f < fine->count; ++f) ++(*child_first)[parent[f] + 1];
        for (int64_t i = 0; i < k; ++i) (*child_first)[i + 1] += (*child_first)[i];
        int32_t *fill = calloc((size_t)(k ? k : 1), sizeof *fill);
        if (!fill) rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "gather sites: out of memory");
        for (int64_t f = 0; rc == DM_OK && f < fine->count; ++f)
            (*children)[(*child_first)[parent[f]] + fill[parent[f]]++] = (int32_t)f;
        free(fill);
    }
    free(parent), free(b.head), free(b.s);
    if (rc != DM_OK) {
        dm_gather_sites_free(coarse);
        free(*child_first), free(*children);
        *child_first = *children = NULL;
    }
    return rc;
}
