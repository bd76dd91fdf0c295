/* bench/common/atlas_regions.h — the region label (dm_ref_regions.h) and skin area of each
 * texel of an N×N texture-space reference, at the reference's own surface point for it;
 * shared by bench/accuracy and bench/ref_convergence. Header-only like bench_util.h. */
#ifndef BENCH_ATLAS_REGIONS_H
#define BENCH_ATLAS_REGIONS_H

#include <stdio.h>
#include <stdlib.h>

#include "reference/dm_ref_regions.h"
#include "reference/dm_reference.h"

/* *label and *area (malloc'd, N² each: the label, the texel's skin area in mm², 0 where no
 * triangle covers it); count[] and area_mm2[] (DM_REF_REGION_COUNT each) add up the texels
 * and areas of each region. 1 on success, 0 with a message. */
static inline int atlas_regions(const dm_ref_regions *rg, const dm_mesh *m, int N, float *rgba, uint8_t **label,
                                float **area, long *count, double *area_mm2)
{
    dm_reference_atlas ra = {N, N, rgba};
    dm_reference_target *tg = NULL;
    int64_t *texel_of = NULL;
    size_t n_targets = 0, n = (size_t)N * N;
    dm_error err = {0};
    if (dm_reference_atlas_targets(m, &ra, 0, &tg, &texel_of, &n_targets, &err) != DM_OK) {
        fprintf(stderr, "error: regions at %d: %s\n", N, err.detail);
        return 0;
    }
    *label = calloc(n, 1), *area = calloc(n, sizeof **area);
    if (!*label || !*area) return free(tg), free(texel_of), 0;
    dm_ref_regions_atlas(rg, N, N, tg, texel_of, n_targets, *label, *area);
    for (size_t i = 0; i < n_targets; ++i)
        ++count[(*label)[texel_of[i]]], area_mm2[(*label)[texel_of[i]]] += (*area)[texel_of[i]];
    free(tg), free(texel_of);
    return 1;
}

#endif
