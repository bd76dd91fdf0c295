/* The ground-truth frame (dm_ref_frame): the renderer's camera against an analytic sphere,
 * silhouettes and misses, a white sky through the exact convolution, the tonemap, thread
 * counts, and the real head against the renderer's own frame. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <criterion/criterion.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/ref_synth.h"
#include "../common/tmpdir.h"
#include "image/dm_exr.h"
#include "reference/dm_ref_frame.h"

enum { W = 64, H = 48 };

static float *frame_of(const dm_ref_surface_desc *d, int w, int h, int threads, int atlas, dm_ref_frame_stats *st)
{
    float *rgba = malloc((size_t)w * h * 4 * sizeof *rgba);
    /* one point sample per pixel and atlas texel: the closed forms below are per point */
    dm_ref_frame_options o = {.width = w, .height = h, .atlas_size = atlas, .thread_count = threads, .stats = st,
                              .pixel_samples = 1, .atlas_samples = 1};
    dm_error err = {0};
    cr_assert_eq(dm_ref_frame_render_desc(d, &o, rgba, &err), DM_OK, "%s", err.detail);
    return rgba;
}

/* Unit direction of pixel (x, y)'s ray for a camera on +Z looking at the origin with up +Y
 * (the renderer's projection: right = +X, up = +Y). */
static void pixel_ray(const dm_scene *s, int x, int y, int w, int h, double dir[3])
{
    double t = tan(0.5 * s->fov_y_deg * SYNTH_PI / 180), aspect = (double)w / h;
    dir[0] = (2.0 * (x + 0.5) / w - 1) * t * aspect;
    dir[1] = (2.0 * (y + 0.5) / h - 1) * t;
    dir[2] = -1;
    double l = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + 1);
    for (int c = 0; c < 3; ++c) dir[c] /= l;
}

/* The ray from the eye (0, 0, ez) meets the sphere |P| = r at its near side; false if it
 * misses. */
static bool sphere_hit(double ez, double r, const double dir[3], double n[3])
{
    double b = ez * dir[2], c = ez * ez - r * r, disc = b * b - c;
    if (disc < 0) return false;
    double t = -b - sqrt(disc);
    n[0] = t * dir[0] / r;
    n[1] = t * dir[1] / r;
    n[2] = (ez + t * dir[2]) / r;
    return true;
}

/* A sphere of radius 10 mm lit from (0.3, 0.4, 0.866), subsurface off: every pixel is
 * Lambert at the analytic hit, within the 48 × 24 tessellation (below). Silhouette: skin pixels = the disk's area within
 * its perimeter. Misses get the constant background. */
Test(ref_frame, sphere_lambert_silhouette_and_misses)
{
    synth sy;
    synth_init(&sy);
    synth_sphere(&sy, (double[3]){0, 0, 0}, 10, 48, 24, (double[4]){0, 0, 1, 1});
    synth_light(&sy, 0.3, 0.4, 0.866, 1.0, false);
    sy.scene.effects[DM_EFFECT_ENVIRONMENT_LIGHTING] = true;
    sy.scene.env_background = true;
    snprintf(sy.scene.environment, sizeof sy.scene.environment, "constant");
    sy.scene.env_intensity = 2.0f;
    const float bg[2][4] = {{0.25f, 0.5f, 1.0f, 1}, {0.25f, 0.5f, 1.0f, 1}};
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    d.env_background = (dm_ref_texture){DM_TEX_RGBA32F, 2, 1, bg, true};
    dm_ref_frame_stats st;
    float *f = frame_of(&d, W, H, 0, 64, &st);
    const float *l = sy.scene.lights[0].direction;
    int skin = 0, judged = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float *p = f + ((size_t)y * W + x) * 4;
            double dir[3], n[3];
            pixel_ray(&sy.scene, x, y, W, H, dir);
            bool hit = sphere_hit(100.0, 10.0, dir, n);
            skin += p[3] == 1.0f;
            if (p[3] == 0.0f) {
                for (int c = 0; c < 3; ++c) cr_assert_float_eq(p[c], 2.0 * bg[0][c], 1e-6, "miss at %d,%d", x, y);
                continue;
            }
            cr_assert(hit, "pixel %d,%d is skin off the sphere", x, y);
            double ndv = -(n[0] * dir[0] + n[1] * dir[1] + n[2] * dir[2]);
            /* the ray meets a facet up to the sagitta R(1 − cos 3.75°) = 0.021 mm inside the
             * sphere, a point up to 0.021·tan θ_v mm aside: 3.7e-3 rad of normal at N·V = 0.5 */
            if (ndv < 0.5) continue;
            double lambert = fmax(n[0] * l[0] + n[1] * l[1] + n[2] * l[2], 0.0);
            cr_assert_float_eq(p[0], lambert, 5e-3, "pixel %d,%d: %g, Lambert %g", x, y, p[0], lambert);
            ++judged;
        }
    double t = tan(0.5 * sy.scene.fov_y_deg * SYNTH_PI / 180), rho = tan(asin(10.0 / 100.0)) / t;
    double r_px = rho * H / 2, area = SYNTH_PI * r_px * r_px;
    cr_assert(fabs(skin - area) < 2 * SYNTH_PI * r_px, "%d skin pixels, disk of %g", skin, area);
    cr_assert_eq(st.skin_pixels, skin);
    cr_assert_gt(judged, 100);
    free(f);
    synth_free(&sy);
}

/* Every term on (subsurface, specular with a mirror-sharp m, energy, shadows, SH,
 * prefiltered levels, background), a huge light: silhouette pixels (skin next to
 * background, N·V → 0) and every other pixel finite, alpha exactly 0 or 1. */
Test(ref_frame, everything_on_is_finite)
{
    synth sy;
    synth_init(&sy);
    synth_sphere(&sy, (double[3]){0, 0, 0}, 10, 32, 16, (double[4]){0, 0, 1, 1});
    synth_light(&sy, 0.0, 0.0, 1.0, 1e6, true); /* behind the camera: mirror highlights */
    synth_light(&sy, 1.0, 0.0, 1e-7, 1e6, true); /* grazing */
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) sy.scene.effects[e] = e != DM_EFFECT_GLOW;
    for (int c = 0; c < 3; ++c) sy.scene.lights[0].color[c] = 1e6f;
    sy.scene.roughness = 0.0f;
    sy.scene.env_background = true;
    snprintf(sy.scene.environment, sizeof sy.scene.environment, "constant");
    const float env[2][4] = {{1e6f, 1, 0, 1}, {0, 1, 1e6f, 1}};
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    d.has_env_sh = true;
    d.env_sh[0][0] = d.env_sh[0][1] = d.env_sh[0][2] = 1e6f;
    d.env_sh[3][0] = -1e6f;
    d.env_level_count = 2;
    d.env_level_m[0] = 0.1f;
    d.env_level_m[1] = 0.5f;
    d.env_levels[0] = d.env_levels[1] = d.env_background = (dm_ref_texture){DM_TEX_RGBA32F, 2, 1, env, true};
    float *f = frame_of(&d, W, H, 0, 64, NULL);
    int rim = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float *p = f + ((size_t)y * W + x) * 4;
            for (int c = 0; c < 3; ++c) cr_assert(isfinite(p[c]) && p[c] >= 0, "pixel %d,%d: %g", x, y, p[c]);
            cr_assert(p[3] == 0.0f || p[3] == 1.0f);
            if (p[3] == 1.0f && x > 0 && x < W - 1 && (p[-1] == 0.0f || p[7] == 0.0f)) ++rim;
        }
    cr_assert_gt(rim, 10);
    uint8_t *px = malloc((size_t)W * H * 4);
    dm_ref_frame_display(&sy.scene, f, W, H, px);
    cr_assert_eq(px[((size_t)(H / 2) * W + W / 2) * 4], 255, "a 1e12 highlight saturates");
    free(px);
    free(f);
    synth_free(&sy);
}

/* A white sky of radiance L on a sphere of radius 100 mm, albedo white, subsurface on: the
 * irradiance is L everywhere, so the normalised convolution gives D = L up to the sphere's
 * curvature (chord vs arc: a Gaussian of variance v gains ~v/R² ≤ 7.4e-4 of its mass). */
Test(ref_frame, white_sky_through_the_convolution)
{
    synth sy;
    synth_init(&sy);
    synth_sphere(&sy, (double[3]){0, 0, 0}, 100, 48, 24, (double[4]){0, 0, 1, 1});
    sy.scene.effects[DM_EFFECT_SUBSURFACE] = sy.scene.effects[DM_EFFECT_ENVIRONMENT_LIGHTING] = true;
    sy.scene.camera_eye[2] = 1000.0f;
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    const double L[3] = {0.9, 0.5, 0.3};
    d.has_env_sh = true;
    for (int c = 0; c < 3; ++c) d.env_sh[0][c] = (float)(2 * sqrt(SYNTH_PI) * L[c]);
    dm_ref_frame_stats st;
    float *f = frame_of(&d, 32, 24, 0, 128, &st);
    cr_assert_gt(st.skin_pixels, 50);
    for (size_t i = 0; i < 32 * 24; ++i) {
        if (f[i * 4 + 3] == 0) { /* a miss without a background: the renderer's black clear */
            cr_assert(f[i * 4] == 0 && f[i * 4 + 1] == 0 && f[i * 4 + 2] == 0, "miss %zu is not black", i);
            continue;
        }
        for (int c = 0; c < 3; ++c) cr_assert_float_eq(f[i * 4 + c], L[c], 2e-3 * L[c], "pixel %zu: %g", i, f[i * 4 + c]);
    }
    free(f);
    synth_free(&sy);
}

/* Byte-identical frames on 1, 2 and 3 threads: shadows, subsurface, specular. */
Test(ref_frame, deterministic)
{
    synth sy;
    synth_init(&sy);
    synth_quad(&sy, (double[3]){-20, -20, -5}, (double[3]){40, 0, 0}, (double[3]){0, 40, 0}, 4,
               (double[4]){0, 0, 0.5, 1});
    synth_sphere(&sy, (double[3]){0, 0, 3}, 6, 32, 16, (double[4]){0.55, 0.05, 0.95, 0.95});
    synth_light(&sy, 0.5, 0.6, 0.8, 1.0, true);
    sy.scene.effects[DM_EFFECT_SUBSURFACE] = sy.scene.effects[DM_EFFECT_SHADOWS] =
        sy.scene.effects[DM_EFFECT_SPECULAR] = sy.scene.effects[DM_EFFECT_ENERGY_CONSERVATION] = true;
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    float *a = frame_of(&d, 40, 30, 1, 64, NULL), *b = frame_of(&d, 40, 30, 2, 64, NULL),
          *c = frame_of(&d, 40, 30, 3, 64, NULL);
    cr_assert_eq(memcmp(a, b, 40 * 30 * 4 * sizeof *a), 0);
    cr_assert_eq(memcmp(a, c, 40 * 30 * 4 * sizeof *a), 0);
    free(a);
    free(b);
    free(c);
    synth_free(&sy);
}

/* The renderer's tonemap (tonemap.glsl) and its plain sRGB path, value by value. */
Test(ref_frame, display)
{
    dm_scene s;
    dm_scene_defaults(&s);
    const float lin[4][4] = {{0, 0, 0, 1}, {0.18f, 1.0f, 1e30f, 1}, {-1, NAN, INFINITY, 0}, {0.5f, 0.5f, 0.5f, 1}};
    uint8_t out[16];
    dm_ref_frame_display(&s, &lin[0][0], 4, 1, out);
    const double A = 0.15, B = 0.50, C = 0.10, D = 0.20, E = 0.02, F = 0.30;
#define HABLE(x) ((((x) * (A * (x) + C * B) + D * E) / ((x) * (A * (x) + B) + D * F)) - E / F)
    double t = HABLE(0.36) / HABLE(11.2), enc = t <= 0.0031308 ? 12.92 * t : 1.055 * pow(t, 1 / 2.4) - 0.055;
    cr_assert_eq(out[0], 0);
    cr_assert_eq(out[4], (uint8_t)lrint(enc * 255), "0.18 → %d", out[4]);
    cr_assert_eq(out[6], 255);
    cr_assert_eq(out[8], 0);
    cr_assert_eq(out[9], 0, "NaN is black");
    cr_assert_eq(out[15], 255);
    s.exposure = 1.0f; /* one stop: 0.09 looks like 0.18 */
    const float half[4] = {0.09f, 0, 0, 1};
    dm_ref_frame_display(&s, half, 1, 1, out);
    cr_assert_eq(out[0], (uint8_t)lrint(enc * 255));
    s.effects[DM_EFFECT_TONEMAP] = false;
    dm_ref_frame_display(&s, &lin[3][0], 1, 1, out);
    cr_assert_eq(out[0], 188); /* sRGB(0.5) = 0.7354 */
#undef HABLE
}

/* ---- the real head ------------------------------------------------------------------ */

/* lps.json at 160 × 120, irradiance 256, glow off (the reference has none) and no
 * alternative maps, packed by dermis-pack. */
static void head_pack(char *dir, size_t dir_size, char *pack_path, size_t pack_size)
{
    cr_assert(test_tmpdir(dir, dir_size));
    char abs_path[PATH_MAX], scene_path[256], cmd[1024], log[256];
    cr_assert(realpath("assets/scenes/lps.json", abs_path), "run from the repository root");
    dm_scene s;
    dm_error err = {0};
    cr_assert_eq(dm_scene_read(abs_path, &s, &err), DM_OK, "%s", err.detail);
    s.irradiance_size = 256;
    s.width = 160;
    s.height = 120;
    s.effects[DM_EFFECT_GLOW] = false;
    s.env_alternative_count = 0;
    char *json = NULL;
    cr_assert_eq(dm_scene_to_json(&s, &json, &err), DM_OK, "%s", err.detail);
    snprintf(scene_path, sizeof scene_path, "%s/scene.json", dir);
    FILE *f = fopen(scene_path, "w");
    cr_assert(f);
    fputs(json, f);
    fclose(f);
    free(json);
    snprintf(pack_path, pack_size, "%s/head.dpk", dir);
    snprintf(log, sizeof log, "%s/pack.log", dir);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack %s -o %s --quiet", scene_path, pack_path);
    cr_assert_eq(test_run(cmd, log), 0, "dermis-pack failed (build it first): see %s", log);
}

/* The reference frame and the renderer's agree on the head: mean over skin pixels away from
 * the silhouette (3×3 erosion of the reference's alpha), per channel, within 3 %. They
 * differ by design in shadow filtering (hard rays vs 3×3 PCF), the diffusion (exact vs six
 * blurred Gaussians that miss seams and thin parts), the 8-bit Beckmann LUT and mipmaps;
 * measured here: R −0.3 %, G +0.4 %, B +1.1 % (at 320 × 180, atlas 512: −0.4, +0.3, +0.8 %). */
Test(ref_frame, head_agrees_with_the_renderer, .timeout = 600)
{
    char dir[128], pack_path[256], cmd[1024], log[256], exr[256];
    head_pack(dir, sizeof dir, pack_path, sizeof pack_path);
    snprintf(exr, sizeof exr, "%s/render.exr", dir);
    snprintf(log, sizeof log, "%s/render.log", dir);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-render %s -o %s --quiet", pack_path, exr);
    cr_assert_eq(test_run(cmd, log), 0, "dermis-render failed (build it first): see %s", log);
    dm_pack pack;
    dm_scene scene;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open(pack_path, &pack, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_pack_scene(&pack, &scene, &err), DM_OK, "%s", err.detail);
    const int w = scene.width, h = scene.height;
    float *ref = malloc((size_t)w * h * 4 * sizeof *ref);
    dm_ref_frame_stats st;
    dm_ref_frame_options o = {.atlas_size = 256, .stats = &st};
    cr_assert_eq(dm_ref_frame_render(&pack, &scene, &o, ref, &err), DM_OK, "%s", err.detail);
    dm_exr_image img;
    cr_assert_eq(dm_exr_read(exr, &img, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(img.width, w);
    cr_assert_eq(img.height, h);
    const char *names[3] = {"R", "G", "B"};
    double sr[3] = {0}, sg[3] = {0};
    int n = 0;
    for (int y = 1; y < h - 1; ++y)
        for (int x = 1; x < w - 1; ++x) {
            bool inner = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) inner &= ref[((size_t)(y + dy) * w + x + dx) * 4 + 3] == 1.0f;
            if (!inner) continue;
            ++n;
            for (int c = 0; c < 3; ++c) {
                sr[c] += ref[((size_t)y * w + x) * 4 + c];
                sg[c] += dm_exr_find(&img, names[c])[(size_t)y * w + x];
            }
        }
    cr_assert_gt(n, 1000, "%d skin pixels", n);
    for (int c = 0; c < 3; ++c) {
        double ratio = sg[c] / sr[c];
        cr_log_info("head %s: reference %.4f, renderer %.4f (%+.2f %%)\n", names[c], sr[c] / n, sg[c] / n,
                    100 * (ratio - 1));
        cr_assert(fabs(ratio - 1) < 0.03, "%s: renderer / reference = %.4f over %d skin pixels", names[c], ratio, n);
    }
    for (size_t i = 0; i < (size_t)w * h * 4; ++i) cr_assert(isfinite(ref[i]));
    dm_exr_free(&img);
    free(ref);
    dm_pack_close(&pack);
}

/* Anti-aliasing: with 2×2 pixel samples (subsurface off, so D plays no part) a skin pixel is
 * the mean of the four point samples at its quarter positions, which are the pixel centres
 * of the frame twice as large; compared where all four hit, to float rounding. */
Test(ref_frame, pixel_samples_average_sub_pixel_points)
{
    synth sy;
    synth_init(&sy);
    synth_sphere(&sy, (double[3]){0, 0, 0}, 10, 48, 24, (double[4]){0, 0, 1, 1});
    synth_light(&sy, 0.3, 0.4, 0.866, 1.0, false);
    sy.scene.effects[DM_EFFECT_SUBSURFACE] = false;
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    float *fine = frame_of(&d, 2 * W, 2 * H, 0, 64, NULL);
    float *aa = malloc((size_t)W * H * 4 * sizeof *aa);
    dm_ref_frame_options o = {.width = W, .height = H, .atlas_size = 64, .pixel_samples = 2, .atlas_samples = 1};
    dm_error err = {0};
    cr_assert_eq(dm_ref_frame_render_desc(&d, &o, aa, &err), DM_OK, "%s", err.detail);
    int judged = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float *p = aa + 4 * ((size_t)y * W + x);
            double mean = 0.0;
            int hits = 0;
            for (int b = 0; b < 2; ++b)
                for (int a = 0; a < 2; ++a) {
                    const float *q = fine + 4 * ((size_t)(2 * y + b) * 2 * W + 2 * x + a);
                    hits += q[3] == 1.0f;
                    mean += q[0] / 4.0;
                }
            if (hits != 4 || p[3] != 1.0f) continue;
            cr_assert(fabs(p[0] - mean) <= 1e-5 * (1.0 + mean), "pixel %d,%d: %g, mean of its points %g", x, y, p[0], mean);
            ++judged;
        }
    cr_assert(judged > 50, "%d pixels judged", judged);
    free(aa);
    free(fine);
}

/* --refine: the pixels whose 2² rays' radiance spreads by more than 2 % (the sphere's
 * terminator and silhouette, with subsurface on) are shaded again from 5² rays, D at each:
 * bit for bit the 5² frame there, the 2² frame elsewhere, on any thread count; refine not
 * above the pixel samples is refused. */
Test(ref_frame, refine_reshades_the_pixels_that_spread)
{
    synth sy;
    synth_init(&sy);
    synth_sphere(&sy, (double[3]){0, 0, 0}, 20, 48, 24, (double[4]){0, 0, 1, 1});
    synth_light(&sy, 1.0, 0.2, 0.3, 1.0, false);
    dm_ref_surface_desc d;
    synth_desc(&sy, &d);
    size_t n = (size_t)W * H * 4;
    float *f[4];
    int ps[4] = {2, 5, 2, 2}, refine[4] = {0, 0, 5, 5}, threads[4] = {0, 0, 1, 3};
    dm_ref_frame_stats st[4];
    for (int i = 0; i < 4; ++i) {
        f[i] = malloc(n * sizeof *f[i]);
        dm_ref_frame_options o = {.width = W, .height = H, .atlas_size = 64, .pixel_samples = ps[i], .atlas_samples = 1,
                                  .refine_samples = refine[i], .thread_count = threads[i], .stats = &st[i]};
        dm_error err = {0};
        cr_assert_eq(dm_ref_frame_render_desc(&d, &o, f[i], &err), DM_OK, "%s", err.detail);
    }
    cr_assert_eq(memcmp(f[2], f[3], n * sizeof *f[2]), 0, "1 and 3 threads differ");
    int64_t refined = 0, coarse = 0;
    for (size_t p = 0; p < n / 4; ++p) {
        const float *r = f[2] + 4 * p;
        if (!memcmp(r, f[1] + 4 * p, 4 * sizeof *r) && memcmp(r, f[0] + 4 * p, 4 * sizeof *r)) ++refined;
        else if (!memcmp(r, f[0] + 4 * p, 4 * sizeof *r)) ++coarse;
        else cr_assert(0, "pixel %zu is neither the 2² nor the 5² frame's", p);
    }
    cr_log_info("refine: %lld of %lld skin pixels refined", (long long)st[2].refined_pixels, (long long)st[2].skin_pixels);
    cr_expect(st[2].refined_pixels > 20 && st[2].refined_pixels < st[2].skin_pixels, "%lld of %lld refined",
              (long long)st[2].refined_pixels, (long long)st[2].skin_pixels);
    cr_expect(refined > 10 && refined <= st[2].refined_pixels, "%lld pixels differ from 2² and match 5²", (long long)refined);
    /* the threshold pinned: 0.2 % refines 62 pixels here (deterministic); 0.19 % gives 65, 0.21 % 60 */
    cr_expect_eq(st[2].refined_pixels, 62, "%lld pixels refined at DM_REF_FRAME_REFINE_DEVIATION",
                 (long long)st[2].refined_pixels);
    float *x = malloc(n * sizeof *x);
    dm_ref_frame_options bad = {.width = W, .height = H, .atlas_size = 64, .pixel_samples = 3, .refine_samples = 3};
    dm_error err = {0};
    cr_expect_eq(dm_ref_frame_render_desc(&d, &bad, x, &err), DM_ERR_RANGE, "refine 3 over 3 pixel samples");
    free(x);
    for (int i = 0; i < 4; ++i) free(f[i]);
    synth_free(&sy);
}
