/* bench/common/frame_truth.h — bench/accuracy's frame comparison, taken apart (issue #27):
 * each setting's final frame at 1280x720 against the ground-truth frame in three runs —
 *   transport: white albedo, no normal map, no shadows (dermis-reference --without
 *              albedo,normal-map,shadows; the renderer with the same maps absent and shadows
 *              off): what subsurface transport alone gets right, measured where it shows
 *              (dm_ref_frame_compare.h: the signal pixels, relative and normalised by the
 *              no-subsurface frame), over the whole skin and per region;
 *   surface:   + albedo and normal map (--without shadows);
 *   full:      + shadows (the scene as it is);
 * each of the fuller runs as the mean relative error over the interior skin pixels, so a
 * row shows what the surface terms and the shadows add. A no-subsurface row (the renderer's
 * Lambert) is the floor every technique must beat. Header-only like bench_util.h; included
 * by accuracy_rows.h. */
#ifndef BENCH_FRAME_TRUTH_H
#define BENCH_FRAME_TRUTH_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reference/dm_ref_frame_compare.h"
#include "render/dm_render.h"
#include "render/dm_render_refcmp.h"

enum { FV_TRANSPORT, FV_SURFACE, FV_FULL, FV_COUNT };
/* what each run leaves out (dermis-reference --without; NULL: nothing) */
static const char *const FV_WITHOUT[FV_COUNT] = {"albedo,normal-map,shadows", "shadows", NULL};
static const char *const FV_NAME[FV_COUNT] = {"transport", "surface", "full"};
/* the transport run without subsurface: the reference of "no subsurface at all" */
static const char *const FV_FLAT = "albedo,normal-map,shadows,subsurface";

/* The other transport references a ranking's margin is also measured against (bench/accuracy.c,
 * reference()): one discretisation a step back from the bench's in each of its two large terms —
 * the rays (the scene profile's without --refine; the dipole's, never refined, at 2² instead of
 * 3²) and the atlas (half, its samples doubled: the same irradiance points; the scene profile's
 * 4096 x 2² against its 8192 x 1) — and the quadrature's step as the convergence table measures
 * it (atlas 1024 with 4² samples, one ray at the pixel centre; the default cut 4 sigma, spacing
 * 0.3 sigma, then 6 sigma, 0.15 sigma). How far the margin moves over each step bounds how far
 * it can still be from the converged truth's. */
enum { FT_COARSE_RAYS, FT_COARSE_ATLAS, FT_QUAD_BASE, FT_QUAD_FINE, FT_STEP_COUNT };

/* The ground truth of one profile for the frame: a reference per run and the flat one, and
 * the transport and flat pairs of each step; what is left of the rays' and the atlas's steps
 * at the bench's settings per unit of the step (frame_rankings.h, margin_bar), and what a
 * margin's bar adds unmeasured (fixed). */
typedef struct frame_truth {
    dm_refcmp_ref ref[FV_COUNT], flat;
    bool have[FV_COUNT];
    dm_refcmp_ref step[FT_STEP_COUNT][2]; /* transport, flat */
    bool have_step[FT_STEP_COUNT];
    double rays_left, atlas_left, fixed;
} frame_truth;

/* Per-row frame results. */
typedef struct frame_result {
    dm_ref_transport_stats tr[DM_REF_REGION_COUNT + 1]; /* per region, then all */
    bool trok[DM_REF_REGION_COUNT + 1];
    dm_ref_error_stats run[FV_COUNT]; /* mean relative error over the interior pixels */
    bool runok[FV_COUNT];
    double step[FT_STEP_COUNT]; /* the transport's normalised error (all skin, all channels) */
    bool stepok[FT_STEP_COUNT];  /* against the truth's pair of that step */
} frame_result;

/* The assets and scene of run v: the transport run drops the albedo and normal maps and
 * shadows, the surface run shadows (a copy: the caller's are unchanged). */
static void frame_variant(const dm_render_assets *a, const dm_scene *scene, int v, dm_render_assets *out_a,
                          dm_scene *out_s)
{
    *out_a = *a, *out_s = *scene;
    out_a->scene = out_s;
    if (v == FV_TRANSPORT) out_a->albedo = (dm_texture){0}, out_a->normal_map = (dm_texture){0};
    if (v != FV_FULL) out_s->effects[DM_EFFECT_SHADOWS] = false;
}

/* One frame of run v at w x h (linear, malloc'd), or NULL with a warning. */
static float *frame_render(const dm_render_assets *a, const dm_scene *scene, dm_render_desc d, int v, int w, int h,
                           const char *name)
{
    dm_render_assets va;
    dm_scene vs;
    frame_variant(a, scene, v, &va, &vs);
    d.width = w, d.height = h, d.timings = false;
    dm_renderer *r = NULL;
    dm_error err = {0};
    float *px = malloc(sizeof *px * 4 * (size_t)w * h);
    bool ok = px && dm_renderer_create(&va, &d, &r, &err) == DM_OK &&
              dm_render_frame(r, &(dm_frame_options){0}, &err) == DM_OK && dm_renderer_read_linear(r, px, &err) == DM_OK;
    dm_renderer_destroy(r);
    if (!ok) fprintf(stderr, "warning: %s: %s frame: %s\n", name, FV_NAME[v], err.detail);
    if (!ok) free(px), px = NULL;
    return px;
}

/* A row's frame results against truth t; label: per pixel (dm_ref_frame_labels). keep (may
 * be NULL) receives the full run's frame. */
static void frame_measure(const dm_render_assets *a, const dm_scene *scene, dm_render_desc d, const frame_truth *t,
                          const uint8_t *label, int w, int h, const char *name, frame_result *fr, float **keep)
{
    size_t n = (size_t)w * h;
    float *wt = malloc(sizeof *wt * n);
    dm_error err = {0};
    *fr = (frame_result){.trok = {false}};
    for (int v = 0; v < FV_COUNT && wt; ++v) {
        if (!t->have[v]) continue;
        float *px = frame_render(a, scene, d, v, w, h, name);
        if (!px) continue;
        dm_ref_frame_interior(t->ref[v].rgba, px, w, h, wt);
        fr->runok[v] = dm_ref_error_stats_compute(t->ref[v].rgba, px, wt, NULL, -1, n, &fr->run[v], &err) == DM_OK;
        for (int g = 0; v == FV_TRANSPORT && g <= DM_REF_REGION_COUNT; ++g)
            fr->trok[g] = dm_ref_transport_compute(t->ref[v].rgba, t->flat.rgba, px, wt, label,
                                                   g < DM_REF_REGION_COUNT ? g : -1, n, 0, &fr->tr[g], &err) == DM_OK;
        for (int k = 0; v == FV_TRANSPORT && k < FT_STEP_COUNT; ++k) {
            dm_ref_transport_stats s;
            fr->stepok[k] = t->have_step[k] && dm_ref_transport_compute(t->step[k][0].rgba, t->step[k][1].rgba, px, wt, NULL,
                                                                         -1, n, 0, &s, &err) == DM_OK;
            fr->step[k] = fr->stepok[k] ? s.normalised_rgb : 0;
        }
        if (v == FV_FULL && keep) *keep = px;
        else free(px);
    }
    free(wt);
}

/* The transport run's one number: normalised over the three channels' sums. */
static double frame_norm3(const dm_ref_transport_stats *s)
{
    return s->normalised_rgb;
}

#endif
