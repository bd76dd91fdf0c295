/* CPU shading of the ground truth (dm_ref_texture, dm_ref_surface, dm_ref_shade) against
 * closed forms: GL's bilinear filter, the exact ρdt, Lambert on a plane and a sphere, the
 * shadow of an occluder, a white sky through the SH, and every hard case finite. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../common/ref_synth.h"
#include "reference/dm_ref_shade.h"
#include "core/dm_half.h"
#include "reference/dm_ref_texture.h"
#include "core/dm_brdf.h"

/* ---- textures ----------------------------------------------------------------------- */

Test(ref_texture, bilinear_clamp_repeat)
{
    const uint8_t r8[4] = {0, 255, 51, 102}; /* 2 × 2: rows bottom-up */
    dm_ref_texture t = {DM_TEX_R8, 2, 2, r8, false};
    double c[4];
    dm_ref_texture_sample(&t, 0.5, 0.5, c); /* the centre: the mean of the four */
    cr_assert_float_eq(c[0], (0 + 255 + 51 + 102) / 4.0 / 255.0, 1e-12);
    cr_assert_float_eq(c[1], 0.0, 0);
    cr_assert_float_eq(c[3], 1.0, 0);
    dm_ref_texture_sample(&t, 0.25, 0.25, c); /* a texel centre: that texel */
    cr_assert_float_eq(c[0], 0.0, 1e-12);
    dm_ref_texture_sample(&t, -3.0, 0.25, c); /* clamped to the left column */
    cr_assert_float_eq(c[0], 0.0, 1e-12);
    t.repeat_u = true;
    dm_ref_texture_sample(&t, 0.0, 0.25, c); /* the seam: half of each edge column */
    cr_assert_float_eq(c[0], 0.5, 1e-12);
    dm_ref_texture_sample(&t, 1.0, 0.25, c);
    cr_assert_float_eq(c[0], 0.5, 1e-12);
}

Test(ref_texture, srgb_and_half)
{
    const uint8_t px[4] = {255, 128, 0, 7};
    dm_ref_texture t = {DM_TEX_RGBA8_SRGB, 1, 1, px, false};
    double c[4];
    dm_ref_texel(&t, 0, 0, c);
    cr_assert_float_eq(c[0], 1.0, 1e-12);
    cr_assert_float_eq(c[1], pow((128 / 255.0 + 0.055) / 1.055, 2.4), 1e-12);
    cr_assert_float_eq(c[3], 7 / 255.0, 1e-12); /* alpha stays linear */
    cr_assert_eq(dm_half_to_float(0x3C00), 1.0f);
    cr_assert_eq(dm_half_to_float(0x7BFF), 65504.0f);
    cr_assert_eq(dm_half_to_float(0x0001), 5.9604644775390625e-8f);
    cr_assert_eq(dm_half_to_float(0xC000), -2.0f);
    cr_assert(isinf(dm_half_to_float(0x7C00)));
}

/* ---- the exact ρdt ------------------------------------------------------------------ */

static double rho_error(dm_ref_surface *s, double m, double c_min)
{
    double worst = 0;
    srand(3);
    for (int k = 0; k < 300; ++k) {
        double c = c_min + (1 - c_min) * pow((double)rand() / RAND_MAX, 3.0); /* dense at grazing */
        worst = fmax(worst, fabs(dm_ref_surface_rho_dt(s, c, m) - dm_rho_dt(c, m, DM_SKIN_F0, 48)));
    }
    return worst;
}

/* The table (√c spacing, 1024 intervals) against direct integration; bounds from the
 * second derivative of ρdt in √c, measured once over dense c (header of dm_ref_surface.h). */
Test(ref_surface, rho_dt_table)
{
    synth sy;
    synth_init(&sy);
    synth_quad(&sy, (double[3]){0, 0, 0}, (double[3]){1, 0, 0}, (double[3]){0, 1, 0}, 1, (double[4]){0, 0, 1, 1});
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    sy.scene.roughness = 0.3f;
    dm_ref_surface *s = synth_surface(&d);
    const double m = sy.scene.roughness; /* 0.3f */
    cr_assert_lt(rho_error(s, m, 0.0), 1.3e-5);
    cr_assert_float_eq(dm_ref_surface_rho_dt(s, 1.0, m), dm_rho_dt(1.0, m, DM_SKIN_F0, 48), 1e-12);
    dm_ref_surface_destroy(s);
    sy.scene.roughness = 0.01f;
    s = synth_surface(&d);
    cr_assert_lt(rho_error(s, sy.scene.roughness, 0.0), 3.1e-4);
    cr_assert_lt(rho_error(s, sy.scene.roughness, 1e-3), 3e-5); /* measured 2.7e-5 */
    dm_ref_surface_destroy(s);
    /* with a roughness map: also linear in m (64 intervals) */
    const uint8_t grey = 77;
    d.roughness_map = (dm_ref_texture){DM_TEX_R8, 1, 1, &grey, false};
    s = synth_surface(&d);
    cr_assert_eq(s->rho_m_count, 65);
    double e = fmax(rho_error(s, 0.3, 0.0), fmax(rho_error(s, 0.55, 0.0), rho_error(s, 0.9, 0.0)));
    cr_assert_lt(e, 2.5e-4, "rho_dt over (c, m): %g", e); /* measured 1.9e-4 */
    dm_ref_surface_destroy(s);
    synth_free(&sy);
}

/* ---- irradiance: closed forms ------------------------------------------------------- */

enum { ATLAS = 128 };
static const double HALF = 20.0; /* the plane is 40 mm square at z = 0 */

/* The plane in UV [0, 0.5] × [0, 1]; x, y of a texel centre. */
static void add_plane(synth *sy)
{
    synth_quad(sy, (double[3]){-HALF, -HALF, 0}, (double[3]){2 * HALF, 0, 0}, (double[3]){0, 2 * HALF, 0}, 8,
               (double[4]){0, 0, 0.5, 1});
}

static void texel_xy(int i, int j, double *x, double *y)
{
    *x = -HALF + 2 * HALF * ((i + 0.5) / ATLAS) / 0.5;
    *y = -HALF + 2 * HALF * ((j + 0.5) / ATLAS);
}

static float *atlas_of(dm_ref_surface *s, int threads)
{
    float *rgba = malloc((size_t)ATLAS * ATLAS * 4 * sizeof *rgba);
    dm_error err = {0};
    cr_assert_eq(dm_ref_shade_atlas(s, ATLAS, threads, rgba, NULL, NULL, NULL, &err), DM_OK, "%s", err.detail);
    return rgba;
}

/* Lambert: colour · intensity · cos θ on every covered texel (albedo white, so albedo^mix
 * = 1); float rounding only. */
Test(ref_shade, plane_lambert)
{
    synth sy;
    synth_init(&sy);
    add_plane(&sy);
    synth_light(&sy, 0, sin(SYNTH_PI / 3), cos(SYNTH_PI / 3), 2.0, false);
    sy.scene.lights[0].color[1] = 0.5f;
    sy.scene.lights[0].color[2] = 0.25f;
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    dm_ref_surface *s = synth_surface(&d);
    float *a = atlas_of(s, 0);
    double cosine = sy.scene.lights[0].direction[2];
    int covered = 0;
    for (int j = 0; j < ATLAS; ++j)
        for (int i = 0; i < ATLAS / 2; ++i) {
            const float *t = a + ((size_t)j * ATLAS + i) * 4;
            cr_assert_eq(t[3], 1.0f, "texel %d,%d of the plane is not covered", i, j);
            ++covered;
            cr_assert_float_eq(t[0], 2.0 * cosine, 1e-6);
            cr_assert_float_eq(t[1], 1.0 * cosine, 1e-6);
            cr_assert_float_eq(t[2], 0.5 * cosine, 1e-6);
        }
    for (int j = 0; j < ATLAS; ++j) /* the right half is gutter: cleared */
        cr_assert_eq(a[((size_t)j * ATLAS + ATLAS - 1) * 4 + 3], 0.0f);
    cr_assert_eq(covered, ATLAS * ATLAS / 2);
    free(a);
    dm_ref_surface_destroy(s);
    synth_free(&sy);
}

/* With energy conservation: × (1 − ρs ρdt(cos θ, m)), ρdt integrated directly (the table's
 * bound, 1.3e-5, times ρs = 0.18). */
Test(ref_shade, plane_energy)
{
    synth sy;
    synth_init(&sy);
    add_plane(&sy);
    synth_light(&sy, 0.8, 0, 0.6, 1.0, false);
    sy.scene.effects[DM_EFFECT_SPECULAR] = sy.scene.effects[DM_EFFECT_ENERGY_CONSERVATION] = true;
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    dm_ref_surface *s = synth_surface(&d);
    float *a = atlas_of(s, 0);
    double c = sy.scene.lights[0].direction[2];
    double expect = c * (1 - sy.scene.rho_s * dm_rho_dt(c, sy.scene.roughness, DM_SKIN_F0, 48));
    for (int j = 0; j < ATLAS; j += 7)
        for (int i = 0; i < ATLAS / 2; i += 5) cr_assert_float_eq(a[((size_t)j * ATLAS + i) * 4], expect, 3e-6);
    free(a);
    dm_ref_surface_destroy(s);
    synth_free(&sy);
}

/* A 4 mm square 5 mm above the plane: its hard shadow along L, exactly 0 inside (0.5 mm
 * from the edge, > 3 texels) and exactly cos θ outside. */
static void check_shadow(double lx, double shift)
{
    synth sy;
    synth_init(&sy);
    add_plane(&sy);
    synth_quad(&sy, (double[3]){-2, -2, 5}, (double[3]){4, 0, 0}, (double[3]){0, 4, 0}, 1,
               (double[4]){0.6, 0.1, 0.9, 0.4});
    synth_light(&sy, lx, 0, 1, 1.0, true);
    sy.scene.effects[DM_EFFECT_SHADOWS] = true;
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    dm_ref_surface *s = synth_surface(&d);
    float *a = atlas_of(s, 0);
    double cosine = sy.scene.lights[0].direction[2];
    int in = 0, out = 0;
    for (int j = 0; j < ATLAS; ++j)
        for (int i = 0; i < ATLAS / 2; ++i) {
            double x, y;
            texel_xy(i, j, &x, &y);
            double dx = fabs(x + shift), dy = fabs(y); /* distance from the shadow's centre */
            float v = a[((size_t)j * ATLAS + i) * 4];
            if (dx < 1.5 && dy < 1.5) {
                cr_assert_eq(v, 0.0f, "(%g, %g) should be in the shadow", x, y);
                ++in;
            } else if (dx > 2.5 || dy > 2.5) {
                cr_assert_float_eq(v, cosine, 1e-6, "(%g, %g) should be lit", x, y);
                ++out;
            }
        }
    cr_assert_gt(in, 30); /* 3 × 3 mm at 0.625 × 0.3125 mm texels: ~46 */
    cr_assert_gt(out, 5000);
    free(a);
    dm_ref_surface_destroy(s);
    synth_free(&sy);
}

Test(ref_shade, occluder_shadow_overhead)
{
    check_shadow(0.0, 0.0);
}

Test(ref_shade, occluder_shadow_oblique)
{
    check_shadow(1.0, 5.0); /* 45°: the shadow moves 5 mm towards −x */
}

/* A white sky of radiance L: SH L00 = 2√π L, E = π L, the irradiance pass adds
 * intensity · E / π = intensity · L whatever the normal. */
Test(ref_shade, sh_white_sky)
{
    synth sy;
    synth_init(&sy);
    synth_sphere(&sy, (double[3]){0, 0, 0}, 10, 48, 24, (double[4]){0, 0, 1, 1});
    sy.scene.effects[DM_EFFECT_ENVIRONMENT_LIGHTING] = true;
    sy.scene.env_intensity = 1.5f;
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    const double L[3] = {0.7, 0.4, 0.2};
    d.has_env_sh = true;
    for (int c = 0; c < 3; ++c) d.env_sh[0][c] = (float)(2 * sqrt(SYNTH_PI) * L[c]);
    dm_ref_surface *s = synth_surface(&d);
    float *a = atlas_of(s, 0);
    int covered = 0;
    for (size_t k = 0; k < (size_t)ATLAS * ATLAS; ++k) {
        if (a[k * 4 + 3] == 0) continue;
        ++covered;
        for (int c = 0; c < 3; ++c) cr_assert_float_eq(a[k * 4 + c], 1.5 * L[c], 2e-7 * 1.5 * L[c] + 1e-7);
    }
    cr_assert_gt(covered, ATLAS * ATLAS * 9 / 10);
    free(a);
    dm_ref_surface_destroy(s);
    synth_free(&sy);
}

/* A sphere lit by a shadow-casting directional light: Lambert at each face centre against
 * the analytic cos of the radial direction (the interpolated normal of a 48 × 24 sphere
 * differs by < 2e-3), no shadow acne anywhere the interpolated normal faces the light
 * (N·L > 0: shadow rays start on the smooth surface, so no terminator band either; see
 * test_ref_terminator.c), full shadow where it looks away from the light by more than the
 * facets can hide: from the smooth surface at N·L = −0.1 a ray dips R(1 − √0.99) = 0.005 R
 * into the sphere, deeper than the facets' centres lie below it (≤ 0.0043 R); at smaller
 * −N·L it may pass over the facets, as it would over the true sphere's tangent plane. */
Test(ref_shade, sphere_lambert_and_self_shadow)
{
    synth sy;
    synth_init(&sy);
    synth_sphere(&sy, (double[3]){0, 0, 0}, 10, 48, 24, (double[4]){0, 0, 1, 1});
    synth_light(&sy, 0.3, 0.5, 0.8, 1.0, true);
    sy.scene.effects[DM_EFFECT_SHADOWS] = true;
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    dm_ref_surface *s = synth_surface(&d);
    const float *l = sy.scene.lights[0].direction;
    const double L[3] = {l[0], l[1], l[2]};
    int lit = 0, dark = 0;
    for (int32_t t = 0; t < s->mesh.triangle_count; ++t) {
        dm_ref_point p;
        dm_ref_surface_point(s, t, 1.0 / 3, 1.0 / 3, &p);
        double r = sqrt(p.p_mm[0] * p.p_mm[0] + p.p_mm[1] * p.p_mm[1] + p.p_mm[2] * p.p_mm[2]);
        double radial = (p.p_mm[0] * L[0] + p.p_mm[1] * L[1] + p.p_mm[2] * L[2]) / r, e[3];
        dm_ref_shade_irradiance(s, &p, e);
        double nl = p.N[0] * L[0] + p.N[1] * L[1] + p.N[2] * L[2];
        if (radial > 0.1) {
            cr_assert_float_eq(e[0], radial, 2e-3, "face %d: %g, Lambert %g", t, e[0], radial);
            ++lit;
        }
        if (nl > 0) cr_assert_eq(dm_ref_shade_visibility(s, &p, 0), 1.0, "acne on face %d (N.L %g)", t, nl);
        if (nl < -0.1) {
            cr_assert_eq(dm_ref_shade_visibility(s, &p, 0), 0.0, "face %d sees the light through the sphere (N.L %g, ng.L %g)", t, nl, p.ng[0] * L[0] + p.ng[1] * L[1] + p.ng[2] * L[2]);
            ++dark;
        }
    }
    cr_assert_gt(lit, 800);
    cr_assert_gt(dark, 800);
    dm_ref_surface_destroy(s);
    synth_free(&sy);
}

/* ---- hard cases --------------------------------------------------------------------- */

static bool finite3(const double v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]) && v[0] >= 0 && v[1] >= 0 && v[2] >= 0;
}

/* A plane with specular, energy, shadows on and one light along (lx, 0, lz). */
static dm_ref_surface *hard_plane(synth *sy, double lx, double lz, double intensity, double roughness)
{
    synth_init(sy);
    add_plane(sy);
    synth_light(sy, lx, 0, lz, intensity, true);
    sy->scene.roughness = (float)roughness;
    sy->scene.effects[DM_EFFECT_SPECULAR] = sy->scene.effects[DM_EFFECT_ENERGY_CONSERVATION] =
        sy->scene.effects[DM_EFFECT_SHADOWS] = true;
    dm_ref_surface_desc d;
    synth_desc(sy, &d);
    return synth_surface(&d);
}

Test(ref_shade, grazing_light)
{
    const double lz[] = {1e-7, 0.0, -1e-7, 1e-30};
    for (size_t k = 0; k < sizeof lz / sizeof lz[0]; ++k) {
        synth sy;
        dm_ref_surface *s = hard_plane(&sy, 1.0, lz[k], 1.0, 0.3);
        dm_ref_point p;
        dm_ref_surface_point(s, 0, 0.3, 0.3, &p);
        double e[3], spec[3];
        dm_ref_shade_irradiance(s, &p, e);
        cr_assert(finite3(e));
        cr_assert_leq(e[0], 1.1e-7, "N.L = %g gives %g", lz[k], e[0]);
        dm_ref_shade_specular(s, &p, (double[3]){0, 0, 1}, spec);
        cr_assert(finite3(spec));
        float *a = atlas_of(s, 0);
        for (size_t i = 0; i < (size_t)ATLAS * ATLAS * 4; ++i) cr_assert(isfinite(a[i]) && a[i] >= 0);
        free(a);
        dm_ref_surface_destroy(s);
        synth_free(&sy);
    }
}

/* N·H → 0: L and V both grazing, 90° apart in azimuth; D → 0, never NaN. */
Test(ref_shade, n_dot_h_to_zero)
{
    const double eps[] = {1e-2, 1e-4, 1e-8, 0.0};
    for (size_t k = 0; k < sizeof eps / sizeof eps[0]; ++k) {
        synth sy;
        dm_ref_surface *s = hard_plane(&sy, 1.0, eps[k], 1.0, 0.3);
        dm_ref_point p;
        dm_ref_surface_point(s, 0, 0.3, 0.3, &p);
        double V[3] = {0, 1, eps[k]}, spec[3];
        double lv = sqrt(1 + eps[k] * eps[k]);
        for (int c = 0; c < 3; ++c) V[c] /= lv;
        dm_ref_shade_specular(s, &p, V, spec);
        cr_assert(finite3(spec), "eps %g", eps[k]);
        cr_assert_lt(spec[0], 1e-6, "eps %g: %g", eps[k], spec[0]);
        dm_ref_surface_destroy(s);
        synth_free(&sy);
    }
}

/* roughness → 0: the mirror direction meets D's m → 0 limit (DM_BECKMANN_D_MAX); finite. */
Test(ref_shade, roughness_to_zero)
{
    const double m[] = {0.0, 1e-6, 1e-3};
    for (size_t k = 0; k < sizeof m / sizeof m[0]; ++k) {
        synth sy;
        dm_ref_surface *s = hard_plane(&sy, 1.0, 1.0, 1.0, m[k]);
        dm_ref_point p;
        dm_ref_surface_point(s, 0, 0.3, 0.3, &p);
        const double V[2][3] = {{-0.70710678118654752, 0, 0.70710678118654752}, {0, 0.6, 0.8}};
        for (int v = 0; v < 2; ++v) {
            double spec[3], e[3];
            dm_ref_shade_specular(s, &p, V[v], spec);
            cr_assert(finite3(spec), "m %g, view %d", m[k], v);
            dm_ref_shade_irradiance(s, &p, e);
            cr_assert(finite3(e));
        }
        float *a = atlas_of(s, 0);
        for (size_t i = 0; i < (size_t)ATLAS * ATLAS * 4; ++i) cr_assert(isfinite(a[i]));
        free(a);
        dm_ref_surface_destroy(s);
        synth_free(&sy);
    }
}

/* A light of colour 1e6 × intensity 1e6 (the scene's limits) on a mirror: finite floats. */
Test(ref_shade, huge_hdr)
{
    synth sy;
    dm_ref_surface *s = hard_plane(&sy, 1.0, 1.0, 1e6, 0.0);
    for (int c = 0; c < 3; ++c) s->light_color[0][c] *= 1e6;
    float *a = atlas_of(s, 0);
    for (size_t i = 0; i < (size_t)ATLAS * ATLAS * 4; ++i) cr_assert(isfinite(a[i]) && a[i] >= 0);
    cr_assert_gt(a[0], 1e11);
    dm_ref_point p;
    dm_ref_surface_point(s, 0, 0.3, 0.3, &p);
    double spec[3];
    dm_ref_shade_specular(s, &p, (double[3]){-0.70710678118654752, 0, 0.70710678118654752}, spec);
    cr_assert(finite3(spec) && spec[0] < 3e38, "%g", spec[0]);
    free(a);
    dm_ref_surface_destroy(s);
    synth_free(&sy);
}

/* The atlas is byte-identical on 1, 2 and 3 threads (shadows, a sphere and a plane). */
Test(ref_shade, atlas_deterministic)
{
    synth sy;
    synth_init(&sy);
    add_plane(&sy);
    synth_sphere(&sy, (double[3]){0, 0, 6}, 5, 32, 16, (double[4]){0.55, 0.05, 0.95, 0.95});
    synth_light(&sy, 0.4, 0.3, 1.0, 1.0, true);
    synth_light(&sy, -0.7, 0.1, 0.4, 0.5, true);
    sy.scene.effects[DM_EFFECT_SHADOWS] = sy.scene.effects[DM_EFFECT_SPECULAR] =
        sy.scene.effects[DM_EFFECT_ENERGY_CONSERVATION] = true;
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    dm_ref_surface *s = synth_surface(&d);
    float *a1 = atlas_of(s, 1), *a2 = atlas_of(s, 2), *a3 = atlas_of(s, 3);
    size_t n = (size_t)ATLAS * ATLAS * 4 * sizeof *a1;
    cr_assert_eq(memcmp(a1, a2, n), 0);
    cr_assert_eq(memcmp(a1, a3, n), 0);
    free(a1);
    free(a2);
    free(a3);
    dm_ref_surface_destroy(s);
    synth_free(&sy);
}
