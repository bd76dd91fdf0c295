/* LUT bakes: the Beckmann PNG texel by texel, orientation by values, saturation, the
 * directional tables' finiteness, determinism, and dermis-bake-lut's behaviour as a tool. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <unistd.h>

#include "../common/png_inflate.h"
#include "../common/tmpdir.h"
#include "image/dm_exr.h"
#include "image/dm_image.h"
#include "bake/dm_lut.h"
#include "core/dm_brdf.h"
#include "core/dm_prov.h"

#define BIN DERMIS_BIN "/dermis-bake-lut"

/* Independent D in long double, and its exact 8-bit code before rounding. */
static long double code_exact(long double c, long double m)
{
    long double c2 = c * c;
    long double d = expl((c2 - 1.0L) / (c2 * m * m)) / (m * m * c2 * c2);
    long double v = 255.0L * 0.5L * powl(d, 0.1L);
    return v > 255.0L ? 255.0L : v;
}

Test(beckmann_png, every_texel_within_quantisation)
{
    char dir[64], path[128], cmd[512];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(cmd, sizeof cmd, BIN " -o %s --tables beckmann --quiet", dir);
    cr_assert_eq(test_run(cmd, NULL), 0);
    snprintf(path, sizeof path, "%s/beckmann.png", dir);
    int w, h, ch, bits;
    uint16_t *px = tpng_read(path, &w, &h, &ch, &bits);
    cr_assert(px, "independent decoder could not read %s", path);
    cr_assert(w == 512 && h == 512 && ch == 1 && bits == 8);
    /* File row y (top-down) holds t = m = (h − 1 − y + 0.5)/h: v = 0 is the bottom row. */
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            long double c = (x + 0.5L) / w, m = (h - 1 - y + 0.5L) / h;
            long double want = code_exact(c, m);
            int got = px[(size_t)y * w + x];
            /* the quantisation bound: round to nearest is within half a step */
            cr_assert(fabsl(got - want) <= 0.5L + 1e-9L, "texel (%d, %d) N.H=%Lg m=%Lg: %d, exact %.6Lf", x, y, c, m,
                      got, want);
        }
    free(px);
}

Test(beckmann_png, orientation_by_values)
{
    char dir[64], path[128], cmd[512];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(cmd, sizeof cmd, BIN " -o %s --tables beckmann --size 64x32 --quiet", dir);
    cr_assert_eq(test_run(cmd, NULL), 0);
    snprintf(path, sizeof path, "%s/beckmann.png", dir);
    int w, h, ch, bits;
    uint16_t *px = tpng_read(path, &w, &h, &ch, &bits);
    cr_assert(px && w == 64 && h == 32, "size WxH is width (N.H) by height (m)");
    /* Top-right of the file: N.H ≈ 1, m ≈ 1 → D ≈ 1, code ≈ 127.5. Bottom-right: m ≈ 0.016,
     * N.H = 1 − 1/128 → D = exp(−61)/m²: tiny, code 12. Left column: N.H ≈ 0 → 0. */
    cr_expect_eq(px[63], (int)lroundl(code_exact(63.5L / 64, 31.5L / 32)));
    cr_expect(px[63] >= 127 && px[63] <= 128);
    cr_expect_eq(px[31 * 64 + 63], (int)lroundl(code_exact(63.5L / 64, 0.5L / 32)));
    cr_expect_lt(px[31 * 64 + 63], 60);
    for (int y = 0; y < 32; ++y) cr_expect_eq(px[y * 64], 0, "N.H = 1/128 column is zero at row %d", y);
    /* and the library's reader (bottom-up rows) agrees with the file's top-down rows */
    dm_image img;
    dm_error err = {0};
    cr_assert_eq(dm_image_read(path, DM_PIXEL_U8, &img, &err), DM_OK, "%s", err.detail);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x) cr_assert_eq(((uint8_t *)img.pixels)[(31 - y) * 64 + x], px[y * 64 + x]);
    cr_expect(img.has_provenance);
    cr_expect_str_eq(img.prov.tool, "dermis-bake-lut");
    cr_expect_eq(dm_prov_find(&img.prov, "width")->i, 64);
    cr_expect_eq(dm_prov_find(&img.prov, "height")->i, 32);
    dm_image_free(&img);
    free(px);
}

Test(beckmann_lut, hard_case_saturation_counted)
{
    /* 8192 wide puts texel centres within 6e-5 of N.H = 1; rows with m < 1/32 then exceed
     * D = 1024 and must saturate at 255, and be counted. */
    dm_beckmann_lut lut;
    dm_error err = {0};
    cr_assert_eq(dm_lut_bake_beckmann(8192, 64, 0, 0, &lut, &err), DM_OK);
    int64_t count = 0;
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 8192; ++i) {
            double d = dm_beckmann((i + 0.5) / 8192, (j + 0.5) / 64);
            if (d >= 1024.0) {
                ++count;
                cr_assert_eq(lut.texels[(size_t)j * 8192 + i], 255);
            }
        }
    cr_expect_gt(count, 0);
    cr_expect_eq(lut.saturated_texels, count);
    cr_expect_gt(lut.clipped_rows, 0);
    cr_expect_lt(lut.max_clipped_m, 1.0 / 32.0);
    dm_beckmann_lut_free(&lut);
}

Test(beckmann_lut, exact_float_copy_is_finite)
{
    dm_beckmann_lut lut;
    cr_assert_eq(dm_lut_bake_beckmann(256, 256, 1, 0, &lut, NULL), DM_OK);
    for (int k = 0; k < 256 * 256; ++k) cr_assert(isfinite(lut.exact[k]) && lut.exact[k] >= 0.0f);
    dm_beckmann_lut_free(&lut);
}

Test(directional_lut, finite_everywhere_including_tiny_sizes)
{
    const int sizes[][2] = {{2, 2}, {3, 7}, {64, 64}, {128, 16}};
    for (int k = 0; k < 4; ++k) {
        dm_directional_lut lut;
        dm_error err = {0};
        cr_assert_eq(dm_lut_bake_directional(sizes[k][0], sizes[k][1], 0.028, 16, 0, &lut, &err), DM_OK, "%s",
                     err.detail);
        for (int i = 0; i < sizes[k][0] * sizes[k][1]; ++i) {
            cr_assert(isfinite(lut.rho_dt[i]) && lut.rho_dt[i] >= 0.0f);
            cr_assert(isfinite(lut.scale[i]) && lut.scale[i] >= 0.0f);
            cr_assert(isfinite(lut.bias[i]) && lut.bias[i] >= 0.0f);
        }
        dm_directional_lut_free(&lut);
    }
}

Test(directional_lut, texels_match_reference)
{
    /* each texel of the default 64² table against a 96-node evaluation at its centre: the
     * issue's 1e-3 absolute requirement, with room (measured max 4.5e-5) */
    dm_directional_lut lut;
    cr_assert_eq(dm_lut_bake_directional(64, 64, 0.028, DM_LUT_NODES_DEFAULT, 0, &lut, NULL), DM_OK);
    for (int j = 0; j < 64; j += 3)
        for (int i = 0; i < 64; i += 3) {
            double ref = dm_rho_dt((i + 0.5) / 64, (j + 0.5) / 64, 0.028, 96);
            cr_assert(fabs(lut.rho_dt[j * 64 + i] - ref) < 1e-3, "(%d, %d): %g vs %g", i, j, lut.rho_dt[j * 64 + i],
                      ref);
        }
    dm_directional_lut_free(&lut);
}

Test(lut, bad_sizes_refused)
{
    dm_beckmann_lut b;
    dm_directional_lut d;
    dm_error err = {0};
    cr_expect_eq(dm_lut_bake_beckmann(0, 16, 0, 0, &b, &err), DM_ERR_RANGE);
    cr_expect(strstr(err.detail, "0x16") != NULL, "%s", err.detail);
    cr_expect_eq(dm_lut_bake_beckmann(16, DM_LUT_SIZE_MAX + 1, 0, 0, &b, &err), DM_ERR_RANGE);
    cr_expect_eq(dm_lut_bake_directional(16, 16, 1.5, 32, 0, &d, &err), DM_ERR_RANGE);
    cr_expect_eq(dm_lut_bake_directional(16, 16, NAN, 32, 0, &d, &err), DM_ERR_RANGE);
    cr_expect_eq(dm_lut_bake_directional(16, 16, 0.028, 4, 0, &d, &err), DM_ERR_RANGE);
}

static int files_equal(const char *a, const char *b)
{
    char *x = test_slurp(a), *y = test_slurp(b);
    FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
    long na = -1, nb = -2;
    if (fa && fb) {
        fseek(fa, 0, SEEK_END);
        fseek(fb, 0, SEEK_END);
        na = ftell(fa);
        nb = ftell(fb);
    }
    if (fa) fclose(fa);
    if (fb) fclose(fb);
    int same = x && y && na == nb && memcmp(x, y, (size_t)na) == 0;
    free(x);
    free(y);
    return same;
}

Test(tool, deterministic_across_runs_and_threads)
{
    char d1[64], d2[64], cmd[512], a[160], b[160];
    cr_assert(test_tmpdir(d1, sizeof d1) && test_tmpdir(d2, sizeof d2));
    snprintf(cmd, sizeof cmd, BIN " -o %s --quiet --size 128 --rho-dt-size 16 --threads 1 --float %s/d.exr", d1, d1);
    cr_assert_eq(test_run(cmd, NULL), 0);
    snprintf(cmd, sizeof cmd, BIN " -o %s --quiet --size 128 --rho-dt-size 16 --threads 2 --float %s/d.exr", d2, d2);
    cr_assert_eq(test_run(cmd, NULL), 0);
    const char *names[] = {"beckmann.png", "rho_dt.exr", "env_brdf.exr", "d.exr"};
    for (int k = 0; k < 4; ++k) {
        snprintf(a, sizeof a, "%s/%s", d1, names[k]);
        snprintf(b, sizeof b, "%s/%s", d2, names[k]);
        cr_expect(files_equal(a, b), "%s differs between runs", names[k]);
    }
}

Test(tool, exr_outputs_carry_provenance_and_true_values)
{
    char dir[64], cmd[512], path[160];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(cmd, sizeof cmd, BIN " -o %s --quiet --tables rho_dt,env_brdf --rho-dt-size 32", dir);
    cr_assert_eq(test_run(cmd, NULL), 0);
    snprintf(path, sizeof path, "%s/rho_dt.exr", dir);
    dm_exr_image img;
    dm_error err = {0};
    cr_assert_eq(dm_exr_read(path, &img, &err), DM_OK, "%s", err.detail);
    cr_assert(img.has_provenance);
    cr_expect_str_eq(img.prov.tool, "dermis-bake-lut");
    cr_expect_float_eq(dm_prov_find(&img.prov, "f0")->d, 0.028, 1e-15);
    const float *r = dm_exr_find(&img, "rho_dt");
    cr_assert(r);
    /* bottom-left texel: N.L = 1/64, m = 1/64, near the m → 0 limit π F(c) ≈ 2.7 > 1:
     * stored as the true value, not clamped */
    cr_expect_gt(r[0], 1.0f);
    cr_expect(fabs(r[0] - dm_rho_dt(0.5 / 32, 0.5 / 32, 0.028, 96)) < 1e-3);
    dm_exr_free(&img);
}

Test(tool, usage_errors_exit_1)
{
    const char *bad[] = {"--size 0", "--size 9000", "--size 12x", "--f0 2", "--nodes 3", "--tables nope",
                         "--bogus", "--size", "-v --quiet", "--tables rho_dt --float x.exr", "--threads -1"};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; ++k) {
        char cmd[256];
        snprintf(cmd, sizeof cmd, BIN " -o /tmp %s", bad[k]);
        cr_expect_eq(test_run(cmd, NULL), 1, "'%s' should be a usage error", bad[k]);
    }
    cr_expect_eq(test_run(BIN " --help", NULL), 0);
}

Test(tool, unwritable_output_exit_4_and_no_partial_file)
{
    char dir[64], cmd[512], log[160];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(log, sizeof log, "%s/log", dir);
    cr_expect_eq(test_run(BIN " -o /dev/null/folder --quiet", log), 4);
    char *text = test_slurp(log);
    cr_expect(text && strstr(text, "error:") && strstr(text, "/dev/null/folder"), "message names the path: %s",
              text ? text : "");
    free(text);
    /* a folder we can write, but the second output goes where we cannot: the first file
     * may land, no temporary file may remain */
    snprintf(cmd, sizeof cmd, BIN " -o %s --quiet --rho-dt /dev/null/r.exr", dir);
    cr_expect_eq(test_run(cmd, NULL), 4);
    cr_expect_eq(test_count_files(dir, ".tmp."), 0);
}
