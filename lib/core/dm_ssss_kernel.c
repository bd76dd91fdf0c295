/* dm_ssss_kernel.c — the screen-space kernels per size of pixel (dm_ssss_kernel.h). */
#include "core/dm_ssss_kernel.h"

#include <math.h>
#include <string.h>

/* Pixels a row considers, each side: out to 12σ of the widest Gaussian (beyond, 2e-33 of its
 * mass), at most MAX_PX; what lies beyond is folded into the last bin, which reaches to
 * infinity. The cache of a row's cumulative masses lives on the stack (49 KB). */
enum { MAX_PX = 2048 };

typedef struct row_fit {
    int n;                     /* pixels 1..n; beyond n, no mass */
    double q[3][MAX_PX + 2];   /* q[c][b]: L's mass in channel c beyond pixel b's inner edge, (b − ½)P */
} row_fit;

static double qv(const row_fit *r, int c, int b)
{
    return b > r->n ? 0.0 : r->q[c][b];
}

/* The best single tap for the pixels s..e: the largest error of the cumulative mass at the
 * bin's inner pixel boundaries, and the tap's position (pixels) in *pos. */
static double bin_error(const row_fit *r, int s, int e, double *pos)
{
    *pos = s;
    if (s == e) return 0.0;
    double w[3];
    for (int c = 0; c < 3; ++c) w[c] = qv(r, c, s) - qv(r, c, e + 1);
    /* left(j): the error at the boundaries below the tap's pixel j, largest at j − 1 (rising
     * with j); right(j): above j + 1, largest at j + 1 (falling) */
#define LEFT(j, c) ((j) > s ? qv(r, c, s) - qv(r, c, (j)) : 0.0)
#define RIGHT(j, c) ((j) + 1 < e ? qv(r, c, (j) + 2) - qv(r, c, e + 1) : 0.0)
    int lo = s, hi = e; /* the first j where left ≥ right */
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        double l = 0, rt = 0;
        for (int c = 0; c < 3; ++c) l = fmax(l, LEFT(mid, c)), rt = fmax(rt, RIGHT(mid, c));
        if (l >= rt) hi = mid;
        else lo = mid + 1;
    }
    double best = INFINITY;
    for (int j = lo - 2 > s ? lo - 2 : s; j <= lo + 1 && j <= e; ++j) {
        double base = 0;
        for (int c = 0; c < 3; ++c) base = fmax(base, fmax(LEFT(j, c), RIGHT(j, c)));
        if (j == e) { /* the tap on the bin's last pixel */
            if (base < best) best = base, *pos = j;
            continue;
        }
        /* at boundary j the fetch's share (1 − f)·W against the mass T through pixel j: the
         * f with the smallest largest |g·W − T|, g = 1 − f, at a zero of one channel's or where
         * two channels' errors meet */
        double t[3], cand[11];
        int nc = 0;
        for (int c = 0; c < 3; ++c) t[c] = qv(r, c, s) - qv(r, c, j + 1);
        cand[nc++] = 0.0, cand[nc++] = 1.0;
        for (int c = 0; c < 3; ++c) {
            if (w[c] > 0) cand[nc++] = t[c] / w[c];
            for (int d = c + 1; d < 3; ++d)
                if (w[c] + w[d] > 0) cand[nc++] = (t[c] + t[d]) / (w[c] + w[d]);
        }
        for (int i = 0; i < nc; ++i) {
            double g = fmin(1.0, fmax(0.0, cand[i])), err = base;
            for (int c = 0; c < 3; ++c) err = fmax(err, fabs(g * w[c] - t[c]));
            if (err < best) best = err, *pos = j + (1.0 - g);
        }
    }
#undef LEFT
#undef RIGHT
    return best;
}

/* The greedy partition of pixels 1..n into at most h bins of error ≤ tau: the bins' last pixels
 * in ends. Returns the bin count, or 0 when h bins do not reach. */
static int partition(const row_fit *r, int h, double tau, int *ends)
{
    int s = 1, g = 0;
    double pos;
    while (s <= r->n) {
        if (g == h) return 0;
        int e = r->n;
        if (bin_error(r, s, e, &pos) > tau) {
            int lo = s, hi = r->n; /* bin_error(s, lo) ≤ tau < bin_error(s, hi) */
            while (hi - lo > 1) {
                int mid = lo + (hi - lo) / 2;
                if (bin_error(r, s, mid, &pos) <= tau) lo = mid;
                else hi = mid;
            }
            e = lo;
        }
        ends[g++] = e;
        s = e + 1;
    }
    return g;
}

static void fit_row(const dm_profile *p, double mm_per_px, int taps, row_fit *r, dm_ssss_kernel *k, int row)
{
    const int h = taps / 2;
    double vmax = 0, wsum[3] = {0, 0, 0};
    for (int j = 0; j < p->count; ++j) {
        vmax = fmax(vmax, p->variance_mm2[j]);
        for (int c = 0; c < 3; ++c) wsum[c] += p->weight[j][c];
    }
    double reach = ceil(12.0 * sqrt(vmax) / mm_per_px + 1.0);
    r->n = reach < MAX_PX ? (int)reach : MAX_PX;
    for (int c = 0; c < 3; ++c)
        for (int b = 1; b <= r->n; ++b) {
            double q = 0;
            for (int j = 0; j < p->count && wsum[c] > 0; ++j)
                q += p->weight[j][c] * 0.5 * erfc((b - 0.5) * mm_per_px / sqrt(2.0 * p->variance_mm2[j]));
            r->q[c][b] = wsum[c] > 0 ? q / wsum[c] : 0.0; /* no weight: the identity kernel */
        }
    int ends[DM_SSSS_MAX_TAPS];
    double tau = 0;
    if (!partition(r, h, 0.0, ends)) { /* bisection on the largest error */
        double lo = 0, hi = 1;
        for (int it = 0; it < 50; ++it) {
            double mid = 0.5 * (lo + hi);
            if (partition(r, h, mid, ends)) hi = mid;
            else lo = mid;
        }
        tau = hi;
    }
    const int bins = partition(r, h, tau, ends);
    k->edge_error[row] = tau;
    /* taps outward from the centre; bins in mm for the 2-D product's error */
    double lw[DM_SSSS_MAX_TAPS][3], lo_mm[DM_SSSS_MAX_TAPS], hi_mm[DM_SSSS_MAX_TAPS];
    for (int c = 0; c < 3; ++c) lw[h][c] = 1.0 - 2.0 * qv(r, c, 1);
    lo_mm[h] = -0.5 * mm_per_px, hi_mm[h] = 0.5 * mm_per_px;
    k->offset_px[row][h] = 0.0f;
    for (int a = 0, s = 1; a < h; ++a) {
        double pos;
        if (a < bins) {
            bin_error(r, s, ends[a], &pos);
            for (int c = 0; c < 3; ++c) lw[h + 1 + a][c] = qv(r, c, s) - qv(r, c, ends[a] + 1);
            hi_mm[h + 1 + a] = a == bins - 1 ? INFINITY : (ends[a] + 0.5) * mm_per_px;
        } else { /* more taps than bins: the spares beyond, weightless */
            pos = r->n + 1 + (a - bins);
            for (int c = 0; c < 3; ++c) lw[h + 1 + a][c] = 0.0;
            hi_mm[h + 1 + a] = INFINITY;
        }
        lo_mm[h + 1 + a] = a < bins ? (s - 0.5) * mm_per_px : INFINITY;
        for (int c = 0; c < 3; ++c) lw[h - 1 - a][c] = lw[h + 1 + a][c];
        lo_mm[h - 1 - a] = -hi_mm[h + 1 + a], hi_mm[h - 1 - a] = -lo_mm[h + 1 + a];
        k->offset_px[row][h + 1 + a] = (float)pos, k->offset_px[row][h - 1 - a] = (float)-pos;
        if (a < bins) s = ends[a] + 1;
    }
    /* p_j[a]: 1-D mass of Gaussian j in bin a; M = Σ_j w_j p_j p_jᵀ / Σ_j w_j against l lᵀ */
    double pm[DM_PROFILE_MAX_GAUSSIANS][DM_SSSS_MAX_TAPS];
    for (int j = 0; j < p->count; ++j) {
        double sd = sqrt(2.0 * p->variance_mm2[j]);
        for (int a = 0; a < taps; ++a)
            pm[j][a] = !(hi_mm[a] > lo_mm[a]) ? 0.0 : 0.5 * (erfc(lo_mm[a] / sd) - erfc(hi_mm[a] / sd));
    }
    for (int c = 0; c < 3; ++c) {
        double e2 = 0, norm2 = 0;
        for (int a = 0; a < taps && wsum[c] > 0; ++a)
            for (int b = 0; b < taps; ++b) {
                double m = 0;
                for (int j = 0; j < p->count; ++j) m += p->weight[j][c] * pm[j][a] * pm[j][b];
                m /= wsum[c];
                e2 += (m - lw[a][c] * lw[b][c]) * (m - lw[a][c] * lw[b][c]);
                norm2 += m * m;
            }
        k->fit_error[row][c] = norm2 > 0 ? sqrt(e2 / norm2) : 0.0;
        for (int a = 0; a < taps; ++a) k->weight[row][a][c] = (float)lw[a][c];
    }
}

double dm_ssss_kernel_row_mm_per_px(const dm_ssss_kernel *k, int r)
{
    return k->rows < 2 ? k->mm_per_px[0] : k->mm_per_px[0] * pow(k->mm_per_px[1] / k->mm_per_px[0], (double)r / (k->rows - 1));
}

dm_result dm_ssss_kernel_fit(const dm_profile *p, int taps, dm_ssss_kernel *k, dm_error *err)
{
    if (taps < 3 || taps > DM_SSSS_MAX_TAPS || taps % 2 == 0)
        return dm_fail(err, DM_ERR_RANGE, "screen-space kernel: %d taps, expected an odd count in [3, %d]", taps,
                       DM_SSSS_MAX_TAPS);
    if (p->count < 1 || p->count > DM_PROFILE_MAX_GAUSSIANS)
        return dm_fail(err, DM_ERR_RANGE, "screen-space kernel: profile has %d Gaussians, expected 1..%d", p->count,
                       DM_PROFILE_MAX_GAUSSIANS);
    for (int j = 0; j < p->count; ++j)
        if (!(p->variance_mm2[j] > 0) || !isfinite(p->variance_mm2[j]))
            return dm_fail(err, DM_ERR_RANGE, "screen-space kernel: variance %d is %g mm^2, expected > 0", j,
                           p->variance_mm2[j]);
    memset(k, 0, sizeof *k);
    k->taps = taps;
    k->rows = DM_SSSS_ROWS;
    k->mm_per_px[0] = DM_SSSS_ROW0_MM_PER_PX;
    k->mm_per_px[1] = ldexp(DM_SSSS_ROW0_MM_PER_PX, DM_SSSS_ROWS - 1);
    row_fit r;
    for (int row = 0; row < k->rows; ++row) fit_row(p, dm_ssss_kernel_row_mm_per_px(k, row), taps, &r, k, row);
    return DM_OK;
}

void dm_ssss_kernel_texels(const dm_ssss_kernel *k, float *out)
{
    for (int r = 0; r < k->rows; ++r)
        for (int a = 0; a < k->taps; ++a) {
            float *t = out + ((size_t)r * k->taps + a) * 4;
            for (int c = 0; c < 3; ++c) t[c] = k->weight[r][a][c];
            t[3] = k->offset_px[r][a];
        }
}

dm_result dm_ssss_kernel_from_texels(const float *t, int taps, int rows, const float *mm_per_px, dm_ssss_kernel *k,
                                     dm_error *err)
{
    if (taps < 3 || taps > DM_SSSS_MAX_TAPS || taps % 2 == 0)
        return dm_fail(err, DM_ERR_RANGE, "sss.kernel: %d taps, expected an odd count in [3, %d]", taps,
                       DM_SSSS_MAX_TAPS);
    if (mm_per_px ? rows < 1 || rows > DM_SSSS_MAX_ROWS : rows != 1)
        return dm_fail(err, DM_ERR_RANGE, "sss.kernel: %d rows, expected %s", rows,
                       mm_per_px ? "1 to 8 (one per size of pixel)" : "1 (no sizes of pixel: offsets in mm)");
    memset(k, 0, sizeof *k);
    k->taps = taps;
    k->rows = rows;
    k->mm_per_px[0] = mm_per_px ? mm_per_px[0] : 1.0, k->mm_per_px[1] = mm_per_px ? mm_per_px[1] : 1.0;
    for (int i = 0; i < 2; ++i)
        if (!(k->mm_per_px[i] >= DM_SSSS_MM_PER_PX_MIN && k->mm_per_px[i] <= DM_SSSS_MM_PER_PX_MAX))
            return dm_fail(err, DM_ERR_RANGE, "sss.kernel: size of pixel %d is %g mm, expected within [%g, %g]", i,
                           k->mm_per_px[i], DM_SSSS_MM_PER_PX_MIN, DM_SSSS_MM_PER_PX_MAX);
    if (rows == 1 ? k->mm_per_px[1] != k->mm_per_px[0] : !(k->mm_per_px[1] > k->mm_per_px[0]))
        return dm_fail(err, DM_ERR_RANGE, "sss.kernel: sizes of pixel %g to %g mm over %d rows, expected %s",
                       k->mm_per_px[0], k->mm_per_px[1], rows, rows == 1 ? "equal" : "ascending");
    for (int r = 0; r < rows; ++r) {
        const double row_mm = dm_ssss_kernel_row_mm_per_px(k, r);
        double sum[3] = {0, 0, 0};
        for (int a = 0; a < taps; ++a) {
            const float *x = t + ((size_t)r * taps + a) * 4;
            for (int c = 0; c < 4; ++c)
                if (!isfinite(x[c]))
                    return dm_fail(err, DM_ERR_RANGE, "sss.kernel: row %d tap %d value %d is not finite", r, a, c);
            if (a > 0 && !(x[3] > x[-1]))
                return dm_fail(err, DM_ERR_RANGE, "sss.kernel: row %d: offset of tap %d (%g) not above tap %d's", r,
                               a, (double)x[3], a - 1);
            if (!(fabs(x[3]) * row_mm <= DM_SSSS_OFFSET_MAX_MM))
                return dm_fail(err, DM_ERR_RANGE, "sss.kernel: row %d: offset of tap %d reaches %g mm, expected within "
                               "+-%g mm", r, a, fabs(x[3]) * row_mm, DM_SSSS_OFFSET_MAX_MM);
            for (int c = 0; c < 3; ++c) {
                if (!(x[c] >= 0.0f))
                    return dm_fail(err, DM_ERR_RANGE, "sss.kernel: row %d tap %d weight %d is %g, expected >= 0", r, a,
                                   c, (double)x[c]);
                k->weight[r][a][c] = x[c];
                sum[c] += x[c];
            }
            k->offset_px[r][a] = x[3];
        }
        for (int c = 0; c < 3; ++c)
            if (fabs(sum[c] - 1.0) > 1e-4)
                return dm_fail(err, DM_ERR_RANGE, "sss.kernel: row %d channel %d weights sum to %.6g, expected 1", r, c,
                               sum[c]);
    }
    return DM_OK;
}
