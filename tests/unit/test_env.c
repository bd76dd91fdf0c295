/* Environment bake: direction convention, SH projection, prefiltering, background,
 * input refusal and the output file. Every map is a small synthetic one written through
 * dm_exr_write into a temporary folder and read back through OpenImageIO, as the tool does. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bake/dm_env_bake.h"
#include "bake/dm_env_prefilter.h"
#include "bake/dm_env_sh.h"
#include "bake/dm_envmap.h"
#include "image/dm_exr.h"
#include "core/dm_equirect.h"
#include "core/dm_math.h"
#include "core/dm_sh.h"

/* ---- helpers ------------------------------------------------------------------------ */

static char tmpdir[256];

static void make_tmpdir(void)
{
    snprintf(tmpdir, sizeof tmpdir, "/tmp/dermis-test-env-XXXXXX");
    cr_assert_not_null(mkdtemp(tmpdir));
}

static void remove_tmpdir(void)
{
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "warning: could not remove %s\n", tmpdir);
}

TestSuite(env, .init = make_tmpdir, .fini = remove_tmpdir);

/* rgb: w*h*3 interleaved, bottom-up. Writes NAME.exr in tmpdir, returns its path. */
static const char *write_map(const char *name, const float *rgb, int w, int h)
{
    static char path[512];
    snprintf(path, sizeof path, "%s/%s.exr", tmpdir, name);
    size_t n = (size_t)w * h;
    float *planes = malloc(n * 3 * sizeof(float));
    for (size_t k = 0; k < n; ++k)
        for (int c = 0; c < 3; ++c) planes[c * n + k] = rgb[k * 3 + c];
    dm_exr_channel ch[3] = {{"R", planes, DM_EXR_FLOAT}, {"G", planes + n, DM_EXR_FLOAT},
                            {"B", planes + 2 * n, DM_EXR_FLOAT}};
    dm_provenance prov;
    dm_prov_init(&prov, "test_env");
    dm_error err = {0};
    dm_result r = dm_exr_write(path, w, h, ch, 3, &prov, &err);
    free(planes);
    cr_assert_eq(r, DM_OK, "%s", err.detail);
    return path;
}

static float *filled(int w, int h, float v)
{
    float *p = malloc((size_t)w * h * 3 * sizeof(float));
    for (size_t k = 0; k < (size_t)w * h * 3; ++k) p[k] = v;
    return p;
}

static void load(const char *path, dm_envmap *map)
{
    dm_error err = {0};
    cr_assert_eq(dm_envmap_load(path, DM_ENVMAP_NEGATIVE_TOLERANCE_DEFAULT, map, &err), DM_OK, "%s", err.detail);
}

static void set_texel(float *p, int w, int i, int j, float r, float g, float b)
{
    p[((size_t)j * w + i) * 3 + 0] = r;
    p[((size_t)j * w + i) * 3 + 1] = g;
    p[((size_t)j * w + i) * 3 + 2] = b;
}

/* The test's own basis, from the formulas in core/dm_sh.h's comment (independent of the
 * separable integrals in bake/dm_env_sh.c). */
static void basis_ref(const double d[3], double y[9])
{
    double x = d[0], yy = d[1], z = d[2];
    double c0 = 0.5 / sqrt(DM_PI), c1 = sqrt(3.0 / (4 * DM_PI)), c2 = sqrt(15.0 / (4 * DM_PI)),
           c3 = sqrt(5.0 / (16 * DM_PI)), c4 = sqrt(15.0 / (16 * DM_PI));
    double v[9] = {c0, c1 * yy, c1 * z, c1 * x, c2 * x * yy, c2 * yy * z, c3 * (3 * z * z - 1), c2 * x * z,
                   c4 * (x * x - yy * yy)};
    memcpy(y, v, sizeof v);
}

/* ---- direction convention ------------------------------------------------------------ */

Test(env, equirect_axes_and_round_trip)
{
    double d[3];
    dm_equirect_dir(0.5, 0.5, d); /* image centre looks along −Z */
    cr_assert(fabs(d[0]) < 1e-15 && fabs(d[1]) < 1e-15 && fabs(d[2] + 1) < 1e-15);
    dm_equirect_dir(0.75, 0.5, d); /* +X */
    cr_assert(fabs(d[0] - 1) < 1e-15);
    dm_equirect_dir(0.3, 1.0, d); /* top row is +Y */
    cr_assert(fabs(d[1] - 1) < 1e-15);
    for (int k = 0; k < 50; ++k) {
        double u = (k + 0.37) / 50, v = 0.01 + 0.98 * ((k * 7) % 50) / 50.0, uu, vv;
        dm_equirect_dir(u, v, d);
        dm_equirect_uv(d, &uu, &vv);
        cr_assert(fabs(u - uu) < 1e-12 && fabs(v - vv) < 1e-12, "(%g, %g) came back as (%g, %g)", u, v, uu, vv);
    }
}

Test(env, texel_solid_angles_sum_to_4pi)
{
    for (int h = 1; h <= 512; h *= 8) {
        double s = 0;
        for (int j = 0; j < h; ++j) s += 2 * h * dm_equirect_texel_solid_angle(j, 2 * h, h);
        cr_assert(fabs(s - 4 * DM_PI) < 1e-12, "%dx%d sums to %.15g", 2 * h, h, s);
    }
}

/* ---- SH -------------------------------------------------------------------------------- */

/* White furnace: uniform L gives E(n) = π L everywhere. The projection integrates every
 * texel exactly, so only rounding remains (≈ 1e-15 relative); 1e-4 is the issue's bound. */
static void furnace_sh(float value, int w, double rotate)
{
    float *px = filled(w, w / 2, value);
    dm_envmap map;
    load(write_map("white", px, w, w / 2), &map);
    free(px);
    double sh[9][3];
    dm_error err = {0};
    cr_assert_eq(dm_env_project_sh9(&map, rotate, 2, sh, &err), DM_OK);
    for (int c = 0; c < 3; ++c) {
        cr_assert(fabs(sh[0][c] / (2 * sqrt(DM_PI) * value) - 1) < 1e-12, "L00 = %.17g", sh[0][c]);
        for (int k = 1; k < 9; ++k) cr_assert(fabs(sh[k][c]) < 1e-12 * value, "L%d = %g", k, sh[k][c]);
    }
    for (int k = 0; k < 64; ++k) {
        double n[3];
        dm_equirect_dir((k + 0.5) / 64, ((k * 37) % 64 + 0.5) / 64, n);
        double e[3];
        dm_sh9_irradiance((const double(*)[3])sh, n, e);
        for (int c = 0; c < 3; ++c)
            cr_assert(fabs(e[c] / (DM_PI * value) - 1) < 1e-4, "E = %.9g, expected pi * %g", e[c], value);
    }
    dm_envmap_free(&map);
}

Test(env, white_furnace_sh_irradiance_is_pi_L)
{
    furnace_sh(1.0f, 64, 0.0);
    furnace_sh(1.0f, 8, 0.0);   /* exact at any size, even 8x4 */
    furnace_sh(0.73f, 64, 33.3); /* and any rotation */
}

Test(env, white_furnace_sh_at_1e6)
{
    furnace_sh(1e6f, 64, 0.0);
}

/* One bright texel: its coefficients are L ∫_texel Y_k dω. Reference: the test's basis
 * integrated over the texel's spherical rectangle by a 64 × 64 midpoint rule in (θ, φ)
 * with weight sin θ (error O(h²) ≈ (0.05 rad / 64)² ≈ 1e-6 relative). The closed form of
 * a point source, L Ω Y_k(centre), holds to second order in the texel's size
 * (0.05 rad here: about 3e-3 of L Ω max|Y|). */
Test(env, single_bright_texel_sh_matches_closed_form)
{
    const int w = 128, h = 64, ti = 37, tj = 45;
    const float L = 1000.0f;
    float *px = filled(w, h, 0.0f);
    set_texel(px, w, ti, tj, L, 2 * L, 0.5f * L);
    dm_envmap map;
    load(write_map("texel", px, w, h), &map);
    free(px);
    double sh[9][3];
    cr_assert_eq(dm_env_project_sh9(&map, 0.0, 1, sh, NULL), DM_OK);

    double ref[9] = {0};
    const int sub = 64;
    double th0 = DM_PI * (1.0 - (tj + 1.0) / h), th1 = DM_PI * (1.0 - (double)tj / h);
    double ph0 = DM_2PI * ((double)ti / w - 0.5), ph1 = DM_2PI * ((ti + 1.0) / w - 0.5);
    for (int a = 0; a < sub; ++a)
        for (int b = 0; b < sub; ++b) {
            double th = th0 + (th1 - th0) * (a + 0.5) / sub, ph = ph0 + (ph1 - ph0) * (b + 0.5) / sub;
            double d[3] = {sin(th) * sin(ph), cos(th), -sin(th) * cos(ph)}, y[9];
            basis_ref(d, y);
            double dw = sin(th) * (th1 - th0) / sub * (ph1 - ph0) / sub;
            for (int k = 0; k < 9; ++k) ref[k] += y[k] * dw;
        }
    double omega = dm_equirect_texel_solid_angle(tj, w, h), centre[3], yc[9];
    dm_equirect_dir((ti + 0.5) / w, (tj + 0.5) / h, centre);
    basis_ref(centre, yc);
    const double scale[3] = {1, 2, 0.5};
    for (int k = 0; k < 9; ++k)
        for (int c = 0; c < 3; ++c) {
            double lc = L * scale[c];
            cr_assert(fabs(sh[k][c] - lc * ref[k]) < 1e-6 * lc * omega, "L%d[%d] = %.12g, quadrature %.12g", k, c,
                      sh[k][c], lc * ref[k]);
            cr_assert(fabs(sh[k][c] - lc * omega * yc[k]) < 3e-3 * lc * omega, "L%d[%d] = %.9g, point source %.9g",
                      k, c, sh[k][c], lc * omega * yc[k]);
        }
    dm_envmap_free(&map);
}

/* Rotating by a quarter turn is the same as moving the texel a quarter of the width to
 * the left (core/dm_equirect.h: the rotated map samples the source at u + α/2π). */
Test(env, sh_rotation_matches_moved_texel)
{
    const int w = 64, h = 32;
    float *a = filled(w, h, 0.0f), *b = filled(w, h, 0.0f);
    set_texel(a, w, 40, 20, 5, 5, 5);
    set_texel(b, w, 40 - w / 4, 20, 5, 5, 5);
    dm_envmap ma, mb;
    cr_assert_eq(dm_envmap_from_pixels(a, w, h, 3, 0.0, "a", &ma, NULL), DM_OK);
    cr_assert_eq(dm_envmap_from_pixels(b, w, h, 3, 0.0, "b", &mb, NULL), DM_OK);
    double sa[9][3], sb[9][3];
    dm_env_project_sh9(&ma, 90.0, 1, sa, NULL);
    dm_env_project_sh9(&mb, 0.0, 1, sb, NULL);
    for (int k = 0; k < 9; ++k) cr_assert(fabs(sa[k][0] - sb[k][0]) < 1e-12, "L%d: %g vs %g", k, sa[k][0], sb[k][0]);
    free(a);
    free(b);
    dm_envmap_free(&ma);
    dm_envmap_free(&mb);
}

/* ---- prefiltering ----------------------------------------------------------------------- */

/* Uniform L: every sample reads L and the weights are normalised, so every level is L up
 * to float rounding of the running sums (relative 1e-6). */
Test(env, white_furnace_prefilter_levels_equal_input)
{
    const float values[2] = {1.0f, 1e6f};
    for (int t = 0; t < 2; ++t) {
        float *px = filled(64, 32, values[t]);
        dm_envmap map;
        load(write_map("white", px, 64, 32), &map);
        free(px);
        dm_env_options opt = {.samples = 64, .check_texels = -1, .threads = 2};
        dm_env_bake bake;
        dm_error err = {0};
        cr_assert_eq(dm_env_bake_run(&map, &opt, &bake, &err), DM_OK, "%s", err.detail);
        for (int k = 0; k < bake.level_count; ++k) {
            const dm_env_level *lv = &bake.levels[k];
            for (size_t q = 0; q < (size_t)lv->width * lv->height * 3; ++q)
                cr_assert(fabs(lv->rgb[q] / values[t] - 1) < 1e-6, "level %d (m %g) texel %zu = %.9g", k, lv->m,
                          q / 3, lv->rgb[q]);
        }
        for (size_t q = 0; q < (size_t)bake.background_width * bake.background_height * 3; ++q)
            cr_assert_eq(bake.background[q], values[t]);
        dm_env_bake_free(&bake);
        dm_envmap_free(&map);
    }
}

/* A 1e6 sun over a unit sky: nothing overflows, SH L00 is the exact sum, every prefiltered
 * texel is finite, ≥ 0 and at most the sun. */
Test(env, huge_sun_stays_finite)
{
    const int w = 128, h = 64;
    float *px = filled(w, h, 1.0f);
    for (int i = 60; i < 62; ++i)
        for (int j = 50; j < 52; ++j) set_texel(px, w, i, j, 1e6f, 1e6f, 1e6f);
    dm_envmap map;
    load(write_map("sun", px, w, h), &map);
    free(px);
    dm_env_options opt = {.samples = 256, .check_texels = 8, .threads = 2};
    dm_env_bake bake;
    dm_error err = {0};
    cr_assert_eq(dm_env_bake_run(&map, &opt, &bake, &err), DM_OK, "%s", err.detail);
    double sun_sa = 2 * (dm_equirect_texel_solid_angle(50, w, h) + dm_equirect_texel_solid_angle(51, w, h));
    double l00 = (4 * DM_PI + (1e6 - 1) * sun_sa) * 0.28209479177387814;
    cr_assert(fabs(bake.sh[0][0] / l00 - 1) < 1e-12, "L00 %.17g expected %.17g", bake.sh[0][0], l00);
    for (int k = 0; k < 9; ++k) cr_assert(isfinite(bake.sh[k][1]));
    for (int k = 0; k < bake.level_count; ++k) {
        const dm_env_level *lv = &bake.levels[k];
        for (size_t q = 0; q < (size_t)lv->width * lv->height * 3; ++q)
            cr_assert(isfinite(lv->rgb[q]) && lv->rgb[q] >= 0.0f && lv->rgb[q] <= 1e6f, "level %d: %g", k, lv->rgb[q]);
        cr_assert(isfinite(lv->error.rms_rel) && isfinite(lv->error.max_rel));
    }
    dm_env_bake_free(&bake);
    dm_envmap_free(&map);
}

/* A linear environment L(d) = 1 + 0.5 d·a is smooth, so 256 samples must match the exact
 * quadrature closely: 1 % is several times the error measured (≈ 0.2 %). */
Test(env, prefilter_matches_reference_on_smooth_map)
{
    const int w = 128, h = 64;
    float *px = malloc((size_t)w * h * 3 * sizeof(float));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            double d[3];
            dm_equirect_dir((i + 0.5) / w, (j + 0.5) / h, d);
            set_texel(px, w, i, j, (float)(1 + 0.5 * d[0]), (float)(1 + 0.5 * d[1]), (float)(1 + 0.5 * d[2]));
        }
    dm_envmap map;
    cr_assert_eq(dm_envmap_from_pixels(px, w, h, 3, 0.0, "linear", &map, NULL), DM_OK);
    free(px);
    const double ms[] = {0.1, 0.4, 1.0};
    for (int t = 0; t < 3; ++t) {
        int lw = dm_env_level_width(ms[t], 64, w);
        float *out = malloc((size_t)lw * lw / 2 * 3 * sizeof(float));
        cr_assert_eq(dm_env_prefilter(&map, ms[t], 256, 0.0, lw, 2, out, NULL), DM_OK);
        dm_env_error e;
        dm_env_prefilter_error(&map, ms[t], 0.0, out, lw, 64, 2, &e);
        cr_assert(e.max_rel < 0.01, "m %g: max error %g at (%g, %g)", ms[t], e.max_rel, e.worst_u, e.worst_v);
        free(out);
    }
    dm_envmap_free(&map);
}

/* m → 0: the lobe shrinks to the mirror direction, so the level reproduces the map. On
 * the linear map above the lobe average differs from L(r) by O(m²) = 1e-4; 1e-3 leaves
 * room for the bilinear reconstruction between texel centres (linear data: exact but for
 * the pole rows, which are clamped). */
Test(env, prefilter_small_m_is_mirror)
{
    const int w = 64, h = 32;
    float *px = malloc((size_t)w * h * 3 * sizeof(float));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            double d[3];
            dm_equirect_dir((i + 0.5) / w, (j + 0.5) / h, d);
            set_texel(px, w, i, j, (float)(1 + 0.5 * d[0]), (float)(1 + 0.5 * d[1]), (float)(1 + 0.5 * d[2]));
        }
    dm_envmap map;
    cr_assert_eq(dm_envmap_from_pixels(px, w, h, 3, 0.0, "linear", &map, NULL), DM_OK);
    float *out = malloc((size_t)w * h * 3 * sizeof(float));
    cr_assert_eq(dm_env_prefilter(&map, DM_ENV_M_MIN, 64, 0.0, w, 1, out, NULL), DM_OK);
    for (int j = 1; j < h - 1; ++j)
        for (int i = 0; i < w; ++i)
            for (int c = 0; c < 3; ++c) {
                float got = out[((size_t)j * w + i) * 3 + c], want = px[((size_t)j * w + i) * 3 + c];
                cr_assert(fabs(got - want) < 1e-3, "texel (%d, %d)[%d] %g, map %g", i, j, c, got, want);
            }
    free(px);
    free(out);
    dm_envmap_free(&map);
}

/* The same bake on 1 and 2 threads gives identical bytes. */
Test(env, bake_is_deterministic_across_threads)
{
    const int w = 64, h = 32;
    float *px = filled(w, h, 0.5f);
    set_texel(px, w, 10, 20, 300, 200, 100);
    dm_envmap map;
    cr_assert_eq(dm_envmap_from_pixels(px, w, h, 3, 0.0, "det", &map, NULL), DM_OK);
    free(px);
    dm_env_bake a, b;
    dm_env_options o1 = {.samples = 32, .check_texels = -1, .threads = 1, .rotate_deg = 17};
    dm_env_options o2 = o1;
    o2.threads = 2;
    cr_assert_eq(dm_env_bake_run(&map, &o1, &a, NULL), DM_OK);
    cr_assert_eq(dm_env_bake_run(&map, &o2, &b, NULL), DM_OK);
    cr_assert(!memcmp(a.sh, b.sh, sizeof a.sh));
    for (int k = 0; k < a.level_count; ++k)
        cr_assert(!memcmp(a.levels[k].rgb, b.levels[k].rgb, (size_t)a.levels[k].width * a.levels[k].height * 12));
    cr_assert(!memcmp(a.background, b.background, (size_t)a.background_width * a.background_height * 12));
    dm_env_bake_free(&a);
    dm_env_bake_free(&b);
    dm_envmap_free(&map);
}

/* ---- background ------------------------------------------------------------------------- */

Test(env, background_copy_rotation_and_downsize)
{
    const int w = 64, h = 32;
    float *px = malloc((size_t)w * h * 3 * sizeof(float));
    for (size_t k = 0; k < (size_t)w * h * 3; ++k) px[k] = (float)((k * 7919) % 1000) / 10.0f;
    dm_envmap map;
    cr_assert_eq(dm_envmap_from_pixels(px, w, h, 3, 0.0, "bg", &map, NULL), DM_OK);
    float *out = malloc((size_t)w * h * 3 * sizeof(float));
    dm_env_background(&map, w, 0.0, 1, out);
    cr_assert(!memcmp(out, px, (size_t)w * h * 12), "same size, no rotation: an exact copy");
    /* +90°: the rotated map at u samples the source at u + 1/4: column i reads i + w/4. */
    dm_env_background(&map, w, 90.0, 1, out);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            cr_assert_eq(out[((size_t)j * w + i) * 3], px[((size_t)j * w + (i + w / 4) % w) * 3]);
    /* Half size: the 2×2 box average. */
    dm_env_background(&map, w / 2, 0.0, 1, out);
    for (int j = 0; j < h / 2; ++j)
        for (int i = 0; i < w / 2; ++i) {
            double s = 0;
            for (int q = 0; q < 4; ++q) s += px[((size_t)(2 * j + q / 2) * w + 2 * i + q % 2) * 3];
            cr_assert(fabs(out[((size_t)j * (w / 2) + i) * 3] - 0.25 * s) < 1e-4);
        }
    free(px);
    free(out);
    dm_envmap_free(&map);
}

/* ---- refused inputs ---------------------------------------------------------------------- */

static void expect_refused(const char *name, float *px, int w, int h, double tol, dm_result code, const char *where)
{
    const char *path = write_map(name, px, w, h);
    dm_envmap map;
    dm_error err = {0};
    cr_assert_eq(dm_envmap_load(path, tol, &map, &err), code, "%s: got %s: %s", name, dm_result_name(err.code),
                 err.detail);
    cr_assert_not_null(strstr(err.detail, where), "message '%s' does not name %s", err.detail, where);
    cr_assert_not_null(strstr(err.detail, path), "message '%s' does not name the file", err.detail);
    dm_envmap_free(&map);
}

/* Memory row j is file row h − 1 − j: texel (5, 3) of a 16 × 8 map is x=5, y=4 in the file. */
Test(env, negative_texel_refused_with_position)
{
    float *px = filled(16, 8, 1.0f);
    set_texel(px, 16, 5, 3, 1.0f, -1.0f, 1.0f);
    expect_refused("negative", px, 16, 8, DM_ENVMAP_NEGATIVE_TOLERANCE_DEFAULT, DM_ERR_RANGE, "(x=5, y=4) channel G");
    free(px);
}

Test(env, small_negative_clamped_within_tolerance_refused_without)
{
    float *px = filled(16, 8, 1.0f);
    set_texel(px, 16, 2, 7, -0.001f, 1.0f, 1.0f);
    const char *path = write_map("ringing", px, 16, 8);
    dm_envmap map;
    dm_error err = {0};
    cr_assert_eq(dm_envmap_load(path, 0.01, &map, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(map.clamped_texels, 1);
    cr_assert(map.most_negative_x == 2 && map.most_negative_y == 0 && fabs(map.most_negative + 0.001) < 1e-9);
    cr_assert_eq(map.level[0][((size_t)7 * 16 + 2) * 3], 0.0f);
    dm_envmap_free(&map);
    expect_refused("ringing", px, 16, 8, 0.0, DM_ERR_RANGE, "(x=2, y=0) channel R");
    free(px);
}

Test(env, nan_texel_refused_with_position)
{
    float *px = filled(16, 8, 1.0f);
    set_texel(px, 16, 15, 0, 1.0f, 1.0f, NAN);
    expect_refused("nan", px, 16, 8, 0.01, DM_ERR_NON_FINITE, "(x=15, y=7) channel B is NaN");
    free(px);
}

Test(env, inf_texel_refused_with_position)
{
    float *px = filled(16, 8, 1.0f);
    set_texel(px, 16, 0, 7, INFINITY, 1.0f, 1.0f);
    expect_refused("inf", px, 16, 8, 0.01, DM_ERR_NON_FINITE, "(x=0, y=0) channel R is infinite");
    free(px);
}

Test(env, non_2to1_refused)
{
    const int sizes[][2] = {{16, 16}, {17, 8}, {16, 9}, {8, 16}};
    for (int t = 0; t < 4; ++t) {
        float *px = filled(sizes[t][0], sizes[t][1], 1.0f);
        expect_refused("square", px, sizes[t][0], sizes[t][1], 0.01, DM_ERR_FORMAT, "2:1");
        free(px);
    }
}

Test(env, unreadable_input_refused)
{
    char path[512];
    snprintf(path, sizeof path, "%s/missing.hdr", tmpdir);
    dm_envmap map;
    dm_error err = {0};
    cr_assert_neq(dm_envmap_load(path, 0.01, &map, &err), DM_OK);
    cr_assert_not_null(strstr(err.detail, path));
    dm_envmap_free(&map);
}

Test(env, bad_options_refused)
{
    float *px = filled(16, 8, 1.0f);
    dm_envmap map;
    cr_assert_eq(dm_envmap_from_pixels(px, 16, 8, 3, 0.0, "opt", &map, NULL), DM_OK);
    free(px);
    dm_env_bake bake;
    dm_env_options bad[] = {{.samples = -1}, {.level_count = DM_ENV_LEVEL_MAX + 1}, {.background_width = 7},
                            {.roughness_count = 2, .roughness = {0.5, 0.4}}, {.roughness_count = 1, .roughness = {0}}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        dm_error err = {0};
        cr_assert_eq(dm_env_bake_run(&map, &bad[k], &bake, &err), DM_ERR_RANGE, "options %zu accepted", k);
        dm_env_bake_free(&bake);
    }
    dm_envmap_free(&map);
}

/* ---- the output file ----------------------------------------------------------------------- */

Test(env, write_read_round_trip)
{
    const int w = 64, h = 32;
    float *px = filled(w, h, 0.25f);
    set_texel(px, w, 3, 4, 70000, 10, 1); /* above half-float range: must survive */
    dm_envmap map;
    cr_assert_eq(dm_envmap_from_pixels(px, w, h, 3, 0.0, "rt", &map, NULL), DM_OK);
    free(px);
    dm_env_options opt = {.samples = 16, .check_texels = 4, .roughness_count = 3, .roughness = {0.1, 0.5, 1.0},
                          .background_width = 32};
    dm_env_bake bake, back;
    dm_error err = {0};
    cr_assert_eq(dm_env_bake_run(&map, &opt, &bake, &err), DM_OK, "%s", err.detail);
    dm_provenance prov, got;
    dm_prov_init(&prov, "test_env");
    dm_prov_add_int(&prov, "samples", 16);
    char path[512];
    snprintf(path, sizeof path, "%s/out.env.exr", tmpdir);
    cr_assert_eq(dm_env_write(path, &bake, &prov, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_env_read(path, &back, &got, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(back.level_count, 3);
    cr_assert_eq(back.samples, 16);
    cr_assert_eq(back.background_width, 32);
    for (int k = 0; k < 9; ++k)
        for (int c = 0; c < 3; ++c) cr_assert_eq(back.sh[k][c], (double)(float)bake.sh[k][c]);
    cr_assert(!memcmp(back.background, bake.background, 32 * 16 * 12));
    for (int k = 0; k < 3; ++k) {
        cr_assert_eq(back.levels[k].m, bake.levels[k].m);
        cr_assert_eq(back.levels[k].width, bake.levels[k].width);
        cr_assert_eq(back.levels[k].error.rms_rel, bake.levels[k].error.rms_rel);
        cr_assert(!memcmp(back.levels[k].rgb, bake.levels[k].rgb,
                          (size_t)bake.levels[k].width * bake.levels[k].height * 12));
    }
    cr_assert_not_null(dm_prov_find(&got, "level2_m"));
    dm_env_bake_free(&bake);
    dm_env_bake_free(&back);
    dm_envmap_free(&map);
}
