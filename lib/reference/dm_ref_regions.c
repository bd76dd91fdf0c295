/* dm_ref_regions.c — seam / thin / smooth labels from the mesh, texel areas, weighted
 * error statistics. See dm_ref_regions.h. */
#include "reference/dm_ref_regions.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/dm_seam_edges.h"

/* A uniform grid of buckets over items' bounding boxes (cell edge `cell` mm, at most
 * GRID_CELLS_MAX cells: larger meshes get larger cells). */
enum { GRID_CELLS_MAX = 1 << 22 };

typedef struct grid {
    double lo[3], cell;
    int dim[3];
    size_t *start; /* cells + 1 */
    uint32_t *items;
} grid;

typedef struct seg {
    double a[3], b[3];
} seg;

struct dm_ref_regions {
    const dm_mesh *mesh;
    double mm, seam_mm, thin_mm;
    double *pos;    /* vertex_count * 3, mm */
    double *normal; /* triangle_count * 3, unit geometric normal (0 for zero area) */
    seg *segs;
    size_t seg_count;
    grid seam_grid, tri_grid;
    dm_ref_regions_info info;
};

const char *dm_ref_region_name(dm_ref_region r)
{
    static const char *names[DM_REF_REGION_COUNT] = {"smooth", "seam", "thin"};
    return (unsigned)r < DM_REF_REGION_COUNT ? names[r] : "?";
}

static void grid_free(grid *g) { free(g->start), free(g->items); }

/* box(i, lo, hi) gives item i's bounding box. */
static bool grid_build(grid *g, size_t n, double cell, const double lo[3], const double hi[3],
                       void (*box)(const void *, size_t, double *, double *), const void *user)
{
    memset(g, 0, sizeof *g);
    for (;;) {
        double cells = 1;
        for (int c = 0; c < 3; ++c) cells *= floor((hi[c] - lo[c]) / cell) + 1;
        if (cells <= GRID_CELLS_MAX) break;
        cell *= 2;
    }
    g->cell = cell;
    for (int c = 0; c < 3; ++c) g->lo[c] = lo[c], g->dim[c] = (int)floor((hi[c] - lo[c]) / cell) + 1;
    size_t cells = (size_t)g->dim[0] * g->dim[1] * g->dim[2];
    g->start = calloc(cells + 1, sizeof *g->start);
    size_t *fill = calloc(cells, sizeof *fill);
    if (!g->start || !fill) return free(fill), false;
    for (int pass = 0; pass < 2; ++pass) {
        if (pass) {
            for (size_t c = 0; c < cells; ++c) g->start[c + 1] += g->start[c];
            g->items = malloc(sizeof *g->items * (g->start[cells] + 1));
            if (!g->items) return free(fill), false;
        }
        for (size_t i = 0; i < n; ++i) {
            double bl[3], bh[3];
            int a[3], b[3];
            box(user, i, bl, bh);
            for (int c = 0; c < 3; ++c) {
                a[c] = (int)floor((bl[c] - g->lo[c]) / cell), b[c] = (int)floor((bh[c] - g->lo[c]) / cell);
                if (a[c] < 0) a[c] = 0;
                if (b[c] >= g->dim[c]) b[c] = g->dim[c] - 1;
            }
            for (int z = a[2]; z <= b[2]; ++z)
                for (int y = a[1]; y <= b[1]; ++y)
                    for (int x = a[0]; x <= b[0]; ++x) {
                        size_t k = ((size_t)z * g->dim[1] + y) * g->dim[0] + x;
                        if (!pass) ++g->start[k + 1];
                        else g->items[g->start[k] + fill[k]++] = (uint32_t)i;
                    }
        }
    }
    free(fill);
    return true;
}

/* Cells overlapping the box p ± r: their index range per axis (empty when outside). */
static bool grid_range(const grid *g, const double p[3], double r, int a[3], int b[3])
{
    for (int c = 0; c < 3; ++c) {
        double lo = floor((p[c] - r - g->lo[c]) / g->cell), hi = floor((p[c] + r - g->lo[c]) / g->cell);
        if (hi < 0 || lo >= g->dim[c]) return false;
        a[c] = lo < 0 ? 0 : (int)lo;
        b[c] = hi >= g->dim[c] ? g->dim[c] - 1 : (int)hi;
    }
    return true;
}

static void seg_box(const void *u, size_t i, double *lo, double *hi)
{
    const seg *s = (const seg *)u + i;
    for (int c = 0; c < 3; ++c) lo[c] = fmin(s->a[c], s->b[c]), hi[c] = fmax(s->a[c], s->b[c]);
}

static const double *tri_p(const dm_ref_regions *r, size_t t, int c)
{
    return r->pos + 3 * (size_t)r->mesh->indices[3 * t + c];
}

static void tri_box(const void *u, size_t t, double *lo, double *hi)
{
    const dm_ref_regions *r = u;
    for (int c = 0; c < 3; ++c) {
        lo[c] = fmin(fmin(tri_p(r, t, 0)[c], tri_p(r, t, 1)[c]), tri_p(r, t, 2)[c]);
        hi[c] = fmax(fmax(tri_p(r, t, 0)[c], tri_p(r, t, 1)[c]), tri_p(r, t, 2)[c]);
    }
}

/* The seam edges (mesh/dm_seam_edges.h) as segments in mm. */
static bool build_seams(dm_ref_regions *r)
{
    dm_seam_edges se;
    dm_error e2;
    if (dm_seam_edges_find(r->mesh, &se, &e2) != DM_OK) return false;
    r->segs = malloc(sizeof *r->segs * (se.count + 1));
    if (!r->segs) return dm_seam_edges_free(&se), false;
    for (size_t i = 0; i < se.count; ++i) {
        for (int c = 0; c < 3; ++c)
            r->segs[i].a[c] = r->pos[3 * (size_t)se.edges[i].a + c], r->segs[i].b[c] = r->pos[3 * (size_t)se.edges[i].b + c];
    }
    r->seg_count = se.count;
    r->info.seam_edges = (int64_t)se.count;
    r->info.boundary_edges = se.boundary_edges;
    dm_seam_edges_free(&se);
    return true;
}

dm_result dm_ref_regions_create(const dm_mesh *mesh, double mm_per_unit, const dm_ref_regions_options *opt,
                                dm_ref_regions **out, dm_error *err)
{
    *out = NULL;
    dm_ref_regions_options o = opt ? *opt : (dm_ref_regions_options){0};
    if (!(mm_per_unit > 0) || !isfinite(mm_per_unit))
        return dm_fail(err, DM_ERR_RANGE, "regions: mm_per_unit %g is not finite and > 0", mm_per_unit);
    if (o.seam_mm == 0) o.seam_mm = 3;
    if (o.thin_mm == 0) o.thin_mm = 5;
    if (!(o.seam_mm > 0) || !(o.thin_mm > 0) || !isfinite(o.seam_mm) || !isfinite(o.thin_mm))
        return dm_fail(err, DM_ERR_RANGE, "regions: seam_mm %g and thin_mm %g must be finite and > 0", o.seam_mm,
                       o.thin_mm);
    if (mesh->vertex_count < 3 || mesh->triangle_count < 1)
        return dm_fail(err, DM_ERR_EMPTY, "regions: a mesh of %d vertices and %d triangles", mesh->vertex_count,
                       mesh->triangle_count);
    dm_ref_regions *r = calloc(1, sizeof *r);
    if (!r) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "regions: out of memory");
    r->mesh = mesh, r->mm = mm_per_unit, r->seam_mm = o.seam_mm, r->thin_mm = o.thin_mm;
    size_t nv = (size_t)mesh->vertex_count, nt = (size_t)mesh->triangle_count;
    r->pos = malloc(sizeof *r->pos * 3 * nv);
    r->normal = malloc(sizeof *r->normal * 3 * nt);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; r->pos && i < 3 * nv; ++i) {
        r->pos[i] = mesh->positions[i] * mm_per_unit;
        lo[i % 3] = fmin(lo[i % 3], r->pos[i]), hi[i % 3] = fmax(hi[i % 3], r->pos[i]);
    }
    if (!r->pos || !r->normal || !build_seams(r)) {
        dm_ref_regions_destroy(r);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "regions: out of memory (%d triangles)", mesh->triangle_count);
    }
    for (size_t t = 0; t < nt; ++t) {
        const double *p0 = tri_p(r, t, 0), *p1 = tri_p(r, t, 1), *p2 = tri_p(r, t, 2);
        double u[3], v[3], n[3];
        for (int c = 0; c < 3; ++c) u[c] = p1[c] - p0[c], v[c] = p2[c] - p0[c];
        n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2], n[2] = u[0] * v[1] - u[1] * v[0];
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        r->info.surface_area_mm2 += 0.5 * l;
        for (int c = 0; c < 3; ++c) r->normal[3 * t + c] = l > 0 ? n[c] / l : 0;
    }
    if (!grid_build(&r->seam_grid, r->seg_count, r->seam_mm, lo, hi, seg_box, r->segs) ||
        !grid_build(&r->tri_grid, nt, r->thin_mm, lo, hi, tri_box, r)) {
        dm_ref_regions_destroy(r);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "regions: out of memory (grid)");
    }
    *out = r;
    return DM_OK;
}

void dm_ref_regions_destroy(dm_ref_regions *r)
{
    if (!r) return;
    grid_free(&r->seam_grid), grid_free(&r->tri_grid);
    free(r->pos), free(r->normal), free(r->segs), free(r);
}

void dm_ref_regions_get_info(const dm_ref_regions *r, dm_ref_regions_info *info) { *info = r->info; }

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static double seg_dist2(const double p[3], const seg *s)
{
    double ab[3], ap[3];
    for (int c = 0; c < 3; ++c) ab[c] = s->b[c] - s->a[c], ap[c] = p[c] - s->a[c];
    double l2 = dot3(ab, ab), t = l2 > 0 ? fmin(fmax(dot3(ab, ap) / l2, 0), 1) : 0, d2 = 0;
    for (int c = 0; c < 3; ++c) d2 += (ap[c] - t * ab[c]) * (ap[c] - t * ab[c]);
    return d2;
}

/* The point q of triangle abc closest to p (Ericson, Real-Time Collision Detection 5.1.5). */
static void tri_closest(const double p[3], const double a[3], const double b[3], const double c[3], double q[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    for (int k = 0; k < 3; ++k)
        ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], ap[k] = p[k] - a[k], bp[k] = p[k] - b[k], cp[k] = p[k] - c[k];
    double d1 = dot3(ab, ap), d2 = dot3(ac, ap), d3 = dot3(ab, bp), d4 = dot3(ac, bp), d5 = dot3(ab, cp),
           d6 = dot3(ac, cp);
    double va = d3 * d6 - d5 * d4, vb = d5 * d2 - d1 * d6, vc = d1 * d4 - d3 * d2;
    double s = 0, t = 0; /* q = a + s ab + t ac */
    if (d1 <= 0 && d2 <= 0) s = 0, t = 0;
    else if (d3 >= 0 && d4 <= d3) s = 1, t = 0;
    else if (d6 >= 0 && d5 <= d6) s = 0, t = 1;
    else if (vc <= 0 && d1 >= 0 && d3 <= 0) s = d1 / (d1 - d3), t = 0;
    else if (vb <= 0 && d2 >= 0 && d6 <= 0) s = 0, t = d2 / (d2 - d6);
    else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) t = (d4 - d3) / ((d4 - d3) + (d5 - d6)), s = 1 - t;
    else {
        double den = va + vb + vc;
        s = den != 0 ? vb / den : 0, t = den != 0 ? vc / den : 0;
    }
    for (int k = 0; k < 3; ++k) q[k] = a[k] + s * ab[k] + t * ac[k];
}

static double tri_dist2(const double p[3], const double a[3], const double b[3], const double c[3])
{
    double q[3], d = 0;
    tri_closest(p, a, b, c, q);
    for (int k = 0; k < 3; ++k) d += (p[k] - q[k]) * (p[k] - q[k]);
    return d;
}

static bool near_seam(const dm_ref_regions *r, const double p[3])
{
    int a[3], b[3];
    if (!r->seg_count || !grid_range(&r->seam_grid, p, r->seam_mm, a, b)) return false;
    const grid *g = &r->seam_grid;
    double lim = r->seam_mm * r->seam_mm;
    for (int z = a[2]; z <= b[2]; ++z)
        for (int y = a[1]; y <= b[1]; ++y)
            for (int x = a[0]; x <= b[0]; ++x) {
                size_t k = ((size_t)z * g->dim[1] + y) * g->dim[0] + x;
                for (size_t i = g->start[k]; i < g->start[k + 1]; ++i)
                    if (seg_dist2(p, &r->segs[g->items[i]]) <= lim) return true;
            }
    return false;
}

static bool thin(const dm_ref_regions *r, const double p[3], const double n[3])
{
    int a[3], b[3];
    if (!grid_range(&r->tri_grid, p, r->thin_mm, a, b)) return false;
    const grid *g = &r->tri_grid;
    double lim = r->thin_mm * r->thin_mm;
    for (int z = a[2]; z <= b[2]; ++z)
        for (int y = a[1]; y <= b[1]; ++y)
            for (int x = a[0]; x <= b[0]; ++x) {
                size_t k = ((size_t)z * g->dim[1] + y) * g->dim[0] + x;
                for (size_t i = g->start[k]; i < g->start[k + 1]; ++i) {
                    size_t t = g->items[i];
                    if (dot3(r->normal + 3 * t, n) < 0 &&
                        tri_dist2(p, tri_p(r, t, 0), tri_p(r, t, 1), tri_p(r, t, 2)) <= lim)
                        return true;
                }
            }
    return false;
}

dm_ref_region dm_ref_regions_classify(const dm_ref_regions *r, int32_t tri, double b1, double b2)
{
    double p[3], b0 = 1 - b1 - b2;
    for (int c = 0; c < 3; ++c) p[c] = b0 * tri_p(r, tri, 0)[c] + b1 * tri_p(r, tri, 1)[c] + b2 * tri_p(r, tri, 2)[c];
    if (near_seam(r, p)) return DM_REF_REGION_SEAM;
    double n[3];
    memcpy(n, r->normal + 3 * (size_t)tri, sizeof n);
    if (!dot3(n, n)) /* a zero-area triangle: its interpolated corner normals */
        for (int c = 0; c < 3; ++c) {
            const float *cn = r->mesh->normals + 9 * (size_t)tri + c;
            n[c] = b0 * cn[0] + b1 * cn[3] + b2 * cn[6];
        }
    if (dot3(n, n) > 0 && thin(r, p, n)) return DM_REF_REGION_THIN;
    return DM_REF_REGION_SMOOTH;
}

void dm_ref_regions_atlas(const dm_ref_regions *r, int width, int height, const dm_reference_target *targets,
                          const int64_t *texel_of, size_t count, uint8_t *label, float *area_mm2)
{
    const dm_mesh *m = r->mesh;
    for (size_t i = 0; i < count; ++i) {
        int32_t t = targets[i].triangle;
        const float *uv = m->uvs + 6 * (size_t)t;
        double uv_area = 0.5 * fabs((uv[2] - uv[0]) * (uv[5] - uv[1]) - (uv[4] - uv[0]) * (uv[3] - uv[1]));
        double p[3][3], u[3], v[3], n[3];
        for (int k = 0; k < 3; ++k) memcpy(p[k], tri_p(r, (size_t)t, k), sizeof p[k]);
        for (int c = 0; c < 3; ++c) u[c] = p[1][c] - p[0][c], v[c] = p[2][c] - p[0][c];
        n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2], n[2] = u[0] * v[1] - u[1] * v[0];
        double area = 0.5 * sqrt(dot3(n, n));
        area_mm2[texel_of[i]] = uv_area > 0 ? (float)(area / uv_area / ((double)width * height)) : 0.0f;
        label[texel_of[i]] = (uint8_t)dm_ref_regions_classify(r, t, targets[i].b1, targets[i].b2);
    }
}

typedef struct wv {
    double rel, w;
} wv;

static int wv_cmp(const void *x, const void *y)
{
    double a = ((const wv *)x)->rel, b = ((const wv *)y)->rel;
    return (a > b) - (a < b);
}

dm_result dm_ref_error_stats_compute(const float *ref, const float *render, const float *weight,
                                     const uint8_t *label, int region, size_t texel_count, dm_ref_error_stats *st,
                                     dm_error *err)
{
    memset(st, 0, sizeof *st);
    double refsum[3] = {0, 0, 0};
    for (size_t i = 0; i < texel_count; ++i) {
        double w = weight ? weight[i] : 1;
        if (ref[4 * i + 3] < 0.5f || render[4 * i + 3] < 0.5f || !(w > 0) || (label && region >= 0 && label[i] != region))
            continue;
        ++st->count, st->weight_sum += w;
        for (int c = 0; c < 3; ++c) refsum[c] += w * ref[4 * i + c];
    }
    if (!st->count) return dm_fail(err, DM_ERR_EMPTY, "error stats: no texel compared (region %d)", region);
    wv *v = malloc(sizeof *v * (size_t)st->count);
    if (!v) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "error stats: %ld texels", st->count);
    for (int c = 0; c < 3; ++c) {
        st->floor[c] = DM_REF_ERROR_FLOOR * refsum[c] / st->weight_sum;
        size_t n = 0;
        double sum = 0;
        for (size_t i = 0; i < texel_count; ++i) {
            double w = weight ? weight[i] : 1;
            if (ref[4 * i + 3] < 0.5f || render[4 * i + 3] < 0.5f || !(w > 0) ||
                (label && region >= 0 && label[i] != region))
                continue;
            double den = fmax(ref[4 * i + c], st->floor[c]);
            double rel = den > 0 ? fabs((double)render[4 * i + c] - ref[4 * i + c]) / den : 0;
            v[n++] = (wv){rel, w};
            sum += w * rel;
            st->max[c] = fmax(st->max[c], rel);
        }
        st->mean[c] = sum / st->weight_sum;
        qsort(v, n, sizeof *v, wv_cmp);
        double acc = 0, goal = 0.95 * st->weight_sum;
        st->p95[c] = v[n - 1].rel;
        for (size_t i = 0; i < n; ++i)
            if ((acc += v[i].w) >= goal) {
                st->p95[c] = v[i].rel;
                break;
            }
    }
    free(v);
    return DM_OK;
}
