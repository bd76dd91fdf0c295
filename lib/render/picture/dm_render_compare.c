#include "render/dm_render_compare.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static float *read_named(dm_renderer *r, const char *name, dm_target_info *info)
{
    int idx = dm_renderer_find_target(r, name);
    if (idx < 0) return NULL;
    dm_renderer_target_info(r, idx, info);
    float *px = malloc((size_t)info->width * info->height * info->channels * sizeof *px);
    dm_error err = {0};
    if (px && dm_renderer_read_target(r, idx, px, &err) != DM_OK) {
        free(px);
        return NULL;
    }
    return px;
}

/* Bilinear, clamp-to-border-0 sample of an RGBA n×n image at uv (texel centres at (i+0.5)/n). */
static void bilinear(const float *img, int n, double u, double v, double out[4])
{
    double x = u * n - 0.5, y = v * n - 0.5;
    int x0 = (int)floor(x), y0 = (int)floor(y);
    double fx = x - x0, fy = y - y0;
    for (int c = 0; c < 4; ++c) out[c] = 0;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            int xi = x0 + i, yj = y0 + j;
            if (xi < 0 || yj < 0 || xi >= n || yj >= n) continue;
            double w = (i ? fx : 1 - fx) * (j ? fy : 1 - fy);
            for (int c = 0; c < 4; ++c) out[c] += w * img[((size_t)yj * n + xi) * 4 + c];
        }
}

dm_result dm_render_compare(dm_renderer *ref, dm_renderer *r, const char *level, dm_render_difference *e,
                            dm_error *err)
{
    memset(e, 0, sizeof *e);
    int w, h, w2, h2;
    dm_renderer_size(ref, &w, &h, NULL);
    dm_renderer_size(r, &w2, &h2, NULL);
    if (w != w2 || h != h2)
        return dm_fail(err, DM_ERR_MISMATCH, "compare: outputs %dx%d and %dx%d differ in size", w, h, w2, h2);
    size_t n = (size_t)w * h;
    float *a = malloc(n * 4 * sizeof *a), *b = malloc(n * 4 * sizeof *b);
    uint8_t *da = malloc(n * 4), *db = malloc(n * 4);
    dm_result rc = a && b && da && db ? DM_OK : dm_fail(err, DM_ERR_OUT_OF_MEMORY, "compare: out of memory");
    if (rc == DM_OK) rc = dm_renderer_read_linear(ref, a, err);
    if (rc == DM_OK) rc = dm_renderer_read_linear(r, b, err);
    if (rc == DM_OK) {
        double sum = 0;
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) {
                double d = fabs((double)a[i * 4 + c] - b[i * 4 + c]);
                e->out_max = fmax(e->out_max, d);
                e->out_peak = fmax(e->out_peak, a[i * 4 + c]);
                sum += d;
            }
        e->out_mean = sum / (double)(n * 3);
    }
    if (rc == DM_OK) rc = dm_renderer_read_display(ref, da, err);
    if (rc == DM_OK) rc = dm_renderer_read_display(r, db, err);
    if (rc == DM_OK)
        for (size_t i = 0; i < n * 4; ++i) {
            int d = abs((int)da[i] - (int)db[i]);
            if (d > e->display_steps) e->display_steps = d;
        }
    free(a), free(b), free(da), free(db);
    if (rc != DM_OK || !level) return rc;
    dm_target_info ia, ib;
    float *la = read_named(ref, level, &ia), *lb = read_named(r, level, &ib);
    if (la && lb) {
        int na = ia.width, nb = ib.width;
        double sum = 0;
        size_t count = 0;
        for (int j = 0; j < na; ++j)
            for (int i = 0; i < na; ++i) {
                const float *pa = la + ((size_t)j * na + i) * 4;
                if (pa[3] <= 1e-4f) continue;
                double pb[4];
                bilinear(lb, nb, (i + 0.5) / na, (j + 0.5) / na, pb);
                for (int c = 0; c < 3; ++c) {
                    double ra = pa[c] / pa[3], rb = pb[3] > 1e-4 ? pb[c] / pb[3] : 0.0;
                    double d = fabs(ra - rb);
                    e->level_max = fmax(e->level_max, d);
                    e->level_peak = fmax(e->level_peak, ra);
                    sum += d;
                    ++count;
                }
            }
        e->level_mean = count ? sum / (double)count : 0;
    }
    free(la), free(lb);
    return DM_OK;
}
