/* The seam map in the renderer (issue #29 point 1): a flat plate cut into two UV charts along
 * x = L/2 (tests/common/seam_plate.h), lit by a point light beside the seam so the irradiance
 * changes across it, packed by dermis-pack (which bakes the seam map) and blurred in texture
 * space. The same plate uncut (one chart) is the truth the cut one must reproduce: the surface,
 * the light and the profile are the same, only the atlas differs. With the seam map the
 * diffusion near the seam matches the uncut plate's; without it (the blurs stop at the seam)
 * it does not. And a mesh without seams: its empty seam map changes nothing, bit for bit. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/obj_write.h"
#include "../common/seam_plate.h"
#include "../common/tmpdir.h"
#include "host/dm_osmesa.h"
#include "pack/dm_pack.h"
#include "render/dm_render.h"
#include "render/dm_render_pack.h"

enum { IRR = 256 };

typedef struct plate_pack {
    dm_pack pack;
    dm_scene scene;
    dm_profile profile;
    dm_render_assets assets;
} plate_pack;

/* Writes the plate as OBJ (one vt per corner), a scene with subsurface only and a point light
 * 6 mm above the left chart, 4 mm from the seam; packs it with dermis-pack and opens it. */
static void pack_mesh(const char *dir, const char *name, const dm_mesh *m, plate_pack *out)
{
    char path[256], cmd[1024], log[256];
    snprintf(path, sizeof path, "%s/%s.obj", dir, name);
    test_write_obj(path, m);
    snprintf(path, sizeof path, "%s/%s.json", dir, name);
    FILE *f = fopen(path, "w");
    cr_assert(f);
    fprintf(f, "{\"mesh\": {\"path\": \"%s.obj\", \"mm_per_unit\": 1},\n"
               " \"lights\": [{\"type\": \"point\", \"position\": [23, 20, 3], \"intensity\": 40}],\n"
               " \"effects\": {\"subsurface\": {\"irradiance_size\": %d}},\n"
               " \"camera\": {\"eye\": [20, 20, 80], \"target\": [20, 20, 0]}, \"output\": {\"width\": 64, \"height\": 64}}\n",
            name, IRR);
    fclose(f);
    snprintf(cmd, sizeof cmd, "cd '%s' && " DERMIS_BIN "/dermis-pack %s.json -o %s.dpk --threads 1 --quiet", dir, name, name);
    snprintf(log, sizeof log, "%s/%s.log", dir, name);
    int rc = test_run(cmd, log);
    char *text = rc ? test_slurp(log) : NULL;
    cr_assert_eq(rc, 0, "dermis-pack failed: %s", text ? text : "");
    snprintf(path, sizeof path, "%s/%s.dpk", dir, name);
    dm_error err = {0};
    cr_assert_eq(dm_pack_open(path, &out->pack, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_assets_from_pack(&out->pack, &out->scene, &out->profile, &out->assets, &err), DM_OK, "%s",
                 err.detail);
    cr_assert_not_null(out->assets.seam.texels, "dermis-pack made no seam map");
}

static void pack_plate(const char *dir, const char *name, const seam_plate *p, plate_pack *out)
{
    dm_mesh m;
    seam_plate_mesh(p, &m);
    pack_mesh(dir, name, &m, out);
    dm_mesh_free(&m);
}

/* The diffusion view (IRR², RGBA) of the assets, the seam map left out when without_seam. The
 * pack's thin gather (which also takes the widest levels near seams) is left out unless
 * with_gather: these tests hold the seam map's own work. The renderer uses the seam map beside
 * the gather too (since 2026-12-02). */
static dm_blur_path blur_path = DM_BLUR_PATH_AUTO; /* llvmpipe: the CPU's */
static bool with_gather = false;

static float *view_at(const plate_pack *pp, bool without_seam, int irr, dm_view view)
{
    dm_render_assets a = pp->assets;
    if (without_seam) a.seam = (dm_texture){0};
    if (!with_gather) a.gather_index = a.gather_taps = a.gather_half_index = a.gather_half_taps = (dm_texture){0};
    dm_osmesa *ctx = NULL;
    dm_renderer *r = NULL;
    dm_error err = {0};
    cr_assert_eq(dm_osmesa_create(&ctx, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_renderer_create(&a, &(dm_render_desc){.width = 64, .height = 64, .irradiance_size = irr, .blur_path = blur_path},
                                    &r, &err),
                 DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_frame(r, &(dm_frame_options){.view = view}, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_renderer_thin_gather(r), with_gather);
    cr_assert_eq(dm_renderer_seam_map(r), !without_seam && irr == pp->assets.seam.width);
    int w, h;
    dm_renderer_view_size(r, &w, &h);
    cr_assert(w == irr && h == irr);
    float *px = malloc(sizeof *px * 4 * (size_t)irr * irr);
    cr_assert_eq(dm_renderer_read_view(r, px, &err), DM_OK, "%s", err.detail);
    dm_renderer_destroy(r);
    dm_osmesa_destroy(ctx);
    return px;
}

static float *diffusion_at(const plate_pack *pp, bool without_seam, int irr)
{
    return view_at(pp, without_seam, irr, DM_VIEW_DIFFUSION);
}

static float *diffusion(const plate_pack *pp, bool without_seam) { return diffusion_at(pp, without_seam, IRR); }

static const float *at(const float *px, const double uv[2])
{
    int i = (int)floor(uv[0] * IRR), j = (int)floor(uv[1] * IRR);
    return px + 4 * ((size_t)j * IRR + i);
}

/* Mean relative error (red) of the cut plate's diffusion against the uncut one's at the texel
 * centres of the cut plate's charts within `band` mm of the seam, clear of the plate's other
 * edges by 8 mm; both charts. */
static double seam_error(const seam_plate *p, const float *cut, const float *uncut, double band, int *count)
{
    const seam_plate whole = {.a = p->a, .b = p->a, .uncut = 1};
    double sum = 0;
    *count = 0;
    for (int right = 0; right < 2; ++right)
        for (int j = 0; j < IRR; ++j)
            for (int i = 0; i < IRR; ++i) {
                double u = (i + 0.5) / IRR, v = (j + 0.5) / IRR, x, y, s = right ? p->b : p->a;
                y = (v - 0.1) / s;
                if (!right) x = (u - 0.05) / p->a;
                else x = p->mirrored ? SEAM_PLATE_L - (u - 0.55) / p->b : (u - 0.55) / p->b + SEAM_PLATE_L / 2;
                double beyond = fabs(x - SEAM_PLATE_L / 2);
                if (right ? x < SEAM_PLATE_L / 2 : x > SEAM_PLATE_L / 2) continue;
                if (!(beyond < band && y > 8 && y < SEAM_PLATE_L - 8)) continue;
                double uv[2], uw[2] = {u, v};
                seam_plate_uv(&whole, 0, x, y, uv);
                const float *c = at(cut, uw), *t = at(uncut, uv);
                cr_assert(c[3] > 0.5f && t[3] > 0.5f && t[0] > 0);
                sum += fabs(c[0] - t[0]) / t[0];
                ++*count;
            }
    return sum / *count;
}

/* The cut plate (same texel density on both sides, so the truth's discretisation is the
 * cut plate's) against the whole one within 3 mm of the seam; returns the errors with and
 * without the seam map. */
static void cut_against_whole(const seam_plate *cut_p, double *e_with, double *e_without)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    const seam_plate whole_p = {.a = cut_p->a, .b = cut_p->a, .uncut = 1};
    plate_pack cut, whole;
    pack_plate(dir, "cut", cut_p, &cut);
    pack_plate(dir, "whole", &whole_p, &whole);
    float *with = diffusion(&cut, false), *without = diffusion(&cut, true), *truth = diffusion(&whole, false);
    int n1, n2;
    *e_with = seam_error(cut_p, with, truth, 3.0, &n1), *e_without = seam_error(cut_p, without, truth, 3.0, &n2);
    cr_log_info("%s: within 3 mm of the seam (%d texels): mean |cut - whole| / whole, red: %.3f %% with the seam map, "
                "%.3f %% without", cut_p->mirrored ? "mirrored" : "plain", n1, 100 * *e_with, 100 * *e_without);
    cr_assert_gt(n1, 500);
    free(with), free(without), free(truth);
    dm_pack_close(&cut.pack), dm_pack_close(&whole.pack);
}

/* Measured: 0.15 % with, 2.0 % without (the light is over the other chart, 3 mm above it, 3 mm
 * from the seam: without the map the near side never receives it). 0.5 % leaves room for the
 * texel rounding of the continuation; 5x is what a continuation at all must give. */
Test(seam, the_blur_crosses_a_cut_as_if_the_plate_were_whole, .timeout = 120)
{
    double with, without;
    cut_against_whole(&(seam_plate){.a = 0.01, .b = 0.01}, &with, &without);
    cr_expect_lt(with, 0.005, "with the seam map: %.3f %%", 100 * with);
    cr_expect_gt(without, 5 * with, "without: %.3f %%, with: %.3f %%", 100 * without, 100 * with);
}

Test(seam, the_blur_crosses_into_a_mirrored_chart, .timeout = 120)
{
    double with, without;
    cut_against_whole(&(seam_plate){.a = 0.01, .b = 0.01, .mirrored = 1}, &with, &without);
    cr_expect_lt(with, 0.005, "with the seam map: %.3f %%", 100 * with);
    cr_expect_gt(without, 5 * with, "without: %.3f %%, with: %.3f %%", 100 * without, 100 * with);
}

/* With the pack's thin gather, which takes the two widest levels within 3 mm of the cut as the
 * 3-D sum over the plate's surface: even without the seam map the cut side then receives the
 * light from across (measured 0.34 %, against 2.0 % with neither), and the seam map beside it,
 * the default, carries the narrower levels across too (0.17 %). 0.7x: the map must still take
 * off a good part of what the gather leaves. The truth, the whole plate, is rendered with its
 * gather too (along its outer rim, clear of the band measured). */
Test(seam, the_gather_carries_the_widest_levels_across_a_cut, .timeout = 120)
{
    double with, without;
    with_gather = true;
    cut_against_whole(&(seam_plate){.a = 0.01, .b = 0.01}, &with, &without);
    cr_expect_lt(with, 0.005, "with the seam map and the gather (the default): %.3f %%", 100 * with);
    cr_expect_lt(without, 0.005, "with the gather alone: %.3f %%", 100 * without);
    cr_expect_lt(with, 0.7 * without, "the seam map beside the gather: %.3f %%, the gather alone: %.3f %%", 100 * with,
                 100 * without);
}

/* The same on the blurs in GL: both paths read the band the irradiance pass lit. */
Test(seam, the_blur_in_gl_crosses_a_cut_too, .timeout = 120)
{
    double with, without;
    blur_path = DM_BLUR_PATH_GL;
    cut_against_whole(&(seam_plate){.a = 0.01, .b = 0.01}, &with, &without);
    cr_expect_lt(with, 0.005, "with the seam map: %.3f %%", 100 * with);
    cr_expect_gt(without, 5 * with, "without: %.3f %%, with: %.3f %%", 100 * without, 100 * with);
}

Test(seam, a_mesh_without_seams_renders_the_same_bit_for_bit, .timeout = 120)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    const seam_plate whole_p = {.a = 0.01, .b = 0.01, .uncut = 1};
    plate_pack whole;
    pack_plate(dir, "whole", &whole_p, &whole);
    float *with = diffusion(&whole, false), *without = diffusion(&whole, true);
    cr_assert_eq(memcmp(with, without, sizeof *with * 4 * IRR * IRR), 0);
    free(with), free(without);
    dm_pack_close(&whole.pack);
}

/* A seam map baked for another irradiance size is not used (its gutters are other texels):
 * the cut plate at half the pack's size renders as without one, bit for bit. */
Test(seam, a_map_of_another_size_is_left_out, .timeout = 120)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    plate_pack cut;
    pack_plate(dir, "cut", &(seam_plate){.a = 0.01, .b = 0.01}, &cut);
    float *with = diffusion_at(&cut, false, IRR / 2), *without = diffusion_at(&cut, true, IRR / 2);
    cr_assert_eq(memcmp(with, without, sizeof *with * 4 * (IRR / 2) * (IRR / 2)), 0);
    free(with), free(without);
    dm_pack_close(&cut.pack);
}

/* The debug view "seam" (DM_VIEW_SEAM): per texel (mm beyond the chart's edge, continued, 0,
 * chart coverage) of the pack's seam map: the continued gutter texels flagged at their
 * distance and off the charts, the rest unflagged. */
Test(seam, the_debug_view_shows_the_map, .timeout = 120)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    plate_pack cut;
    pack_plate(dir, "cut", &(seam_plate){.a = 0.01, .b = 0.01}, &cut);
    float *px = view_at(&cut, false, IRR, DM_VIEW_SEAM);
    const float *map = cut.assets.seam.texels;
    int flagged = 0;
    for (size_t i = 0; i < (size_t)IRR * IRR; ++i) {
        const float *p = px + 4 * i, *m = map + 4 * i;
        cr_assert(p[1] == m[2] && p[0] == m[3], "texel %zu: (%g mm, %g), the map's (%g, %g)", i, p[0], p[1], m[3], m[2]);
        if (m[2] > 0.5f) {
            cr_assert_eq(p[3], 0.0f, "texel %zu: continued but on a chart", i);
            ++flagged;
        }
    }
    cr_assert_gt(flagged, 100);
    free(px);
    dm_pack_close(&cut.pack);
}

/* The cut plate with a strip beside its left chart in the atlas (2 texels below it, as wide as
 * the chart and 8 mm tall) that lies 60 mm behind the plate in 3-D, facing away from the light:
 * unlit, coverage 1. A blur tap that lands on the strip reads another place of the surface; the
 * seam points leave it out (core/dm_level_blur.h), so the plate's diffusion is that of the plate
 * alone. Measured within 8 mm of the plate's lower edge, red: 10.8 % at most without the check
 * (the strip's black pulls the edge down), 0.22 % with it (what still reaches through gutter
 * texels more than 2 texels from every chart, which have no point); 0.5 % holds the one and fails
 * the other. GL and the CPU agree. */
static void plate_and_strip(dm_mesh *m)
{
    const seam_plate p = {.a = 0.01, .b = 0.01};
    dm_mesh plate;
    seam_plate_mesh(&p, &plate);
    dm_error err = {0};
    int nv = plate.vertex_count, nt = plate.triangle_count;
    cr_assert_eq(dm_mesh_alloc(nv + 4, nt + 2, m, &err), DM_OK);
    memcpy(m->positions, plate.positions, sizeof(float) * 3 * (size_t)nv);
    memcpy(m->indices, plate.indices, sizeof(uint32_t) * 3 * (size_t)nt);
    memcpy(m->uvs, plate.uvs, sizeof(float) * 6 * (size_t)nt);
    const float corner[4][2] = {{0, -8}, {20, -8}, {20, 0}, {0, 0}}; /* x, y in mm at z = −60 */
    for (int k = 0; k < 4; ++k) {
        float *q = m->positions + 3 * (size_t)(nv + k);
        q[0] = corner[k][0], q[1] = corner[k][1], q[2] = -60.0f;
    }
    const int tri[2][3] = {{0, 2, 1}, {0, 3, 2}}; /* clockwise from +z: faces −z, away from the light */
    double gap = 2.0 / IRR;
    for (int t = 0; t < 2; ++t)
        for (int k = 0; k < 3; ++k) {
            int c = tri[t][k];
            m->indices[3 * (nt + t) + k] = (uint32_t)(nv + c);
            m->uvs[6 * (nt + t) + 2 * k] = (float)(0.05 + 0.01 * corner[c][0]);
            m->uvs[6 * (nt + t) + 2 * k + 1] = (float)(0.1 - gap + 0.01 * corner[c][1]);
        }
    dm_mesh_free(&plate);
    dm_mesh_compute_normals(m);
    cr_assert_eq(dm_mesh_validate(m, "plate and strip", &err), DM_OK, "%s", err.detail);
}

Test(seam, a_chart_beside_another_in_the_atlas_lends_it_no_light, .timeout = 180)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    dm_mesh m;
    plate_and_strip(&m);
    plate_pack both, alone;
    pack_mesh(dir, "both", &m, &both);
    dm_mesh_free(&m);
    pack_plate(dir, "alone", &(seam_plate){.a = 0.01, .b = 0.01}, &alone);
    float *px[2][2];
    for (int path = 0; path < 2; ++path) {
        blur_path = path ? DM_BLUR_PATH_GL : DM_BLUR_PATH_CPU;
        px[path][0] = diffusion(&both, false), px[path][1] = diffusion(&alone, false);
    }
    blur_path = DM_BLUR_PATH_AUTO;
    /* the left chart's texels within 8 mm of its lower edge (the strip's side), both paths */
    double worst[2] = {0, 0}, paths = 0;
    int count = 0;
    for (int j = 0; j < IRR; ++j)
        for (int i = 0; i < IRR; ++i) {
            double x = ((i + 0.5) / IRR - 0.05) / 0.01, y = ((j + 0.5) / IRR - 0.1) / 0.01;
            if (!(x > 0.5 && x < 19.5 && y > 0.5 && y < 8)) continue;
            const float *t = px[0][1] + 4 * ((size_t)j * IRR + i);
            cr_assert(t[3] > 0.5f && t[0] > 0.0f);
            for (int path = 0; path < 2; ++path) {
                const float *c = px[path][0] + 4 * ((size_t)j * IRR + i);
                worst[path] = fmax(worst[path], fabs(c[0] - t[0]) / t[0]);
            }
            const float *g = px[1][0] + 4 * ((size_t)j * IRR + i), *c = px[0][0] + 4 * ((size_t)j * IRR + i);
            paths = fmax(paths, fabs(g[0] - c[0]) / t[0]);
            ++count;
        }
    cr_log_info("strip beside the plate: %d texels, largest |with strip - alone| / alone: CPU %.2e, GL %.2e; "
                "|GL - CPU| %.2e", count, worst[0], worst[1], paths);
    cr_assert_gt(count, 500);
    cr_expect_lt(worst[0], 0.005, "CPU: %g", worst[0]);
    cr_expect_lt(worst[1], 0.005, "GL: %g", worst[1]);
    cr_expect_lt(paths, 1e-4, "GL against CPU: %g", paths);
    for (int path = 0; path < 2; ++path) free(px[path][0]), free(px[path][1]);
    dm_pack_close(&both.pack), dm_pack_close(&alone.pack);
}

/* The seam points (seam_points.glsl) on the cut plate, along the row at y = 20 mm: a covered
 * texel has its own point; a gutter texel the seam map continues, its continuation's (the flat
 * plate goes on across the seam, so the point is the texel's own place on it); a gutter texel
 * outside the plate's left edge (a boundary: nothing continues) the nearest covered texel's
 * point within 2 texels, and none 3 texels out. */
Test(seam, every_texel_gets_the_point_it_is_lit_at, .timeout = 120)
{
    char dir[64];
    cr_assert(test_tmpdir(dir, sizeof dir));
    plate_pack cut;
    const seam_plate p = {.a = 0.01, .b = 0.01};
    pack_plate(dir, "cut", &p, &cut);
    dm_osmesa *ctx = NULL;
    dm_renderer *r = NULL;
    dm_error err = {0};
    cr_assert_eq(dm_osmesa_create(&ctx, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_renderer_create(&cut.assets, &(dm_render_desc){.width = 64, .height = 64, .irradiance_size = IRR},
                                    &r, &err),
                 DM_OK, "%s", err.detail);
    cr_assert_eq(dm_render_frame(r, &(dm_frame_options){.view = DM_VIEW_DIFFUSION}, &err), DM_OK, "%s", err.detail);
    int idx = dm_renderer_find_target(r, "seam_points");
    cr_assert_geq(idx, 0);
    dm_target_info info;
    dm_renderer_target_info(r, idx, &info);
    cr_assert(info.width == IRR && info.height == IRR && info.channels == 4);
    float *px = malloc(sizeof *px * 4 * IRR * IRR);
    cr_assert_eq(dm_renderer_read_target(r, idx, px, &err), DM_OK, "%s", err.detail);
    int j = (int)(0.3 * IRR); /* v = 0.1 + 0.01 · y: y ≈ 20 mm */
    double y = ((j + 0.5) / IRR - 0.1) / 0.01;
    int first = -1, continued = 0;
    for (int i = 0; i < IRR; ++i) {
        const float *q = px + 4 * ((size_t)j * IRR + i);
        double u = (i + 0.5) / IRR, x = (u - 0.05) / 0.01; /* the left chart's map, extended */
        if (x > 0 && x < SEAM_PLATE_L / 2) { /* covered, left chart */
            if (first < 0) first = i;
            cr_expect_gt(q[3], 0.5f, "texel %d", i);
            cr_expect(fabs(q[0] - x) < 1e-3 && fabs(q[1] - y) < 1e-3 && fabs(q[2]) < 1e-3, "texel %d: (%g, %g, %g), expected (%g, %g, 0)",
                      i, (double)q[0], (double)q[1], (double)q[2], x, y);
        } else if (x > SEAM_PLATE_L / 2 && x < SEAM_PLATE_L / 2 + 4) { /* the seam's gutter: the plate continued */
            if (q[3] > 0.5f && fabs(q[0] - x) < 0.2 && fabs(q[1] - y) < 1e-3) ++continued;
        }
    }
    cr_assert_gt(first, 3);
    cr_expect_gt(continued, 5, "%d continued gutter texels along the row (4 mm: 10)", continued);
    const float *edge = px + 4 * ((size_t)j * IRR + first);
    for (int k = 1; k <= 3; ++k) {
        const float *q = px + 4 * ((size_t)j * IRR + first - k);
        if (k <= 2)
            cr_expect(q[3] > 0.5f && q[0] == edge[0] && q[1] == edge[1] && q[2] == edge[2],
                      "%d texels out: (%g, %g, %g, %g), expected the edge texel's point", k, (double)q[0], (double)q[1],
                      (double)q[2], (double)q[3]);
        else
            cr_expect_eq(q[3], 0.0f, "%d texels out: a point (%g)", k, (double)q[3]);
    }
    free(px);
    dm_renderer_destroy(r);
    dm_osmesa_destroy(ctx);
    dm_pack_close(&cut.pack);
}
