/* dm_reference_elements.c — the wide Gaussians' sources: every triangle cut into its pieces
 * of the cells between texel centres (exact polygon clipping in UV; I is bilinear inside), each piece a point at its centroid with
 * its exact area in mm² and I read there (dm_ref_lookup.h); sorted into a uniform grid
 * (dm_ref_grid.h).
 *
 * Triangles of (near) zero UV area, or UV extents beyond 4× the atlas, have no texel
 * cells to be cut by: they are subdivided into n² congruent sub-triangles of edge about
 * one texel instead (n ≤ 64), I read at each centroid's (degenerate) UV. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reference/dm_reference_impl.h"
#include "core/dm_parallel.h"

enum { POLY_MAX = 12, SUBDIVIDE_MAX = 64 };

typedef struct poly {
    int n;
    double x[POLY_MAX], y[POLY_MAX];
} poly;

/* Keeps the part of `in` on the side axis·sign ≥ bound·sign (axis 0: x, 1: y). */
static void clip(const poly *in, int axis, double bound, double sign, poly *out)
{
    out->n = 0;
    for (int i = 0; i < in->n; ++i) {
        int j = (i + 1) % in->n;
        double a = (axis ? in->y[i] : in->x[i]) - bound, b = (axis ? in->y[j] : in->x[j]) - bound;
        a *= sign;
        b *= sign;
        if (a >= 0.0) {
            out->x[out->n] = in->x[i];
            out->y[out->n] = in->y[i];
            out->n++;
        }
        if ((a >= 0.0) != (b >= 0.0)) {
            double t = a / (a - b);
            out->x[out->n] = in->x[i] + t * (in->x[j] - in->x[i]);
            out->y[out->n] = in->y[i] + t * (in->y[j] - in->y[i]);
            out->n++;
        }
    }
}

/* Signed area and centroid of a polygon (shoelace). */
static double poly_area(const poly *p, double *cx, double *cy)
{
    double a = 0.0, x = 0.0, y = 0.0;
    for (int i = 0; i < p->n; ++i) {
        int j = (i + 1) % p->n;
        double c = p->x[i] * p->y[j] - p->x[j] * p->y[i];
        a += c;
        x += (p->x[i] + p->x[j]) * c;
        y += (p->y[i] + p->y[j]) * c;
    }
    a *= 0.5;
    if (a != 0.0) {
        *cx = x / (6.0 * a);
        *cy = y / (6.0 * a);
    }
    return a;
}

typedef struct build_ctx {
    dm_reference *ref;
    int64_t *offset; /* triangle_count + 1: where each triangle's elements go */
    dm_ref_element *out; /* NULL: count only */
    double *unlit;       /* triangle_count: area where I could not be read */
} build_ctx;

static void emit(const dm_reference *ref, dm_ref_element *e, const double p[3], double area_mm2, double u, double v,
                 double *unlit)
{
    double rgb[3];
    if (!dm_ref_sample(&ref->lookup, u, v, rgb) && unlit) *unlit += area_mm2;
    for (int a = 0; a < 3; ++a) {
        e->pos[a] = (float)p[a];
        e->flux[a] = (float)(rgb[a] * area_mm2);
    }
}

/* Elements of triangle t: written to out (when non-NULL); returns their count. */
static int64_t triangle_elements(const dm_reference *ref, int32_t t, dm_ref_element *out, double *unlit)
{
    const dm_mesh *m = ref->mesh;
    double area = ref->tri_area[t];
    if (!(area > 0.0)) return 0;
    const double W = ref->atlas.width, H = ref->atlas.height;
    const float *uv = m->uvs + (size_t)t * 6;
    const double *P[3];
    for (int c = 0; c < 3; ++c) P[c] = ref->pos_mm + 3 * (size_t)m->indices[3 * (size_t)t + c];
    poly tri = {3, {uv[0] * W, uv[2] * W, uv[4] * W}, {uv[1] * H, uv[3] * H, uv[5] * H}};
    double x0 = fmin(tri.x[0], fmin(tri.x[1], tri.x[2])), x1 = fmax(tri.x[0], fmax(tri.x[1], tri.x[2]));
    double y0 = fmin(tri.y[0], fmin(tri.y[1], tri.y[2])), y1 = fmax(tri.y[0], fmax(tri.y[1], tri.y[2]));
    double ux1 = tri.x[1] - tri.x[0], uy1 = tri.y[1] - tri.y[0], ux2 = tri.x[2] - tri.x[0], uy2 = tri.y[2] - tri.y[0];
    double det = ux1 * uy2 - ux2 * uy1; /* 2 × signed UV area, texels² */
    int64_t n = 0;
    if (fabs(det) > 1e-9 && x1 - x0 < 4.0 * W && y1 - y0 < 4.0 * H) {
        double mm2_per_texel2 = area / (0.5 * fabs(det));
        if (tri.n == 3 && det < 0.0) { /* clip a counter-clockwise polygon */
            double tx = tri.x[1], ty = tri.y[1];
            tri.x[1] = tri.x[2], tri.y[1] = tri.y[2], tri.x[2] = tx, tri.y[2] = ty;
        }
        /* cells between texel centres: I is bilinear (smooth) inside each piece */
        for (int j = (int)floor(y0 - 0.5); j <= (int)floor(y1 - 0.5); ++j) {
            poly a, row;
            clip(&tri, 1, j + 0.5, 1.0, &a);
            clip(&a, 1, j + 1.5, -1.0, &row);
            if (row.n < 3) continue;
            double rx0 = row.x[0], rx1 = row.x[0];
            for (int k = 1; k < row.n; ++k) rx0 = fmin(rx0, row.x[k]), rx1 = fmax(rx1, row.x[k]);
            for (int i = (int)floor(rx0 - 0.5); i <= (int)floor(rx1 - 0.5); ++i) {
                poly b, cell;
                clip(&row, 0, i + 0.5, 1.0, &b);
                clip(&b, 0, i + 1.5, -1.0, &cell);
                if (cell.n < 3) continue;
                double cx = 0.0, cy = 0.0, pa = poly_area(&cell, &cx, &cy);
                if (!(pa > 0.0)) continue;
                if (out) {
                    /* barycentrics of the centroid (affine map, the original winding) */
                    double dx = cx - uv[0] * W, dy = cy - uv[1] * H;
                    double b1 = (dx * uy2 - ux2 * dy) / det, b2 = (ux1 * dy - dx * uy1) / det;
                    double p[3];
                    for (int q = 0; q < 3; ++q) p[q] = P[0][q] + b1 * (P[1][q] - P[0][q]) + b2 * (P[2][q] - P[0][q]);
                    emit(ref, &out[n], p, pa * mm2_per_texel2, cx / W, cy / H, unlit);
                }
                ++n;
            }
        }
        return n;
    }
    /* no UV cells: congruent sub-triangles of edge about one texel */
    double texel = ref->stats.texel_mm > 0.0 ? ref->stats.texel_mm : ref->tri_edge[t];
    int s = (int)ceil(ref->tri_edge[t] / texel);
    s = s < 1 ? 1 : s > SUBDIVIDE_MAX ? SUBDIVIDE_MAX : s;
    if (!out) return (int64_t)s * s;
    double sub_area = area / ((double)s * s);
    for (int i = 0; i < s; ++i)
        for (int j = 0; i + j < s; ++j)
            for (int down = 0; down < 2; ++down) {
                if (down && i + j > s - 2) continue;
                double b1 = (i + (down ? 2.0 : 1.0) / 3.0) / s, b2 = (j + (down ? 2.0 : 1.0) / 3.0) / s, p[3];
                for (int q = 0; q < 3; ++q) p[q] = P[0][q] + b1 * (P[1][q] - P[0][q]) + b2 * (P[2][q] - P[0][q]);
                double u = uv[0] + b1 * (uv[2] - uv[0]) + b2 * (uv[4] - uv[0]);
                double v = uv[1] + b1 * (uv[3] - uv[1]) + b2 * (uv[5] - uv[1]);
                emit(ref, &out[n++], p, sub_area, u, v, unlit);
            }
    return n;
}

static void count_range(void *vctx, size_t begin, size_t end)
{
    build_ctx *ctx = vctx;
    for (size_t t = begin; t < end; ++t) ctx->offset[t + 1] = triangle_elements(ctx->ref, (int32_t)t, NULL, NULL);
}

static void fill_range(void *vctx, size_t begin, size_t end)
{
    build_ctx *ctx = vctx;
    for (size_t t = begin; t < end; ++t) triangle_elements(ctx->ref, (int32_t)t, ctx->out + ctx->offset[t], &ctx->unlit[t]);
}

static int64_t element_cell(const dm_ref_grid *g, const float p[3])
{
    const double q[3] = {p[0], p[1], p[2]};
    return dm_ref_grid_cell(g, q);
}

dm_result dm_ref_build_elements(dm_reference *ref, dm_error *err)
{
    const dm_mesh *m = ref->mesh;
    size_t nt = (size_t)m->triangle_count;
    build_ctx ctx = {.ref = ref};
    ctx.offset = calloc(nt + 1, sizeof *ctx.offset);
    ctx.unlit = calloc(nt ? nt : 1, sizeof *ctx.unlit);
    if (!ctx.offset || !ctx.unlit) {
        free(ctx.offset);
        free(ctx.unlit);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference: element offsets");
    }
    dm_parallel_for(nt, 0, ref->opt.thread_count, count_range, &ctx);
    for (size_t t = 0; t < nt; ++t) ctx.offset[t + 1] += ctx.offset[t];
    int64_t count = ctx.offset[nt];
    dm_ref_element *tmp = malloc(sizeof *tmp * (size_t)(count ? count : 1));
    if (!tmp) {
        free(ctx.offset);
        free(ctx.unlit);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference: %lld texel elements", (long long)count);
    }
    ctx.out = tmp;
    dm_parallel_for(nt, 0, ref->opt.thread_count, fill_range, &ctx);
    free(ctx.offset);

    for (size_t t = 0; t < nt; ++t) ref->stats.unlit_area_mm2 += ctx.unlit[t]; /* serial: deterministic */
    free(ctx.unlit);

    /* the grid: a point per element, cells of half the wide radius; elements reordered
     * by cell (stable), so each cell's elements are contiguous */
    dm_ref_grid *g = &ref->element_grid;
    dm_ref_grid_init(g, ref->lo_mm, ref->hi_mm, 0.5 * ref->group[ref->wide_group].radius_mm);
    int64_t cells = (int64_t)g->dim[0] * g->dim[1] * g->dim[2];
    g->start = calloc((size_t)cells + 1, sizeof *g->start);
    ref->element = malloc(sizeof *ref->element * (size_t)(count ? count : 1));
    if (!g->start || !ref->element) {
        free(tmp);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference: element grid");
    }
    for (int64_t e = 0; e < count; ++e) g->start[element_cell(g, tmp[e].pos) + 1]++;
    for (int64_t c = 0; c < cells; ++c) g->start[c + 1] += g->start[c];
    int64_t *fill = malloc(sizeof *fill * (size_t)cells);
    if (!fill) {
        free(tmp);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference: element grid");
    }
    memcpy(fill, g->start, sizeof *fill * (size_t)cells);
    for (int64_t e = 0; e < count; ++e) ref->element[fill[element_cell(g, tmp[e].pos)]++] = tmp[e];
    free(fill);
    free(tmp);
    ref->element_count = count;
    return DM_OK;
}
