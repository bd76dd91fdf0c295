/* dm_lsq.h — small dense least squares shared by the profile fits (dm_profile_fit.c):
 * Householder QR, least squares, Lawson–Hanson NNLS, Cholesky. Matrices are column-major
 * doubles (Cholesky: row-major); every size is at most DM_LSQ_MAX columns (scratch lives on the stack). Internal
 * to lib/bake: deterministic, no allocation, no threads. */
#ifndef DM_LSQ_H
#define DM_LSQ_H

enum { DM_LSQ_MAX = 32 };

/* Householder QR in place of a (rows × cols, rows ≥ cols). The reflector of column k is
 * stored in a[k][k..rows) with its scale in beta[k]; R's diagonal in rdiag, R's upper part
 * above the diagonal of a. */
void dm_lsq_qr(double *a, int rows, int cols, double *beta, double *rdiag);
/* y ← Qᵀ y, and y ← Q y, with the reflectors of dm_lsq_qr. */
void dm_lsq_qr_apply(const double *a, int rows, int cols, const double *beta, double *y);
void dm_lsq_qr_apply_q(const double *a, int rows, int cols, const double *beta, double *y);
/* min ‖A z − y‖ for A of rows × cols ≤ DM_LSQ_MAX × DM_LSQ_MAX; columns whose R diagonal
 * vanishes get z = 0. */
void dm_lsq_small_lsq(const double *a_in, int rows, int cols, const double *y_in, double *z);
/* Lawson–Hanson NNLS: min ‖R w − c‖, w ≥ 0, for the n × n upper-triangular R (full storage,
 * zeros below) left by the QR of the full problem; n ≤ DM_LSQ_MAX. */
void dm_lsq_nnls(const double *rm, int n, const double *c, double *w);
/* min ‖A w_j − y_j‖, w_j ≥ 0, for rhs_count right-hand sides that share A (rows × cols,
 * column-major, rows ≥ cols, cols ≤ DM_LSQ_MAX): one QR of A, then dm_lsq_nnls per
 * right-hand side. y_j is column j of y (rows × rhs_count, column-major, unchanged); w_j is
 * written to w + j·cols. scratch holds rows·(cols + 1) doubles (the caller's). */
void dm_lsq_nnls_shared(const double *a, int rows, int cols, const double *y, int rhs_count, double *scratch,
                        double *w);
/* Solves the symmetric positive definite n × n system m x = y; 0 when it is not SPD. */
int dm_lsq_cholesky_solve(const double *m_in, int n, const double *y, double *x);

#endif
