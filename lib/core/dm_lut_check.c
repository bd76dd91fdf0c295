#include "core/dm_lut_check.h"

#include <math.h>
#include <string.h>

#include "core/dm_brdf.h"

enum { GRID = 8, RANDOM = 32, MAX_SAMPLES = 4 + GRID * GRID + RANDOM };

/* The sample texels; returns their count. */
static int sample_texels(int w, int h, int is[MAX_SAMPLES], int js[MAX_SAMPLES])
{
    int n = 0;
    const int ci[4] = {0, w - 1, 0, w - 1}, cj[4] = {0, 0, h - 1, h - 1};
    for (int k = 0; k < 4; ++k, ++n) {
        is[n] = ci[k];
        js[n] = cj[k];
    }
    for (int gy = 0; gy < GRID; ++gy)
        for (int gx = 0; gx < GRID; ++gx, ++n) {
            is[n] = (int)(((gx + 0.5) * w) / GRID);
            js[n] = (int)(((gy + 0.5) * h) / GRID);
        }
    uint64_t x = 0x9e3779b97f4a7c15ull;
    for (int k = 0; k < RANDOM; ++k, ++n) {
        x = x * 6364136223846793005ull + 1442695040888963407ull;
        is[n] = (int)((x >> 33) % (uint64_t)w);
        x = x * 6364136223846793005ull + 1442695040888963407ull;
        js[n] = (int)((x >> 33) % (uint64_t)h);
    }
    return n;
}

static void record(dm_lut_check *c, int i, int j, double value, double expected, double tol)
{
    double e = fabs(value - expected);
    if (!(e <= tol)) c->failures++; /* NaN fails */
    if (!(e <= c->max_error)) {
        c->max_error = isnan(e) ? INFINITY : e;
        c->worst_i = i;
        c->worst_j = j;
        c->worst_value = value;
        c->worst_expected = expected;
    }
    c->samples++;
}

void dm_lut_check_beckmann(const uint8_t *texels, int width, int height, dm_lut_check *out)
{
    memset(out, 0, sizeof *out);
    int is[MAX_SAMPLES], js[MAX_SAMPLES];
    int n = sample_texels(width, height, is, js);
    for (int k = 0; k < n; ++k) {
        double s = (is[k] + 0.5) / width, t = (js[k] + 0.5) / height;
        double expected = dm_beckmann_encode8(dm_beckmann(s, t));
        record(out, is[k], js[k], texels[(size_t)js[k] * (size_t)width + (size_t)is[k]], expected, 1.0);
    }
}

void dm_lut_check_directional(const float *table, int stride, int channels, int width, int height, double f0,
                              int nodes, dm_lut_check *out)
{
    memset(out, 0, sizeof *out);
    int is[MAX_SAMPLES], js[MAX_SAMPLES];
    int n = sample_texels(width, height, is, js);
    for (int k = 0; k < n; ++k) {
        double c = (is[k] + 0.5) / width, m = (js[k] + 0.5) / height, scale, bias;
        dm_ks_directional(c, m, nodes, &scale, &bias);
        const float *v = table + ((size_t)js[k] * (size_t)width + (size_t)is[k]) * (size_t)stride;
        if (channels == 1) {
            double e = f0 * scale + bias;
            record(out, is[k], js[k], v[0], e, 1e-3 * fmax(1.0, fabs(e)));
        } else {
            record(out, is[k], js[k], v[0], scale, 1e-3 * fmax(1.0, fabs(scale)));
            record(out, is[k], js[k], v[1], bias, 1e-3 * fmax(1.0, fabs(bias)));
        }
    }
}
