/* Debug views at full precision, the diffusion view, and the comparison with a reference
 * (render/dm_render_refcmp.h, dermis-render --reference), on the synthetic sphere. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../common/tmpdir.h"
#include "image/dm_exr.h"
#include "core/dm_exr_read.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_image.h"
#include "render/dm_render_legend.h"
#include "render/dm_render_refcmp.h"
#include "render/dm_render_synth.h"

#define N 128 /* irradiance size */

typedef struct fixture {
    dm_osmesa *ctx;
    dm_synth *synth;
    dm_renderer *r;
} fixture;

static void open_synth(fixture *f)
{
    dm_error err = {0};
    memset(f, 0, sizeof *f);
    dm_synth_options so = {.beckmann_size = 128, .directional_size = 16, .stretch_size = 64};
    cr_assert_eq(dm_osmesa_create(&f->ctx, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_synth_create(&so, &f->synth, &err), DM_OK, "%s", err.detail);
}

/* blur_reduce_from < 0: full-resolution levels summed per pixel (diffusion_per_pixel) */
static void open_renderer(fixture *f, int blur_reduce_from)
{
    dm_error err = {0};
    dm_render_desc d = {.width = 96, .height = 64, .irradiance_size = N, .shadow_size = 256,
                        .blur_reduce_from = blur_reduce_from > 0 ? blur_reduce_from : 0,
                        .diffusion_per_pixel = blur_reduce_from < 0};
    cr_assert_eq(dm_renderer_create(&f->synth->assets, &d, &f->r, &err), DM_OK, "%s", err.detail);
}

static void open_fixture(fixture *f, int blur_reduce_from)
{
    open_synth(f);
    open_renderer(f, blur_reduce_from);
}

static void close_fixture(fixture *f)
{
    dm_renderer_destroy(f->r);
    dm_synth_free(f->synth);
    dm_osmesa_destroy(f->ctx);
}

static float *frame_view(fixture *f, dm_view view, int index, int *w, int *h)
{
    dm_error err = {0};
    dm_frame_options o = {.view = view, .view_index = index};
    cr_assert_eq(dm_render_frame(f->r, &o, &err), DM_OK, "%s", err.detail);
    dm_renderer_view_size(f->r, w, h);
    float *px = malloc((size_t)*w * *h * 4 * sizeof *px);
    cr_assert_eq(dm_renderer_read_view(f->r, px, &err), DM_OK, "%s", err.detail);
    return px;
}

static float *target(fixture *f, const char *name, int *w, int *h)
{
    int idx = dm_renderer_find_target(f->r, name);
    cr_assert_geq(idx, 0, "no target %s", name);
    dm_target_info info;
    dm_renderer_target_info(f->r, idx, &info);
    *w = info.width, *h = info.height;
    float *px = malloc((size_t)info.width * info.height * 4 * sizeof *px);
    dm_error err = {0};
    cr_assert_eq(dm_renderer_read_target(f->r, idx, px, &err), DM_OK, "%s", err.detail);
    return px;
}

/* The irradiance view is the target itself: same size, float32, rgb bit for bit where
 * covered, alpha = the chart coverage (0 in gutters, 1 on charts). Through the EXR writer
 * and the runtime's reader too. */
Test(views, irradiance_view_is_the_target_bit_for_bit)
{
    fixture f;
    open_fixture(&f, 0);
    int w, h, tw, th;
    float *v = frame_view(&f, DM_VIEW_IRRADIANCE, 0, &w, &h);
    float *t = target(&f, "irradiance", &tw, &th);
    cr_assert_eq(w, N);
    cr_assert_eq(h, N);
    cr_assert_eq(tw, N);
    long covered = 0, gutter = 0;
    for (size_t i = 0; i < (size_t)N * N; ++i) {
        cr_assert(t[i * 4 + 3] == 0.0f || t[i * 4 + 3] == 1.0f, "irradiance alpha %g is not 0 or 1", t[i * 4 + 3]);
        cr_assert(memcmp(&v[i * 4 + 3], &t[i * 4 + 3], 4) == 0, "alpha differs at %zu", i);
        if (t[i * 4 + 3] == 1.0f) {
            ++covered;
            cr_assert(memcmp(&v[i * 4], &t[i * 4], 12) == 0, "texel %zu: view %a %a %a, target %a %a %a", i, v[i * 4],
                      v[i * 4 + 1], v[i * 4 + 2], t[i * 4], t[i * 4 + 1], t[i * 4 + 2]);
        } else {
            ++gutter;
            cr_assert(v[i * 4] == 0 && v[i * 4 + 1] == 0 && v[i * 4 + 2] == 0);
        }
    }
    cr_assert_gt(covered, N * N / 4);
    cr_assert_gt(gutter, 0, "the sphere's atlas has gutters");
    /* EXR (dm_render_write_exr, uncompressed) read back by core/dm_exr_read */
    char dir[256], path[300];
    cr_assert_not_null(test_tmpdir(dir, sizeof dir));
    snprintf(path, sizeof path, "%s/irr.exr", dir);
    dm_provenance prov;
    dm_prov_init(&prov, "test_render_views");
    dm_error err = {0};
    cr_assert_eq(dm_render_write_exr(path, w, h, v, &prov, &err), DM_OK, "%s", err.detail);
    dm_exr_file file;
    cr_assert_eq(dm_exr_load(path, &file, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(file.compression, 0);
    const float *ch[4] = {dm_exr_file_channel(&file, "R"), dm_exr_file_channel(&file, "G"),
                          dm_exr_file_channel(&file, "B"), dm_exr_file_channel(&file, "A")};
    for (size_t i = 0; i < (size_t)N * N; ++i)
        for (int c = 0; c < 4; ++c) cr_assert(memcmp(&ch[c][i], &v[i * 4 + c], 4) == 0);
    dm_exr_file_free(&file);
    remove(path);
    rmdir(dir);
    free(v);
    free(t);
    close_fixture(&f);
}

/* diffusion = sum_k w_k L_k with L_k = rgb_k / a_k (a_k > 1e-4) and w normalised per
 * channel over the levels, computed here on the CPU from the read-back targets and the
 * profile, on the charts (coverage 1); off them (coverage 0) the diffusion pass's sum is
 * zero, the view black (summed per pixel, as with reduced levels, the levels' spill shows
 * there). Tolerance: the GPU's division and multiply-add round differently
 * from the CPU (a few ulp per level, 6 levels): 2e-6 relative. */
static void check_diffusion(int blur_reduce_from)
{
    fixture f;
    open_fixture(&f, blur_reduce_from);
    int w, h;
    float *v = frame_view(&f, DM_VIEW_DIFFUSION, 0, &w, &h);
    cr_assert_eq(w, N);
    const dm_profile *p = &f.synth->scene.profile;
    float *lv[8] = {0};
    int size[8];
    for (int k = 0; k < p->count; ++k) {
        char name[16];
        snprintf(name, sizeof name, k ? "blur%d" : "irradiance", k);
        int hh;
        lv[k] = target(&f, name, &size[k], &hh);
    }
    double wsum[3] = {0, 0, 0};
    for (int k = 0; k < p->count; ++k)
        for (int c = 0; c < 3; ++c) wsum[c] += p->weight[k][c];
    double max_rel = 0;
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            const float *t0 = lv[0] + ((size_t)j * N + i) * 4;
            cr_assert(v[((size_t)j * N + i) * 4 + 3] == t0[3], "alpha is the chart coverage");
            if (t0[3] == 0.0f && blur_reduce_from == 0) {
                for (int c = 0; c < 3; ++c)
                    cr_assert(v[((size_t)j * N + i) * 4 + c] == 0.0f, "texel %d, %d off the charts is not black", i, j);
                continue;
            }
            for (int c = 0; c < 3; ++c) {
                double sum = 0;
                for (int k = 0; k < p->count; ++k) {
                    float wk = (float)(p->weight[k][c] / wsum[c]);
                    double l;
                    if (size[k] == N) {
                        const float *t = lv[k] + ((size_t)j * N + i) * 4;
                        l = t[3] > 1e-4f ? t[c] / t[3] : 0.0;
                    } else { /* half resolution: the bilinear sample at this texel's centre */
                        int n = size[k];
                        double x = (i + 0.5) / N * n - 0.5, y = (j + 0.5) / N * n - 0.5;
                        int x0 = (int)floor(x), y0 = (int)floor(y);
                        double fx = x - x0, fy = y - y0, acc[4] = {0, 0, 0, 0};
                        for (int q = 0; q < 4; ++q) {
                            int xi = x0 + (q & 1), yi = y0 + (q >> 1);
                            double wq = ((q & 1) ? fx : 1 - fx) * ((q >> 1) ? fy : 1 - fy);
                            if (xi < 0 || yi < 0 || xi >= n || yi >= n) continue; /* border: 0 */
                            const float *t = lv[k] + ((size_t)yi * n + xi) * 4;
                            acc[c] += wq * t[c];
                            acc[3] += wq * t[3];
                        }
                        l = acc[3] > 1e-4 ? acc[c] / acc[3] : 0.0;
                    }
                    sum += wk * l;
                }
                double got = v[((size_t)j * N + i) * 4 + c];
                double rel = fabs(got - sum) / fmax(fabs(sum), 1e-3);
                if (rel > max_rel) max_rel = rel;
            }
        }
    /* reduced levels: llvmpipe's bilinear weights are 8-bit fixed point (1/256 steps) */
    double tol = blur_reduce_from ? 1e-2 : 2e-6;
    cr_expect_leq(max_rel, tol, "diffusion view against the CPU sum: max relative %g (tolerance %g)", max_rel, tol);
    for (int k = 0; k < p->count; ++k) free(lv[k]);
    free(v);
    close_fixture(&f);
}

Test(views, diffusion_view_is_the_weighted_sum_of_the_levels) { check_diffusion(0); }
Test(views, diffusion_view_upsamples_reduced_levels_like_final) { check_diffusion(3); }
Test(views, diffusion_view_summed_per_pixel_is_the_same_sum) { check_diffusion(-1); }

/* diffusion_per_pixel takes the diffusion pass out of the plan and its target away. The final
 * pictures differ where the levels' coverage varies under a pixel's bilinear footprint: along
 * the sphere's seam (u = 0 | 1), within the widest Gaussian's reach of it, where
 * bilerp(rgb) / bilerp(a) and bilerp(rgb / a) part in second order, ~1e-3 relative. Elsewhere
 * the same sum to float rounding (1e-5). A wrong weight or a missing level would show by
 * 1e-2 or more on every pixel. */
Test(views, diffusion_per_pixel_drops_the_pass_and_differs_only_along_chart_edges)
{
    float *px[2];
    for (int i = 0; i < 2; ++i) { /* one context at a time */
        fixture f;
        open_fixture(&f, i ? -1 : 0);
        int w, h;
        px[i] = frame_view(&f, DM_VIEW_FINAL, 0, &w, &h);
        cr_expect_eq(dm_render_plan_find(dm_renderer_plan(f.r), "diffusion") >= 0, i == 0);
        cr_expect_eq(dm_renderer_find_target(f.r, "diffusion") >= 0, i == 0);
        close_fixture(&f);
    }
    double worst = 0;
    long head = 0, differ = 0, band_lo = 96, band_hi = -1;
    for (size_t i = 0; i < 96 * 64; ++i) {
        cr_assert(px[0][4 * i + 3] == px[1][4 * i + 3], "coverage differs at %zu", i);
        if (px[0][4 * i + 3] < 1.0f) continue;
        ++head;
        double rel = 0;
        for (int c = 0; c < 3; ++c) {
            double a = px[0][4 * i + c], b = px[1][4 * i + c];
            cr_assert(isfinite(a) && isfinite(b));
            rel = fmax(rel, fabs(a - b) / fmax(fabs(b), 1e-3));
        }
        worst = fmax(worst, rel);
        if (rel > 1e-5) {
            ++differ;
            band_lo = (long)(i % 96) < band_lo ? (long)(i % 96) : band_lo;
            band_hi = (long)(i % 96) > band_hi ? (long)(i % 96) : band_hi;
        }
    }
    cr_assert_gt(head, 1000);
    cr_expect_leq(worst, 1e-2, "largest relative difference %g", worst);
    cr_expect_gt(differ, 0, "the seam shows no difference at all: is the per-pixel sum running?");
    cr_expect_leq(differ, head / 4, "%ld of %ld head pixels differ by more than 1e-5", differ, head);
    cr_expect_leq(band_hi - band_lo, 12, "the differing pixels span columns %ld..%ld, not one band", band_lo, band_hi);
    free(px[0]), free(px[1]);
}

/* The final linear image carries coverage: alpha 1 on the head, 0 on the background. */
Test(views, final_linear_alpha_is_coverage)
{
    fixture f;
    open_fixture(&f, 0);
    int w, h;
    float *v = frame_view(&f, DM_VIEW_FINAL, 0, &w, &h);
    cr_assert_eq(w, 96);
    cr_assert_eq(h, 64);
    long on = 0, off = 0;
    for (size_t i = 0; i < (size_t)w * h; ++i) {
        cr_assert(v[i * 4 + 3] == 0.0f || v[i * 4 + 3] == 1.0f);
        on += v[i * 4 + 3] == 1.0f;
        off += v[i * 4 + 3] == 0.0f;
    }
    cr_assert_gt(on, 100);
    cr_assert_gt(off, 100, "the corners are background");
    cr_assert_eq(v[3], 0.0f, "corner pixel");
    free(v);
    close_fixture(&f);
}

/* The renderer's own diffusion view written as a texture-space reference (image/dm_exr.h,
 * ZIP) compares with zero error; the same reference 1 % brighter gives 1/1.01 relative
 * error wherever ref exceeds the floor (all but the darkest texels). */
Test(views, refcmp_own_diffusion_is_zero_error_and_a_known_offset_is_measured)
{
    fixture f;
    open_fixture(&f, 0);
    int w, h;
    float *v = frame_view(&f, DM_VIEW_DIFFUSION, 0, &w, &h);
    size_t n = (size_t)w * h;
    float *pl[4];
    for (int c = 0; c < 4; ++c) {
        pl[c] = malloc(n * sizeof(float));
        for (size_t i = 0; i < n; ++i) pl[c][i] = v[i * 4 + c];
    }
    char dir[256], path[300];
    cr_assert_not_null(test_tmpdir(dir, sizeof dir));
    snprintf(path, sizeof path, "%s/ref.exr", dir);
    dm_provenance prov;
    dm_prov_init(&prov, "test_render_views");
    dm_prov_add_string(&prov, "mode", "texture-space");
    dm_exr_channel ch[4] = {{"R", pl[0], DM_EXR_FLOAT}, {"G", pl[1], DM_EXR_FLOAT}, {"B", pl[2], DM_EXR_FLOAT},
                            {"A", pl[3], DM_EXR_FLOAT}};
    dm_error err = {0};
    cr_assert_eq(dm_exr_write(path, w, h, ch, 4, &prov, &err), DM_OK, "%s", err.detail);
    dm_refcmp_ref ref;
    cr_assert_eq(dm_refcmp_load(path, &ref, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(ref.mode, DM_REFCMP_TEXTURE_SPACE);
    cr_assert_eq(ref.width, N);
    dm_refcmp_stats st;
    float *rel = malloc(n * sizeof *rel);
    cr_assert_eq(dm_refcmp_stats_compute(ref.rgba, v, w, h, &st, rel, &err), DM_OK, "%s", err.detail);
    cr_assert_gt(st.count, N * N / 4);
    cr_assert_eq(st.ref_only + st.render_only, 0);
    for (int c = 0; c < 3; ++c) cr_assert(st.mean[c] == 0 && st.p95[c] == 0 && st.max[c] == 0);
    /* 1 % brighter reference */
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) ref.rgba[i * 4 + c] *= 1.01f;
    cr_assert_eq(dm_refcmp_stats_compute(ref.rgba, v, w, h, &st, rel, &err), DM_OK, "%s", err.detail);
    for (int c = 0; c < 3; ++c) {
        cr_expect(fabs(st.p95[c] - 0.01 / 1.01) < 1e-5, "channel %d p95 %g", c, st.p95[c]);
        cr_expect(st.mean[c] <= 0.01 / 1.01 + 1e-5 && st.mean[c] > 0.009, "channel %d mean %g", c, st.mean[c]);
    }
    /* the picture: every layout draws without touching outside the buffer (ASan) */
    for (int l = 0; l < DM_REFCMP_LAYOUT_COUNT; ++l) {
        int ow = l ? 200 : 3 * w, oh = l ? 150 : h + dm_refcmp_legend_height(3 * w);
        uint8_t *img = malloc((size_t)ow * oh * 4);
        dm_refcmp_view view = {.layout = (dm_refcmp_layout)l, .split = 0.3f};
        dm_refcmp_compose(ref.rgba, v, rel, w, h, &st, &view, img, ow, oh);
        free(img);
    }
    /* a reference without a mode is refused, naming what it expects */
    dm_prov_init(&prov, "test_render_views");
    cr_assert_eq(dm_exr_write(path, w, h, ch, 4, &prov, &err), DM_OK, "%s", err.detail);
    dm_refcmp_ref bad;
    cr_assert_eq(dm_refcmp_load(path, &bad, &err), DM_ERR_FORMAT);
    cr_assert(strstr(err.detail, "texture-space"), "%s", err.detail);
    dm_refcmp_ref_free(&ref);
    free(rel);
    for (int c = 0; c < 4; ++c) free(pl[c]);
    free(v);
    remove(path);
    rmdir(dir);
    close_fixture(&f);
}

#define BIN DERMIS_BIN "/dermis-render"

/* The tool: its own diffusion and final EXRs as references give zero error, exit 0. */
Test(views, tool_reference_round_trip, .timeout = 120)
{
    char dir[256], cmd[1024], log[300];
    cr_assert_not_null(test_tmpdir(dir, sizeof dir));
    snprintf(log, sizeof log, "%s/log", dir);
    snprintf(cmd, sizeof cmd, BIN " --synthetic sphere --view diffusion --irradiance 64 -o %s/d.exr", dir);
    cr_assert_eq(test_run(cmd, log), 0);
    snprintf(cmd, sizeof cmd, BIN " --synthetic sphere --reference %s/d.exr -o %s/cmp.png", dir, dir);
    cr_assert_eq(test_run(cmd, log), 0);
    char *text = test_slurp(log);
    cr_assert(text && strstr(text, "texture-space, 64x64") && strstr(text, "R: mean 0.0000 %, p95 0.0000 %"), "%s",
              text ? text : "");
    free(text);
    snprintf(cmd, sizeof cmd, BIN " --synthetic sphere --size 80x48 -o %s/f.exr >/dev/null && " BIN
             " --synthetic sphere --reference %s/f.exr -o %s/cmpf.png", dir, dir, dir);
    cr_assert_eq(test_run(cmd, log), 0);
    text = test_slurp(log);
    cr_assert(text && strstr(text, "frame, 80x48") && strstr(text, "G: mean 0.0000 %"), "%s", text ? text : "");
    free(text);
    snprintf(cmd, sizeof cmd, BIN " --synthetic sphere --reference %s/d.exr --irradiance 32 -o %s/x.png", dir, dir);
    cr_expect_eq(test_run(cmd, NULL), 1, "--irradiance disagreeing with the reference");
    snprintf(cmd, sizeof cmd, "head -c 300 %s/d.exr > %s/cut.exr; " BIN " --synthetic sphere --reference %s/cut.exr",
             dir, dir, dir);
    cr_expect_eq(test_run(cmd, NULL), 2, "a truncated reference is a load error");
}

/* The stretch view's colour scale is the texel size in mm: a flat 64 mm quad whose UVs span
 * [0, 1] has s_u = s_v = 1/64 UV per mm, so its 64-texel stretch map holds 1 mm per texel
 * everywhere (lo = 1, hi just above). */
Test(views, stretch_view_scale_is_mm_per_texel)
{
    dm_error err = {0};
    dm_osmesa *ctx = NULL;
    dm_synth *synth = NULL;
    dm_renderer *r = NULL;
    dm_synth_options so = {.shape = DM_SYNTH_QUAD, .quad_side_mm = 64, .stretch_size = 64};
    cr_assert_eq(dm_osmesa_create(&ctx, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_synth_create(&so, &synth, &err), DM_OK, "%s", err.detail);
    dm_render_desc d = {.width = 64, .height = 64, .irradiance_size = 64, .shadow_size = 256};
    cr_assert_eq(dm_renderer_create(&synth->assets, &d, &r, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_frame(r, &(dm_frame_options){.view = DM_VIEW_STRETCH}, &err), DM_OK, "%s", err.detail);
    float lo, hi;
    const char *q = NULL;
    dm_renderer_view_scale(r, &lo, &hi, &q);
    cr_expect_float_eq(lo, 1.0f, 1e-5f);
    cr_expect(hi >= lo && hi - lo < 1e-4f, "lo %g hi %g", (double)lo, (double)hi);
    cr_expect_str_eq(q, "mm per texel");
    /* the picture: every chart pixel the scale's low end (turbo(0), sRGB) */
    uint8_t *px = malloc(64 * 64 * 4), c0[3];
    cr_assert_eq(dm_renderer_read_display(r, px, &err), DM_OK, "%s", err.detail);
    dm_render_turbo(0.0, c0);
    const uint8_t *mid = px + (32 * 64 + 32) * 4;
    for (int c = 0; c < 3; ++c) cr_expect(abs(mid[c] - c0[c]) <= 1, "channel %d: %d, turbo(0) %d", c, mid[c], c0[c]);
    free(px);
    dm_renderer_destroy(r);
    dm_synth_free(synth);
    dm_osmesa_destroy(ctx);
}

/* The specular view is exposed to be read: the head's 99th percentile near display white,
 * the gain finite; with nothing specular (the effect off) the gain stays 1, no NaN. */
static void specular_case(bool specular_on)
{
    fixture f;
    open_fixture(&f, 0);
    f.synth->scene.effects[DM_EFFECT_SPECULAR] = specular_on;
    dm_error err = {0};
    dm_renderer_destroy(f.r);
    dm_render_desc d = {.width = 96, .height = 64, .irradiance_size = N, .shadow_size = 256};
    cr_assert_eq(dm_renderer_create(&f.synth->assets, &d, &f.r, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_frame(f.r, &(dm_frame_options){.view = DM_VIEW_SPECULAR}, &err), DM_OK, "%s", err.detail);
    float gain = dm_renderer_view_gain(f.r);
    cr_expect(isfinite(gain) && gain > 0, "gain %g", (double)gain);
    float *lin = malloc(96 * 64 * 4 * sizeof *lin);
    cr_assert_eq(dm_renderer_read_linear(f.r, lin, &err), DM_OK, "%s", err.detail);
    float top = 0;
    for (int i = 0; i < 96 * 64 * 4; ++i) cr_assert(isfinite(lin[i]));
    for (int i = 0; i < 96 * 64; ++i)
        if (lin[4 * i + 3] >= 0.5f) top = fmaxf(top, fmaxf(lin[4 * i], fmaxf(lin[4 * i + 1], lin[4 * i + 2])));
    if (specular_on) {
        cr_expect_gt(gain, 1.0f);
        /* the 99th percentile lands at 4 / 2^exposure (tonemap) or 0.9: the maximum at least that */
        float white = f.synth->scene.effects[DM_EFFECT_TONEMAP] ? 4.0f / exp2f(f.synth->scene.exposure) : 0.9f;
        cr_expect_geq(top, white * 0.999f, "brightest %g, white %g", (double)top, (double)white);
    } else {
        cr_expect_eq(gain, 1.0f);
    }
    free(lin);
    close_fixture(&f);
}

Test(views, specular_view_is_exposed) { specular_case(true); }
Test(views, specular_view_without_specular_stays_finite) { specular_case(false); }

/* The legend strip: the bar runs the turbo colours from its left to its right end. */
Test(views, scalar_legend_draws_the_colour_bar)
{
    enum { W = 400, H = 120 };
    uint8_t *img = calloc(W * H * 4, 1), lo[3], hi[3];
    int lh = dm_render_scalar_legend_height(W);
    cr_assert(lh > 0 && lh < H);
    dm_render_scalar_legend(img, W, H, 0.5, 2.0, "mm per texel", NULL);
    dm_render_turbo(0.0, lo), dm_render_turbo(1.0, hi);
    /* the bar's first row: 6 rows below the strip's top (top-down), x from 8 to W - 8 */
    int row = H - 1 - (H - lh + 6); /* bottom-up memory row */
    const uint8_t *l = img + ((size_t)row * W + 8) * 4, *r = img + ((size_t)row * W + W - 9) * 4;
    for (int c = 0; c < 3; ++c) {
        cr_expect(abs(l[c] - lo[c]) <= 8, "left %d: %d vs %d", c, l[c], lo[c]);
        cr_expect(abs(r[c] - hi[c]) <= 8, "right %d: %d vs %d", c, r[c], hi[c]);
    }
    free(img);
}

/* Without a background or glow pass the tonemap shades only the head's pixels (the rest is
 * the clear colour, which the curve takes to black): the display must still be the curve of
 * every pixel, against a CPU reference in double (exposure, Hable's filmic curve with
 * exposure bias 2 and white 11.2, sRGB) within one 8-bit step, and exactly black with alpha
 * 255 off the head. */
static double hable(double x)
{
    const double A = 0.15, B = 0.50, C = 0.10, D = 0.20, E = 0.02, F = 0.30;
    return ((x * (A * x + C * B) + D * E) / (x * (A * x + B) + D * F)) - E / F;
}

Test(views, tonemap_of_the_head_pixels_only_is_the_curve_everywhere)
{
    fixture f;
    open_synth(&f);
    dm_scene *s = &f.synth->scene;
    s->env_background = false;
    s->effects[DM_EFFECT_GLOW] = false;
    s->effects[DM_EFFECT_TONEMAP] = true;
    s->exposure = 0.75f;
    open_renderer(&f, 0);
    dm_error err = {0};
    dm_frame_options o = {.view = DM_VIEW_FINAL};
    cr_assert_eq(dm_render_frame(f.r, &o, &err), DM_OK, "%s", err.detail);
    int w, h, irr;
    dm_renderer_size(f.r, &w, &h, &irr);
    float *lin = malloc((size_t)w * h * 4 * sizeof *lin);
    uint8_t *disp = malloc((size_t)w * h * 4);
    cr_assert_eq(dm_renderer_read_linear(f.r, lin, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_renderer_read_display(f.r, disp, &err), DM_OK, "%s", err.detail);
    int head = 0, bg = 0;
    for (int i = 0; i < w * h; ++i) {
        const float *c = lin + (size_t)i * 4;
        const uint8_t *d = disp + (size_t)i * 4;
        cr_assert_eq(d[3], 255, "pixel %d alpha %d", i, d[3]);
        if (c[3] == 0.0f) {
            ++bg;
            cr_assert(d[0] == 0 && d[1] == 0 && d[2] == 0, "background pixel %d is (%d %d %d)", i, d[0], d[1], d[2]);
            continue;
        }
        ++head;
        for (int k = 0; k < 3; ++k) {
            double x = fmax(c[k] * exp2(0.75), 0.0), t = fmin(fmax(hable(2.0 * x) / hable(11.2), 0.0), 1.0);
            double e = t < 0.0031308 ? 12.92 * t : 1.055 * pow(t, 1.0 / 2.4) - 0.055;
            cr_assert(fabs(e * 255.0 - d[k]) <= 1.0, "head pixel %d channel %d: %d, curve %.3f", i, k, d[k], e * 255.0);
        }
    }
    cr_expect_gt(head, 500);
    cr_expect_gt(bg, 500);
    free(lin), free(disp);
    close_fixture(&f);
}
