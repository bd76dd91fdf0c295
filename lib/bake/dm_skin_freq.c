/* dm_skin_freq.c — the skin fits' frequency-domain quadrature (dm_skin_freq.h). */
#include "bake/dm_skin_freq.h"

#include <assert.h>
#include <math.h>

#include "bake/dm_skin_ad.h"
#include "bake/dm_skin_layers.h"

void dm_skin_freq_nodes(double s_lo, double s_hi, int count, double *s, double *sq)
{
    assert(s_lo > 0.0 && s_hi > s_lo && count >= 3 && count % 2 == 1);
    double u0 = log(s_lo), h = (log(s_hi) - u0) / (count - 1);
    for (int i = 0; i < count; ++i) {
        s[i] = exp(u0 + i * h);
        double simpson = (i == 0 || i == count - 1 ? 1.0 : i % 2 ? 4.0 : 2.0) * h / 3.0;
        sq[i] = sqrt(simpson) * s[i];
    }
}

void dm_skin_freq_design(const double *s, const double *sq, int count, const double *variance_mm2, int n, double *a)
{
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < count; ++i)
            a[(size_t)k * count + i] = sq[i] * exp(-0.5 * variance_mm2[k] * s[i] * s[i]);
}

void dm_skin_freq_totals(const dm_skin_params *p, int pairs, int ad_stream_count, double *total, double *scale)
{
    for (int l = 0; l < DM_SKIN_LAMBDA_COUNT; ++l) {
        double t = dm_skin_ad_total_at(p, l, ad_stream_count);
        if (total) total[l] = t;
        if (scale) {
            dm_skin_dual r;
            dm_skin_reflectance_at(p, l, pairs, 0.0, &r, NULL);
            scale[l] = r.v > 0.0 ? t / r.v : 0.0;
        }
    }
}

void dm_skin_freq_spectral(const dm_skin_params *p, int pairs, const double *scale, const double *s, const double *sq,
                           int count, double *y)
{
    for (int l = 0; l < DM_SKIN_LAMBDA_COUNT; ++l)
        for (int i = 0; i < count; ++i) {
            dm_skin_dual r;
            dm_skin_reflectance_at(p, l, pairs, s[i], &r, NULL);
            y[(size_t)l * count + i] = sq[i] * (scale ? scale[l] : 1.0) * r.v;
        }
}

void dm_skin_freq_channels(const dm_skin_params *p, int pairs, const double *scale, const double *s, const double *sq,
                           int count, const double (*w)[3], double *yc)
{
    for (int i = 0; i < count; ++i) {
        double v[3] = {0.0, 0.0, 0.0};
        for (int l = 0; l < DM_SKIN_LAMBDA_COUNT; ++l) {
            dm_skin_dual r;
            dm_skin_reflectance_at(p, l, pairs, s[i], &r, NULL);
            double y = sq[i] * (scale ? scale[l] : 1.0) * r.v; /* as dm_skin_freq_spectral stores it */
            for (int c = 0; c < 3; ++c) v[c] += w[l][c] * y;
        }
        for (int c = 0; c < 3; ++c) yc[(size_t)c * count + i] = v[c];
    }
}
