/* The pre-integrated technique (lib/render/passes/dm_pass_preint.c, shaders/final.glsl with
 * DM_PRE_INTEGRATED) on the synthetic shapes under llvmpipe, with a table baked here by
 * bake/dm_preintegrated.h and a constant curvature: flat (curvature 0) it is Lambert, on a
 * curved surface light reaches past the terminator, red most; the plan is one pass; missing
 * assets are refused by name. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_preintegrated.h"
#include "core/dm_scene.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_synth.h"

typedef struct fixture {
    dm_osmesa *ctx;
    dm_synth *synth;
    float *lut; /* RGBA32F, as dermis-pack packs it */
    float curvature;
} fixture;

static void open_fixture(fixture *f, dm_synth_shape shape, float curvature_per_mm)
{
    dm_error err = {0};
    memset(f, 0, sizeof *f);
    dm_synth_options so = {.shape = shape, .beckmann_size = 128, .directional_size = 16, .stretch_size = 64};
    cr_assert_eq(dm_osmesa_create(&f->ctx, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_synth_create(&so, &f->synth, &err), DM_OK, "%s", err.detail);
    dm_scene *s = &f->synth->scene;
    s->sss_technique = DM_SSS_PRE_INTEGRATED;
    s->effects[DM_EFFECT_GLOW] = s->effects[DM_EFFECT_TONEMAP] = false;
    s->effects[DM_EFFECT_ENVIRONMENT_LIGHTING] = false; /* unlit means 0 */
    dm_preint_lut l;
    cr_assert_eq(dm_preint_bake(&s->profile, 64, 32, 1.0, 0, &l, &err), DM_OK, "%s", err.detail);
    size_t n = (size_t)l.width * l.height;
    f->lut = malloc(n * 4 * sizeof *f->lut);
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) f->lut[4 * i + c] = l.rgb[c * n + i];
        f->lut[4 * i + 3] = 1.0f;
    }
    f->synth->assets.preintegrated = (dm_texture){DM_TEX_RGBA32F, l.width, l.height, f->lut};
    f->curvature = curvature_per_mm;
    f->synth->assets.curvature = (dm_texture){DM_TEX_R32F, 1, 1, &f->curvature};
    f->synth->assets.preint_curvature_max_per_mm = 1.0f;
    dm_preint_lut_free(&l);
}

static float *render(fixture *f, int w, int h)
{
    dm_error err = {0};
    dm_render_desc d = {.width = w, .height = h, .shadow_size = 256};
    dm_renderer *r = NULL;
    cr_assert_eq(dm_renderer_create(&f->synth->assets, &d, &r, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_frame(r, &(dm_frame_options){0}, &err), DM_OK, "%s", err.detail);
    float *px = malloc((size_t)w * h * 4 * sizeof *px);
    cr_assert_eq(dm_renderer_read_linear(r, px, &err), DM_OK, "%s", err.detail);
    for (size_t i = 0; i < (size_t)w * h * 4; ++i) cr_assert(isfinite(px[i]), "value %zu is %g", i, (double)px[i]);
    dm_renderer_destroy(r);
    return px;
}

static void close_fixture(fixture *f)
{
    dm_synth_free(f->synth);
    dm_osmesa_destroy(f->ctx);
    free(f->lut);
}

/* Row 0 of the table is max(0, N.L) at texel centres, linear in between: on a flat quad the
 * technique is Lambert. Measured 2.3e-7 relative (float rounding); bound 1e-5 (even 8-bit
 * bilinear weights would land within 1/512 texel on a slope of 2/64 per texel: 6e-5 absolute). */
Test(preint_render, flat_is_lambert)
{
    fixture f;
    open_fixture(&f, DM_SYNTH_QUAD, 0.0f);
    float *pre = render(&f, 160, 120);
    f.synth->scene.effects[DM_EFFECT_SUBSURFACE] = false;
    float *lam = render(&f, 160, 120);
    int skin = 0;
    double worst = 0;
    for (int i = 0; i < 160 * 120; ++i) {
        if (lam[4 * i + 3] == 0) continue;
        ++skin;
        for (int c = 0; c < 3; ++c)
            worst = fmax(worst, fabs(pre[4 * i + c] - lam[4 * i + c]) / fmax(lam[4 * i + c], 1e-3));
    }
    cr_expect_gt(skin, 1000);
    cr_log_info("flat quad: max relative difference to Lambert %.3g", worst);
    cr_expect_lt(worst, 1e-5, "flat quad: pre-integrated differs from Lambert by %g", worst);
    free(pre);
    free(lam);
    close_fixture(&f);
}

/* On the sphere with a high curvature (0.5 /mm in the table's terms) light passes the
 * terminator: skin pixels that Lambert leaves black get light, red more than green more
 * than blue (gems3-skin scatters red farthest); the lit side keeps its energy. */
Test(preint_render, light_wraps_past_the_terminator_red_most)
{
    fixture f;
    open_fixture(&f, DM_SYNTH_SPHERE, 0.5f);
    float *pre = render(&f, 160, 120);
    f.synth->scene.effects[DM_EFFECT_SUBSURFACE] = false;
    float *lam = render(&f, 160, 120);
    int dark = 0, wrapped = 0, ordered = 0;
    double sum_pre = 0, sum_lam = 0;
    for (int i = 0; i < 160 * 120; ++i) {
        if (lam[4 * i + 3] == 0) continue;
        sum_pre += pre[4 * i + 1], sum_lam += lam[4 * i + 1];
        if (lam[4 * i] + lam[4 * i + 1] + lam[4 * i + 2] > 0) continue;
        ++dark;
        if (pre[4 * i] > 0) ++wrapped;
        if (pre[4 * i] > 0 && pre[4 * i] >= pre[4 * i + 1] && pre[4 * i + 1] >= pre[4 * i + 2]) ++ordered;
    }
    cr_log_info("sphere: %d of %d unlit skin pixels lit, green total / Lambert %.4f", wrapped, dark, sum_pre / sum_lam);
    cr_expect_gt(dark, 100, "no unlit skin to test: %d pixels", dark);
    cr_expect_gt(wrapped, 20, "%d of %d unlit pixels got light", wrapped, dark);
    cr_expect_eq(ordered, wrapped, "red >= green >= blue in %d of %d wrapped pixels", ordered, wrapped);
    /* the blur moves light from lit to unlit parts, it does not make light: green (the middle
     * channel) within 10 % of Lambert's total over the sphere */
    cr_expect(fabs(sum_pre / sum_lam - 1.0) < 0.1, "green total %.4g vs Lambert %.4g", sum_pre, sum_lam);
    free(pre);
    free(lam);
    close_fixture(&f);
}

Test(preint_render, one_pass_plan_and_missing_assets)
{
    fixture f;
    open_fixture(&f, DM_SYNTH_SPHERE, 0.02f);
    dm_render_plan p;
    dm_error err = {0};
    cr_assert_eq(dm_render_plan_build(&f.synth->scene, DM_VIEW_FINAL, 0, &p, &err), DM_OK, "%s", err.detail);
    char list[512] = "";
    for (int i = 0; i < p.pass_count; ++i)
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", i ? " " : "", p.passes[i].name);
    cr_expect_str_eq(list, "shadow0 gbuffer final");
    cr_expect(p.pre_integrated && !p.texture_space && !p.screen_space);
    char text[8192];
    dm_render_plan_explain(&p, text, sizeof text);
    cr_expect(strstr(text, "subsurface technique: pre-integrated") && strstr(text, "pre-integrated (Penner)"), "%s",
              text);
    cr_expect_eq(dm_render_plan_build(&f.synth->scene, DM_VIEW_BLUR, 1, &p, &err), DM_ERR_INVALID_ARGUMENT);
    cr_expect(strstr(err.detail, "pre-integrated"), "%s", err.detail);
    dm_render_desc d = {.width = 32, .height = 32, .shadow_size = 64};
    dm_renderer *r = NULL;
    f.synth->assets.curvature.texels = NULL;
    cr_expect_eq(dm_renderer_create(&f.synth->assets, &d, &r, &err), DM_ERR_MISMATCH);
    cr_expect(strstr(err.detail, "curvature"), "%s", err.detail);
    f.synth->assets.preintegrated.texels = NULL;
    cr_expect_eq(dm_renderer_create(&f.synth->assets, &d, &r, &err), DM_ERR_MISMATCH);
    cr_expect(strstr(err.detail, "pre-integrated table"), "%s", err.detail);
    cr_expect_null(r);
    close_fixture(&f);
}

/* The curvature view: the map's values at full precision (EXR), its colour scale from the
 * 1st to the 99th percentile (a constant map: lo = that constant), named in 1/mm. */
Test(preint_render, curvature_view_shows_the_map)
{
    fixture f;
    open_fixture(&f, DM_SYNTH_SPHERE, 0.0625f);
    dm_error err = {0};
    dm_renderer *r = NULL;
    dm_render_desc d = {.width = 64, .height = 64, .shadow_size = 256};
    cr_assert_eq(dm_renderer_create(&f.synth->assets, &d, &r, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_frame(r, &(dm_frame_options){.view = DM_VIEW_CURVATURE}, &err), DM_OK, "%s", err.detail);
    int w, h;
    dm_renderer_view_size(r, &w, &h);
    cr_assert_eq(w, 1);
    float px[4];
    cr_assert_eq(dm_renderer_read_view(r, px, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(px[0], 0.0625f);
    float lo, hi;
    const char *q = NULL;
    dm_renderer_view_scale(r, &lo, &hi, &q);
    cr_expect_eq(lo, 0.0625f);
    cr_expect(hi > lo && hi - lo < 1e-5f, "hi %g", (double)hi);
    cr_expect_str_eq(q, "mean curvature, 1/mm");
    dm_renderer_destroy(r);
    close_fixture(&f);
}

/* A texture-space scene has no curvature map: the view says what it needs. */
Test(preint_render, curvature_view_needs_the_pre_integrated_technique)
{
    fixture f;
    open_fixture(&f, DM_SYNTH_SPHERE, 0.0f);
    f.synth->scene.sss_technique = DM_SSS_TEXTURE_SPACE;
    dm_error err = {0};
    dm_renderer *r = NULL;
    dm_render_desc d = {.width = 64, .height = 64, .irradiance_size = 64, .shadow_size = 256};
    cr_assert_eq(dm_renderer_create(&f.synth->assets, &d, &r, &err), DM_OK, "%s", err.detail);
    cr_expect_neq(dm_render_frame(r, &(dm_frame_options){.view = DM_VIEW_CURVATURE}, &err), DM_OK);
    cr_expect(strstr(err.detail, "pre-integrated") != NULL, "%s", err.detail);
    dm_renderer_destroy(r);
    close_fixture(&f);
}
