#include "mesh/dm_seam_edges.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

typedef struct wkey {
    float p[3];
    uint32_t i;
} wkey;

static int wkey_cmp(const void *x, const void *y)
{
    const wkey *a = x, *b = y;
    int c = memcmp(a->p, b->p, sizeof a->p);
    return c ? c : (a->i > b->i) - (a->i < b->i);
}

typedef struct half {
    uint32_t a, b; /* welded ends, a < b */
    int32_t tri;
    int8_t corner; /* the edge from corner to corner + 1 of tri */
    float uva[2], uvb[2]; /* the UVs tri gives a and b */
} half;

static int half_cmp(const void *x, const void *y)
{
    const half *e = x, *f = y;
    if (e->a != f->a) return e->a < f->a ? -1 : 1;
    if (e->b != f->b) return e->b < f->b ? -1 : 1;
    return (e->tri > f->tri) - (e->tri < f->tri);
}

dm_result dm_seam_edges_find(const dm_mesh *m, dm_seam_edges *out, dm_error *err)
{
    memset(out, 0, sizeof *out);
    size_t nv = (size_t)m->vertex_count, ec = 3 * (size_t)m->triangle_count;
    wkey *order = malloc(sizeof *order * (nv + 1));
    half *e = malloc(sizeof *e * (ec + 1));
    out->weld = malloc(sizeof *out->weld * (nv + 1));
    out->edges = malloc(sizeof *out->edges * (ec + 1));
    out->adj = malloc(sizeof *out->adj * (ec + 1));
    if (!order || !e || !out->weld || !out->edges || !out->adj) {
        free(order), free(e), dm_seam_edges_free(out);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "seam edges: out of memory (%d triangles)", m->triangle_count);
    }
    for (size_t i = 0; i < nv; ++i) memcpy(order[i].p, m->positions + 3 * i, sizeof order[i].p), order[i].i = (uint32_t)i;
    qsort(order, nv, sizeof *order, wkey_cmp);
    for (size_t i = 0; i < nv; ++i)
        out->weld[order[i].i] =
            i && !memcmp(order[i].p, order[i - 1].p, sizeof order[i].p) ? out->weld[order[i - 1].i] : order[i].i;
    for (size_t t = 0; t < (size_t)m->triangle_count; ++t)
        for (int c = 0; c < 3; ++c) {
            int c2 = (c + 1) % 3;
            uint32_t a = out->weld[m->indices[3 * t + c]], b = out->weld[m->indices[3 * t + c2]];
            const float *ua = m->uvs + (3 * t + c) * 2, *ub = m->uvs + (3 * t + c2) * 2;
            if (a > b) {
                uint32_t k = a;
                const float *u = ua;
                a = b, b = k, ua = ub, ub = u;
            }
            e[3 * t + c] = (half){a, b, (int32_t)t, (int8_t)c, {ua[0], ua[1]}, {ub[0], ub[1]}};
        }
    qsort(e, ec, sizeof *e, half_cmp);
    for (size_t i = 0; i < ec; ++i) out->adj[i] = -1;
    for (size_t i = 0; i < ec;) {
        size_t j = i + 1;
        while (j < ec && e[j].a == e[i].a && e[j].b == e[i].b) ++j;
        if (j - i == 2 && e[i].a != e[i].b) {
            out->adj[3 * (size_t)e[i].tri + e[i].corner] = e[i + 1].tri;
            out->adj[3 * (size_t)e[i + 1].tri + e[i + 1].corner] = e[i].tri;
        }
        bool seam = j - i != 2 || memcmp(e[i].uva, e[i + 1].uva, sizeof e[i].uva) ||
                    memcmp(e[i].uvb, e[i + 1].uvb, sizeof e[i].uvb);
        if (seam && e[i].a != e[i].b) {
            bool cut = j - i == 2;
            out->edges[out->count++] = (dm_seam_edge){e[i].a, e[i].b, {e[i].tri, cut ? e[i + 1].tri : -1},
                                                      {e[i].corner, cut ? e[i + 1].corner : 0}, (int32_t)(j - i)};
            out->boundary_edges += j - i == 1;
            out->nonmanifold_edges += j - i > 2;
        }
        i = j;
    }
    free(order), free(e);
    return DM_OK;
}

void dm_seam_edges_free(dm_seam_edges *s)
{
    free(s->edges), free(s->weld), free(s->adj);
    memset(s, 0, sizeof *s);
}
