/* dm_skin_weights.c — the live weights for fixed variances (dm_skin_weights.h). */
#include "bake/dm_skin_weights.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bake/dm_lsq.h"
#include "bake/dm_skin_ad.h"
#include "bake/dm_skin_freq.h"
#include "bake/dm_skin_rgb.h"
#include "core/dm_diffusion.h"

enum { NMAX = DM_SKIN_WEIGHTS_NODES_MAX, GMAX = DM_PROFILE_MAX_GAUSSIANS };

dm_result dm_skin_weights_plan_init(dm_skin_weights_plan *plan, const double *variance_mm2, int gaussian_count,
                                    const dm_skin_weights_options *opt, dm_error *err)
{
    dm_skin_weights_options o = opt ? *opt : (dm_skin_weights_options){0};
    if (o.node_count == 0) o.node_count = DM_SKIN_WEIGHTS_NODES_DEFAULT;
    if (o.node_count < 3 || o.node_count > NMAX || o.node_count % 2 == 0)
        return dm_fail(err, DM_ERR_RANGE, "skin weights: node_count = %d, expected 0 (%d) or odd 3..%d", o.node_count,
                       DM_SKIN_WEIGHTS_NODES_DEFAULT, NMAX);
    if (o.pair_count == 0) o.pair_count = DM_SKIN_WEIGHTS_PAIRS_DEFAULT;
    if (o.pair_count < 0 || o.pair_count > DM_MULTIPOLE_PAIRS_MAX)
        return dm_fail(err, DM_ERR_RANGE, "skin weights: pair_count = %d, expected 0 (%d) or 1..%d", o.pair_count,
                       DM_SKIN_WEIGHTS_PAIRS_DEFAULT,
                       DM_MULTIPOLE_PAIRS_MAX);
    if (o.stream_count == 0) o.stream_count = DM_SKIN_WEIGHTS_STREAMS_DEFAULT;
    if (o.stream_count < 2 || o.stream_count > DM_SKIN_AD_STREAMS_MAX || o.stream_count % 2)
        return dm_fail(err, DM_ERR_RANGE, "skin weights: stream_count = %d, expected 0 (%d) or even 2..%d",
                       o.stream_count, DM_SKIN_WEIGHTS_STREAMS_DEFAULT, DM_SKIN_AD_STREAMS_MAX);
    /* the variances by the profile's own rule: a shape with no weight yet */
    dm_profile shape = {.count = gaussian_count};
    if (gaussian_count >= 1 && gaussian_count <= GMAX)
        memcpy(shape.variance_mm2, variance_mm2, sizeof(double) * (size_t)gaussian_count);
    dm_result rc = dm_profile_validate(&shape, "skin weights: variances", err);
    if (rc != DM_OK) return rc;
    memset(plan, 0, sizeof *plan);
    plan->gaussian_count = gaussian_count;
    memcpy(plan->variance_mm2, shape.variance_mm2, sizeof plan->variance_mm2);
    plan->node_count = o.node_count, plan->pair_count = o.pair_count, plan->stream_count = o.stream_count;
    double top = sqrt(2.0 * log(1.0 / DM_SKIN_WEIGHTS_CUT) / variance_mm2[0]);
    plan->s_hi_per_mm = fmax(fmin(top, DM_SKIN_FREQ_S_HI_PER_MM), 2.0 * DM_SKIN_FREQ_S_LO_PER_MM);
    dm_skin_freq_nodes(DM_SKIN_FREQ_S_LO_PER_MM, plan->s_hi_per_mm, plan->node_count, plan->s, plan->sq);
    dm_skin_freq_design(plan->s, plan->sq, plan->node_count, plan->variance_mm2, gaussian_count, plan->design);
    dm_skin_rgb_weights(plan->rgb);
    return DM_OK;
}

dm_result dm_skin_weights_fit(const dm_skin_weights_plan *plan, const dm_skin_params *p, const char *name,
                              dm_profile *out, dm_error *err)
{
    return dm_skin_weights_fit_colour(plan, p, name, out, NULL, err);
}

dm_result dm_skin_weights_fit_colour(const dm_skin_weights_plan *plan, const dm_skin_params *p, const char *name,
                                     dm_profile *out, double total_rgb[3], dm_error *err)
{
    dm_result rc = dm_skin_params_validate(p, "skin weights", err);
    if (rc != DM_OK) return rc;
    int m = plan->node_count, n = plan->gaussian_count;
    double yc[3 * NMAX], scratch[NMAX * (GMAX + 1)], wk[3 * GMAX], scale[DM_SKIN_LAMBDA_COUNT];
    double total[DM_SKIN_LAMBDA_COUNT];
    dm_skin_freq_totals(p, plan->pair_count, plan->stream_count, total, scale);
    for (int c = 0; total_rgb && c < 3; ++c) {
        total_rgb[c] = 0.0;
        for (int l = 0; l < DM_SKIN_LAMBDA_COUNT; ++l) total_rgb[c] += plan->rgb[l][c] * total[l];
    }
    dm_skin_freq_channels(p, plan->pair_count, scale, plan->s, plan->sq, m, (const double(*)[3])plan->rgb, yc);
    dm_lsq_nnls_shared(plan->design, m, n, yc, 3, scratch, wk);
    memset(out, 0, sizeof *out);
    snprintf(out->name, sizeof out->name, "%s", name ? name : "");
    out->count = n;
    for (int k = 0; k < n; ++k) {
        out->variance_mm2[k] = plan->variance_mm2[k];
        for (int c = 0; c < 3; ++c) out->weight[k][c] = wk[c * n + k];
    }
    return DM_OK;
}
