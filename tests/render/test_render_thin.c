/* The thin-part map in the renderer (issue #29 point 2): a thin sheet — two parallel plates
 * s mm apart, back to back, each its own UV chart (tests/common/thin_sheet.h) — lit from above,
 * so only the top plate receives light. The atlas blur cannot carry it to the bottom plate;
 * the thin-part map (here in closed form: every texel's point straight across) lets the
 * diffusion pass add Σ_k w_k exp(−s²/2v_k) L_k(across). For infinite parallel sheets under
 * uniform light that is exact: far from the plates' edges the bottom's diffusion is the top's
 * times Σ_k w_k exp(−s²/2v_k), per channel, and the top's own is unchanged (nothing lights the
 * bottom). On the GL and the CPU blur path alike; a map of another size is left out, and an
 * empty one changes nothing, bit for bit. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/obj_write.h"
#include "../common/thin_sheet.h"
#include "../common/tmpdir.h"
#include "host/dm_osmesa.h"
#include "pack/dm_pack.h"
#include "render/dm_render.h"
#include "render/dm_render_pack.h"

enum { IRR = 256 };

typedef struct sheet_pack {
    dm_pack pack;
    dm_scene scene;
    dm_profile profile;
    dm_render_assets assets;
} sheet_pack;

/* The sheet s mm thick, a directional light straight above, subsurface only (no shadows: the
 * bottom faces away from the light anyway) with `profile` (a JSON text; NULL: gems3-skin), packed
 * by dermis-pack and opened. */
static void pack_sheet_with(const char *dir, double s_mm, const char *profile, sheet_pack *out)
{
    dm_mesh m;
    thin_sheet_mesh(s_mm, &m);
    char path[256], cmd[1024], log[256];
    snprintf(path, sizeof path, "%s/sheet.obj", dir);
    test_write_obj(path, &m);
    dm_mesh_free(&m);
    FILE *f;
    if (profile) {
        snprintf(path, sizeof path, "%s/profile.json", dir);
        cr_assert((f = fopen(path, "w")));
        fputs(profile, f), fclose(f);
    }
    snprintf(path, sizeof path, "%s/sheet.json", dir);
    f = fopen(path, "w");
    cr_assert(f);
    fprintf(f, "{\"mesh\": {\"path\": \"sheet.obj\", \"mm_per_unit\": 1},\n"
               " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1]}],\n"
               " \"effects\": {\"subsurface\": {\"irradiance_size\": %d%s}},\n"
               " \"camera\": {\"eye\": [20, 20, 80], \"target\": [20, 20, 0]}, \"output\": {\"width\": 64, \"height\": 64}}\n",
            IRR, profile ? ", \"profile\": \"profile.json\"" : "");
    fclose(f);
    snprintf(cmd, sizeof cmd, "cd '%s' && " DERMIS_BIN "/dermis-pack sheet.json -o sheet.dpk --threads 1 --quiet", dir);
    snprintf(log, sizeof log, "%s/sheet.log", dir);
    int rc = test_run(cmd, log);
    char *text = rc ? test_slurp(log) : NULL;
    cr_assert_eq(rc, 0, "dermis-pack failed: %s", text ? text : "");
    snprintf(path, sizeof path, "%s/sheet.dpk", dir);
    dm_error err = {0};
    cr_assert_eq(dm_pack_open(path, &out->pack, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_assets_from_pack(&out->pack, &out->scene, &out->profile, &out->assets, &err), DM_OK, "%s",
                 err.detail);
}

static void pack_sheet(const char *dir, double s_mm, sheet_pack *out)
{
    pack_sheet_with(dir, s_mm, NULL, out);
}

/* A texture view (irr², RGBA) of the assets at irradiance size irr; whether the renderer used
 * a thin-part map, and the view's colour scale when lo is not NULL. */
static float *render_view(const dm_render_assets *a, int irr, dm_blur_path path, dm_view view, bool *used, float *lo,
                          float *hi, const char **quantity)
{
    dm_osmesa *ctx = NULL;
    dm_renderer *r = NULL;
    dm_error err = {0};
    cr_assert_eq(dm_osmesa_create(&ctx, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_renderer_create(a, &(dm_render_desc){.width = 64, .height = 64, .irradiance_size = irr, .blur_path = path},
                                    &r, &err),
                 DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_frame(r, &(dm_frame_options){.view = view}, &err), DM_OK, "%s", err.detail);
    *used = dm_renderer_thin_map(r);
    if (lo) dm_renderer_view_scale(r, lo, hi, quantity);
    int w, h;
    dm_renderer_view_size(r, &w, &h);
    cr_assert(w == irr && h == irr);
    float *px = malloc(sizeof *px * 4 * (size_t)irr * irr);
    cr_assert_eq(dm_renderer_read_view(r, px, &err), DM_OK, "%s", err.detail);
    dm_renderer_destroy(r);
    dm_osmesa_destroy(ctx);
    return px;
}

/* The same at IRR with the given thin-part map texels (NULL: none) of n × 2n, the pack's thin
 * gather left out (these tests hold the map's own formula; the gather's are below). */
static float *view_with(const sheet_pack *sp, const float *map, int n, dm_blur_path path, dm_view view, bool *used,
                        float *lo, float *hi, const char **quantity)
{
    dm_render_assets a = sp->assets;
    a.thin = map ? (dm_texture){DM_TEX_RGBA32F, n, 2 * n, map} : (dm_texture){0};
    a.gather_index = a.gather_taps = a.gather_half_index = a.gather_half_taps = (dm_texture){0};
    return render_view(&a, IRR, path, view, used, lo, hi, quantity);
}

static float *diffusion_with(const sheet_pack *sp, const float *map, int n, dm_blur_path path, bool *used)
{
    return view_with(sp, map, n, path, DM_VIEW_DIFFUSION, used, NULL, NULL, NULL);
}

static const float *at(const float *px, int bottom, double x, double y)
{
    double uv[2];
    thin_sheet_uv(bottom, x, y, uv);
    return px + 4 * ((size_t)floor(uv[1] * IRR) * IRR + (size_t)floor(uv[0] * IRR));
}

/* Σ_k w_k exp(−s²/2v_k) per channel, the weights normalised per channel as the renderer's. */
static void across(const dm_profile *p, double s, double out[3])
{
    for (int c = 0; c < 3; ++c) {
        double sum = 0, g = 0;
        for (int k = 0; k < p->count; ++k) sum += p->weight[k][c], g += p->weight[k][c] * exp(-s * s / (2 * p->variance_mm2[k]));
        out[c] = g / sum;
    }
}

/* Over the plates' middle (10 mm clear of every edge: 3.7 σ of the widest Gaussian), the
 * bottom's diffusion over the top's at the same (x, y), per channel: mean and largest
 * departure from the closed form. */
static void check_sheet(dm_blur_path path, double s)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    sheet_pack sp;
    pack_sheet(dir, s, &sp);
    float *map = thin_sheet_map(s, IRR);
    bool used_with, used_without;
    float *with = diffusion_with(&sp, map, IRR, path, &used_with), *without = diffusion_with(&sp, NULL, 0, path, &used_without);
    cr_assert(used_with && !used_without);
    double want[3], worst = 0;
    across(&sp.profile, s, want);
    int count = 0;
    for (double y = 10.25; y < THIN_SHEET_L - 10; y += 0.5)
        for (double x = 10.25; x < THIN_SHEET_L - 10; x += 0.5, ++count) {
            const float *top = at(with, 0, x, y), *bottom = at(with, 1, x, y), *top0 = at(without, 0, x, y),
                        *bottom0 = at(without, 1, x, y);
            for (int c = 0; c < 3; ++c) {
                cr_assert(top[c] > 0.1f, "the top is lit");
                cr_assert_eq(top[c], top0[c], "the top's own light is unchanged (the bottom is dark)");
                cr_assert(bottom0[c] < 1e-6f * top[c], "without the map the bottom is dark: %g", bottom0[c]);
                worst = fmax(worst, fabs(bottom[c] / top[c] / want[c] - 1));
            }
        }
    cr_log_info("sheet %.2f mm (%s blur): across %.5f %.5f %.5f of the top, %d texels, worst %.2e relative", s,
                path == DM_BLUR_PATH_GL ? "GL" : "CPU", want[0], want[1], want[2], count, worst);
    cr_assert_gt(want[0], 0.05, "the test must see light across");
    /* the candidates read the top's levels bilinearly at exact texel centres (both charts on the
     * same grid): what remains is float rounding, ~1e-6; 1e-4 fails a level off by one, a
     * weight unnormalised or exp(−s²/v) */
    cr_assert_lt(worst, 1e-4, "worst %.2e", worst);
    free(with), free(without), free(map);
    dm_pack_close(&sp.pack);
}

Test(thin, parallel_sheets_exact_on_the_cpu_blur, .timeout = 120) { check_sheet(DM_BLUR_PATH_CPU, 1.0); }
Test(thin, parallel_sheets_exact_on_the_gl_blur, .timeout = 120) { check_sheet(DM_BLUR_PATH_GL, 1.0); }
/* thinner than a texel (0.04 mm against 0.39 mm a texel): as exact */
Test(thin, a_sheet_thinner_than_a_texel, .timeout = 120) { check_sheet(DM_BLUR_PATH_CPU, 0.04); }

/* The pack's thin gather (bake/dm_thin_gather.h) on the sheet: the widest levels (σ ≥ 1 mm, `levels`
 * of them) become the 3-D sum over the sites of both plates. Over the plates' middle the bottom
 * over the top is the closed form Σ_k w_k exp(−s²/2v_k) as with the map alone, and the top is the
 * map alone's: to 0.4 % — the sites' quadrature of a plane (each gathered level's sum within 0.4 %
 * of the truncated closed form, tests/unit/test_thin_gather.c) and what it leaves out beyond
 * 3.5 σ. The GL path gathers the same sums (diffusion.glsl's DM_GATHER): to 1e-4 of the range, as
 * the blur paths agree. */
static void check_gather(const char *profile, int levels)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    sheet_pack sp;
    pack_sheet_with(dir, 1.0, profile, &sp);
    cr_assert(sp.assets.gather_index.texels && sp.assets.gather_taps.texels, "dermis-pack baked the gather");
    cr_assert_eq((int)((const float *)sp.assets.gather_taps.texels)[1], levels, "levels gathered");
    float *map = thin_sheet_map(1.0, IRR);
    dm_render_assets a = sp.assets;
    a.thin = (dm_texture){DM_TEX_RGBA32F, IRR, 2 * IRR, map};
    bool used;
    float *gathered = render_view(&a, IRR, DM_BLUR_PATH_CPU, DM_VIEW_DIFFUSION, &used, NULL, NULL, NULL);
    float *alone = diffusion_with(&sp, map, IRR, DM_BLUR_PATH_CPU, &used);
    float *gl = render_view(&a, IRR, DM_BLUR_PATH_GL, DM_VIEW_DIFFUSION, &used, NULL, NULL, NULL);
    float *gl_alone = diffusion_with(&sp, map, IRR, DM_BLUR_PATH_GL, &used);
    cr_assert(memcmp(gl, gl_alone, sizeof *gl * 4 * IRR * IRR), "GL gathers too");
    double want[3], worst_bottom = 0, worst_top = 0, moved = 0, gl_worst = 0, range = 0;
    across(&sp.profile, 1.0, want);
    for (double y = 10.25; y < THIN_SHEET_L - 10; y += 0.5)
        for (double x = 10.25; x < THIN_SHEET_L - 10; x += 0.5) {
            const float *top = at(gathered, 0, x, y), *bottom = at(gathered, 1, x, y), *top1 = at(alone, 0, x, y);
            for (int c = 0; c < 3; ++c) {
                worst_bottom = fmax(worst_bottom, fabs(bottom[c] / top[c] / want[c] - 1));
                worst_top = fmax(worst_top, fabs(top[c] / top1[c] - 1));
                moved = fmax(moved, fabs(bottom[c] - at(alone, 1, x, y)[c]) / top[c]);
            }
        }
    for (size_t i = 0; i < (size_t)4 * IRR * IRR; ++i)
        range = fmax(range, fabs(gl[i])), gl_worst = fmax(gl_worst, fabs(gl[i] - gathered[i]));
    cr_log_info("gathered sheet: bottom/top off the closed form by %.2e at most, top by %.2e, moved %.2e of the top; "
                "GL against the CPU %.2e of the range", worst_bottom, worst_top, moved, gl_worst / range);
    cr_assert_gt(moved, 1e-6, "the gather must run here");
    cr_assert_lt(worst_bottom, 4e-3, "worst %.2e", worst_bottom);
    cr_assert_lt(worst_top, 4e-3, "worst %.2e", worst_top);
    cr_assert_lt(gl_worst, 1e-4 * range);
    free(gathered), free(alone), free(gl), free(gl_alone), free(map);
    dm_pack_close(&sp.pack);
}

Test(thin, the_gather_is_the_sheets_closed_form_on_both_paths, .timeout = 180) { check_gather(NULL, 2); }

/* A profile with four levels of σ ≥ 1 mm (a fit with many Gaussians splits the wide light so):
 * all four gathered, their runs with a count tap. Their variances keep the sites' cells at most
 * 0.6 σ, as gems3-skin's (tests/unit/test_thin_gather.c: at 0.7–1 σ a level's quadrature is off
 * by up to 0.8 %), and the widest (σ 2.8 mm) reaches 9.9 mm, inside the plates' middle's 10 mm. */
Test(thin, four_gathered_levels_are_the_closed_form_on_both_paths, .timeout = 180)
{
    check_gather("{\"format\": \"dermis-profile\", \"version\": 1, \"name\": \"four-wide\", \"gaussians\": [\n"
                 " {\"variance_mm2\": 0.05, \"weights\": [0.05, 0.20, 0.40]},\n"
                 " {\"variance_mm2\": 0.3, \"weights\": [0.10, 0.20, 0.30]},\n"
                 " {\"variance_mm2\": 1.8, \"weights\": [0.20, 0.25, 0.15]},\n"
                 " {\"variance_mm2\": 2.2, \"weights\": [0.25, 0.15, 0.10]},\n"
                 " {\"variance_mm2\": 7.0, \"weights\": [0.20, 0.12, 0.04]},\n"
                 " {\"variance_mm2\": 8.0, \"weights\": [0.20, 0.08, 0.01]}]}\n",
                 4);
}

/* The pack holds the gather at the scene's size and at half of it ("gather.half.*", what a
 * renderer at N/2 reads, as thin.half): used at IRR and IRR / 2 on both blur paths, not at
 * IRR / 4; and at IRR / 2 it moves the sheet's bottom (the gathered levels replace the blur). */
Test(thin, the_gather_at_the_scenes_size_and_half_of_it, .timeout = 180)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    sheet_pack sp;
    pack_sheet(dir, 1.0, &sp);
    cr_assert(sp.assets.gather_half_index.width == IRR / 2 && sp.assets.gather_half_taps.texels,
              "gather.half %d", sp.assets.gather_half_index.width);
    for (int p = 0; p < 2; ++p)
        for (int q = 1; q <= 4; q *= 2) {
            dm_osmesa *ctx = NULL;
            dm_renderer *r = NULL;
            dm_error err = {0};
            cr_assert_eq(dm_osmesa_create(&ctx, &err), DM_OK, "%s", err.detail);
            dm_render_desc d = {.width = 64, .height = 64, .irradiance_size = IRR / q,
                                .blur_path = p ? DM_BLUR_PATH_GL : DM_BLUR_PATH_CPU};
            cr_assert_eq(dm_renderer_create(&sp.assets, &d, &r, &err), DM_OK, "%s", err.detail);
            cr_expect_eq(dm_renderer_thin_gather(r), q <= 2, "irradiance %d, %s blur", IRR / q, p ? "GL" : "CPU");
            dm_renderer_destroy(r);
            dm_osmesa_destroy(ctx);
        }
    dm_render_assets a = sp.assets;
    bool used;
    float *with = render_view(&a, IRR / 2, DM_BLUR_PATH_CPU, DM_VIEW_DIFFUSION, &used, NULL, NULL, NULL);
    a.gather_half_index = a.gather_half_taps = (dm_texture){0};
    float *without = render_view(&a, IRR / 2, DM_BLUR_PATH_CPU, DM_VIEW_DIFFUSION, &used, NULL, NULL, NULL);
    cr_assert(memcmp(with, without, sizeof *with * 4 * (IRR / 2) * (IRR / 2)), "the half-size gather changed nothing");
    free(with), free(without);
    dm_pack_close(&sp.pack);
}

/* A map of another size (its texels are other points) and an empty map: left out or adding
 * nothing, bit for bit. */
Test(thin, another_size_or_an_empty_map_change_nothing, .timeout = 120)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    sheet_pack sp;
    pack_sheet(dir, 1.0, &sp);
    float *half = thin_sheet_map(1.0, IRR / 2), *empty = calloc((size_t)4 * IRR * 2 * IRR, sizeof(float));
    for (int p = 0; p < 2; ++p) {
        dm_blur_path path = p ? DM_BLUR_PATH_GL : DM_BLUR_PATH_CPU;
        bool u0, u1, u2;
        float *none = diffusion_with(&sp, NULL, 0, path, &u0), *other = diffusion_with(&sp, half, IRR / 2, path, &u1),
              *zero = diffusion_with(&sp, empty, IRR, path, &u2);
        cr_assert(!u0 && !u1 && u2);
        cr_assert_eq(memcmp(none, other, sizeof *none * 4 * IRR * IRR), 0, "a map of another size was used");
        cr_assert_eq(memcmp(none, zero, sizeof *none * 4 * IRR * IRR), 0, "an empty map changed the picture");
        free(none), free(other), free(zero);
    }
    free(half), free(empty);
    dm_pack_close(&sp.pack);
}

/* The two blur paths agree with the map as without it: to float rounding (1e-4 of the value,
 * tests/render/test_render_blur_cpu.c's measure). */
Test(thin, the_cpu_and_gl_paths_agree, .timeout = 120)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    sheet_pack sp;
    pack_sheet(dir, 1.0, &sp);
    float *map = thin_sheet_map(1.0, IRR);
    bool u;
    float *cpu = diffusion_with(&sp, map, IRR, DM_BLUR_PATH_CPU, &u), *gl = diffusion_with(&sp, map, IRR, DM_BLUR_PATH_GL, &u);
    double worst = 0, range = 0;
    for (size_t i = 0; i < (size_t)4 * IRR * IRR; ++i) range = fmax(range, fabs(gl[i]));
    for (size_t i = 0; i < (size_t)4 * IRR * IRR; ++i) worst = fmax(worst, fabs(cpu[i] - gl[i]));
    cr_log_info("CPU vs GL with the thin map: %.2e of the range", worst / range);
    cr_assert_lt(worst, 1e-4 * range);
    free(cpu), free(gl), free(map);
    dm_pack_close(&sp.pack);
}

/* dermis-pack bakes the sheet's map itself (bake/dm_thin_map.h): every texel of the closed
 * form's has its candidate, the point straight across to float precision (u′, v′ 1e-5, i.e.
 * 1 µm; d 1e-5 mm), and nothing where the closed form has none but the texels along the
 * charts' rims (the rays from a rim texel may hit the other plate just past its edge). */
Test(thin, dermis_pack_bakes_the_sheets_map, .timeout = 120)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    sheet_pack sp;
    pack_sheet(dir, 1.0, &sp);
    const dm_texture *t = &sp.assets.thin;
    cr_assert(t->texels && t->format == DM_TEX_RGBA32F && t->width == IRR && t->height == 2 * IRR, "no thin map packed");
    float *want = thin_sheet_map(1.0, IRR);
    const float *got = t->texels;
    int matched = 0;
    for (size_t i = 0; i < (size_t)IRR * IRR; ++i) {
        const float *w = want + 4 * i, *g = got + 4 * i;
        if (w[3] > 0.5f) {
            cr_assert(g[3] > 0.5f, "texel %zu: no candidate", i);
            cr_assert(fabsf(g[0] - w[0]) < 1e-5f && fabsf(g[1] - w[1]) < 1e-5f && fabsf(g[2] - w[2]) < 1e-5f,
                      "texel %zu: (%g, %g, %g), expected (%g, %g, %g)", i, g[0], g[1], g[2], w[0], w[1], w[2]);
            ++matched;
        }
        cr_assert(!(got[4 * ((size_t)IRR * IRR + i) + 3] > 0.5f) || w[3] > 0.5f, "texel %zu: a second surface?", i);
    }
    cr_assert_gt(matched, 10000);
    free(want);
    dm_pack_close(&sp.pack);
}

/* The debug view "thin" (DM_VIEW_THIN): at the irradiance grid, per texel (mm across, flag,
 * 0, chart coverage) of the map's nearer point: on the sheet every chart texel flagged at
 * s mm; and its legend runs from 0 to 3 sigma of the widest Gaussian. */
Test(thin, the_debug_view_shows_the_map, .timeout = 120)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    sheet_pack sp;
    pack_sheet(dir, 1.0, &sp);
    float *map = thin_sheet_map(1.0, IRR);
    bool used;
    float lo, hi;
    const char *q;
    float *px = view_with(&sp, map, IRR, DM_BLUR_PATH_AUTO, DM_VIEW_THIN, &used, &lo, &hi, &q);
    int flagged = 0;
    for (size_t i = 0; i < (size_t)IRR * IRR; ++i) {
        const float *p = px + 4 * i, *m = map + 4 * i;
        cr_assert_eq(p[1], m[3], "texel %zu: flag %g, the map's %g", i, p[1], m[3]);
        cr_assert_eq(p[0], m[2], "texel %zu: %g mm, the map's %g", i, p[0], m[2]);
        if (m[3] > 0.5f) {
            cr_assert_eq(p[3], 1.0f, "texel %zu: a point across off the charts", i);
            ++flagged;
        }
    }
    cr_assert_gt(flagged, 10000);
    double reach = 3 * sqrt(sp.profile.variance_mm2[sp.profile.count - 1]);
    cr_assert(lo == 0.0f && fabs(hi - reach) < 1e-5 && q && strstr(q, "thin-part map"), "%g..%g %s", lo, hi, q);
    free(px), free(map);
    dm_pack_close(&sp.pack);
}

/* The debug view "gather" (DM_VIEW_GATHER): at the irradiance grid, per texel (taps of both
 * gathered levels, 1 where it gathers, 0, chart coverage) of the pack's thin gather; its legend
 * runs from 0 to the most taps a texel has. */
Test(thin, the_gather_debug_view_shows_the_taps, .timeout = 120)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    sheet_pack sp;
    pack_sheet(dir, 1.0, &sp);
    bool used;
    float lo, hi;
    const char *q;
    float *px = render_view(&sp.assets, IRR, DM_BLUR_PATH_AUTO, DM_VIEW_GATHER, &used, &lo, &hi, &q);
    const float *ix = sp.assets.gather_index.texels;
    int gathering = 0;
    float most = 0;
    for (size_t i = 0; i < (size_t)IRR * IRR; ++i) {
        const float *p = px + 4 * i, *m = ix + 4 * i;
        float taps = m[1] + m[2];
        most = fmaxf(most, taps);
        cr_assert_eq(p[0], taps, "texel %zu: %g taps, the index's %g", i, p[0], taps);
        cr_assert_eq(p[1], taps > 0 ? 1.0f : 0.0f, "texel %zu: flag %g", i, p[1]);
        gathering += taps > 0;
    }
    cr_assert_gt(gathering, 10000);
    cr_assert(lo == 0.0f && hi == most && q && strstr(q, "thin gather"), "%g..%g %s", lo, hi, q);
    free(px);
    dm_pack_close(&sp.pack);
}

/* The pack holds the map at the scene's size and at half of it ("thin.half", what a renderer
 * at N/2 — dermis-view's default — reads): at IRR / 2 the pack's own maps light the sheet's
 * dark bottom from its top, on both blur paths; at IRR / 4 (neither size) they are left out. */
Test(thin, the_half_size_map_at_half_the_size, .timeout = 120)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    sheet_pack sp;
    pack_sheet(dir, 1.0, &sp);
    cr_assert(sp.assets.thin.width == IRR && sp.assets.thin_half.width == IRR / 2 && sp.assets.thin_half.height == IRR,
              "thin %d, thin.half %dx%d", sp.assets.thin.width, sp.assets.thin_half.width, sp.assets.thin_half.height);
    for (int p = 0; p < 2; ++p)
        for (int q = 2; q <= 4; q += 2) {
            const int n = IRR / q;
            bool used;
            float *px = render_view(&sp.assets, n, p ? DM_BLUR_PATH_GL : DM_BLUR_PATH_CPU, DM_VIEW_DIFFUSION, &used, NULL,
                                    NULL, NULL);
            cr_assert_eq(used, q == 2, "at %d", n);
            double uv[2];
            thin_sheet_uv(1, THIN_SHEET_L / 2, THIN_SHEET_L / 2, uv);
            const float *bottom = px + 4 * ((size_t)floor(uv[1] * n) * n + (size_t)floor(uv[0] * n));
            thin_sheet_uv(0, THIN_SHEET_L / 2, THIN_SHEET_L / 2, uv);
            const float *top = px + 4 * ((size_t)floor(uv[1] * n) * n + (size_t)floor(uv[0] * n));
            double want[3];
            across(&sp.profile, 1.0, want);
            if (q == 2) /* a texel centre off the sheet's middle by up to half a texel: 2 % */
                cr_expect(fabs(bottom[0] / top[0] / want[0] - 1) < 0.02, "at %d: across %g of the top, expected %g", n,
                          bottom[0] / top[0], want[0]);
            else
                cr_expect_lt(bottom[0], 1e-6f * top[0], "at %d: the bottom is lit without a map", n);
            free(px);
        }
    dm_pack_close(&sp.pack);
}
