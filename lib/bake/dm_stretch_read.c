#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/dm_exr.h"
#include "bake/dm_stretch.h"

static float *copy_plane(const float *src, size_t n)
{
    float *p = malloc(n * sizeof *p);
    if (p) memcpy(p, src, n * sizeof *p);
    return p;
}

dm_result dm_stretch_read(const char *path, dm_stretch_map *out, dm_provenance *prov, dm_error *err)
{
    memset(out, 0, sizeof *out);
    dm_exr_image img;
    dm_result r = dm_exr_read(path, &img, err);
    if (r != DM_OK) return r;
    if (!img.has_provenance) {
        dm_exr_free(&img);
        return dm_fail(err, DM_ERR_FORMAT, "%s: no dermis provenance, expected a dermis-bake-stretch EXR", path);
    }
    *prov = img.prov;
    size_t n = (size_t)img.width * img.height;
    out->width = img.width;
    out->height = img.height;
    const float *mask = dm_exr_find(&img, "mask");
    for (int k = 0; k < DM_PROFILE_MAX_GAUSSIANS && r == DM_OK; ++k) {
        char u[32], v[32], var[32];
        snprintf(u, sizeof u, "stretch%d.u", k);
        snprintf(v, sizeof v, "stretch%d.v", k);
        const float *pu = dm_exr_find(&img, u), *pv = dm_exr_find(&img, v);
        if (!pu && !pv) break;
        snprintf(var, sizeof var, "variance_mm2_%d", k);
        const dm_param *vp = dm_prov_find(prov, var);
        if (!pu || !pv || !vp || vp->type == DM_PARAM_STRING) {
            r = dm_fail(err, DM_ERR_FORMAT, "%s: level %d lacks %s, %s or its provenance %s", path, k, u, v, var);
            break;
        }
        out->s_u[k] = copy_plane(pu, n);
        out->s_v[k] = copy_plane(pv, n);
        out->variance_mm2[k] = vp->d;
        out->level_count = k + 1;
        if (!out->s_u[k] || !out->s_v[k]) r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    if (r == DM_OK && (out->level_count == 0 || !mask))
        r = dm_fail(err, DM_ERR_FORMAT, "%s: expected channels stretch0.u, stretch0.v, ... and mask", path);
    if (r == DM_OK && !(out->mask = copy_plane(mask, n))) r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    const dm_param *cov = dm_prov_find(prov, "coverage");
    if (cov && cov->type != DM_PARAM_STRING) out->stats.coverage = cov->d;
    dm_exr_free(&img);
    if (r != DM_OK) dm_stretch_map_free(out);
    return r;
}
