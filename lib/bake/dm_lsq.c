/* dm_lsq.c — small dense least squares for the profile fits (dm_lsq.h). */
#include "bake/dm_lsq.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* Householder QR in place of a (rows × cols, column-major, rows ≥ cols). The reflector of
 * column k is stored in a[k][k..rows) with its scale in beta[k]; R's diagonal in rdiag,
 * R's upper part above the diagonal of a. */
void dm_lsq_qr(double *a, int rows, int cols, double *beta, double *rdiag)
{
    for (int k = 0; k < cols; ++k) {
        double *v = a + (size_t)k * rows;
        double norm = 0.0;
        for (int i = k; i < rows; ++i) norm += v[i] * v[i];
        norm = sqrt(norm);
        double alpha = v[k] > 0 ? -norm : norm;
        rdiag[k] = alpha;
        v[k] -= alpha;
        double vv = 0.0;
        for (int i = k; i < rows; ++i) vv += v[i] * v[i];
        beta[k] = vv > 0.0 ? 2.0 / vv : 0.0;
        for (int j = k + 1; j < cols; ++j) {
            double *x = a + (size_t)j * rows, d = 0.0;
            for (int i = k; i < rows; ++i) d += v[i] * x[i];
            d *= beta[k];
            for (int i = k; i < rows; ++i) x[i] -= d * v[i];
        }
    }
}

/* y ← H_k y: the k-th reflector of dm_lsq_qr() (I − beta_k v_k v_kᵀ, v_k below the diagonal
 * of column k). */
static void reflect(const double *a, int rows, int k, const double *beta, double *y)
{
    const double *v = a + (size_t)k * rows;
    double d = 0.0;
    for (int i = k; i < rows; ++i) d += v[i] * y[i];
    d *= beta[k];
    for (int i = k; i < rows; ++i) y[i] -= d * v[i];
}

/* y ← Qᵀ y with the reflectors of dm_lsq_qr(). */
void dm_lsq_qr_apply(const double *a, int rows, int cols, const double *beta, double *y)
{
    for (int k = 0; k < cols; ++k) reflect(a, rows, k, beta, y);
}

/* y ← Q y: the reflectors of dm_lsq_qr() in reverse order. */
void dm_lsq_qr_apply_q(const double *a, int rows, int cols, const double *beta, double *y)
{
    for (int k = cols - 1; k >= 0; --k) reflect(a, rows, k, beta, y);
}

/* min ‖A z − y‖ for a small A (rows × cols ≤ DM_LSQ_MAX × DM_LSQ_MAX, column-major); columns whose R
 * diagonal is negligible (dependent) get z = 0. */
void dm_lsq_small_lsq(const double *a_in, int rows, int cols, const double *y_in, double *z)
{
    double a[DM_LSQ_MAX * DM_LSQ_MAX], y[DM_LSQ_MAX], beta[DM_LSQ_MAX], rd[DM_LSQ_MAX];
    memcpy(a, a_in, sizeof(double) * (size_t)rows * cols);
    memcpy(y, y_in, sizeof(double) * (size_t)rows);
    dm_lsq_qr(a, rows, cols, beta, rd);
    dm_lsq_qr_apply(a, rows, cols, beta, y);
    double big = 0.0;
    for (int k = 0; k < cols; ++k) big = fmax(big, fabs(rd[k]));
    for (int k = cols - 1; k >= 0; --k) {
        if (!(fabs(rd[k]) > 1e-14 * big)) {
            z[k] = 0.0;
            continue;
        }
        double s = y[k];
        for (int j = k + 1; j < cols; ++j) s -= a[(size_t)j * rows + k] * z[j];
        z[k] = s / rd[k];
    }
}

/* Lawson–Hanson NNLS: min ‖R w − c‖, w ≥ 0, for the n × n upper-triangular R (column-major,
 * full storage, zeros below) left by the QR of the full problem. */
void dm_lsq_nnls(const double *rm, int n, const double *c, double *w)
{
    int in_p[DM_LSQ_MAX] = {0};
    for (int k = 0; k < n; ++k) w[k] = 0.0;
    double gmax0 = 0.0;
    for (int k = 0; k < n; ++k) {
        double gk = 0.0;
        for (int i = 0; i < n; ++i) gk += rm[(size_t)k * n + i] * c[i];
        gmax0 = fmax(gmax0, fabs(gk));
    }
    double tol = 1e-13 * gmax0;
    for (int outer = 0; outer < 3 * n; ++outer) {
        double res[DM_LSQ_MAX];
        for (int i = 0; i < n; ++i) {
            res[i] = c[i];
            for (int k = 0; k < n; ++k) res[i] -= rm[(size_t)k * n + i] * w[k];
        }
        int j = -1;
        double best = tol;
        for (int k = 0; k < n; ++k) {
            if (in_p[k]) continue;
            double gk = 0.0;
            for (int i = 0; i < n; ++i) gk += rm[(size_t)k * n + i] * res[i];
            if (gk > best) best = gk, j = k;
        }
        if (j < 0) break;
        in_p[j] = 1;
        int first = 1;
        for (int inner = 0; inner < 3 * n; ++inner) {
            double sub[DM_LSQ_MAX * DM_LSQ_MAX], z[DM_LSQ_MAX], zp[DM_LSQ_MAX];
            int idx[DM_LSQ_MAX], p = 0;
            for (int k = 0; k < n; ++k)
                if (in_p[k]) {
                    memcpy(sub + (size_t)p * n, rm + (size_t)k * n, sizeof(double) * (size_t)n);
                    idx[p++] = k;
                }
            dm_lsq_small_lsq(sub, n, p, c, zp);
            for (int k = 0; k < n; ++k) z[k] = 0.0;
            for (int t = 0; t < p; ++t) z[idx[t]] = zp[t];
            if (first && !(z[j] > 0.0)) { /* rounding: the new column does not help */
                in_p[j] = 0;
                return;
            }
            first = 0;
            int feasible = 1;
            for (int t = 0; t < p; ++t) feasible &= z[idx[t]] > 0.0;
            if (feasible) {
                memcpy(w, z, sizeof(double) * (size_t)n);
                break;
            }
            double alpha = 1.0;
            for (int t = 0; t < p; ++t) {
                int k = idx[t];
                if (z[k] <= 0.0) alpha = fmin(alpha, w[k] / (w[k] - z[k]));
            }
            for (int t = 0; t < p; ++t) {
                int k = idx[t];
                w[k] += alpha * (z[k] - w[k]);
                if (w[k] <= 1e-300 || (z[k] <= 0.0 && w[k] <= DBL_EPSILON * fabs(z[k]))) {
                    w[k] = 0.0;
                    in_p[k] = 0;
                }
            }
        }
    }
}

void dm_lsq_nnls_shared(const double *a, int rows, int cols, const double *y, int rhs_count, double *scratch,
                        double *w)
{
    double beta[DM_LSQ_MAX], rd[DM_LSQ_MAX], rm[DM_LSQ_MAX * DM_LSQ_MAX];
    double *qr = scratch, *yj = scratch + (size_t)rows * cols;
    memcpy(qr, a, sizeof(double) * (size_t)rows * cols);
    dm_lsq_qr(qr, rows, cols, beta, rd);
    for (int k = 0; k < cols; ++k)
        for (int i = 0; i < cols; ++i) rm[(size_t)k * cols + i] = i < k ? qr[(size_t)k * rows + i] : i == k ? rd[k] : 0.0;
    for (int j = 0; j < rhs_count; ++j) {
        memcpy(yj, y + (size_t)j * rows, sizeof(double) * (size_t)rows);
        dm_lsq_qr_apply(qr, rows, cols, beta, yj);
        dm_lsq_nnls(rm, cols, yj, w + (size_t)j * cols);
    }
}

/* Cholesky solve of the SPD n × n system m x = y (row-major); 0 when not positive definite. */
int dm_lsq_cholesky_solve(const double *m_in, int n, const double *y, double *x)
{
    double l[DM_LSQ_MAX * DM_LSQ_MAX] = {0};
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j <= i; ++j) {
            double s = m_in[i * n + j];
            for (int k = 0; k < j; ++k) s -= l[i * n + k] * l[j * n + k];
            if (i == j) {
                if (!(s > 0.0)) return 0;
                l[i * n + i] = sqrt(s);
            } else {
                l[i * n + j] = s / l[j * n + j];
            }
        }
    }
    double t[DM_LSQ_MAX];
    for (int i = 0; i < n; ++i) {
        double s = y[i];
        for (int k = 0; k < i; ++k) s -= l[i * n + k] * t[k];
        t[i] = s / l[i * n + i];
    }
    for (int i = n - 1; i >= 0; --i) {
        double s = t[i];
        for (int k = i + 1; k < n; ++k) s -= l[k * n + i] * x[k];
        x[i] = s / l[i * n + i];
    }
    return 1;
}

