/* dm_thin_gather.c — the gathered levels' bake. See dm_thin_gather.h. */
#include "bake/dm_thin_gather.h"

#include <math.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_gather_sites.h"
#include "core/dm_parallel.h"
#include "mesh/dm_seam_edges.h"
#include "mesh/dm_uv_raster.h"

#define TWO_PI 6.283185307179586476925
#define GRID 128           /* hash grid cells per axis over the points */
#define SEAM_SAMPLE_MM 0.25 /* the seam edges as points this far apart at most */

typedef struct grid { /* a hash grid over points */
    const double *p;
    int64_t count;
    int32_t *head, *next;
    double lo[3], step;
} grid;

typedef struct job {
    const dm_thin_gather_options *o;
    int n;
    const int32_t *tri;
    const double *p, *nrm, *area; /* per texel */
    dm_gather_sites s[DM_THIN_GATHER_LEVELS], cs[DM_THIN_GATHER_LEVELS]; /* fine and coarse sites */
    int32_t *child_first[DM_THIN_GATHER_LEVELS], *children[DM_THIN_GATHER_LEVELS];
    int32_t most_children; /* the most fine sites a coarse site holds */
    grid g[DM_THIN_GATHER_LEVELS], cg[DM_THIN_GATHER_LEVELS], seam;
    double reach[DM_THIN_GATHER_LEVELS], split[DM_THIN_GATHER_LEVELS];
    int64_t base[DM_THIN_GATHER_LEVELS], cbase[DM_THIN_GATHER_LEVELS]; /* the tap index of each level's first fine, coarse site */
    int32_t *count;       /* per leader texel per level: its group's taps (pass 2) */
    uint8_t *why;         /* per texel: 1 facing away, 2 seam (pass 1) */
    int32_t *lead;        /* per texel: its group's leader texel (−1: uncovered) */
    int32_t *next;        /* per texel: the next member of its group (−1: the last) */
    double *radius;       /* per leader texel: its farthest member, mm */
    uint8_t *gathers;     /* per leader texel: some member gathers */
    const int64_t *first; /* per texel: first tap (pass 3) */
    float *taps;
    int pass;             /* 1 which texels gather, 2 how many taps, 3 the taps */
    atomic_int out_of_memory; /* a worker's scratch could not be had (passes 2 and 3) */
} job;

static double dist2(const double *a, const double *b)
{
    double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
    return d0 * d0 + d1 * d1 + d2 * d2;
}

static int grid_at(const grid *g, const double *p, int k)
{
    int i = (int)floor((p[k] - g->lo[k]) / g->step);
    return i < 0 ? 0 : i >= GRID ? GRID - 1 : i;
}

/* The grid over count points (3 doubles each), cells at least `reach` wide. */
static bool grid_make(grid *g, const double *p, int64_t count, double reach)
{
    memset(g, 0, sizeof *g);
    g->p = p, g->count = count;
    g->head = malloc(sizeof *g->head * GRID * GRID * GRID), g->next = malloc(sizeof *g->next * (size_t)(count ? count : 1));
    if (!g->head || !g->next) return false;
    double hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    g->lo[0] = g->lo[1] = g->lo[2] = INFINITY;
    for (int64_t k = 0; k < count; ++k)
        for (int d = 0; d < 3; ++d) g->lo[d] = fmin(g->lo[d], p[3 * k + d]), hi[d] = fmax(hi[d], p[3 * k + d]);
    double span = fmax(fmax(hi[0] - g->lo[0], hi[1] - g->lo[1]), hi[2] - g->lo[2]);
    g->step = fmax(reach, span / GRID) * (1.0 + 1e-9);
    if (!(g->step > 0) || !isfinite(g->step)) g->step = 1.0;
    for (int c = 0; c < GRID * GRID * GRID; ++c) g->head[c] = -1;
    for (int64_t k = count; k-- > 0;) { /* lists in ascending order */
        int c = (grid_at(g, p + 3 * k, 2) * GRID + grid_at(g, p + 3 * k, 1)) * GRID + grid_at(g, p + 3 * k, 0);
        g->next[k] = g->head[c], g->head[c] = (int32_t)k;
    }
    return true;
}

static void grid_free(grid *g)
{
    free(g->head), free(g->next);
    memset(g, 0, sizeof *g);
}

/* Visits the points within r of q in ascending grid order, then list order; fn returns false to stop. */
typedef bool (*visit_fn)(void *ctx, int32_t k, double d2);
static void visit(const grid *g, const double *q, double r, visit_fn fn, void *ctx)
{
    int g0[3], g1[3];
    for (int k = 0; k < 3; ++k) {
        g0[k] = grid_at(g, (double[3]){q[0] - r, q[1] - r, q[2] - r}, k);
        g1[k] = grid_at(g, (double[3]){q[0] + r, q[1] + r, q[2] + r}, k);
    }
    for (int z = g0[2]; z <= g1[2]; ++z)
        for (int y = g0[1]; y <= g1[1]; ++y)
            for (int x = g0[0]; x <= g1[0]; ++x)
                for (int32_t k = g->head[(z * GRID + y) * GRID + x]; k >= 0; k = g->next[k]) {
                    double d2 = dist2(q, g->p + 3 * (size_t)k);
                    if (d2 <= r * r && !fn(ctx, k, d2)) return;
                }
}

typedef struct probe {
    const job *j;
    const double *n, *q;
    int level;
    bool found;
    int32_t count;
    float *out;
    int32_t leader;   /* the group whose taps these are (its members: j->next from it) */
    double members;   /* how many */
    double *fine;     /* scratch: a coarse site's fine sites' weights summed over the members */
    uint8_t *used;    /* scratch: which of them some member reads */
} probe;

static bool find_away(void *ctx, int32_t k, double d2)
{
    (void)d2;
    probe *p = ctx;
    const double *sn = p->j->s[p->j->o->level_count - 1].nrm + 3 * (size_t)k;
    p->found = sn[0] * p->n[0] + sn[1] * p->n[1] + sn[2] * p->n[2] < 0;
    return !p->found;
}

static bool find_any(void *ctx, int32_t k, double d2)
{
    (void)k, (void)d2;
    ((probe *)ctx)->found = true;
    return false;
}

/* A site of area a at distance² d2 as a point of mass G · A, but never more than any patch of its
 * area can hold under G (a disc around the centre: 1 − exp(−A / 2πv)). */
static double site_weight(double v, double a, double d2)
{
    return fmin(exp(-d2 / (2.0 * v)) / (TWO_PI * v) * a, -expm1(-a / (TWO_PI * v)));
}

static void emit(probe *p, int64_t index, double w)
{
    if (p->out) p->out[2 * p->count] = (float)index, p->out[2 * p->count + 1] = (float)w;
    ++p->count;
}

/* A coarse site near the group: for each member within reach of it, the coarse site itself when
 * split or farther (its weight its fine sites' sum, exact), else its fine sites within reach;
 * each tap's weight the members' mean (one member: the texel's own). */
static bool add_taps(void *ctx, int32_t k, double d2)
{
    (void)d2;
    probe *p = ctx;
    const job *j = p->j;
    const int g = p->level;
    const double v = j->o->variance_mm2[g], reach2 = j->reach[g] * j->reach[g], split2 = j->split[g] * j->split[g];
    const int32_t c0 = j->child_first[g][k], c1 = j->child_first[g][k + 1];
    const double *cp = j->cs[g].p + 3 * (size_t)k;
    double coarse = 0.0;
    bool any_coarse = false;
    for (int32_t c = c0; c < c1; ++c) p->fine[c - c0] = 0.0, p->used[c - c0] = 0;
    for (int32_t m = p->leader; m >= 0; m = j->next[m]) {
        const double *q = j->p + 3 * (size_t)m, dm = dist2(q, cp);
        if (dm > reach2) continue;
        if (dm >= split2) {
            double w = 0.0;
            for (int32_t c = c0; c < c1; ++c) {
                int32_t f = j->children[g][c];
                w += site_weight(v, j->s[g].area[f], dist2(q, j->s[g].p + 3 * (size_t)f));
            }
            coarse += w, any_coarse = true;
            continue;
        }
        for (int32_t c = c0; c < c1; ++c) {
            int32_t f = j->children[g][c];
            double df = dist2(q, j->s[g].p + 3 * (size_t)f);
            if (df <= reach2) p->fine[c - c0] += site_weight(v, j->s[g].area[f], df), p->used[c - c0] = 1;
        }
    }
    if (any_coarse) emit(p, j->cbase[g] + k, coarse / p->members);
    for (int32_t c = c0; c < c1; ++c)
        if (p->used[c - c0]) emit(p, j->base[g] + j->children[g][c], p->fine[c - c0] / p->members);
    return true;
}

static void rows(void *ctx, size_t begin, size_t end)
{
    job *j = ctx;
    const int L = j->o->level_count;
    double *fine = j->pass > 1 ? malloc(sizeof *fine * (size_t)(j->most_children + 1)) : NULL;
    uint8_t *used = j->pass > 1 ? malloc((size_t)(j->most_children + 1)) : NULL;
    if (j->pass > 1 && (!fine || !used)) { /* the bake fails with DM_ERR_OUT_OF_MEMORY */
        atomic_store(&j->out_of_memory, 1);
        free(fine), free(used);
        return;
    }
    for (size_t y = begin; y < end; ++y)
        for (int x = 0; x < j->n; ++x) {
            size_t i = y * (size_t)j->n + (size_t)x;
            if (j->tri[i] < 0 || !(j->area[i] > 0)) continue;
            const double *q = j->p + 3 * i;
            if (j->pass == 1) { /* a site facing away within near_mm, or a seam within seam_mm? */
                probe pr = {j, j->nrm + 3 * i, q, 0, false, 0, NULL, 0, 0, NULL, NULL};
                visit(&j->g[L - 1], q, j->o->near_mm, find_away, &pr);
                j->why[i] = pr.found ? 1 : 0;
                if (!pr.found && j->o->seam_mm > 0 && j->seam.count) {
                    visit(&j->seam, q, j->o->seam_mm, find_any, &pr);
                    j->why[i] = pr.found ? 2 : 0;
                }
                continue;
            }
            if (j->lead[i] != (int32_t)i || !j->gathers[i] || (j->pass == 3 && j->first[i + 1] == j->first[i])) continue;
            float *out = j->pass == 3 ? j->taps + 2 * j->first[i] : NULL;
            if (out && L > 2) /* the run's count tap: gathered levels 2 and 3's taps */
                out[0] = (float)j->count[L * i + 2], out[1] = L > 3 ? (float)j->count[L * i + 3] : 0.0f, out += 2;
            double members = 0;
            for (int32_t m = (int32_t)i; m >= 0; m = j->next[m]) ++members;
            for (int g = 0; g < L; ++g) {
                probe pr = {j, NULL, q, g, false, 0, out, (int32_t)i, members, fine, used};
                /* sites in ascending order within the visit: the sum at run time is deterministic */
                visit(&j->cg[g], q, j->reach[g] + j->radius[i], add_taps, &pr);
                if (j->pass == 2) j->count[L * i + g] = pr.count;
                if (out) out += 2 * pr.count;
            }
        }
    free(fine), free(used);
}

/* The groups of `block` × `block` texels that share one run of taps: in each block, in row order,
 * a covered texel not yet taken leads a group of the block's untaken covered texels within
 * DM_THIN_GATHER_JOIN · block · h of it in 3-D (a block across a chart's edge, or a squashed
 * chart's texels, give groups of their own); a group gathers when one of its members does.
 * block 1: every texel alone. */
static void group(job *j, int block, double h)
{
    const int n = j->n;
    const double join2 = (DM_THIN_GATHER_JOIN * block * h) * (DM_THIN_GATHER_JOIN * block * h);
    for (size_t i = 0; i < (size_t)n * n; ++i) j->lead[i] = -1, j->next[i] = -1, j->radius[i] = 0, j->gathers[i] = 0;
    for (int by = 0; by < n; by += block)
        for (int bx = 0; bx < n; bx += block)
            for (int y = by; y < by + block && y < n; ++y)
                for (int x = bx; x < bx + block && x < n; ++x) {
                    int32_t l = y * n + x, last = l;
                    if (j->tri[l] < 0 || !(j->area[l] > 0) || j->lead[l] >= 0) continue;
                    j->lead[l] = l, j->gathers[l] = j->why[l] != 0;
                    for (int yy = y; yy < by + block && yy < n; ++yy)
                        for (int xx = yy == y ? x + 1 : bx; xx < bx + block && xx < n; ++xx) {
                            int32_t m = yy * n + xx;
                            double d2;
                            if (j->tri[m] < 0 || !(j->area[m] > 0) || j->lead[m] >= 0 ||
                                (d2 = dist2(j->p + 3 * (size_t)l, j->p + 3 * (size_t)m)) > join2)
                                continue;
                            j->lead[m] = l, j->next[last] = m, last = m;
                            j->radius[l] = fmax(j->radius[l], sqrt(d2));
                            j->gathers[l] |= j->why[m] != 0;
                        }
                }
}

void dm_thin_gather_options_for(const double *variance_mm2, int count, int size, double mm_per_unit,
                                dm_thin_gather_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->size = size, opt->mm_per_unit = mm_per_unit;
    int first = count;
    while (first > 0 && count - first < DM_THIN_GATHER_LEVELS && variance_mm2[first - 1] >= 1.0) --first;
    opt->first_level = first, opt->level_count = count - first;
    for (int g = 0; g < opt->level_count; ++g) opt->variance_mm2[g] = variance_mm2[first + g];
    opt->near_mm = opt->level_count ? 2.0 * sqrt(variance_mm2[count - 1]) : 0.0;
    opt->seam_mm = opt->level_count ? DM_THIN_GATHER_SEAM_SIGMAS * sqrt(variance_mm2[count - 1]) : 0.0;
}

/* Per covered texel: its surface point (mm), unit normal (the triangle's), skin area (mm²). */
static void texel_geometry(const dm_mesh *m, int n, double mm, const int32_t *tri, double *p, double *nrm, double *area)
{
    for (size_t i = 0; i < (size_t)n * n; ++i) {
        int32_t t = tri[i];
        if (t < 0) continue;
        const uint32_t *ix = m->indices + 3 * (size_t)t;
        double c[3][3], b1, b2, e1[3], e2[3], cr[3];
        for (int k = 0; k < 3; ++k)
            for (int d = 0; d < 3; ++d) c[k][d] = (double)m->positions[3 * (size_t)ix[k] + d] * mm;
        dm_uv_raster_barycentrics(m, t, ((double)(i % (size_t)n) + 0.5) / n, ((double)(i / (size_t)n) + 0.5) / n, &b1, &b2);
        for (int d = 0; d < 3; ++d) {
            p[3 * i + d] = (1.0 - b1 - b2) * c[0][d] + b1 * c[1][d] + b2 * c[2][d];
            e1[d] = c[1][d] - c[0][d], e2[d] = c[2][d] - c[0][d];
        }
        cr[0] = e1[1] * e2[2] - e1[2] * e2[1], cr[1] = e1[2] * e2[0] - e1[0] * e2[2], cr[2] = e1[0] * e2[1] - e1[1] * e2[0];
        double a3 = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
        const float *uv = m->uvs + 6 * (size_t)t;
        double auv = fabs((uv[2] - uv[0]) * (uv[5] - uv[1]) - (uv[4] - uv[0]) * (uv[3] - uv[1]));
        area[i] = a3 > 0 && auv > 0 ? a3 / auv / ((double)n * n) : 0.0;
        for (int d = 0; d < 3; ++d) nrm[3 * i + d] = a3 > 0 ? cr[d] / a3 : 0.0;
    }
}

/* The seam edges as points at most SEAM_SAMPLE_MM apart (*out malloc'd, 3 doubles each). */
static dm_result seam_points(const dm_mesh *m, double mm, double **out, int64_t *count, dm_error *err)
{
    *out = NULL, *count = 0;
    dm_seam_edges se;
    dm_result rc = dm_seam_edges_find(m, &se, err);
    int64_t total = 0;
    for (size_t e = 0; rc == DM_OK && e < se.count; ++e) {
        const float *a = m->positions + 3 * (size_t)se.edges[e].a, *b = m->positions + 3 * (size_t)se.edges[e].b;
        double len = mm * sqrt((double)(b[0] - a[0]) * (b[0] - a[0]) + (double)(b[1] - a[1]) * (b[1] - a[1]) +
                               (double)(b[2] - a[2]) * (b[2] - a[2]));
        total += 1 + (int64_t)fmin(ceil(len / SEAM_SAMPLE_MM), 1e6);
    }
    if (rc == DM_OK && !(*out = malloc(sizeof **out * 3 * (size_t)(total ? total : 1))))
        rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "thin gather: seam points: out of memory");
    for (size_t e = 0; rc == DM_OK && e < se.count; ++e) {
        const float *a = m->positions + 3 * (size_t)se.edges[e].a, *b = m->positions + 3 * (size_t)se.edges[e].b;
        double len = mm * sqrt((double)(b[0] - a[0]) * (b[0] - a[0]) + (double)(b[1] - a[1]) * (b[1] - a[1]) +
                               (double)(b[2] - a[2]) * (b[2] - a[2]));
        int64_t s = (int64_t)fmin(ceil(len / SEAM_SAMPLE_MM), 1e6);
        for (int64_t k = 0; k <= s; ++k) {
            double t = s ? (double)k / (double)s : 0.0;
            for (int d = 0; d < 3; ++d) (*out)[3 * *count + d] = mm * ((1.0 - t) * a[d] + t * b[d]);
            ++*count;
        }
    }
    dm_seam_edges_free(&se);
    return rc;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Checks the options; DM_OK or DM_ERR_RANGE. */
static dm_result check(const dm_thin_gather_options *opt, dm_error *err)
{
    if (opt->size < 1 || opt->size > DM_THIN_GATHER_SIZE_MAX || opt->level_count < 1 ||
        opt->level_count > DM_THIN_GATHER_LEVELS || opt->first_level < 0 || opt->threads < 0 || opt->block < 0 ||
        opt->block > DM_THIN_GATHER_BLOCK_MAX || (opt->block & (opt->block - 1)) || opt->taps_max < 0)
        return dm_fail(err, DM_ERR_RANGE,
                       "thin gather: size %d (1..%d), levels %d (1..%d) from %d, threads %d, block %d (0 or a power of "
                       "two up to %d), taps_max %lld (>= 0)", opt->size, DM_THIN_GATHER_SIZE_MAX, opt->level_count,
                       DM_THIN_GATHER_LEVELS, opt->first_level, opt->threads, opt->block, DM_THIN_GATHER_BLOCK_MAX,
                       (long long)opt->taps_max);
    bool finite = opt->mm_per_unit > 0 && isfinite(opt->mm_per_unit) && opt->near_mm > 0 && isfinite(opt->near_mm) &&
                  opt->seam_mm >= 0 && isfinite(opt->seam_mm);
    for (int g = 0; g < opt->level_count; ++g)
        finite = finite && opt->variance_mm2[g] > 0 && isfinite(opt->variance_mm2[g]);
    if (!finite)
        return dm_fail(err, DM_ERR_RANGE,
                       "thin gather: mm_per_unit, near_mm and the variances must be finite and > 0, seam_mm ≥ 0");
    return DM_OK;
}

dm_result dm_thin_gather_bake(const dm_mesh *m, const dm_thin_gather_options *opt, dm_thin_gather *out,
                              dm_thin_gather_stats *stats, dm_error *err)
{
    memset(out, 0, sizeof *out);
    if (stats) memset(stats, 0, sizeof *stats);
    dm_result rc = check(opt, err);
    if (rc == DM_OK) rc = dm_mesh_validate(m, "thin gather: mesh", err);
    if (rc != DM_OK) return rc;
    const int n = opt->size, L = opt->level_count;
    const size_t texels = (size_t)n * n;
    job j = {.o = opt, .n = n};
    int32_t *tri = malloc(sizeof *tri * texels);
    double *p = calloc(3 * texels, sizeof *p), *nrm = calloc(3 * texels, sizeof *nrm), *area = calloc(texels, sizeof *area);
    double *sides = malloc(sizeof *sides * texels), *seam = NULL;
    int32_t *count = calloc((size_t)L * texels, sizeof *count);
    uint8_t *why = calloc(texels, 1), *gathers = malloc(texels);
    int32_t *lead = malloc(sizeof *lead * texels), *next = malloc(sizeof *next * texels);
    double *radius = malloc(sizeof *radius * texels);
    int64_t *first = malloc(sizeof *first * (texels + 1)), seam_count = 0;
    out->index = calloc(4 * texels, sizeof *out->index);
    rc = tri && p && nrm && area && sides && count && why && gathers && lead && next && radius && first && out->index
             ? DM_OK
             : dm_fail(err, DM_ERR_OUT_OF_MEMORY, "thin gather %dx%d: out of memory", n, n);
    if (rc == DM_OK) rc = dm_uv_raster(m, NULL, n, n, opt->threads, tri, NULL, err);
    double h = 0;
    size_t covered = 0;
    int64_t sites = DM_THIN_GATHER_HEADER_TAPS;
    if (rc == DM_OK) {
        texel_geometry(m, n, opt->mm_per_unit, tri, p, nrm, area);
        for (size_t i = 0; i < texels; ++i)
            if (tri[i] >= 0 && area[i] > 0) sides[covered++] = sqrt(area[i]);
        if (covered) qsort(sides, covered, sizeof *sides, cmp_double), h = sides[covered / 2];
        for (int g = 0; g < L && rc == DM_OK; ++g) {
            int C = 1;
            double sigma = sqrt(opt->variance_mm2[g]);
            while (2 * C <= n && 2 * C * h <= DM_THIN_GATHER_CELL_SIGMAS * sigma) C *= 2;
            j.reach[g] = DM_THIN_GATHER_REACH_SIGMAS * sigma;
            out->cell[g] = C;
            j.split[g] = DM_THIN_GATHER_SPLIT_SIGMAS * sigma;
            rc = dm_gather_sites_build(m, tri, n, opt->mm_per_unit, C, DM_THIN_GATHER_CLUSTER_SIGMAS * sigma, &j.s[g], err);
            if (rc == DM_OK)
                rc = dm_gather_sites_coarsen(&j.s[g], tri, n, 2 * C <= n ? 2 * C : C, DM_THIN_GATHER_COARSE_CLUSTER_SIGMAS * sigma,
                                             &j.cs[g], &j.child_first[g], &j.children[g], err);
            if (rc == DM_OK && (!grid_make(&j.g[g], j.s[g].p, j.s[g].count, fmax(j.reach[g], opt->near_mm)) ||
                                !grid_make(&j.cg[g], j.cs[g].p, j.cs[g].count, j.reach[g])))
                rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "thin gather: sites: out of memory");
            for (int64_t k = 0; rc == DM_OK && k < j.cs[g].count; ++k)
                j.most_children = j.most_children > j.child_first[g][k + 1] - j.child_first[g][k]
                                      ? j.most_children : j.child_first[g][k + 1] - j.child_first[g][k];
            j.base[g] = sites, sites += j.s[g].count;
            j.cbase[g] = sites, sites += j.cs[g].count;
            out->sites[g] = j.s[g].count + j.cs[g].count;
        }
        if (rc == DM_OK && (double)sites >= DM_THIN_GATHER_FLOAT_EXACT)
            rc = dm_fail(err, DM_ERR_RANGE, "thin gather %dx%d: %lld sites, a float counts exactly below 2^24", n, n,
                         (long long)sites);
    }
    if (rc == DM_OK && opt->seam_mm > 0) rc = seam_points(m, opt->mm_per_unit, &seam, &seam_count, err);
    if (rc == DM_OK && opt->seam_mm > 0 && !grid_make(&j.seam, seam, seam_count, opt->seam_mm))
        rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "thin gather: seam points: out of memory");
    int block = opt->block ? opt->block : 1;
    const int64_t taps_max = opt->taps_max ? opt->taps_max : DM_THIN_GATHER_TAPS_MAX;
    if (rc == DM_OK) {
        j.tri = tri, j.p = p, j.nrm = nrm, j.area = area, j.count = count, j.why = why;
        j.lead = lead, j.next = next, j.radius = radius, j.gathers = gathers;
        j.pass = 1;
        dm_parallel_for((size_t)n, 1, opt->threads, rows, &j); /* pass 1: which texels */
    }
    while (rc == DM_OK) { /* pass 2: how many taps, block by block until they fit (block 0: auto) */
        group(&j, block, h);
        memset(count, 0, sizeof *count * (size_t)L * texels);
        j.pass = 2;
        dm_parallel_for((size_t)n, 1, opt->threads, rows, &j);
        if (atomic_load(&j.out_of_memory)) {
            rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "thin gather %dx%d: scratch: out of memory", n, n);
            break;
        }
        first[0] = sites;
        for (size_t i = 0; i < texels; ++i) {
            /* the index marks a gathering texel by its first two levels' taps: a run with none
             * (no site in reach: never on a mesh) gathers nothing */
            if (count[L * i] + (L > 1 ? count[L * i + 1] : 0) == 0)
                for (int g = 0; g < L; ++g) count[L * i + g] = 0;
            int64_t c = L > 2 && count[L * i] + count[L * i + 1] > 0 ? DM_THIN_GATHER_COUNT_TAPS : 0;
            for (int g = 0; g < L; ++g) {
                c += count[L * i + g];
                if ((double)count[L * i + g] >= DM_THIN_GATHER_FLOAT_EXACT) rc = DM_ERR_RANGE;
            }
            first[i + 1] = first[i] + c;
        }
        out->tap_count = first[texels];
        if (rc != DM_OK) rc = dm_fail(err, DM_ERR_RANGE, "thin gather %dx%d: a texel has 2^24 taps or more", n, n);
        else if (out->tap_count - sites <= taps_max) break;
        else if (opt->block || block >= DM_THIN_GATHER_BLOCK_MAX)
            rc = dm_fail(err, DM_ERR_RANGE, "thin gather %dx%d: %lld taps in blocks of %d x %d, more than %lld", n, n,
                         (long long)(out->tap_count - sites), block, block, (long long)taps_max);
        else block *= 2;
    }
    if (rc == DM_OK) {
        out->taps_rows = (int)((out->tap_count + DM_THIN_GATHER_TAPS_WIDTH - 1) / DM_THIN_GATHER_TAPS_WIDTH);
        out->taps = calloc(2 * (size_t)DM_THIN_GATHER_TAPS_WIDTH * (size_t)out->taps_rows, sizeof *out->taps);
        if (!out->taps) rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "thin gather: %lld taps: out of memory", (long long)out->tap_count);
    }
    if (rc == DM_OK) {
        j.first = first, j.taps = out->taps, j.pass = 3;
        dm_parallel_for((size_t)n, 1, opt->threads, rows, &j); /* pass 3: the taps */
        if (atomic_load(&j.out_of_memory))
            rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "thin gather %dx%d: scratch: out of memory", n, n);
    }
    if (rc == DM_OK) {
        out->taps[0] = (float)opt->first_level, out->taps[1] = (float)L;
        out->taps[2] = (float)DM_THIN_GATHER_FORMAT, out->taps[3] = (float)(sites - DM_THIN_GATHER_HEADER_TAPS);
        for (int g = 0; g < L; ++g) {
            memcpy(out->taps + 2 * j.base[g], j.s[g].uv, sizeof(float) * 2 * (size_t)j.s[g].count);
            memcpy(out->taps + 2 * j.cbase[g], j.cs[g].uv, sizeof(float) * 2 * (size_t)j.cs[g].count);
        }
        double most = 0;
        int64_t gathering = 0;
        for (size_t i = 0; i < texels; ++i) {
            size_t l = lead[i] >= 0 ? (size_t)lead[i] : i; /* its group's run */
            if (first[l + 1] == first[l]) continue;
            float *o = out->index + 4 * i;
            o[0] = (float)(first[l] / DM_THIN_GATHER_TAPS_WIDTH), o[3] = (float)(first[l] % DM_THIN_GATHER_TAPS_WIDTH);
            o[1] = (float)count[L * l], o[2] = L > 1 ? (float)count[L * l + 1] : 0.0f;
            ++gathering, most = fmax(most, (double)(first[l + 1] - first[l]));
            if (stats) stats->thin_texels += why[i] == 1, stats->seam_texels += why[i] == 2;
        }
        out->size = n, out->first_level = opt->first_level, out->level_count = L, out->block = block;
        if (stats) {
            stats->covered_texels = (int64_t)covered, stats->gathering_texels = gathering;
            stats->taps = out->tap_count - sites, stats->texel_mm = h, stats->max_taps = most;
            stats->dropped_mm2 = j.s[L - 1].dropped_mm2, stats->block = block;
            for (int g = 0; g < L; ++g) stats->cell[g] = out->cell[g], stats->sites[g] = out->sites[g];
        }
    }
    for (int g = 0; g < DM_THIN_GATHER_LEVELS; ++g) {
        grid_free(&j.g[g]), grid_free(&j.cg[g]), dm_gather_sites_free(&j.s[g]), dm_gather_sites_free(&j.cs[g]);
        free(j.child_first[g]), free(j.children[g]);
    }
    grid_free(&j.seam);
    free(tri), free(p), free(nrm), free(area), free(sides), free(count), free(why), free(first), free(seam);
    free(gathers), free(lead), free(next), free(radius);
    if (rc != DM_OK) dm_thin_gather_free(out);
    return rc;
}

void dm_thin_gather_free(dm_thin_gather *g)
{
    free(g->index), free(g->taps);
    memset(g, 0, sizeof *g);
}

void dm_thin_gather_stats_prov(const dm_thin_gather_stats *s, dm_provenance *p)
{
    dm_prov_add_int(p, "gather_covered_texels", s->covered_texels);
    dm_prov_add_int(p, "gathering_texels", s->gathering_texels);
    dm_prov_add_int(p, "gathering_thin_texels", s->thin_texels);
    dm_prov_add_int(p, "gathering_seam_texels", s->seam_texels);
    dm_prov_add_int(p, "gather_taps", s->taps);
    dm_prov_add_int(p, "gather_sites0", s->sites[0]);
    dm_prov_add_int(p, "gather_sites1", s->sites[1]);
    dm_prov_add_int(p, "gather_cell0", s->cell[0]);
    dm_prov_add_int(p, "gather_cell1", s->cell[1]);
    for (int g = 2; g < DM_THIN_GATHER_LEVELS; ++g) /* only with a third or fourth gathered level */
        if (s->sites[g] > 0) {
            char key[32];
            snprintf(key, sizeof key, "gather_sites%d", g), dm_prov_add_int(p, key, s->sites[g]);
            snprintf(key, sizeof key, "gather_cell%d", g), dm_prov_add_int(p, key, s->cell[g]);
        }
    if (s->block > 1) dm_prov_add_int(p, "gather_block", s->block); /* absent: every texel alone */
    dm_prov_add_double(p, "gather_texel_mm", s->texel_mm);
    dm_prov_add_double(p, "gather_dropped_mm2", s->dropped_mm2);
}
