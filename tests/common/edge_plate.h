/* edge_plate.h — the screen-space technique at an albedo edge (issue #29): a flat plate with an
 * albedo step under uniform light, rendered, against the edge the diffusion profile gives,
 * computed here in double precision from the profile's Gaussians. For
 * tests/render/test_render_ss_edge.c and bench/accuracy.c (header-only, no test framework).
 *
 * What a straight edge sees of a radial profile R(r) = Σ_j w_j G₂(v_j, r) is its marginal along
 * the edge (the line-spread function): a 2-D Gaussian of variance v integrates along y to the
 * 1-D Gaussian of variance v, so the line-spread is Σ_j w_j G₁(v_j, x) and the edge-spread, per
 * channel with the weights normalised, ESF(x) = Σ_j ŵ_j ½(1 + erf(x/√(2 v_j))).
 *
 * The renderer's texturing (final.glsl with DM_SCREEN_SPACE, ss_blur.glsl): the blurred term is
 * E·A^mix, the blur's result is multiplied by A^(1−mix) at the pixel (the scene's mix, 0.5 by
 * default: the sqrt split). Under uniform irradiance E and an albedo step A = a₀ (x < 0), a₁
 * (x > 0) the exact response is therefore
 *     out(x) = E · A(x)^(1−mix) · (a₀^mix + (a₁^mix − a₀^mix) · ESF(x)),
 * compared at each pixel centre of the middle row; the error is |out − reference| over the step
 * E·|a₁ − a₀|. The light is the synthetic scene's one directional light on a plate square on to
 * the camera (E the same everywhere), with no shadows, specular, environment, energy term, glow
 * or tonemap; E per channel is read from the leftmost pixel, over 11 mm from the edge, beyond
 * the kernel's 8.2 mm reach (so there out = E·a₀ exactly). The albedo the G-buffer holds is
 * checked first to be the sharp step the reference assumes.
 *
 * The plate: the synthetic quad, EDGE_PLATE_W + 16 pixels wide, its albedo one row of as many
 * texels, the camera on +z at the distance that gives mm_per_px (fov and mm_per_unit the
 * scene's): a plane square on to the camera projects affinely, so every pixel centre sits on a
 * texel centre and every pixel's albedo is a₀ or a₁, the step between columns W/2 − 1 and W/2. */
#ifndef TEST_EDGE_PLATE_H
#define TEST_EDGE_PLATE_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "render/dm_render.h"
#include "render/dm_render_synth.h"

enum { EDGE_PLATE_W = 224, EDGE_PLATE_H = 32 };

/* the step: a dark mole on skin (sRGB) */
static const uint8_t edge_plate_lo[3] = {96, 56, 40}, edge_plate_hi[3] = {224, 172, 150};

static inline double edge_plate_srgb(int v)
{
    double c = v / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* The profile's edge-spread function in channel c at x mm (weights normalised per channel). */
static inline double edge_plate_esf(const dm_profile *p, int c, double x)
{
    double sum = 0, wsum = 0;
    for (int j = 0; j < p->count; ++j) {
        sum += p->weight[j][c] * 0.5 * (1.0 + erf(x / sqrt(2.0 * p->variance_mm2[j])));
        wsum += p->weight[j][c];
    }
    return sum / wsum;
}

/* Renders the plate at mm_per_px with the screen-space kernel of `taps` taps (0: the scene's
 * default) on the current GL context and writes the largest error per channel over the middle
 * row, as a fraction of the step, into err. Returns 0, or −1 with msg saying what went wrong. */
static inline int edge_plate_error(double mm_per_px, int taps, double err[3], char *msg, size_t msg_size)
{
    enum { W = EDGE_PLATE_W, H = EDGE_PLATE_H, TEXELS = EDGE_PLATE_W + 16 };
    dm_synth *sy = NULL;
    dm_renderer *r = NULL;
    dm_error e = {0};
    int rc = -1;
    float *albedo = malloc(sizeof *albedo * W * H * 4), *px = malloc(sizeof *px * W * H * 4);
    uint8_t *tex = malloc(TEXELS * 4);
    dm_synth_options so = {.shape = DM_SYNTH_QUAD, .quad_side_mm = (float)(TEXELS * mm_per_px), .beckmann_size = 128,
                           .directional_size = 16, .stretch_size = 64};
    snprintf(msg, msg_size, "out of memory");
    if (!albedo || !px || !tex) goto done;
    if (dm_synth_create(&so, &sy, &e) != DM_OK) goto fail;
    for (int i = 0; i < TEXELS; ++i)
        for (int c = 0; c < 4; ++c) tex[i * 4 + c] = c == 3 ? 255 : i < TEXELS / 2 ? edge_plate_lo[c] : edge_plate_hi[c];
    sy->assets.albedo = (dm_texture){DM_TEX_RGBA8_SRGB, TEXELS, 1, tex};
    dm_scene *s = &sy->scene;
    double t = tan(0.5 * s->fov_y_deg * 3.14159265358979323846 / 180.0);
    for (int k = 0; k < 3; ++k) s->camera_eye[k] = s->camera_target[k] = s->camera_up[k] = 0.0f;
    s->camera_eye[2] = (float)(mm_per_px * H / (2.0 * t) / s->mm_per_unit);
    s->camera_up[1] = 1.0f;
    for (int k = 0; k < DM_EFFECT_COUNT; ++k) s->effects[k] = k == DM_EFFECT_SUBSURFACE;
    s->env_background = false;
    s->sss_technique = DM_SSS_SCREEN_SPACE;
    if (taps) s->screen_taps = taps;
    if (dm_renderer_create(&sy->assets, &(dm_render_desc){.width = W, .height = H, .shadow_size = 256}, &r, &e) != DM_OK ||
        dm_render_frame(r, &(dm_frame_options){0}, &e) != DM_OK ||
        dm_renderer_read_target(r, dm_renderer_find_target(r, "gbuffer3"), albedo, &e) != DM_OK ||
        dm_renderer_read_linear(r, px, &e) != DM_OK)
        goto fail;
    const size_t row = (size_t)(H / 2) * W;
    const double m = s->mix;
    for (int c = 0; c < 3; ++c) {
        /* the albedo the shading read: the texture's sRGB decode (llvmpipe's within half an 8-bit
         * step of the formula's), the same on each side of the step */
        int vlo = edge_plate_lo[c], vhi = edge_plate_hi[c];
        double a0 = albedo[row * 4 + c], a1 = albedo[(row + W - 1) * 4 + c], E = px[row * 4 + c] / a0;
        if (!(fabs(a0 - edge_plate_srgb(vlo)) < 0.5 * (edge_plate_srgb(vlo + 1) - edge_plate_srgb(vlo)) &&
              fabs(a1 - edge_plate_srgb(vhi)) < 0.5 * (edge_plate_srgb(vhi + 1) - edge_plate_srgb(vhi)) && E > 0)) {
            snprintf(msg, msg_size, "%.3f mm/px: channel %d: albedo %.6f and %.6f, light %g", mm_per_px, c, a0, a1, E);
            goto done;
        }
        err[c] = 0;
        for (int x = 0; x < W; ++x) {
            double a = x < W / 2 ? a0 : a1, xm = (x + 0.5 - W / 2) * mm_per_px;
            if (!(fabs(albedo[(row + x) * 4 + c] - a) < 1e-3 * fabs(a1 - a0))) {
                snprintf(msg, msg_size, "%.3f mm/px: pixel %d's albedo %d is %.6f, not the step's %.6f", mm_per_px, x, c,
                         (double)albedo[(row + x) * 4 + c], a);
                goto done;
            }
            double ref = E * pow(a, 1 - m) * (pow(a0, m) + (pow(a1, m) - pow(a0, m)) * edge_plate_esf(&s->profile, c, xm));
            err[c] = fmax(err[c], fabs(px[(row + x) * 4 + c] - ref) / (E * fabs(a1 - a0)));
        }
    }
    snprintf(msg, msg_size, "%.3f mm/px, %d taps: largest error %.2f / %.2f / %.2f %% of the step R / G / B", mm_per_px,
             s->screen_taps, 100 * err[0], 100 * err[1], 100 * err[2]);
    rc = 0;
    goto done;
fail:
    snprintf(msg, msg_size, "%.3f mm/px: %.200s", mm_per_px, e.detail);
done:
    dm_renderer_destroy(r);
    dm_synth_free(sy);
    free(albedo), free(px), free(tex);
    return rc;
}

#endif
