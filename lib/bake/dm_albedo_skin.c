/* dm_albedo_skin.c — the diffuse colour from the physical skin model (bake/dm_albedo_skin.h). */
#include "bake/dm_albedo_skin.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "core/dm_srgb.h"
#include "mesh/dm_uv_raster.h"

dm_result dm_albedo_skin_weights(const dm_mesh *m, double mm_per_unit, int width, int height, int thread_count,
                                 float *weight, double *skin_area_mm2, dm_error *err)
{
    const size_t texels = (size_t)width * (size_t)height;
    int32_t *tri = malloc(texels * sizeof *tri);
    double *mm2_per_texel = malloc((size_t)m->triangle_count * sizeof *mm2_per_texel + 1);
    if (!tri || !mm2_per_texel) {
        free(tri);
        free(mm2_per_texel);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "albedo weights %dx%d: out of memory", width, height);
    }
    dm_result r = dm_uv_raster(m, NULL, width, height, thread_count, tri, NULL, err);
    /* a triangle's mm² over the texels its UV image spans (zero UV area covers none) */
    for (int32_t t = 0; r == DM_OK && t < m->triangle_count; ++t) {
        double uv_texels = fabs(dm_mesh_triangle_uv_area(m, t)) * width * height;
        mm2_per_texel[t] = uv_texels > 0 ? dm_mesh_triangle_area(m, t) * mm_per_unit * mm_per_unit / uv_texels : 0.0;
    }
    double sum = 0.0;
    for (size_t i = 0; r == DM_OK && i < texels; ++i) {
        weight[i] = tri[i] >= 0 ? (float)mm2_per_texel[tri[i]] : 0.0f;
        sum += weight[i];
    }
    if (skin_area_mm2) *skin_area_mm2 = sum;
    free(tri);
    free(mm2_per_texel);
    return r;
}

static double luminance(const double c[3])
{
    return DM_ALBEDO_SKIN_LUMA_R * c[0] + DM_ALBEDO_SKIN_LUMA_G * c[1] + DM_ALBEDO_SKIN_LUMA_B * c[2];
}

dm_result dm_albedo_skin_apply(const uint8_t *rgba, int width, int height, const float *weight,
                               const double total_rgb[3], const char *what, uint8_t *out, dm_albedo_skin_stats *stats,
                               dm_error *err)
{
    double linear[256];
    for (int v = 0; v < 256; ++v) linear[v] = dm_srgb_to_linear(v / 255.0);
    const size_t texels = (size_t)width * (size_t)height;
    dm_albedo_skin_stats st = {0};
    double w_sum = 0.0, wy_sum = 0.0;
    for (size_t i = 0; i < texels; ++i) {
        if (!(weight[i] > 0.0f)) continue;
        const uint8_t *p = rgba + 4 * i;
        double c[3] = {linear[p[0]], linear[p[1]], linear[p[2]]};
        w_sum += weight[i];
        wy_sum += weight[i] * luminance(c);
        ++st.covered_texels;
    }
    if (st.covered_texels == 0)
        return dm_fail(err, DM_ERR_EMPTY, "%s: the mesh's UV charts cover none of its %dx%d texels, expected some skin",
                       what, width, height);
    if (!(wy_sum > 0.0))
        return dm_fail(err, DM_ERR_EMPTY,
                       "%s: black over all %lld texels of skin (mean luminance 0), expected some luminance detail",
                       what, (long long)st.covered_texels);
    st.mean_luminance = wy_sum / w_sum;
    double t[3], out_sum[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) t[k] = total_rgb[k] > 0.0 ? total_rgb[k] : 0.0;
    for (size_t i = 0; i < texels; ++i) {
        const uint8_t *p = rgba + 4 * i;
        double c[3] = {linear[p[0]], linear[p[1]], linear[p[2]]};
        const double detail = luminance(c) / st.mean_luminance;
        const uint8_t alpha = p[3];
        bool clipped = false;
        for (int k = 0; k < 3; ++k) {
            const double v = t[k] * detail;
            clipped = clipped || v > 1.0;
            out[4 * i + k] = dm_srgb8_from_linear(v);
            out_sum[k] += weight[i] * linear[out[4 * i + k]];
        }
        out[4 * i + 3] = alpha;
        st.clipped_texels += clipped && weight[i] > 0.0f;
    }
    for (int k = 0; k < 3; ++k) st.mean_rgb[k] = out_sum[k] / w_sum;
    if (stats) *stats = st;
    return DM_OK;
}
