/* dm_render_compare.h — how far a renderer's last frame is from a reference renderer's
 * (the exact path: dm_render_desc{.shadow_pcf_taps = 9}, everything else default), so
 * that every speed setting can report its error beside its time (DESIGN.md promise 1).
 * Used by dermis-render --compare-exact and by the render bench. */
#ifndef DM_RENDER_COMPARE_H
#define DM_RENDER_COMPARE_H

#include "render/dm_render.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_render_difference {
    double out_max, out_mean, out_peak; /* linear radiance before tonemapping, over RGB of every
                                         * pixel: max and mean |Δ|, and the reference's peak */
    int display_steps;                  /* largest 8-bit difference of the displayed picture */
    double level_max, level_mean, level_peak; /* the named texture-space level, coverage-
                                               * normalised (rgb / alpha) where the reference
                                               * has coverage; a reduced-resolution level is
                                               * sampled bilinearly at the reference's texels */
} dm_render_difference;

/* Compares the last frames of ref and r, which must have the same output size. level
 * names a texture-space target ("blur5", "irradiance") or is NULL. */
dm_result dm_render_compare(dm_renderer *ref, dm_renderer *r, const char *level, dm_render_difference *out,
                            dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
