/* dm_thin_gather.c — the gathered levels' bake. See dm_thin_gather.h. */
#include "bake/dm_thin_gather.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_parallel.h"
#include "mesh/dm_uv_raster.h"

#define TWO_PI 6.283185307179586476925
#define GRID 128 /* hash grid cells per axis over the cells' points */

typedef struct cells {
    int C, m;            /* block side in texels, blocks per side (ceil(N / C)) */
    double *p, *nrm, *a; /* per cell: mean point (mm), summed unit normal, skin area (mm²) */
    int *head, *next;    /* the hash grid over the points (cells with area) */
    double lo[3], step;
} cells;

typedef struct job {
    const dm_thin_gather_options *o;
    int n;
    const int32_t *tri;
    const double *p, *nrm, *area; /* per texel */
    cells c[DM_THIN_GATHER_LEVELS];
    double reach[DM_THIN_GATHER_LEVELS];
    int32_t *count; /* per texel per level: taps (pass 1) */
    const int64_t *first; /* per texel: first tap (pass 2) */
    float *taps;
    bool fill;
} job;

static double dist2(const double *a, const double *b)
{
    double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
    return d0 * d0 + d1 * d1 + d2 * d2;
}

static int grid_at(const cells *c, const double *p, int k)
{
    int i = (int)floor((p[k] - c->lo[k]) / c->step);
    return i < 0 ? 0 : i >= GRID ? GRID - 1 : i;
}

/* Cells of C × C texels: the mean point of their member texels, the sum of their areas. */
static bool make_cells(cells *c, int C, int n, const int32_t *tri, const double *p, const double *nrm,
                       const double *area, double reach)
{
    c->C = C, c->m = (n + C - 1) / C;
    size_t mm = (size_t)c->m * (size_t)c->m;
    double *cnt = calloc(mm, sizeof *cnt);
    c->p = calloc(3 * mm, sizeof *c->p), c->nrm = calloc(3 * mm, sizeof *c->nrm), c->a = calloc(mm, sizeof *c->a);
    c->head = malloc(sizeof *c->head * GRID * GRID * GRID), c->next = malloc(sizeof *c->next * mm);
    if (!cnt || !c->p || !c->nrm || !c->a || !c->head || !c->next) return free(cnt), false;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            size_t i = (size_t)y * n + x, k = (size_t)(y / C) * c->m + (size_t)(x / C);
            if (tri[i] < 0 || !(area[i] > 0)) continue;
            for (int d = 0; d < 3; ++d) c->p[3 * k + d] += p[3 * i + d], c->nrm[3 * k + d] += nrm[3 * i + d];
            c->a[k] += area[i], cnt[k] += 1;
        }
    c->lo[0] = c->lo[1] = c->lo[2] = INFINITY;
    double hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t k = 0; k < mm; ++k) {
        if (!(cnt[k] > 0)) continue;
        for (int d = 0; d < 3; ++d) {
            c->p[3 * k + d] /= cnt[k];
            c->lo[d] = fmin(c->lo[d], c->p[3 * k + d]), hi[d] = fmax(hi[d], c->p[3 * k + d]);
        }
    }
    double span = fmax(fmax(hi[0] - c->lo[0], hi[1] - c->lo[1]), hi[2] - c->lo[2]);
    c->step = fmax(reach, span / GRID) * (1.0 + 1e-9);
    if (!(c->step > 0) || !isfinite(c->step)) c->step = 1.0;
    for (int g = 0; g < GRID * GRID * GRID; ++g) c->head[g] = -1;
    for (size_t k = mm; k-- > 0;) { /* lists in ascending cell order */
        if (!(cnt[k] > 0)) continue;
        int g = (grid_at(c, c->p + 3 * k, 2) * GRID + grid_at(c, c->p + 3 * k, 1)) * GRID + grid_at(c, c->p + 3 * k, 0);
        c->next[k] = c->head[g], c->head[g] = (int)k;
    }
    free(cnt);
    return true;
}

static void free_cells(cells *c)
{
    free(c->p), free(c->nrm), free(c->a), free(c->head), free(c->next);
    memset(c, 0, sizeof *c);
}

/* Visits the cells within r of q in ascending grid order, then list order; fn returns false to stop. */
typedef bool (*visit_fn)(void *ctx, int cell, double d2);
static void visit(const cells *c, const double *q, double r, visit_fn fn, void *ctx)
{
    int g0[3], g1[3];
    for (int k = 0; k < 3; ++k) {
        g0[k] = grid_at(c, (double[3]){q[0] - r, q[1] - r, q[2] - r}, k);
        g1[k] = grid_at(c, (double[3]){q[0] + r, q[1] + r, q[2] + r}, k);
    }
    for (int z = g0[2]; z <= g1[2]; ++z)
        for (int y = g0[1]; y <= g1[1]; ++y)
            for (int x = g0[0]; x <= g1[0]; ++x)
                for (int k = c->head[(z * GRID + y) * GRID + x]; k >= 0; k = c->next[k]) {
                    double d2 = dist2(q, c->p + 3 * (size_t)k);
                    if (d2 <= r * r && !fn(ctx, k, d2)) return;
                }
}

typedef struct probe {
    const job *j;
    const double *n;
    int level;
    bool away;
    int32_t count;
    float *out;
} probe;

static bool find_away(void *ctx, int k, double d2)
{
    (void)d2;
    probe *p = ctx;
    const double *cn = p->j->c[p->j->o->level_count - 1].nrm + 3 * (size_t)k;
    p->away = cn[0] * p->n[0] + cn[1] * p->n[1] + cn[2] * p->n[2] < 0;
    return !p->away;
}

static bool add_tap(void *ctx, int k, double d2)
{
    probe *p = ctx;
    const cells *c = &p->j->c[p->level];
    /* the cell as a point of mass G · A, but never more than any patch of its area can hold
     * under G (a disc around the centre: 1 − exp(−A / 2πv)): a cell far larger than σ (a
     * squashed chart's texels) would otherwise count many times its light */
    double v = p->j->o->variance_mm2[p->level], a = c->a[k];
    double w = fmin(exp(-d2 / (2.0 * v)) / (TWO_PI * v) * a, -expm1(-a / (TWO_PI * v)));
    if (p->out) p->out[2 * p->count] = (float)k, p->out[2 * p->count + 1] = (float)w;
    ++p->count;
    return true;
}

static void rows(void *ctx, size_t begin, size_t end)
{
    job *j = ctx;
    const int L = j->o->level_count;
    for (size_t y = begin; y < end; ++y)
        for (int x = 0; x < j->n; ++x) {
            size_t i = y * (size_t)j->n + (size_t)x;
            if (j->tri[i] < 0 || !(j->area[i] > 0)) continue;
            const double *q = j->p + 3 * i;
            if (!j->fill) { /* does a cell facing away lie within near_mm? */
                probe pr = {j, j->nrm + 3 * i, 0, false, 0, NULL};
                visit(&j->c[L - 1], q, j->o->near_mm, find_away, &pr);
                if (!pr.away) continue;
            } else if (j->first[i + 1] == j->first[i]) {
                continue;
            }
            float *out = j->fill ? j->taps + 2 * j->first[i] : NULL;
            for (int g = 0; g < L; ++g) {
                probe pr = {j, NULL, g, false, 0, out};
                /* cells in ascending order within the visit: the sum at run time is deterministic */
                visit(&j->c[g], q, j->reach[g], add_tap, &pr);
                if (!j->fill) j->count[L * i + g] = pr.count;
                if (out) out += 2 * pr.count;
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

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

dm_result dm_thin_gather_bake(const dm_mesh *m, const dm_thin_gather_options *opt, dm_thin_gather *out,
                              dm_thin_gather_stats *stats, dm_error *err)
{
    memset(out, 0, sizeof *out);
    if (stats) memset(stats, 0, sizeof *stats);
    if (opt->size < 1 || opt->size > DM_THIN_GATHER_SIZE_MAX || opt->level_count < 1 ||
        opt->level_count > DM_THIN_GATHER_LEVELS || opt->first_level < 0 || opt->threads < 0)
        return dm_fail(err, DM_ERR_RANGE, "thin gather: size %d (1..%d), levels %d (1..%d) from %d, threads %d",
                       opt->size, DM_THIN_GATHER_SIZE_MAX, opt->level_count, DM_THIN_GATHER_LEVELS,
                       opt->first_level, opt->threads);
    bool finite = opt->mm_per_unit > 0 && isfinite(opt->mm_per_unit) && opt->near_mm > 0 && isfinite(opt->near_mm);
    for (int g = 0; g < opt->level_count; ++g)
        finite = finite && opt->variance_mm2[g] > 0 && isfinite(opt->variance_mm2[g]);
    if (!finite)
        return dm_fail(err, DM_ERR_RANGE, "thin gather: mm_per_unit, near_mm and the variances must be finite and > 0");
    dm_result rc = dm_mesh_validate(m, "thin gather: mesh", err);
    if (rc != DM_OK) return rc;
    const int n = opt->size, L = opt->level_count;
    const size_t texels = (size_t)n * n;
    job j = {.o = opt, .n = n};
    int32_t *tri = malloc(sizeof *tri * texels);
    double *p = calloc(3 * texels, sizeof *p), *nrm = calloc(3 * texels, sizeof *nrm), *area = calloc(texels, sizeof *area);
    double *sides = malloc(sizeof *sides * texels);
    int32_t *count = calloc((size_t)L * texels, sizeof *count);
    int64_t *first = malloc(sizeof *first * (texels + 1));
    out->index = calloc(4 * texels, sizeof *out->index);
    rc = tri && p && nrm && area && sides && count && first && out->index
             ? DM_OK
             : dm_fail(err, DM_ERR_OUT_OF_MEMORY, "thin gather %dx%d: out of memory", n, n);
    if (rc == DM_OK) rc = dm_uv_raster(m, NULL, n, n, opt->threads, tri, NULL, err);
    double h = 0;
    size_t covered = 0;
    if (rc == DM_OK) {
        texel_geometry(m, n, opt->mm_per_unit, tri, p, nrm, area);
        for (size_t i = 0; i < texels; ++i)
            if (tri[i] >= 0 && area[i] > 0) sides[covered++] = sqrt(area[i]);
        if (covered) qsort(sides, covered, sizeof *sides, cmp_double), h = sides[covered / 2];
        for (int g = 0; g < L && rc == DM_OK; ++g) {
            int C = 1;
            while (2 * C <= n && 2 * C * h <= DM_THIN_GATHER_CELL_SIGMAS * sqrt(opt->variance_mm2[g])) C *= 2;
            j.reach[g] = DM_THIN_GATHER_REACH_SIGMAS * sqrt(opt->variance_mm2[g]);
            out->cell[g] = C;
            if (!make_cells(&j.c[g], C, n, tri, p, nrm, area, fmax(j.reach[g], opt->near_mm)))
                rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "thin gather: cells: out of memory");
        }
    }
    if (rc == DM_OK) {
        j.tri = tri, j.p = p, j.nrm = nrm, j.area = area, j.count = count;
        dm_parallel_for((size_t)n, 1, opt->threads, rows, &j); /* pass 1: which texels, how many taps */
        first[0] = DM_THIN_GATHER_HEADER_TAPS;
        for (size_t i = 0; i < texels; ++i) {
            int64_t c = 0;
            for (int g = 0; g < L; ++g) c += count[L * i + g];
            first[i + 1] = first[i] + c;
        }
        out->tap_count = first[texels];
        if ((double)out->tap_count >= DM_THIN_GATHER_FLOAT_EXACT)
            rc = dm_fail(err, DM_ERR_RANGE, "thin gather %dx%d: %lld taps, a float counts exactly below 2^24", n, n,
                         (long long)out->tap_count);
    }
    if (rc == DM_OK) {
        out->taps_rows = (int)((out->tap_count + DM_THIN_GATHER_TAPS_WIDTH - 1) / DM_THIN_GATHER_TAPS_WIDTH);
        out->taps = calloc(2 * (size_t)DM_THIN_GATHER_TAPS_WIDTH * (size_t)out->taps_rows, sizeof *out->taps);
        if (!out->taps) rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "thin gather: %lld taps: out of memory", (long long)out->tap_count);
    }
    if (rc == DM_OK) {
        j.first = first, j.taps = out->taps, j.fill = true;
        dm_parallel_for((size_t)n, 1, opt->threads, rows, &j); /* pass 2: the taps */
        out->taps[0] = (float)opt->first_level, out->taps[1] = (float)L;
        out->taps[2] = (float)out->cell[0], out->taps[3] = (float)(L > 1 ? out->cell[1] : 0);
        double most = 0;
        int64_t gathering = 0;
        for (size_t i = 0; i < texels; ++i) {
            float *o = out->index + 4 * i;
            o[3] = tri[i] >= 0 && area[i] > 0 ? 1.0f : 0.0f;
            if (first[i + 1] == first[i]) continue;
            o[0] = (float)first[i], o[1] = (float)count[L * i], o[2] = L > 1 ? (float)count[L * i + 1] : 0.0f;
            ++gathering, most = fmax(most, (double)(first[i + 1] - first[i]));
        }
        out->size = n, out->first_level = opt->first_level, out->level_count = L;
        if (stats) {
            stats->covered_texels = (int64_t)covered, stats->gathering_texels = gathering;
            stats->taps = out->tap_count - DM_THIN_GATHER_HEADER_TAPS, stats->texel_mm = h, stats->max_taps = most;
            for (int g = 0; g < L; ++g) stats->cell[g] = out->cell[g];
        }
    }
    for (int g = 0; g < DM_THIN_GATHER_LEVELS; ++g) free_cells(&j.c[g]);
    free(tri), free(p), free(nrm), free(area), free(sides), free(count), free(first);
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
    dm_prov_add_int(p, "gather_taps", s->taps);
    dm_prov_add_int(p, "gather_cell0", s->cell[0]);
    dm_prov_add_int(p, "gather_cell1", s->cell[1]);
    dm_prov_add_double(p, "gather_texel_mm", s->texel_mm);
}
