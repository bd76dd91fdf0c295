#include "bake/dm_curvature.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/dm_gutter.h"
#include "mesh/dm_uv_raster.h"
#include "core/dm_cli.h"
#include "core/dm_parallel.h"
#include "core/dm_sort.h"

enum { BOUNDARY_PASSES = 8 };

double dm_curvature_profile_scale_mm(const dm_profile *p)
{
    double num = 0.0, den = 0.0;
    for (int k = 0; k < p->count; ++k)
        for (int c = 0; c < 3; ++c) {
            num += p->weight[k][c] * p->variance_mm2[k];
            den += p->weight[k][c];
        }
    return den > 0.0 ? sqrt(num / den) : 0.0;
}

/* ---- welding ------------------------------------------------------------------------- */

typedef struct x_index {
    float x;
    int32_t index;
} x_index;

static int cmp_x(const void *a, const void *b)
{
    const x_index *p = a, *q = b;
    return p->x != q->x ? (p->x > q->x) - (p->x < q->x) : (p->index > q->index) - (p->index < q->index);
}

static int32_t root(int32_t *parent, int32_t v)
{
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
}

/* weld[v] = the lowest index of the vertices within eps (mm-free: 1e-6 of the bounding box's
 * diagonal, in mesh units) of v, transitively: exporters write seam copies that differ in
 * the last bit (sin 2π ≠ sin 0). */
static void weld_vertices(const dm_mesh *m, x_index *order, int32_t *weld, int32_t *count)
{
    int32_t n = m->vertex_count;
    const float *p = m->positions;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int32_t v = 0; v < n; ++v) {
        order[v] = (x_index){m->positions[3 * (size_t)v], v};
        weld[v] = v;
        for (int d = 0; d < 3; ++d) lo[d] = fmin(lo[d], p[3 * v + d]), hi[d] = fmax(hi[d], p[3 * v + d]);
    }
    double diag = n ? sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                           (hi[2] - lo[2]) * (hi[2] - lo[2]))
                    : 0.0;
    double eps = 1e-6 * diag, eps2 = eps * eps;
    qsort(order, (size_t)n, sizeof *order, cmp_x);
    for (int32_t a = 0; a < n; ++a) {
        int32_t i = order[a].index;
        for (int32_t b = a + 1; b < n && order[b].x - order[a].x <= eps; ++b) {
            int32_t j = order[b].index;
            double dy = p[3 * j + 1] - p[3 * i + 1], dz = p[3 * j + 2] - p[3 * i + 2], dx = p[3 * j] - p[3 * i];
            if (dx * dx + dy * dy + dz * dz > eps2) continue;
            int32_t ri = root(weld, i), rj = root(weld, j);
            if (ri < rj) weld[rj] = ri;
            else if (rj < ri) weld[ri] = rj;
        }
    }
    int32_t c = 0;
    for (int32_t v = 0; v < n; ++v) {
        weld[v] = root(weld, v);
        c += weld[v] == v;
    }
    *count = c;
}

/* ---- the cotangent Laplacian ----------------------------------------------------------- */

typedef struct vec3 {
    double x, y, z;
} vec3;
static vec3 sub(vec3 a, vec3 b) { return (vec3){a.x - b.x, a.y - b.y, a.z - b.z}; }
static double dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static vec3 cross(vec3 a, vec3 b) { return (vec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
static double len(vec3 a) { return sqrt(dot(a, a)); }

static vec3 position(const dm_mesh *m, int32_t v, double mm)
{
    const float *p = m->positions + 3 * (size_t)v;
    return (vec3){p[0] * mm, p[1] * mm, p[2] * mm};
}

static int cmp_edge(const void *a, const void *b)
{
    const int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

static int cmp_pair(const void *a, const void *b)
{
    const int64_t *x = a, *y = b;
    return x[0] != y[0] ? (x[0] > y[0]) - (x[0] < y[0]) : (x[1] > y[1]) - (x[1] < y[1]);
}

/* Marks vertices on boundary or non-manifold edges (welded ids); skip: degenerate triangles. */
static dm_result mark_boundary(const dm_mesh *m, const int32_t *weld, const uint8_t *skip, uint8_t *boundary,
                               dm_error *err)
{
    int64_t *e = malloc(sizeof(int64_t) * 3 * (size_t)m->triangle_count + 1);
    if (!e) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "curvature: %d triangles' edges", m->triangle_count);
    size_t n = 0;
    for (int32_t t = 0; t < m->triangle_count; ++t) {
        if (skip[t]) continue;
        for (int k = 0; k < 3; ++k) {
            int64_t a = weld[m->indices[3 * t + k]], b = weld[m->indices[3 * t + (k + 1) % 3]];
            e[n++] = a < b ? (a << 32) | b : (b << 32) | a;
        }
    }
    qsort(e, n, sizeof *e, cmp_edge);
    for (size_t i = 0; i < n;) {
        size_t j = i;
        while (j < n && e[j] == e[i]) ++j;
        if (j - i != 2) boundary[e[i] >> 32] = boundary[e[i] & 0xffffffff] = 1;
        i = j;
    }
    free(e);
    return DM_OK;
}

/* Mean curvature per welded vertex into h (indexed by welded id), vertex areas into area. */
static void cotan_curvature(const dm_mesh *m, const int32_t *weld, double mm, uint8_t *skip, double *h, double *area,
                            int32_t *degenerate)
{
    size_t nv = (size_t)m->vertex_count;
    vec3 *k = calloc(nv, sizeof *k), *n = calloc(nv, sizeof *n);
    if (!k || !n) { /* callers allocated far more than this already; keep it simple */
        free(k);
        free(n);
        return;
    }
    *degenerate = 0;
    for (int32_t t = 0; t < m->triangle_count; ++t) {
        int32_t v[3];
        vec3 p[3];
        for (int c = 0; c < 3; ++c) {
            v[c] = weld[m->indices[3 * t + c]];
            p[c] = position(m, v[c], mm);
        }
        vec3 fn = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        double a2 = len(fn), emax = 0.0;
        for (int c = 0; c < 3; ++c) emax = fmax(emax, dot(sub(p[(c + 1) % 3], p[c]), sub(p[(c + 1) % 3], p[c])));
        skip[t] = v[0] == v[1] || v[1] == v[2] || v[0] == v[2] || !(a2 > 1e-12 * emax) || !isfinite(a2);
        if (skip[t]) {
            ++*degenerate;
            continue;
        }
        double cot[3], tri_area = 0.5 * a2;
        int obtuse = -1;
        for (int c = 0; c < 3; ++c) {
            vec3 u = sub(p[(c + 1) % 3], p[c]), w = sub(p[(c + 2) % 3], p[c]);
            cot[c] = dot(u, w) / a2;
            if (dot(u, w) < 0.0) obtuse = c;
        }
        for (int c = 0; c < 3; ++c) {
            int i = (c + 1) % 3, j = (c + 2) % 3; /* edge (i, j) opposite corner c */
            vec3 d = sub(p[i], p[j]);
            k[v[i]].x += cot[c] * d.x, k[v[i]].y += cot[c] * d.y, k[v[i]].z += cot[c] * d.z;
            k[v[j]].x -= cot[c] * d.x, k[v[j]].y -= cot[c] * d.y, k[v[j]].z -= cot[c] * d.z;
            n[v[c]].x += fn.x, n[v[c]].y += fn.y, n[v[c]].z += fn.z;
        }
        /* mixed Voronoi area (Meyer et al. 2003, fig. 4) */
        for (int c = 0; c < 3; ++c) {
            double a;
            if (obtuse < 0) {
                int i = (c + 1) % 3, j = (c + 2) % 3;
                vec3 ei = sub(p[i], p[c]), ej = sub(p[j], p[c]);
                a = (dot(ej, ej) * cot[i] + dot(ei, ei) * cot[j]) / 8.0;
            } else {
                a = obtuse == c ? tri_area / 2.0 : tri_area / 4.0;
            }
            area[v[c]] += a;
        }
    }
    for (size_t i = 0; i < nv; ++i) {
        double nl = len(n[i]);
        h[i] = area[i] > 0.0 && nl > 0.0 ? 0.5 * dot(k[i], n[i]) / (nl * 2.0 * area[i]) : 0.0;
    }
    free(k);
    free(n);
}

/* Boundary vertices take the mean of known ring neighbours, ring by ring inwards. */
static void fill_boundary(const dm_mesh *m, const int32_t *weld, const uint8_t *skip, uint8_t *unknown, double *h)
{
    size_t nv = (size_t)m->vertex_count;
    double *sum = calloc(nv, sizeof *sum);
    int32_t *cnt = calloc(nv, sizeof *cnt);
    if (!sum || !cnt) goto done;
    for (int pass = 0; pass < BOUNDARY_PASSES; ++pass) {
        memset(sum, 0, nv * sizeof *sum);
        memset(cnt, 0, nv * sizeof *cnt);
        int any = 0;
        for (int32_t t = 0; t < m->triangle_count; ++t) {
            if (skip[t]) continue;
            for (int c = 0; c < 3; ++c) {
                int32_t a = weld[m->indices[3 * t + c]];
                if (!unknown[a]) continue;
                any = 1;
                for (int d = 1; d < 3; ++d) {
                    int32_t b = weld[m->indices[3 * t + (c + d) % 3]];
                    if (!unknown[b]) sum[a] += h[b], ++cnt[a];
                }
            }
        }
        if (!any) break;
        for (size_t i = 0; i < nv; ++i)
            if (unknown[i] && cnt[i]) h[i] = sum[i] / cnt[i], unknown[i] = 0;
    }
    for (size_t i = 0; i < nv; ++i)
        if (unknown[i]) h[i] = 0.0;
done:
    free(sum);
    free(cnt);
}

/* ---- smoothing ------------------------------------------------------------------------- */

typedef struct smooth_ctx {
    const dm_mesh *m;
    const int32_t *rep;    /* welded representatives, sorted by cell */
    const int64_t *cell;   /* their cell keys, ascending */
    int32_t rep_count;
    const double *h, *area;
    double mm, sigma, cell_size, lo[3];
    double *out; /* per representative index */
} smooth_ctx;

static int64_t cell_key(int64_t x, int64_t y, int64_t z) { return (x << 42) | (y << 21) | z; }

static void cell_of(const smooth_ctx *s, vec3 p, int64_t c[3])
{
    const double q[3] = {p.x, p.y, p.z};
    for (int d = 0; d < 3; ++d) c[d] = (int64_t)floor((q[d] - s->lo[d]) / s->cell_size);
}

static size_t lower_bound(const int64_t *a, size_t n, int64_t key)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (a[mid] < key) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

static void smooth_range(void *vctx, size_t begin, size_t end)
{
    smooth_ctx *s = vctx;
    double inv = 1.0 / (2.0 * s->sigma * s->sigma), r2 = 9.0 * s->sigma * s->sigma;
    for (size_t q = begin; q < end; ++q) {
        int32_t v = s->rep[q];
        vec3 p = position(s->m, v, s->mm);
        int64_t c[3];
        cell_of(s, p, c);
        double num = 0.0, den = 0.0;
        for (int64_t dx = -1; dx <= 1; ++dx)
            for (int64_t dy = -1; dy <= 1; ++dy)
                for (int64_t dz = -1; dz <= 1; ++dz) {
                    int64_t x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
                    if (x < 0 || y < 0 || z < 0 || x >= (1 << 21) || y >= (1 << 21) || z >= (1 << 21)) continue;
                    int64_t key = cell_key(x, y, z);
                    for (size_t i = lower_bound(s->cell, (size_t)s->rep_count, key);
                         i < (size_t)s->rep_count && s->cell[i] == key; ++i) {
                        int32_t u = s->rep[i];
                        vec3 d = sub(position(s->m, u, s->mm), p);
                        double dd = dot(d, d);
                        if (dd > r2) continue;
                        double w = s->area[u] * exp(-dd * inv);
                        num += w * s->h[u];
                        den += w;
                    }
                }
        s->out[q] = den > 0.0 ? num / den : s->h[v];
    }
}

static dm_result smooth(const dm_mesh *m, const int32_t *weld, double mm, double sigma, int threads, double *h,
                        const double *area, dm_error *err)
{
    size_t nv = (size_t)m->vertex_count;
    int32_t *rep = malloc(nv * sizeof *rep);
    int64_t *cell = malloc(nv * sizeof *cell);
    double *out = malloc(nv * sizeof *out);
    dm_result r = DM_OK;
    if (!rep || !cell || !out) {
        r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "curvature smoothing: %d vertices", m->vertex_count);
        goto done;
    }
    smooth_ctx s = {.m = m, .rep = rep, .cell = cell, .h = h, .area = area, .mm = mm, .sigma = sigma, .out = out};
    double hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    s.lo[0] = s.lo[1] = s.lo[2] = INFINITY;
    for (size_t v = 0; v < nv; ++v) {
        vec3 p = position(m, (int32_t)v, mm);
        const double q[3] = {p.x, p.y, p.z};
        for (int d = 0; d < 3; ++d) s.lo[d] = fmin(s.lo[d], q[d]), hi[d] = fmax(hi[d], q[d]);
    }
    double extent = fmax(hi[0] - s.lo[0], fmax(hi[1] - s.lo[1], hi[2] - s.lo[2]));
    s.cell_size = fmax(3.0 * sigma, extent / ((1 << 20) - 1)); /* keys stay within 21 bits */
    /* representatives sorted by (cell, index): insertion by key then a stable sort */
    int32_t n = 0;
    for (size_t v = 0; v < nv; ++v)
        if (weld[v] == (int32_t)v) rep[n++] = (int32_t)v;
    s.rep_count = n;
    int64_t *key = malloc((size_t)n * 2 * sizeof *key);
    if (!key) {
        r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "curvature smoothing: %d vertices", n);
        goto done;
    }
    for (int32_t i = 0; i < n; ++i) {
        int64_t c[3];
        cell_of(&s, position(m, rep[i], mm), c);
        key[2 * i] = cell_key(c[0], c[1], c[2]);
        key[2 * i + 1] = rep[i];
    }
    qsort(key, (size_t)n, 2 * sizeof *key, cmp_pair); /* by cell, then index: a total order */
    for (int32_t i = 0; i < n; ++i) {
        cell[i] = key[2 * i];
        rep[i] = (int32_t)key[2 * i + 1];
    }
    free(key);
    dm_parallel_for((size_t)n, 0, threads, smooth_range, &s);
    for (int32_t i = 0; i < n; ++i) h[rep[i]] = out[i];
done:
    free(rep);
    free(cell);
    free(out);
    return r;
}

dm_result dm_curvature_vertices(const dm_mesh *m, double mm_per_unit, double smooth_mm, int thread_count, double *h,
                                dm_curvature_stats *stats, dm_error *err)
{
    dm_curvature_stats local;
    if (!stats) stats = &local;
    if (!(mm_per_unit > 0.0 && mm_per_unit <= 1e6))
        return dm_fail(err, isfinite(mm_per_unit) ? DM_ERR_RANGE : DM_ERR_NON_FINITE,
                       "curvature: mm_per_unit = %g, expected (0, 1e6]", mm_per_unit);
    if (!(smooth_mm >= 0.0 && smooth_mm <= DM_CURVATURE_SMOOTH_MAX_MM))
        return dm_fail(err, isfinite(smooth_mm) ? DM_ERR_RANGE : DM_ERR_NON_FINITE,
                       "curvature: smooth_mm = %g, expected [0, %g]", smooth_mm, DM_CURVATURE_SMOOTH_MAX_MM);
    size_t nv = (size_t)m->vertex_count, nt = (size_t)m->triangle_count;
    x_index *order = malloc(nv * sizeof *order);
    int32_t *weld = malloc(nv * sizeof *weld);
    double *area = calloc(nv, sizeof *area);
    uint8_t *skip = calloc(nt + 1, 1), *boundary = calloc(nv, 1);
    dm_result r = DM_OK;
    if (!order || !weld || !area || !skip || !boundary) {
        r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "curvature: %d vertices", m->vertex_count);
        goto done;
    }
    double t0 = dm_now_ms();
    weld_vertices(m, order, weld, &stats->welded_vertices);
    cotan_curvature(m, weld, mm_per_unit, skip, h, area, &stats->degenerate_triangles);
    if ((r = mark_boundary(m, weld, skip, boundary, err)) != DM_OK) goto done;
    stats->boundary_vertices = 0;
    for (size_t v = 0; v < nv; ++v) stats->boundary_vertices += boundary[v];
    for (size_t v = 0; v < nv; ++v) /* vertices no valid triangle touches are unknown too */
        if (weld[v] == (int32_t)v && !(area[v] > 0.0)) boundary[v] = 1;
    fill_boundary(m, weld, skip, boundary, h);
    stats->vertex_ms = dm_now_ms() - t0;
    t0 = dm_now_ms();
    for (size_t v = 0; v < nv; ++v) /* every vertex an area, so the smoothing weighs all */
        if (!(area[v] > 0.0)) area[v] = 0.0;
    if (smooth_mm > 0.0 && (r = smooth(m, weld, mm_per_unit, smooth_mm, thread_count, h, area, err)) != DM_OK)
        goto done;
    for (size_t v = 0; v < nv; ++v) h[v] = h[weld[v]];
    stats->smooth_ms = dm_now_ms() - t0;
done:
    free(order);
    free(weld);
    free(area);
    free(skip);
    free(boundary);
    return r;
}

/* ---- the texel map --------------------------------------------------------------------- */

typedef struct texel_ctx {
    const dm_mesh *m;
    const int32_t *tri_of;
    const double *h;
    int width, height;
    float *curvature, *mask;
} texel_ctx;

static void texel_rows(void *vctx, size_t begin, size_t end)
{
    texel_ctx *c = vctx;
    for (size_t j = begin; j < end; ++j)
        for (int i = 0; i < c->width; ++i) {
            size_t at = j * (size_t)c->width + i;
            int32_t t = c->tri_of[at];
            if (t < 0) {
                c->curvature[at] = 0.0f;
                c->mask[at] = 0.0f;
                continue;
            }
            double b1, b2;
            dm_uv_raster_barycentrics(c->m, t, (i + 0.5) / c->width, (j + 0.5) / c->height, &b1, &b2);
            double b0 = 1.0 - b1 - b2;
            const uint32_t *v = c->m->indices + 3 * (size_t)t;
            double value = b0 * c->h[v[0]] + b1 * c->h[v[1]] + b2 * c->h[v[2]];
            c->curvature[at] = (float)value;
            c->mask[at] = 1.0f;
        }
}

void dm_curvature_map_free(dm_curvature_map *map)
{
    free(map->curvature);
    free(map->mask);
    memset(map, 0, sizeof *map);
}

dm_result dm_curvature_bake(const dm_mesh *m, const dm_curvature_options *opt, dm_curvature_map *out,
                            dm_error *err)
{
    memset(out, 0, sizeof *out);
    dm_curvature_options o = opt ? *opt : (dm_curvature_options){0};
    if (!o.width) o.width = DM_CURVATURE_SIZE_DEFAULT;
    if (!o.height) o.height = o.width;
    if (o.mm_per_unit == 0.0) o.mm_per_unit = 50.0;
    if (o.width < 1 || o.width > DM_CURVATURE_SIZE_MAX || o.height < 1 || o.height > DM_CURVATURE_SIZE_MAX)
        return dm_fail(err, DM_ERR_RANGE, "curvature: size %dx%d, expected 1..%d", o.width, o.height,
                       DM_CURVATURE_SIZE_MAX);
    dm_result r = dm_mesh_validate(m, "curvature: mesh", err);
    if (r != DM_OK) return r;
    size_t texels = (size_t)o.width * o.height;
    double *h = malloc(sizeof(double) * ((size_t)m->vertex_count + 1));
    int32_t *tri_of = malloc(sizeof(int32_t) * texels);
    uint8_t *covered = malloc(texels);
    out->curvature = malloc(sizeof(float) * texels);
    out->mask = malloc(sizeof(float) * texels);
    out->width = o.width;
    out->height = o.height;
    dm_curvature_stats *st = &out->stats;
    if (!h || !tri_of || !covered || !out->curvature || !out->mask) {
        r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "curvature: %dx%d texels", o.width, o.height);
        goto done;
    }
    if ((r = dm_curvature_vertices(m, o.mm_per_unit, o.smooth_mm, o.thread_count, h, st, err)) != DM_OK) goto done;
    double t0 = dm_now_ms();
    dm_uv_raster_stats rs;
    if ((r = dm_uv_raster(m, NULL, o.width, o.height, o.thread_count, tri_of, &rs, err)) != DM_OK) goto done;
    st->mirrored_triangles = 0;
    for (int32_t t = 0; t < m->triangle_count; ++t) {
        const float *uv = m->uvs + 6 * (size_t)t;
        double d = (uv[2] - uv[0]) * (uv[5] - uv[1]) - (uv[4] - uv[0]) * (uv[3] - uv[1]);
        st->mirrored_triangles += d < 0.0;
    }
    texel_ctx tc = {.m = m, .tri_of = tri_of, .h = h, .width = o.width, .height = o.height,
                    .curvature = out->curvature, .mask = out->mask};
    dm_parallel_for((size_t)o.height, 1, o.thread_count, texel_rows, &tc);
    st->raster_ms = dm_now_ms() - t0;
    t0 = dm_now_ms();
    st->covered_texels = 0;
    for (size_t i = 0; i < texels; ++i) {
        covered[i] = out->mask[i] > 0.0f;
        st->covered_texels += covered[i];
    }
    if (st->covered_texels == 0) {
        r = dm_fail(err, DM_ERR_EMPTY, "curvature: no triangle covers a texel centre at %dx%d", o.width, o.height);
        goto done;
    }
    /* statistics over covered texels, before the gutters take copies of them */
    float *vals = (float *)tri_of; /* reuse: int32 and float are the same size */
    size_t n = 0;
    for (size_t i = 0; i < texels; ++i)
        if (covered[i]) vals[n++] = out->curvature[i];
    dm_sort_floats(vals, n);
    static const double pct[5] = {0.01, 0.05, 0.5, 0.95, 0.99};
    for (int k = 0; k < 5; ++k) st->percentile[k] = vals[(size_t)(pct[k] * (double)(n - 1) + 0.5)];
    st->min = vals[0];
    st->max = vals[n - 1];
    dm_gutter_stats gs;
    float *planes[1] = {out->curvature};
    if ((r = dm_gutter_fill(covered, o.width, o.height, planes, 1, o.thread_count, &gs, err)) != DM_OK) goto done;
    st->gutter_texels = gs.filled_texels;
    st->coverage = (double)st->covered_texels / (double)texels;
    st->fill_ms = dm_now_ms() - t0;
done:
    free(h);
    free(tri_of);
    free(covered);
    return r;
}
