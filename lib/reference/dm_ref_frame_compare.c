#include "reference/dm_ref_frame_compare.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>

#include "reference/dm_ref_frame.h"

void dm_ref_frame_interior(const float *ref, const float *render, int width, int height, float *weight_out)
{
    assert(ref && render && weight_out);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            bool in = x > 0 && y > 0 && x < width - 1 && y < height - 1;
            for (int k = 0; in && k < 5; ++k) {
                size_t i = (size_t)(y + (k == 1) - (k == 2)) * (size_t)width + (size_t)(x + (k == 3) - (k == 4));
                in = ref[4 * i + 3] >= 0.5f && render[4 * i + 3] >= 0.5f;
            }
            weight_out[(size_t)y * (size_t)width + (size_t)x] = in ? 1.0f : 0.0f;
        }
}

dm_result dm_ref_frame_labels(const dm_ref_surface *s, const dm_ref_regions *rg, int width, int height,
                              int thread_count, uint8_t *label_out, dm_error *err)
{
    assert(s && rg && label_out);
    size_t n = (size_t)width * (size_t)height;
    dm_reference_target *hit = malloc((n ? n : 1) * sizeof *hit);
    if (!hit) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "frame labels: cannot allocate %zu hits", n);
    dm_result r = dm_ref_frame_hits(s, width, height, thread_count, hit, err);
    for (size_t i = 0; r == DM_OK && i < n; ++i)
        label_out[i] = hit[i].triangle < 0 ? DM_REF_LABEL_BACKGROUND
                                           : (uint8_t)dm_ref_regions_classify(rg, hit[i].triangle, hit[i].b1, hit[i].b2);
    free(hit);
    return r;
}

static bool selected(const float *weight, const uint8_t *label, int region, size_t i)
{
    return !(weight && !(weight[i] > 0)) && !(label && region >= 0 && label[i] != region);
}

dm_result dm_ref_transport_compute(const float *ref, const float *flat, const float *render, const float *weight,
                                   const uint8_t *label, int region, size_t n, double threshold,
                                   dm_ref_transport_stats *st, dm_error *err)
{
    assert(ref && flat && render && st);
    if (threshold == 0) threshold = DM_REF_TRANSPORT_THRESHOLD;
    if (!(threshold > 0 && threshold < 1))
        return dm_fail(err, DM_ERR_RANGE, "transport statistics: threshold %g, expected (0, 1)", threshold);
    *st = (dm_ref_transport_stats){.signal = {0}};
    long any = 0;
    double num_all = 0, den_all = 0;
    for (int c = 0; c < 3; ++c) {
        double rel = 0, num = 0, den = 0, floor = 0;
        long count = 0;
        for (size_t i = 0; i < n; ++i)
            if (selected(weight, label, region, i) && isfinite(ref[4 * i + (size_t)c])) floor += ref[4 * i + (size_t)c], ++count;
        floor = count ? DM_REF_ERROR_FLOOR * floor / count : 0.0;
        count = 0;
        for (size_t i = 0; i < n; ++i) {
            if (!selected(weight, label, region, i)) continue;
            double R = ref[4 * i + (size_t)c], F = flat[4 * i + (size_t)c], X = render[4 * i + (size_t)c];
            double Rf = fmax(R, floor);
            if (!(R > 0) || !(fabs(R - F) > threshold * Rf) || !isfinite(X) || !isfinite(F)) continue;
            rel += fabs(X - R) / Rf;
            num += fabs(X - R), den += fabs(F - R);
            ++count;
        }
        st->signal[c] = count;
        st->mean[c] = count ? rel / count : 0.0;
        st->normalised[c] = den > 0 ? num / den : 0.0;
        num_all += num, den_all += den;
        any += count;
    }
    st->normalised_rgb = den_all > 0 ? num_all / den_all : 0.0;
    if (!any) return dm_fail(err, DM_ERR_EMPTY, "transport statistics: no pixel where subsurface changes the frame");
    return DM_OK;
}
