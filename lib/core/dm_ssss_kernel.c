#include "core/dm_ssss_kernel.h"

#include <math.h>
#include <string.h>

static double phi(double x) /* standard normal CDF */
{
    return 0.5 * erfc(-x / sqrt(2.0));
}

dm_result dm_ssss_kernel_fit(const dm_profile *p, int taps, dm_ssss_kernel *k, dm_error *err)
{
    if (taps < 3 || taps > DM_SSSS_MAX_TAPS || taps % 2 == 0)
        return dm_fail(err, DM_ERR_RANGE, "screen-space kernel: %d taps, expected an odd count in [3, %d]", taps,
                       DM_SSSS_MAX_TAPS);
    if (p->count < 1 || p->count > DM_PROFILE_MAX_GAUSSIANS)
        return dm_fail(err, DM_ERR_RANGE, "screen-space kernel: profile has %d Gaussians, expected 1..%d", p->count,
                       DM_PROFILE_MAX_GAUSSIANS);
    memset(k, 0, sizeof *k);
    k->taps = taps;
    double vmax = 0;
    for (int j = 0; j < p->count; ++j) vmax = fmax(vmax, p->variance_mm2[j]);
    if (!(vmax > 0) || !isfinite(vmax))
        return dm_fail(err, DM_ERR_RANGE, "screen-space kernel: widest variance %g mm^2, expected > 0", vmax);
    const int h = taps / 2;
    const double range = 3.0 * sqrt(vmax);
    k->range_mm = range;
    double off[DM_SSSS_MAX_TAPS], lo[DM_SSSS_MAX_TAPS], hi[DM_SSSS_MAX_TAPS];
    for (int a = 0; a < taps; ++a) {
        double t = (double)(a - h) / h;
        off[a] = range * t * fabs(t);
    }
    for (int a = 0; a < taps; ++a) { /* bins between midpoints; the end bins take the tails */
        lo[a] = a == 0 ? -INFINITY : 0.5 * (off[a - 1] + off[a]);
        hi[a] = a == taps - 1 ? INFINITY : 0.5 * (off[a] + off[a + 1]);
    }
    /* p_j[a]: 1-D mass of Gaussian j in bin a */
    double pm[DM_PROFILE_MAX_GAUSSIANS][DM_SSSS_MAX_TAPS];
    for (int j = 0; j < p->count; ++j) {
        double s = sqrt(p->variance_mm2[j]);
        for (int a = 0; a < taps; ++a) {
            double ph = isinf(hi[a]) ? 1.0 : s > 0 ? phi(hi[a] / s) : (hi[a] >= 0 ? 1.0 : 0.0);
            double pl = isinf(lo[a]) ? 0.0 : s > 0 ? phi(lo[a] / s) : (lo[a] >= 0 ? 1.0 : 0.0);
            pm[j][a] = ph - pl;
        }
    }
    for (int c = 0; c < 3; ++c) {
        /* the line-spread function's bin masses, l = Σ_j w_j p_j / Σ_j w_j: the marginal of M */
        double wsum = 0, l[DM_SSSS_MAX_TAPS];
        for (int j = 0; j < p->count; ++j) wsum += p->weight[j][c];
        if (!(wsum > 0)) { /* a channel with no weight: identity kernel, nothing to fit */
            k->weight[h][c] = 1.0f;
            continue;
        }
        for (int a = 0; a < taps; ++a) {
            l[a] = 0;
            for (int j = 0; j < p->count; ++j) l[a] += p->weight[j][c] * pm[j][a];
            l[a] /= wsum;
        }
        /* what the product l lᵀ loses of the 2-D profile's bins M/ΣM (ΣM = wsum: each p_j sums to 1) */
        double e2 = 0, norm2 = 0;
        for (int a = 0; a < taps; ++a)
            for (int b = 0; b < taps; ++b) {
                double m = 0;
                for (int j = 0; j < p->count; ++j) m += p->weight[j][c] * pm[j][a] * pm[j][b];
                m /= wsum;
                e2 += (m - l[a] * l[b]) * (m - l[a] * l[b]);
                norm2 += m * m;
            }
        k->fit_error[c] = norm2 > 0 ? sqrt(e2 / norm2) : 0.0;
        for (int a = 0; a < taps; ++a) k->weight[a][c] = (float)l[a];
    }
    for (int a = 0; a < taps; ++a) k->offset_mm[a] = (float)off[a];
    return DM_OK;
}

void dm_ssss_kernel_texels(const dm_ssss_kernel *k, float *out)
{
    for (int a = 0; a < k->taps; ++a) {
        for (int c = 0; c < 3; ++c) out[a * 4 + c] = k->weight[a][c];
        out[a * 4 + 3] = k->offset_mm[a];
    }
}

dm_result dm_ssss_kernel_from_texels(const float *t, int taps, dm_ssss_kernel *k, dm_error *err)
{
    if (taps < 3 || taps > DM_SSSS_MAX_TAPS || taps % 2 == 0)
        return dm_fail(err, DM_ERR_RANGE, "sss.kernel: %d taps, expected an odd count in [3, %d]", taps,
                       DM_SSSS_MAX_TAPS);
    memset(k, 0, sizeof *k);
    k->taps = taps;
    double sum[3] = {0, 0, 0};
    for (int a = 0; a < taps; ++a) {
        for (int c = 0; c < 4; ++c)
            if (!isfinite(t[a * 4 + c]))
                return dm_fail(err, DM_ERR_RANGE, "sss.kernel: tap %d value %d is not finite", a, c);
        if (a > 0 && !(t[a * 4 + 3] > t[a * 4 - 1]))
            return dm_fail(err, DM_ERR_RANGE, "sss.kernel: offset of tap %d (%g mm) not above tap %d's", a,
                           (double)t[a * 4 + 3], a - 1);
        if (!(fabs(t[a * 4 + 3]) <= DM_SSSS_OFFSET_MAX_MM))
            return dm_fail(err, DM_ERR_RANGE, "sss.kernel: offset of tap %d is %g mm, expected within +-%g mm", a,
                           (double)t[a * 4 + 3], DM_SSSS_OFFSET_MAX_MM);
        for (int c = 0; c < 3; ++c) {
            if (!(t[a * 4 + c] >= 0.0f))
                return dm_fail(err, DM_ERR_RANGE, "sss.kernel: tap %d weight %d is %g, expected >= 0", a, c,
                               (double)t[a * 4 + c]);
            k->weight[a][c] = t[a * 4 + c];
            sum[c] += t[a * 4 + c];
        }
        k->offset_mm[a] = t[a * 4 + 3];
    }
    for (int c = 0; c < 3; ++c)
        if (fabs(sum[c] - 1.0) > 1e-4)
            return dm_fail(err, DM_ERR_RANGE, "sss.kernel: channel %d weights sum to %.6g, expected 1", c, sum[c]);
    k->range_mm = fabs(k->offset_mm[0]);
    return DM_OK;
}
