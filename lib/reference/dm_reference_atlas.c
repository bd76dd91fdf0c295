/* dm_reference_atlas.c — the targets of a texture-space reference: each covered texel
 * centre located on the mesh (dm_uv_raster) as a triangle and barycentrics. */
#include <math.h>
#include <stdlib.h>

#include "reference/dm_reference.h"
#include "mesh/dm_uv_raster.h"

/* Barycentrics (of corners 1, 2) of UV point (u, v) in triangle t; the centroid when the
 * triangle has no UV area. Outside the triangle they extrapolate its plane. */
static void uv_barycentrics(const dm_mesh *m, int32_t t, double u, double v, float *b1, float *b2)
{
    const float *uv = m->uvs + 6 * (size_t)t;
    double ux1 = uv[2] - uv[0], vy1 = uv[3] - uv[1], ux2 = uv[4] - uv[0], vy2 = uv[5] - uv[1];
    double det = ux1 * vy2 - ux2 * vy1, du = u - uv[0], dv = v - uv[1];
    if (fabs(det) < 1e-30) {
        *b1 = *b2 = 1.0f / 3.0f;
        return;
    }
    *b1 = (float)((du * vy2 - ux2 * dv) / det);
    *b2 = (float)((ux1 * dv - du * vy1) / det);
}

dm_result dm_reference_atlas_targets(const dm_mesh *mesh, const dm_reference_atlas *atlas, int thread_count,
                                     dm_reference_target **targets, int64_t **texel_of, size_t *count,
                                     dm_error *err)
{
    *targets = NULL;
    *texel_of = NULL;
    *count = 0;
    const int W = atlas->width, H = atlas->height;
    size_t texels = (size_t)W * H;
    int32_t *tri = malloc(sizeof *tri * texels);
    if (!tri) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference: %dx%d raster", W, H);
    dm_result r = dm_uv_raster(mesh, NULL, W, H, thread_count, tri, NULL, err);
    if (r != DM_OK) {
        free(tri);
        return r;
    }
    size_t n = 0;
    for (size_t i = 0; i < texels; ++i) n += atlas->rgba[4 * i + 3] > 0.0f;
    dm_reference_target *tg = malloc(sizeof *tg * (n ? n : 1));
    int64_t *of = malloc(sizeof *of * (n ? n : 1));
    if (!tg || !of) {
        free(tri);
        free(tg);
        free(of);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference: %zu targets", n);
    }
    size_t k = 0;
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            size_t x = (size_t)j * W + i;
            if (!(atlas->rgba[4 * x + 3] > 0.0f)) continue;
            int32_t t = tri[x];
            /* covered by the renderer but not by the raster (an edge rule's difference):
             * the nearest rasterized texel's triangle, its plane extrapolated */
            for (int rad = 1; t < 0 && rad <= 16; ++rad)
                for (int dj = -rad; dj <= rad && t < 0; ++dj)
                    for (int di = -rad; di <= rad && t < 0; ++di) {
                        int ii = i + di, jj = j + dj;
                        if ((abs(di) != rad && abs(dj) != rad) || ii < 0 || jj < 0 || ii >= W || jj >= H) continue;
                        t = tri[(size_t)jj * W + ii];
                    }
            if (t < 0) t = 0; /* nothing within 16 texels: any triangle keeps the output finite */
            tg[k].triangle = t;
            uv_barycentrics(mesh, t, (i + 0.5) / W, (j + 0.5) / H, &tg[k].b1, &tg[k].b2);
            of[k] = (int64_t)x;
            ++k;
        }
    free(tri);
    *targets = tg;
    *texel_of = of;
    *count = n;
    return DM_OK;
}
