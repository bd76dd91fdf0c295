#include "mesh/dm_mesh.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

dm_result dm_mesh_alloc(int32_t vertex_count, int32_t triangle_count, dm_mesh *out, dm_error *err)
{
    assert(out);
    memset(out, 0, sizeof *out);
    if (vertex_count < 1 || triangle_count < 1 || triangle_count > DM_MESH_TRIANGLES_MAX)
        return dm_fail(err, DM_ERR_RANGE, "mesh of %d vertices and %d triangles: expected >= 1 and <= %d triangles",
                       vertex_count, triangle_count, (int)DM_MESH_TRIANGLES_MAX);
    size_t corners = (size_t)triangle_count * 3;
    out->vertex_count = vertex_count;
    out->triangle_count = triangle_count;
    out->positions = calloc((size_t)vertex_count * 3, sizeof(float));
    out->indices = calloc(corners, sizeof(uint32_t));
    out->uvs = calloc(corners * 2, sizeof(float));
    out->normals = calloc(corners * 3, sizeof(float));
    if (!out->positions || !out->indices || !out->uvs || !out->normals) {
        dm_mesh_free(out);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "mesh of %d vertices and %d triangles: out of memory", vertex_count,
                       triangle_count);
    }
    return DM_OK;
}

void dm_mesh_free(dm_mesh *m)
{
    if (!m) return;
    free(m->positions);
    free(m->indices);
    free(m->uvs);
    free(m->normals);
    free(m->tangents);
    memset(m, 0, sizeof *m);
}

dm_result dm_mesh_validate(const dm_mesh *m, const char *what, dm_error *err)
{
    assert(m && what);
    if (m->triangle_count < 1 || m->vertex_count < 1 || !m->positions || !m->indices || !m->uvs || !m->normals)
        return dm_fail(err, DM_ERR_EMPTY, "%s: %d vertices, %d triangles: expected at least one of each", what,
                       m->vertex_count, m->triangle_count);
    for (int64_t i = 0; i < (int64_t)m->vertex_count * 3; ++i)
        if (!isfinite(m->positions[i]))
            return dm_fail(err, DM_ERR_NON_FINITE, "%s: vertex %lld has a non-finite coordinate (%g)", what,
                           (long long)(i / 3), (double)m->positions[i]);
    for (int64_t t = 0; t < m->triangle_count; ++t)
        for (int c = 0; c < 3; ++c) {
            size_t k = (size_t)t * 3 + (size_t)c;
            if (m->indices[k] >= (uint32_t)m->vertex_count)
                return dm_fail(err, DM_ERR_RANGE, "%s: triangle %lld corner %d uses vertex %u, expected < %d", what,
                               (long long)t, c, m->indices[k], m->vertex_count);
            for (int d = 0; d < 2; ++d)
                if (!isfinite(m->uvs[k * 2 + d]))
                    return dm_fail(err, DM_ERR_NON_FINITE, "%s: triangle %lld corner %d has a non-finite UV (%g)", what,
                                   (long long)t, c, (double)m->uvs[k * 2 + d]);
            for (int d = 0; d < 3; ++d)
                if (!isfinite(m->normals[k * 3 + d]))
                    return dm_fail(err, DM_ERR_NON_FINITE, "%s: triangle %lld corner %d has a non-finite normal (%g)",
                                   what, (long long)t, c, (double)m->normals[k * 3 + d]);
        }
    return DM_OK;
}

static void tri_cross(const dm_mesh *m, int32_t t, double n[3])
{
    const float *p0 = m->positions + (size_t)m->indices[(size_t)t * 3 + 0] * 3;
    const float *p1 = m->positions + (size_t)m->indices[(size_t)t * 3 + 1] * 3;
    const float *p2 = m->positions + (size_t)m->indices[(size_t)t * 3 + 2] * 3;
    double e1[3], e2[3];
    for (int d = 0; d < 3; ++d) {
        e1[d] = (double)p1[d] - p0[d];
        e2[d] = (double)p2[d] - p0[d];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

#define DEGENERATE_REL 1e-9 /* dm_mesh_uv_jacobian's "zero", relative (dm_mesh.h) */

void dm_mesh_uv_jacobian(const dm_mesh *m, int32_t t, double scale, dm_uv_jacobian *out)
{
    memset(out, 0, sizeof *out);
    const uint32_t *ix = m->indices + (size_t)t * 3;
    const float *p0 = m->positions + (size_t)ix[0] * 3, *p1 = m->positions + (size_t)ix[1] * 3,
                *p2 = m->positions + (size_t)ix[2] * 3;
    const float *uv = m->uvs + (size_t)t * 6;
    double du1 = (double)uv[2] - uv[0], dv1 = (double)uv[3] - uv[1];
    double du2 = (double)uv[4] - uv[0], dv2 = (double)uv[5] - uv[1];
    double det = du1 * dv2 - du2 * dv1;
    if (!(fabs(det) > DEGENERATE_REL * (du1 * du1 + dv1 * dv1 + du2 * du2 + dv2 * dv2))) {
        out->kind = DM_TRIANGLE_ZERO_UV_AREA;
        return;
    }
    double e1[3], e2[3];
    for (int d = 0; d < 3; ++d) {
        e1[d] = ((double)p1[d] - p0[d]) * scale;
        e2[d] = ((double)p2[d] - p0[d]) * scale;
        out->a[d] = e1[d] * dv2 - e2[d] * dv1;
        out->b[d] = e2[d] * du1 - e1[d] * du2;
    }
    double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2], cz = e1[0] * e2[1] - e1[1] * e2[0];
    double cross = sqrt(cx * cx + cy * cy + cz * cz);
    double edges2 = 0.0;
    for (int d = 0; d < 3; ++d) edges2 += e1[d] * e1[d] + e2[d] * e2[d];
    out->det = det;
    out->la = sqrt(out->a[0] * out->a[0] + out->a[1] * out->a[1] + out->a[2] * out->a[2]);
    out->lb = sqrt(out->b[0] * out->b[0] + out->b[1] * out->b[1] + out->b[2] * out->b[2]);
    if (!(cross > DEGENERATE_REL * edges2) || !(fabs(det) / out->la <= FLT_MAX) || !(fabs(det) / out->lb <= FLT_MAX)) {
        out->kind = DM_TRIANGLE_ZERO_AREA;
        return;
    }
    out->kind = DM_TRIANGLE_OK;
}

double dm_mesh_triangle_area(const dm_mesh *m, int32_t t)
{
    double n[3];
    tri_cross(m, t, n);
    return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

double dm_mesh_triangle_uv_area(const dm_mesh *m, int32_t t)
{
    const float *uv = m->uvs + (size_t)t * 6;
    double du1 = (double)uv[2] - uv[0], dv1 = (double)uv[3] - uv[1];
    double du2 = (double)uv[4] - uv[0], dv2 = (double)uv[5] - uv[1];
    return 0.5 * (du1 * dv2 - du2 * dv1);
}

void dm_mesh_compute_normals(dm_mesh *m)
{
    assert(m);
    double *acc = calloc((size_t)m->vertex_count * 3, sizeof *acc);
    if (!acc) {
        /* No memory for smoothing: fall back to flat face normals, still unit length. */
        for (int32_t t = 0; t < m->triangle_count; ++t) {
            double n[3];
            tri_cross(m, t, n);
            double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (int c = 0; c < 3; ++c)
                for (int d = 0; d < 3; ++d)
                    m->normals[((size_t)t * 3 + c) * 3 + d] =
                        len > 0.0 && isfinite(len) ? (float)(n[d] / len) : (d == 2 ? 1.0f : 0.0f);
        }
        return;
    }
    /* Cross products are twice the area times the unit normal: area weighting for free. */
    for (int32_t t = 0; t < m->triangle_count; ++t) {
        double n[3];
        tri_cross(m, t, n);
        for (int c = 0; c < 3; ++c)
            for (int d = 0; d < 3; ++d) acc[(size_t)m->indices[(size_t)t * 3 + c] * 3 + d] += n[d];
    }
    for (int32_t t = 0; t < m->triangle_count; ++t)
        for (int c = 0; c < 3; ++c) {
            const double *a = acc + (size_t)m->indices[(size_t)t * 3 + c] * 3;
            double len = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
            float *n = m->normals + ((size_t)t * 3 + c) * 3;
            for (int d = 0; d < 3; ++d)
                n[d] = len > 0.0 && isfinite(len) ? (float)(a[d] / len) : (d == 2 ? 1.0f : 0.0f);
        }
    free(acc);
}

/* ---- subdivision ------------------------------------------------------------------ */

typedef struct edge_ref {
    uint64_t key; /* min vertex << 32 | max vertex */
    uint32_t slot; /* triangle * 3 + edge (edge e joins corners e and e+1) */
} edge_ref;

static int cmp_edge(const void *a, const void *b)
{
    const edge_ref *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return x->slot < y->slot ? -1 : x->slot > y->slot;
}

static void mid_normal(const float *a, const float *b, float *out)
{
    double n[3], len2 = 0.0;
    for (int d = 0; d < 3; ++d) {
        n[d] = 0.5 * ((double)a[d] + b[d]);
        len2 += n[d] * n[d];
    }
    double len = sqrt(len2);
    for (int d = 0; d < 3; ++d) out[d] = len > 1e-12 ? (float)(n[d] / len) : a[d];
}

dm_result dm_mesh_subdivide(const dm_mesh *m, dm_mesh *out, dm_error *err)
{
    assert(m && out);
    memset(out, 0, sizeof *out);
    if ((int64_t)m->triangle_count * 4 > DM_MESH_TRIANGLES_MAX)
        return dm_fail(err, DM_ERR_RANGE, "subdivision of %d triangles: more than %d after, too many",
                       m->triangle_count, (int)DM_MESH_TRIANGLES_MAX);
    size_t corners = (size_t)m->triangle_count * 3;
    edge_ref *edges = malloc(corners * sizeof *edges);
    uint32_t *mid = malloc(corners * sizeof *mid); /* midpoint vertex of each slot */
    if (!edges || !mid) {
        free(edges);
        free(mid);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "subdivision of %d triangles: out of memory", m->triangle_count);
    }
    for (size_t s = 0; s < corners; ++s) {
        uint32_t a = m->indices[s], b = m->indices[s - s % 3 + (s % 3 + 1) % 3];
        uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
        edges[s] = (edge_ref){((uint64_t)lo << 32) | hi, (uint32_t)s};
    }
    qsort(edges, corners, sizeof *edges, cmp_edge);
    int64_t unique = 0;
    for (size_t k = 0; k < corners; ++k) {
        if (k > 0 && edges[k].key != edges[k - 1].key) ++unique;
        mid[edges[k].slot] = (uint32_t)(m->vertex_count + unique);
    }
    ++unique;
    if ((int64_t)m->vertex_count + unique > INT32_MAX) {
        free(edges);
        free(mid);
        return dm_fail(err, DM_ERR_RANGE, "subdivision: too many vertices");
    }
    dm_result r = dm_mesh_alloc((int32_t)(m->vertex_count + unique), m->triangle_count * 4, out, err);
    if (r != DM_OK) {
        free(edges);
        free(mid);
        return r;
    }
    out->normals_from_file = m->normals_from_file;
    out->polygon_count = m->polygon_count;
    memcpy(out->positions, m->positions, (size_t)m->vertex_count * 3 * sizeof(float));
    for (size_t k = 0; k < corners; ++k) {
        uint32_t a = (uint32_t)(edges[k].key >> 32), b = (uint32_t)edges[k].key;
        float *p = out->positions + (size_t)mid[edges[k].slot] * 3;
        for (int d = 0; d < 3; ++d) p[d] = 0.5f * (m->positions[(size_t)a * 3 + d] + m->positions[(size_t)b * 3 + d]);
    }
    /* Child c of triangle t: corners given as (parent corner or edge midpoint) codes,
     * 0..2 corners, 3..5 midpoints of edges 0..2 (edge e joins corners e and e+1). */
    static const int child[4][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}};
    for (int32_t t = 0; t < m->triangle_count; ++t) {
        uint32_t vid[6];
        float uv[6][2], nrm[6][3];
        for (int c = 0; c < 3; ++c) {
            size_t s = (size_t)t * 3 + (size_t)c;
            vid[c] = m->indices[s];
            vid[3 + c] = mid[s];
            memcpy(uv[c], m->uvs + s * 2, sizeof uv[c]);
            memcpy(nrm[c], m->normals + s * 3, sizeof nrm[c]);
        }
        for (int e = 0; e < 3; ++e) {
            int a = e, b = (e + 1) % 3;
            for (int d = 0; d < 2; ++d) uv[3 + e][d] = 0.5f * (uv[a][d] + uv[b][d]);
            mid_normal(nrm[a], nrm[b], nrm[3 + e]);
        }
        for (int k = 0; k < 4; ++k)
            for (int c = 0; c < 3; ++c) {
                size_t s = ((size_t)t * 4 + (size_t)k) * 3 + (size_t)c;
                int code = child[k][c];
                out->indices[s] = vid[code];
                memcpy(out->uvs + s * 2, uv[code], sizeof uv[code]);
                memcpy(out->normals + s * 3, nrm[code], sizeof nrm[code]);
            }
    }
    free(edges);
    free(mid);
    return DM_OK;
}

/* ---- UV islands ------------------------------------------------------------------- */

typedef struct corner_ref {
    uint32_t position, u, v; /* u, v: float bits (with −0 folded into +0) */
    uint32_t triangle;
} corner_ref;

static int cmp_corner(const void *a, const void *b)
{
    const corner_ref *x = a, *y = b;
    if (x->position != y->position) return x->position < y->position ? -1 : 1;
    if (x->u != y->u) return x->u < y->u ? -1 : 1;
    if (x->v != y->v) return x->v < y->v ? -1 : 1;
    return x->triangle < y->triangle ? -1 : x->triangle > y->triangle;
}

static uint32_t uf_find(uint32_t *parent, uint32_t i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

dm_result dm_mesh_uv_islands(const dm_mesh *m, int32_t *island_of, int32_t *island_count, dm_error *err)
{
    assert(m && island_count);
    size_t corners = (size_t)m->triangle_count * 3;
    corner_ref *refs = malloc(corners * sizeof *refs);
    uint32_t *parent = malloc((size_t)m->triangle_count * sizeof *parent);
    int32_t *label = malloc((size_t)m->triangle_count * sizeof *label);
    if (!refs || !parent || !label) {
        free(refs);
        free(parent);
        free(label);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "UV islands of %d triangles: out of memory", m->triangle_count);
    }
    for (size_t k = 0; k < corners; ++k) {
        float u = m->uvs[k * 2] + 0.0f, v = m->uvs[k * 2 + 1] + 0.0f;
        refs[k].position = m->indices[k];
        memcpy(&refs[k].u, &u, sizeof u);
        memcpy(&refs[k].v, &v, sizeof v);
        refs[k].triangle = (uint32_t)(k / 3);
    }
    qsort(refs, corners, sizeof *refs, cmp_corner);
    for (int32_t t = 0; t < m->triangle_count; ++t) parent[t] = (uint32_t)t;
    for (size_t k = 1; k < corners; ++k) {
        const corner_ref *a = &refs[k - 1], *b = &refs[k];
        if (a->position != b->position || a->u != b->u || a->v != b->v) continue;
        uint32_t ra = uf_find(parent, a->triangle), rb = uf_find(parent, b->triangle);
        if (ra != rb) parent[ra > rb ? ra : rb] = ra < rb ? ra : rb;
    }
    int32_t count = 0;
    for (int32_t t = 0; t < m->triangle_count; ++t) {
        uint32_t r = uf_find(parent, (uint32_t)t);
        label[t] = r == (uint32_t)t ? count++ : label[r]; /* the root is the lowest index */
        if (island_of) island_of[t] = label[t];
    }
    free(refs);
    free(parent);
    free(label);
    *island_count = count;
    return DM_OK;
}
