/* Shadow rays of the ground truth start on the smooth surface the shading normals describe
 * (dm_ref_surface_smooth_point, Hanika 2021), not on the flat facet: a convex coarse
 * sphere, which cannot shadow itself, is the same with shadows on and off (atlas and
 * frame); a concave bowl still shadows exactly where its rim hides the light; degenerate
 * corners stay finite. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../common/onoff_diff.h"
#include "../common/ref_synth.h"
#include "reference/dm_ref_frame.h"
#include "reference/dm_ref_shade.h"

enum { ATLAS = 128, W = 96, H = 96 };
static const double R = 20.0; /* mm */


/* The 24 × 12-facet sphere of radius R at the origin, smooth vertex normals, one
 * shadow-casting directional light from the camera's right (the camera is on +Z). */
static void coarse_sphere(synth *sy, bool shadows)
{
    synth_init(sy);
    synth_sphere(sy, (double[3]){0, 0, 0}, R, 24, 12, (double[4]){0, 0, 1, 1});
    synth_light(sy, 1.0, 0.3, 0.2, 1.0, true);
    sy->scene.effects[DM_EFFECT_SHADOWS] = shadows;
}

static float *atlas_of(const dm_ref_surface_desc *d)
{
    dm_ref_surface *s = synth_surface(d);
    float *rgba = malloc((size_t)ATLAS * ATLAS * 4 * sizeof *rgba);
    dm_error err = {0};
    cr_assert_eq(dm_ref_shade_atlas(s, ATLAS, 0, rgba, NULL, NULL, NULL, &err), DM_OK, "%s", err.detail);
    dm_ref_surface_destroy(s);
    return rgba;
}

static float *frame_of(const dm_ref_surface_desc *d)
{
    float *rgba = malloc((size_t)W * H * 4 * sizeof *rgba);
    dm_ref_frame_options o = {.width = W, .height = H, .atlas_size = 64, .pixel_samples = 1, .atlas_samples = 1};
    dm_error err = {0};
    cr_assert_eq(dm_ref_frame_render_desc(d, &o, rgba, &err), DM_OK, "%s", err.detail);
    return rgba;
}

/* Expects a (shadows on) and b (off) alike over n values, at least min_lit of them lit; frees
 * both. */
static void expect_alike(const char *what, float *a, float *b, size_t n, int min_lit)
{
    onoff_diff df = onoff_compare(a, b, n);
    cr_log_info("%s: %d lit, mean %.4f %%, %.4f %% over 5 %%, sum ratio %.4f %%", what, df.lit, 100 * df.mean,
                100 * df.over5, 100 * df.sum_ratio);
    cr_assert_gt(df.lit, min_lit, "%s: %d lit", what, df.lit);
    cr_expect_lt(df.mean, 1e-3, "%s: mean relative difference %.3g %%", what, 100 * df.mean);
    cr_expect_lt(df.over5, 1e-3, "%s: %.3g %% of lit values differ by more than 5 %%", what, 100 * df.over5);
    free(a);
    free(b);
}

/* The texture-space irradiance (what --frame diffuses) of the coarse sphere: shadow rays
 * from the flat facets blackened the band where a facet faces away from the light that its
 * interpolated normal still faces (before: 2.6 % mean, see docs/dermis-reference.md). */
Test(ref_terminator, convex_sphere_atlas_same_with_shadows)
{
    synth on, off;
    coarse_sphere(&on, true);
    coarse_sphere(&off, false);
    dm_ref_surface_desc d_on, d_off;
    synth_desc(&on, &d_on);
    synth_desc(&off, &d_off);
    expect_alike("atlas", atlas_of(&d_on), atlas_of(&d_off), (size_t)ATLAS * ATLAS, ATLAS * ATLAS / 3);
    synth_free(&on);
    synth_free(&off);
}

/* The frame (subsurface off: Lambert and specular per pixel, each shadowed by its own ray). */
Test(ref_terminator, convex_sphere_frame_same_with_shadows)
{
    synth on, off;
    coarse_sphere(&on, true);
    coarse_sphere(&off, false);
    for (synth *s = &on; s; s = s == &on ? &off : NULL) {
        s->scene.effects[DM_EFFECT_SPECULAR] = s->scene.effects[DM_EFFECT_ENERGY_CONSERVATION] = true;
        s->scene.camera_eye[2] = 80.0f;
    }
    dm_ref_surface_desc d_on, d_off;
    synth_desc(&on, &d_on);
    synth_desc(&off, &d_off);
    expect_alike("frame", frame_of(&d_on), frame_of(&d_off), (size_t)W * H, 1500);
    synth_free(&on);
    synth_free(&off);
}

/* The lifted point of the coarse sphere lies on the sphere, where the facets lie up to
 * 0.34 mm (1.7 % of R) inside it: within a twentieth of that on either side (measured:
 * 0.0085 mm inside, nothing outside), and never below its facet. */
Test(ref_terminator, smooth_point_of_a_sphere)
{
    synth sy;
    coarse_sphere(&sy, true);
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    dm_ref_surface *s = synth_surface(&d);
    double flat = 0, below = 0, above = 0;
    for (int32_t t = 0; t < s->mesh.triangle_count; ++t)
        for (int i = 0; i <= 6; ++i)
            for (int j = 0; i + j <= 6; ++j) {
                dm_ref_point p;
                dm_ref_surface_point(s, t, i / 6.0, j / 6.0, &p);
                double q[3], up = 0;
                dm_ref_surface_smooth_point(s, &p, q);
                for (int c = 0; c < 3; ++c) up += (q[c] - p.p_mm[c]) * p.ng[c];
                cr_assert_geq(up, -1e-12, "face %d: the lifted point is below the facet", t);
                flat = fmax(flat, R - sqrt(p.p_mm[0] * p.p_mm[0] + p.p_mm[1] * p.p_mm[1] + p.p_mm[2] * p.p_mm[2]));
                double rq = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
                below = fmax(below, R - rq);
                above = fmax(above, rq - R);
            }
    cr_log_info("inside the sphere: facets %.4f mm, lifted %.4f mm; lifted outside by %.4f mm", flat, below, above);
    cr_assert_gt(flat, 0.15);
    cr_assert_lt(below, flat / 20);
    cr_assert_lt(above, flat / 20);
    dm_ref_surface_destroy(s);
    synth_free(&sy);
}

/* ---- a concave bowl ----------------------------------------------------------------- */

/* The inside of the lower half (z ≤ 0) of the sphere of radius R at the origin, open
 * towards +Z: normals towards the centre, front faces inside. nu × nv facets. */
static void bowl(synth *sy, int nu, int nv)
{
    uint32_t base = (uint32_t)sy->nv;
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            double th = 0.5 * SYNTH_PI * j / nv, ph = 2 * SYNTH_PI * i / nu; /* θ from −Z */
            double o[3] = {sin(th) * cos(ph), sin(th) * sin(ph), -cos(th)}, p[3], n[3];
            for (int c = 0; c < 3; ++c) p[c] = R * o[c], n[c] = -o[c];
            synth_vertex(sy, p, n, (double[2]){(double)i / nu, (double)j / nv},
                         (double[4]){-sin(ph), cos(ph), 0, 1});
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            uint32_t a = base + (uint32_t)(j * (nu + 1) + i), b = a + 1, c = a + (uint32_t)nu + 1, e = c + 1;
            if (j > 0) synth_tri(sy, a, e, b); /* at the bottom one half has no area */
            synth_tri(sy, a, c, e);
        }
}

/* Lit from 40° above the horizon: a point Q of the bowl sees the light when the ray from Q
 * leaves the sphere above the rim: its second intersection Q − 2(Q·L)L has z > 0. Inside
 * (by more than the facets' sagitta, projected) the irradiance is exactly 0, outside it is
 * the shadow-free value; the shadow covers a good part of the bowl. */
Test(ref_terminator, concave_bowl_still_shadows)
{
    synth on, off;
    for (synth *s = &on; s; s = s == &on ? &off : NULL) {
        synth_init(s);
        bowl(s, 32, 8);
        synth_light(s, cos(40 * SYNTH_PI / 180), 0.0, sin(40 * SYNTH_PI / 180), 1.0, true);
        s->scene.effects[DM_EFFECT_SHADOWS] = s == &on;
    }
    dm_ref_surface_desc d_on, d_off;
    synth_desc(&on, &d_on);
    synth_desc(&off, &d_off);
    dm_ref_surface *s_on = synth_surface(&d_on), *s_off = synth_surface(&d_off);
    const float *l = on.scene.lights[0].direction;
    const double L[3] = {l[0], l[1], l[2]};
    int shadowed = 0, lit = 0;
    double shadow_sum = 0, lit_sum = 0, lit_off = 0;
    for (int32_t t = 0; t < s_on->mesh.triangle_count; ++t)
        for (int i = 1; i <= 4; ++i)
            for (int j = 1; i + j <= 5; ++j) {
                dm_ref_point p;
                dm_ref_surface_point(s_on, t, i / 6.0, j / 6.0, &p);
                double q[3], r = 0, ql = 0, e_on[3], e_off[3];
                for (int c = 0; c < 3; ++c) r += p.p_mm[c] * p.p_mm[c];
                for (int c = 0; c < 3; ++c) q[c] = p.p_mm[c] * R / sqrt(r), ql += q[c] * L[c];
                double exit_z = q[2] - 2 * ql * L[2];
                dm_ref_shade_irradiance(s_on, &p, e_on);
                dm_ref_shade_irradiance(s_off, &p, e_off);
                if (exit_z < -1.5) {
                    cr_assert_eq(e_on[0], 0.0, "face %d (%g, %g, %g) is lit in the shadow", t, q[0], q[1], q[2]);
                    shadow_sum += e_off[0];
                    ++shadowed;
                } else if (exit_z > 1.5) {
                    cr_assert_eq(e_on[0], e_off[0], "face %d (%g, %g, %g) is shadowed in the light", t, q[0], q[1],
                                 q[2]);
                    lit_sum += e_on[0];
                    lit_off += e_off[0];
                    ++lit;
                }
            }
    cr_log_info("bowl: %d points shadowed (mean %.3f without shadows, 0 with), %d lit (mean %.3f = %.3f)", shadowed,
                shadow_sum / shadowed, lit, lit_sum / lit, lit_off / lit);
    cr_assert_gt(shadowed, 1000);
    cr_assert_gt(lit, 1000);
    cr_assert_gt(shadow_sum / shadowed, 0.2, "the shadowed points face the light");
    dm_ref_surface_destroy(s_on);
    dm_ref_surface_destroy(s_off);
    synth_free(&on);
    synth_free(&off);
}

/* ---- degenerate corners ------------------------------------------------------------- */

/* A zero-area triangle, a corner with a zero normal and two corners with opposing normals:
 * the lifted point is finite (zero normals lift nothing), and shadow rays from it answer
 * 0 or 1. */
Test(ref_terminator, degenerate_corners_stay_finite)
{
    synth sy;
    synth_init(&sy);
    const double t4[4] = {1, 0, 0, 1}, uv[2] = {0.5, 0.5};
    const double up[3] = {0, 0, 1}, down[3] = {0, 0, -1}, zero[3] = {0, 0, 0}, side[3] = {-1, 0, 0};
    /* zero area: three points on a line, then one point three times */
    uint32_t a = synth_vertex(&sy, (double[3]){0, 0, 0}, up, uv, t4);
    uint32_t b = synth_vertex(&sy, (double[3]){1, 0, 0}, down, uv, t4);
    uint32_t c = synth_vertex(&sy, (double[3]){2, 0, 0}, zero, uv, t4);
    synth_tri(&sy, a, b, c);
    synth_tri(&sy, a, a, a);
    /* a real triangle with a zero, an opposing and a sideways normal */
    uint32_t d = synth_vertex(&sy, (double[3]){0, 2, 0}, zero, (double[2]){0, 0}, t4);
    uint32_t e = synth_vertex(&sy, (double[3]){1, 2, 0}, down, (double[2]){1, 0}, t4);
    uint32_t f = synth_vertex(&sy, (double[3]){0, 3, 0}, side, (double[2]){0, 1}, t4);
    synth_tri(&sy, d, e, f);
    synth_tri(&sy, d, f, e); /* the same, seen from below */
    synth_light(&sy, 0.3, 0.2, 1.0, 1.0, true);
    synth_light(&sy, 0.3, 0.2, -1.0, 1.0, true);
    sy.scene.effects[DM_EFFECT_SHADOWS] = true;
    dm_ref_surface_desc desc;
    synth_desc(&sy, &desc);
    dm_ref_surface *s = synth_surface(&desc);
    const double bary[][2] = {{0, 0}, {1, 0}, {0, 1}, {1.0 / 3, 1.0 / 3}, {0.5, 0.5}, {0.1, 0.7}};
    for (int32_t t = 0; t < s->mesh.triangle_count; ++t)
        for (size_t k = 0; k < sizeof bary / sizeof bary[0]; ++k) {
            dm_ref_point p;
            dm_ref_surface_point(s, t, bary[k][0], bary[k][1], &p);
            double q[3], dist = 0;
            dm_ref_surface_smooth_point(s, &p, q);
            for (int i = 0; i < 3; ++i) {
                cr_assert(isfinite(q[i]), "triangle %d, (%g, %g): %g", t, bary[k][0], bary[k][1], q[i]);
                dist += (q[i] - p.p_mm[i]) * (q[i] - p.p_mm[i]);
            }
            cr_assert_leq(sqrt(dist), 3.0, "triangle %d lifted %g mm", t, sqrt(dist));
            for (int l = 0; l < 2; ++l) {
                double v = dm_ref_shade_visibility(s, &p, l);
                cr_assert(v == 0.0 || v == 1.0, "triangle %d, light %d: %g", t, l, v);
            }
            double e[3];
            dm_ref_shade_irradiance(s, &p, e);
            for (int i = 0; i < 3; ++i) cr_assert(isfinite(e[i]) && e[i] >= 0);
        }
    /* the zero-area triangle's corner with the zero normal lifts nothing */
    dm_ref_point p;
    dm_ref_surface_point(s, 0, 0, 1, &p);
    double q[3];
    dm_ref_surface_smooth_point(s, &p, q);
    for (int i = 0; i < 3; ++i) cr_assert_eq(q[i], p.p_mm[i]);
    dm_ref_surface_destroy(s);
    synth_free(&sy);
}
