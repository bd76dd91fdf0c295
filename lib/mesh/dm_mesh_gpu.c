/* The GPU split of a dm_mesh and its tangent frames (dm_mesh.h). */
#include "mesh/dm_mesh.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_hash.h"

typedef struct split_key {
    uint32_t position;
    uint32_t uv[2];     /* float bits */
    uint32_t normal[3]; /* float bits */
    uint32_t mirrored;  /* 1 when the triangle's UVs are mirrored */
} split_key;

static void corner_key(const dm_mesh *m, size_t corner, uint32_t mirrored, split_key *k)
{
    memset(k, 0, sizeof *k);
    k->position = m->indices[corner];
    float uv[2], n[3];
    memcpy(uv, m->uvs + corner * 2, sizeof uv);
    memcpy(n, m->normals + corner * 3, sizeof n);
    /* −0 and +0 are the same vertex. */
    for (int d = 0; d < 2; ++d) uv[d] += 0.0f;
    for (int d = 0; d < 3; ++d) n[d] += 0.0f;
    memcpy(k->uv, uv, sizeof uv);
    memcpy(k->normal, n, sizeof n);
    k->mirrored = mirrored;
}

static void unit_or(double v[3], const double fallback[3])
{
    double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len > 1e-30 && isfinite(len))
        for (int d = 0; d < 3; ++d) v[d] /= len;
    else
        for (int d = 0; d < 3; ++d) v[d] = fallback[d];
}

/* Any unit vector orthogonal to n (n unit): cross with the axis least aligned with n. */
static void any_orthogonal(const double n[3], double t[3])
{
    double ax = fabs(n[0]), ay = fabs(n[1]), az = fabs(n[2]);
    double a[3] = {0, 0, 0};
    a[ax <= ay && ax <= az ? 0 : ay <= az ? 1 : 2] = 1.0;
    t[0] = a[1] * n[2] - a[2] * n[1];
    t[1] = a[2] * n[0] - a[0] * n[2];
    t[2] = a[0] * n[1] - a[1] * n[0];
    static const double x[3] = {1, 0, 0};
    unit_or(t, x);
}

void dm_gpu_mesh_free(dm_gpu_mesh *g)
{
    if (!g) return;
    free(g->positions);
    free(g->normals);
    free(g->uvs);
    free(g->tangents);
    free(g->indices);
    memset(g, 0, sizeof *g);
}

dm_result dm_mesh_split_for_gpu(const dm_mesh *m, dm_gpu_mesh *out, dm_error *err)
{
    assert(m && out);
    memset(out, 0, sizeof *out);
    size_t corners = (size_t)m->triangle_count * 3;
    size_t cap = 16;
    while (cap < corners * 2) cap *= 2;
    int32_t *table = malloc(cap * sizeof *table); /* open addressing: vertex id or −1 */
    split_key *keys = malloc(corners * sizeof *keys);
    out->indices = malloc(corners * sizeof *out->indices);
    out->positions = malloc(corners * 3 * sizeof(float));
    out->normals = malloc(corners * 3 * sizeof(float));
    out->uvs = malloc(corners * 2 * sizeof(float));
    out->tangents = malloc(corners * 4 * sizeof(float));
    double *tan_acc = calloc(corners * 6, sizeof *tan_acc); /* Σ area·t̂, Σ area·b̂ per vertex */
    size_t *first = m->tangents ? malloc(corners * sizeof *first) : NULL; /* first corner of each vertex */
    if ((m->tangents && !first) || !table || !keys || !out->indices || !out->positions || !out->normals || !out->uvs || !out->tangents ||
        !tan_acc) {
        free(table);
        free(keys);
        free(tan_acc);
        free(first);
        dm_gpu_mesh_free(out);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "GPU split of %d triangles: out of memory", m->triangle_count);
    }
    memset(table, 0xff, cap * sizeof *table);
    int32_t count = 0;
    for (int32_t t = 0; t < m->triangle_count; ++t) {
        uint32_t mirrored = dm_mesh_triangle_uv_area(m, t) < 0.0;
        for (int c = 0; c < 3; ++c) {
            size_t corner = (size_t)t * 3 + (size_t)c;
            split_key k;
            corner_key(m, corner, mirrored, &k);
            size_t h = (size_t)dm_hash64(&k, sizeof k) & (cap - 1);
            while (table[h] >= 0 && memcmp(&keys[table[h]], &k, sizeof k) != 0) h = (h + 1) & (cap - 1);
            if (table[h] < 0) {
                table[h] = count;
                keys[count] = k;
                memcpy(out->positions + (size_t)count * 3, m->positions + (size_t)k.position * 3, 3 * sizeof(float));
                memcpy(out->normals + (size_t)count * 3, m->normals + corner * 3, 3 * sizeof(float));
                memcpy(out->uvs + (size_t)count * 2, m->uvs + corner * 2, 2 * sizeof(float));
                if (first) first[count] = corner;
                ++count;
            }
            out->indices[corner] = (uint32_t)table[h];
        }
    }
    free(table);
    free(keys);
    out->vertex_count = count;
    out->index_count = (int32_t)corners;

    /* Tangent frames: per triangle, ∂P/∂u and ∂P/∂v from the exact Jacobian, made unit
     * and weighted by surface area, summed per split vertex. */
    for (int32_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *ix = out->indices + (size_t)t * 3;
        dm_uv_jacobian j;
        dm_mesh_uv_jacobian(m, t, 1.0, &j);
        double area = dm_mesh_triangle_area(m, t);
        if (j.kind != DM_TRIANGLE_OK || !(area > 0.0)) continue;
        double tu[3], tv[3];
        for (int d = 0; d < 3; ++d) {
            tu[d] = j.a[d] / j.det;
            tv[d] = j.b[d] / j.det;
        }
        double lu = sqrt(tu[0] * tu[0] + tu[1] * tu[1] + tu[2] * tu[2]);
        double lv = sqrt(tv[0] * tv[0] + tv[1] * tv[1] + tv[2] * tv[2]);
        if (!(lu > 0.0) || !(lv > 0.0) || !isfinite(lu) || !isfinite(lv)) continue;
        for (int c = 0; c < 3; ++c)
            for (int d = 0; d < 3; ++d) {
                tan_acc[(size_t)ix[c] * 6 + d] += area * tu[d] / lu;
                tan_acc[(size_t)ix[c] * 6 + 3 + d] += area * tv[d] / lv;
            }
    }
    for (int32_t i = 0; i < count; ++i) {
        double n[3], t[3], b[3];
        for (int d = 0; d < 3; ++d) {
            n[d] = out->normals[(size_t)i * 3 + d];
            t[d] = tan_acc[(size_t)i * 6 + d];
            b[d] = tan_acc[(size_t)i * 6 + 3 + d];
        }
        /* Gram–Schmidt against the normal; the handedness compares the accumulated
         * bitangent with cross(n, t). */
        double nt = n[0] * t[0] + n[1] * t[1] + n[2] * t[2];
        for (int d = 0; d < 3; ++d) t[d] -= nt * n[d];
        double len = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        double w = 1.0;
        if (first) { /* the file's tangent, when it is not along the normal */
            const float *ft = m->tangents + first[i] * 4;
            double f[3] = {ft[0], ft[1], ft[2]}, nf = n[0] * f[0] + n[1] * f[1] + n[2] * f[2];
            for (int d = 0; d < 3; ++d) f[d] -= nf * n[d];
            double lf = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
            if (lf > 1e-6 && isfinite(lf)) {
                for (int d = 0; d < 3; ++d) out->tangents[(size_t)i * 4 + d] = (float)(f[d] / lf);
                out->tangents[(size_t)i * 4 + 3] = ft[3] < 0.0f ? -1.0f : 1.0f;
                continue;
            }
        }
        if (len > 1e-12 && isfinite(len)) {
            for (int d = 0; d < 3; ++d) t[d] /= len;
            double c[3] = {n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0]};
            w = c[0] * b[0] + c[1] * b[1] + c[2] * b[2] < 0.0 ? -1.0 : 1.0;
        } else {
            any_orthogonal(n, t);
        }
        for (int d = 0; d < 3; ++d) out->tangents[(size_t)i * 4 + d] = (float)t[d];
        out->tangents[(size_t)i * 4 + 3] = (float)w;
    }
    free(tan_acc);
    free(first);
    /* Shrink to the split size (the arrays were sized for the worst case). */
    float *p;
    if ((p = realloc(out->positions, (size_t)count * 3 * sizeof(float)))) out->positions = p;
    if ((p = realloc(out->normals, (size_t)count * 3 * sizeof(float)))) out->normals = p;
    if ((p = realloc(out->uvs, (size_t)count * 2 * sizeof(float)))) out->uvs = p;
    if ((p = realloc(out->tangents, (size_t)count * 4 * sizeof(float)))) out->tangents = p;
    return DM_OK;
}
