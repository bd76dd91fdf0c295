/* dm_skin_profile.c — the physical skin's Gaussian profile, fitted in the frequency domain
 * (dm_skin_profile.h). */
#include "bake/dm_skin_profile.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_lsq.h"
#include "bake/dm_skin_ad.h"
#include "bake/dm_skin_freq.h"
#include "bake/dm_skin_layers.h"
#include "bake/dm_skin_rgb.h"
#include "core/dm_diffusion.h"

const double DM_SKIN_GEMS3_VARIANCES_MM2[6] = {0.0064, 0.0484, 0.187, 0.567, 1.99, 7.41};

enum { M = DM_SKIN_FREQ_NODES, L = DM_SKIN_LAMBDA_COUNT, ND = DM_SKIN_DENSE_GAUSSIANS };
#define S_LO_PER_MM DM_SKIN_FREQ_S_LO_PER_MM
#define S_HI_PER_MM DM_SKIN_FREQ_S_HI_PER_MM
#define DENSE_SIGMA_LO_MM 0.004
#define DENSE_SIGMA_HI_MM 16.0

/* ‖a w − y‖² / ‖y‖² for one right-hand side (0 when y is 0). */
static double relative_residual(const double *a, int n, const double *w, const double *y)
{
    double e = 0.0, norm = 0.0;
    for (int i = 0; i < M; ++i) {
        double d = -y[i];
        for (int k = 0; k < n; ++k) d += a[(size_t)k * M + i] * w[k];
        e += d * d;
        norm += y[i] * y[i];
    }
    return norm > 0.0 ? e / norm : 0.0;
}

static dm_result check_options(const dm_skin_profile_options *opt, int *n, const double **v, int *pairs,
                               int *streams, dm_error *err)
{
    *n = 6, *v = DM_SKIN_GEMS3_VARIANCES_MM2, *pairs = 0, *streams = 0;
    if (!opt) return DM_OK;
    *pairs = opt->pair_count, *streams = opt->stream_count;
    if (opt->pair_count < 0 || opt->pair_count > DM_MULTIPOLE_PAIRS_MAX)
        return dm_fail(err, DM_ERR_RANGE, "skin profile: pair_count = %d, expected 0 (default) or 1..%d",
                       opt->pair_count, DM_MULTIPOLE_PAIRS_MAX);
    if (opt->stream_count < 0 || opt->stream_count > DM_SKIN_AD_STREAMS_MAX || opt->stream_count % 2)
        return dm_fail(err, DM_ERR_RANGE, "skin profile: stream_count = %d, expected 0 (default, %d) or even 2..%d",
                       opt->stream_count, DM_SKIN_AD_STREAMS_DEFAULT, DM_SKIN_AD_STREAMS_MAX);
    if (opt->gaussian_count == 0) return DM_OK;
    if (opt->gaussian_count < 1 || opt->gaussian_count > DM_PROFILE_MAX_GAUSSIANS)
        return dm_fail(err, DM_ERR_RANGE, "skin profile: gaussian_count = %d, expected 0 (GPU Gems 3's six) or 1..%d",
                       opt->gaussian_count, DM_PROFILE_MAX_GAUSSIANS);
    for (int k = 0; k < opt->gaussian_count; ++k) {
        double x = opt->variance_mm2[k];
        if (!(isfinite(x) && x > 0.0 && x <= DM_PROFILE_VARIANCE_MAX_MM2) || (k && !(x > opt->variance_mm2[k - 1])))
            return dm_fail(err, DM_ERR_RANGE,
                           "skin profile: variance_mm2[%d] = %g, expected finite, in (0, %g] and above the one before",
                           k, x, DM_PROFILE_VARIANCE_MAX_MM2);
    }
    *n = opt->gaussian_count, *v = opt->variance_mm2;
    return DM_OK;
}

/* What the report says besides the fit: totals, RMS radii, the fallback wavelengths; the
 * transform normalised by scale (dm_skin_freq_totals), as the fit's targets are. */
static void physics_report(const dm_skin_params *p, int pairs, const double *scale, const double (*w)[3],
                           dm_skin_report *rep)
{
    double f[3] = {0, 0, 0}, d[3] = {0, 0, 0};
    rep->epidermis_invalid_count = rep->dermis_invalid_count = 0;
    for (int l = 0; l < L; ++l) {
        dm_skin_dual r;
        dm_skin_reflectance_at(p, l, pairs, 0.0, &r, &rep->invalid[l]);
        rep->diffusion_total_spectral[l] = r.v;
        r.v *= scale[l], r.d *= scale[l];
        rep->total_spectral[l] = r.v;
        rep->epidermis_invalid_count += (rep->invalid[l] & DM_SKIN_INVALID_EPIDERMIS) != 0;
        rep->dermis_invalid_count += (rep->invalid[l] & DM_SKIN_INVALID_DERMIS) != 0;
        for (int c = 0; c < 3; ++c) f[c] += w[l][c] * r.v, d[c] += w[l][c] * r.d;
    }
    for (int c = 0; c < 3; ++c) {
        rep->total_rgb[c] = f[c];
        double m2 = -4.0 * d[c]; /* ∫ r² R 2πr dr */
        rep->rms_radius_mm[c] = f[c] > 0.0 && m2 > 0.0 ? sqrt(m2 / f[c]) : 0.0;
    }
}

dm_result dm_skin_physics_report(const dm_skin_params *p, int pair_count, dm_skin_report *rep, dm_error *err)
{
    dm_result res = dm_skin_params_validate(p, "skin", err);
    if (res != DM_OK) return res;
    if (pair_count < 0 || pair_count > DM_MULTIPOLE_PAIRS_MAX)
        return dm_fail(err, DM_ERR_RANGE, "skin: pair_count = %d, expected 0 (default) or 1..%d", pair_count,
                       DM_MULTIPOLE_PAIRS_MAX);
    double w[L][3], scale[L];
    dm_skin_rgb_weights(w);
    dm_skin_freq_totals(p, pair_count, 0, NULL, scale); /* the default fit's: adding-doubling's totals */
    memset(rep, 0, sizeof *rep);
    physics_report(p, pair_count, scale, (const double (*)[3])w, rep);
    return DM_OK;
}

dm_result dm_skin_profile_fit(const dm_skin_params *p, const dm_skin_profile_options *opt, const char *name,
                              dm_profile *out, dm_skin_report *rep, dm_error *err)
{
    dm_result res = dm_skin_params_validate(p, "skin profile", err);
    int n, pairs, streams;
    const double *variance;
    if (res != DM_OK || (res = check_options(opt, &n, &variance, &pairs, &streams, err)) != DM_OK) return res;
    /* s, √q, the design (M × n), lsq scratch (M × (n + 1)), channel targets (M × 3) */
    double *buf = malloc(sizeof(double) * (size_t)M * (2 + 2 * n + 1 + 3));
    if (!buf) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "skin profile");
    double *s = buf, *sq = s + M, *a = sq + M, *scratch = a + (size_t)M * n, *yc = scratch + (size_t)M * (n + 1);
    double w[L][3], wk[3 * DM_PROFILE_MAX_GAUSSIANS], scale[L]; /* channel c's weights at wk + c·n */
    dm_skin_rgb_weights(w);
    dm_skin_freq_totals(p, pairs, streams, NULL, scale);
    dm_skin_freq_nodes(S_LO_PER_MM, S_HI_PER_MM, M, s, sq);
    dm_skin_freq_design(s, sq, M, variance, n, a);
    dm_skin_freq_channels(p, pairs, scale, s, sq, M, (const double(*)[3])w, yc);
    dm_lsq_nnls_shared(a, M, n, yc, 3, scratch, wk);
    memset(out, 0, sizeof *out);
    snprintf(out->name, sizeof out->name, "%s", name ? name : "");
    out->count = n;
    dm_skin_report local;
    dm_skin_report *r = rep ? rep : &local;
    memset(r, 0, sizeof *r);
    for (int k = 0; k < n; ++k) {
        out->variance_mm2[k] = variance[k];
        for (int c = 0; c < 3; ++c) out->weight[k][c] = wk[c * n + k], r->fit_total_rgb[c] += wk[c * n + k];
    }
    for (int c = 0; c < 3; ++c) {
        r->fit_error_relative[c] = sqrt(relative_residual(a, n, wk + c * n, yc + (size_t)c * M));
        r->fit_error_relative_max = fmax(r->fit_error_relative_max, r->fit_error_relative[c]);
    }
    physics_report(p, pairs, scale, (const double(*)[3])w, r);
    free(buf);
    return DM_OK;
}

dm_result dm_skin_dense_profile(const dm_skin_params *p, int pair_count, dm_skin_dense *out, dm_error *err)
{
    dm_result res = dm_skin_params_validate(p, "skin dense profile", err);
    if (res != DM_OK) return res;
    if (pair_count < 0 || pair_count > DM_MULTIPOLE_PAIRS_MAX)
        return dm_fail(err, DM_ERR_RANGE, "skin dense profile: pair_count = %d, expected 0 (default) or 1..%d",
                       pair_count, DM_MULTIPOLE_PAIRS_MAX);
    double *buf = malloc(sizeof(double) * ((size_t)M * (2 + 2 * ND + 1 + L) + (size_t)ND * L));
    if (!buf) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "skin dense profile");
    double *s = buf, *sq = s + M, *a = sq + M, *scratch = a + (size_t)M * ND, *y = scratch + (size_t)M * (ND + 1);
    double *wl = y + (size_t)M * L, w[L][3], scale[L];
    for (int k = 0; k < ND; ++k) {
        double sigma = DENSE_SIGMA_LO_MM * pow(DENSE_SIGMA_HI_MM / DENSE_SIGMA_LO_MM, (double)k / (ND - 1));
        out->variance_mm2[k] = sigma * sigma;
    }
    dm_skin_rgb_weights(w);
    dm_skin_freq_nodes(S_LO_PER_MM, S_HI_PER_MM, M, s, sq);
    dm_skin_freq_design(s, sq, M, out->variance_mm2, ND, a);
    dm_skin_freq_totals(p, pair_count, 0, NULL, scale);
    dm_skin_freq_spectral(p, pair_count, scale, s, sq, M, y);
    dm_lsq_nnls_shared(a, M, ND, y, L, scratch, wl);
    out->error_relative_max = 0.0;
    memset(out->weight, 0, sizeof out->weight);
    for (int l = 0; l < L; ++l) {
        out->error_relative_max = fmax(out->error_relative_max,
                                       sqrt(relative_residual(a, ND, wl + (size_t)l * ND, y + (size_t)l * M)));
        for (int k = 0; k < ND; ++k)
            for (int c = 0; c < 3; ++c) out->weight[k][c] += w[l][c] * wl[(size_t)l * ND + k];
    }
    free(buf);
    return DM_OK;
}

void dm_skin_dense_eval(const dm_skin_dense *d, double r_mm, double rgb[3])
{
    rgb[0] = rgb[1] = rgb[2] = 0.0;
    for (int k = 0; k < ND; ++k) {
        double g = dm_gaussian(d->variance_mm2[k], r_mm);
        for (int c = 0; c < 3; ++c) rgb[c] += d->weight[k][c] * g;
    }
}

void dm_skin_dense_total(const dm_skin_dense *d, double rgb[3])
{
    rgb[0] = rgb[1] = rgb[2] = 0.0;
    for (int k = 0; k < ND; ++k)
        for (int c = 0; c < 3; ++c) rgb[c] += d->weight[k][c];
}
