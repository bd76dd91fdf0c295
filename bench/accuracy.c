/* bench/accuracy — what each renderer setting costs in time and in accuracy against the
 * ground truth (DESIGN.md promise 1): the exact surface convolution of dermis-reference.
 *
 * Scene: assets/scenes/lps-sss.json (subsurface, shadows, tonemap; no glow), packed here.
 * One row per setting (add_rows; a technique added later is one more row there):
 * irradiance size 256…1024 (2048 with DERMIS_BENCH_LARGE=1), blur taps, 1…8 Gaussians
 * fitted to one profile (the skin1 dipole when dermis-reference offers --dipole, else
 * gems3-skin; one pack each) and compared with ONE reference of that profile, stretch
 * correction off (the chain replaced by one constant texture of the chart's median s_u,
 * s_v), the dm_render_desc speed knobs, screen-space SSS, translucency; and two fits against
 * their own truth, texture space only: six Gaussians fitted to Burley, and the six the packer
 * fits to the physical skin's Caucasian exemplar against that skin's own profile. Columns:
 *   - frame ms: median of DERMIS_BENCH_FRAMES (default 7, at least 5) final frames at
 *     1280x720 after one warm-up, every row's renderer alive and the frames run round
 *     robin so the shared machine's load hits every row alike;
 *   - texture-space error: the `diffusion` view at irradiance N against `dermis-reference
 *     PACK --texture-space N`, area-weighted (dm_ref_regions.h: texel area in mm²), mean and
 *     p95 per channel, over the whole skin and per region (smooth, within 3 mm of a UV
 *     seam, thin parts and folds); on stderr each region's signed bias and its error by ring
 *     from the chart's edge (ring 1 touches an uncovered texel: where the blur meets a chart's
 *     outline);
 *   - frame error, taken apart (common/frame_truth.h): the final linear frame at 1280x720
 *     against `dermis-reference PACK --frame` in a transport run (white albedo, no normal
 *     map, no shadows; normalised by the no-subsurface frame where subsurface shows), then
 *     with the surface terms and with shadows; a no-subsurface row is the floor. The 2048
 *     row renders the scene packed at irradiance 2048 (its maps baked for that size; its
 *     thin gather in blocks of 2 x 2 texels, bake/dm_thin_gather.h).
 * References are computed once by the dermis-reference tool and cached under
 * BUILD/cache/accuracy/ by pack hash, truth and size, reused when their provenance matches.
 * DERMIS_BENCH_QUICK=1: irradiance 256 only, fewer Gaussian rows, 5 frames.
 * DERMIS_BENCH_TEXTURE_ONLY=1: the texture-space columns only (no frame reference is computed
 * or read; the frame columns say –), to measure a texture-space change quickly.
 * DERMIS_BENCH_ROWS=a,b,...: only the rows of those short names (the region table's first
 * column, e.g. "1024,1024 reduce5") and only the truths and packs they need (without a
 * Gaussian-count row, not the dipole's frames: hours), to measure a change quickly; write to
 * another OUTDIR (a results file from such a run says so under its title).
 * Writes OUTDIR/accuracy.md, accuracy.png (Pareto plot, gnuplot), accuracy-frame.png
 * (reference | default render | error, the frame), accuracy-regions.png (the labels) and
 * accuracy-seam-error.png, accuracy-thin-error.png (the default row's signed red error in those regions)
 * through common/accuracy_report.h. argv[2], optional: a pack of SCENE made earlier (its
 * cached references are reused; the Gaussian-count packs are made from SCENE). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "reference/dm_ref_regions.h"
#include "reference/dm_ref_surface.h"
#include "reference/dm_reference.h"
#include "common/bench_util.h"
#include "core/dm_hash.h"
#include "pack/dm_pack.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_image.h"
#include "render/dm_render_pack.h"
#include "render/dm_render_refcmp.h"

#include "common/accuracy_report.h"
#include "common/accuracy_packs.h"
#include "common/accuracy_refs.h"
#include "common/atlas_regions.h"

static bool texture_only; /* DERMIS_BENCH_TEXTURE_ONLY=1: no frame references, no frame error */

static setting *add(int size, int taps, int g, bool flat, dm_render_desc knobs, const char *name, const char *what)
{
    static setting skipped; /* a row DERMIS_BENCH_ROWS leaves out */
    const char *only = getenv("DERMIS_BENCH_ROWS");
    char key[64], list[1024];
    snprintf(key, sizeof key, ",%s,", name);
    snprintf(list, sizeof list, ",%s,", only ? only : "");
    if (only && !strstr(list, key)) return &skipped;
    if (nrows == MAX_ROWS) {
        fprintf(stderr, "error: more than %d rows (MAX_ROWS)\n", MAX_ROWS);
        exit(3);
    }
    setting *s = &rows_s[nrows++];
    *s = (setting){.size = size, .taps = taps, .gaussians = g, .flat_stretch = flat, .knobs = knobs};
    snprintf(s->name, sizeof s->name, "%s", name);
    snprintf(s->what, sizeof s->what, "%s", what);
    return s;
}

/* The row of g Gaussians fitted to the truth (the dipole, or gems3-skin), at irradiance N. */
static void add_fit(int N, int g)
{
    char n[40], w[160];
    snprintf(n, sizeof n, "%d G%d", N, g);
    if (dipole) snprintf(w, sizeof w, "%d, %d Gaussian%s fitted to the %s dipole", N, g, g > 1 ? "s" : "", dipole);
    else snprintf(w, sizeof w, "%d, %d Gaussian%s fitted to gems3-skin%s", N, g, g > 1 ? "s" : "", g == 6 ? " (its own six)" : "");
    add(N, 0, g, false, (dm_render_desc){0}, n, w);
}

/* The rows; B is the size the knobs are measured at. */
static void add_rows(bool quick, bool large, int B)
{
    char n[40], w[160];
    for (int N = 256; N <= (large ? 2048 : 1024) && (N == 256 || !quick); N *= 2) {
        snprintf(n, sizeof n, "%d", N), snprintf(w, sizeof w, "irradiance %d, 7 taps%s", N, N == 1024 ? " (the scene's default)" : "");
        add(N, 0, 0, false, (dm_render_desc){0}, n, w)->technique_row = N >= 1024; /* the scene's size, or finer */
    }
    if (!quick && !large) { /* the frame's ranking of 2048 (its texture-space reference: DERMIS_BENCH_LARGE) */
        setting *f = add(2048, 0, 0, false, (dm_render_desc){0}, "2048 frame", "irradiance 2048, 7 taps (frame only)");
        f->frame_only = f->technique_row = true;
    }
    /* the floor: what leaving subsurface out costs */
    add(B, 0, 0, false, (dm_render_desc){0}, "no subsurface", "no subsurface (Lambert x albedo): the floor")->no_subsurface = true;
    /* the levels summed per pixel by the final pass instead of once per texel by the diffusion
     * pass (dm_render_desc.diffusion_per_pixel): the two differ along chart edges */
    for (int N = 256; N <= 1024 && (N == 256 || !quick); N *= 2) {
        snprintf(n, sizeof n, "%d per-pixel", N);
        snprintf(w, sizeof w, "irradiance %d, the levels summed per pixel (--diffusion-per-pixel)", N);
        add(N, 0, 0, false, (dm_render_desc){.diffusion_per_pixel = true}, n, w);
    }
    /* the automatic blur resolution (dm_render_desc.blur_auto_resolution) */
    for (int N = quick ? 256 : 512; N <= 1024; N *= 2) {
        snprintf(n, sizeof n, "%d auto", N);
        snprintf(w, sizeof w, "irradiance %d, blur levels at the automatic resolution (--blur-auto)", N);
        add(N, 0, 0, false, (dm_render_desc){.blur_auto_resolution = true}, n, w);
    }
    for (int t = 5; t <= 9; t += 4) {
        snprintf(n, sizeof n, "%d taps %d", B, t), snprintf(w, sizeof w, "irradiance %d, %d taps", B, t);
        add(B, t, 0, false, (dm_render_desc){0}, n, w);
    }
    /* the fits at the scene's irradiance size, where every map the pack bakes applies; the last
     * two again at B, not a check (the pack's half-size maps, no seam map at that size) */
    for (int g = 1; g <= MAX_G; ++g)
        if (!quick || g == 1 || g == 3) add_fit(quick ? B : 1024, g);
    for (int g = MAX_G - 1; g <= MAX_G && !quick; ++g) add_fit(B, g);
    /* the seam map left out (issue #29 point 1): beside the gather, the gather alone carries the
     * widest levels across seams (the default before 2026-12-02; at 512 there is no map at that
     * size); the thin-part map left out (point 2): no light from across thin parts and folds */
    if (!quick) add(1024, 0, 0, false, (dm_render_desc){0}, "1024 no seam map",
                    "1024, without the seam map (--no-seam-map: the gather alone across seams)")->no_seam = true;
    for (int N = 512; N <= 1024 && !quick; N *= 2) {
        snprintf(n, sizeof n, "%d no thin", N), snprintf(w, sizeof w, "%d, without the thin-part map (no light across thin parts)", N);
        add(N, 0, 0, false, (dm_render_desc){0}, n, w)->no_thin = true;
    }
    /* the thin gather left out: the widest levels from the atlas blur and the thin-part map */
    if (!quick) add(1024, 0, 0, false, (dm_render_desc){0}, "1024 no gather",
                    "1024, without the thin gather (the widest levels from the atlas blur)")->no_gather = true;
    /* none of issue #29's maps: the texture-space frame its cost aim is measured against */
    if (!quick) {
        setting *s = add(1024, 0, 0, false, (dm_render_desc){0}, "1024 no maps",
                         "1024, without the seam map, the thin-part map and the gather (before issue #29)");
        s->no_seam = s->no_thin = true;
    }
    snprintf(n, sizeof n, "%d no stretch", B), snprintf(w, sizeof w, "%d, stretch correction off (one median s_u, s_v)", B);
    add(B, 0, 0, true, (dm_render_desc){0}, n, w);
    snprintf(n, sizeof n, "%d reduce3", B), snprintf(w, sizeof w, "%d, --blur-reduce-from 3 (levels 3..5 at %d)", B, B / 2);
    add(B, 0, 0, false, (dm_render_desc){.blur_reduce_from = 3}, n, w);
    /* the reduced levels at the scene's default size: what issue #16's frame aim would cost */
    for (int K = 5; K >= 3 && !quick; --K) {
        snprintf(n, sizeof n, "1024 reduce%d", K);
        if (K == 5) snprintf(w, sizeof w, "1024, --blur-reduce-from 5 (level 5 at 512)");
        else snprintf(w, sizeof w, "1024, --blur-reduce-from %d (levels %d..5 at 512)", K, K);
        add(1024, 0, 0, false, (dm_render_desc){.blur_reduce_from = K}, n, w);
    }
    snprintf(n, sizeof n, "%d pcf1", B), snprintf(w, sizeof w, "%d, --pcf-taps 1 (one bilinear shadow compare)", B);
    add(B, 0, 0, false, (dm_render_desc){.shadow_pcf_taps = 1}, n, w);
    snprintf(n, sizeof n, "%d half", B), snprintf(w, sizeof w, "%d, --half-float (RGBA16F targets)", B);
    add(B, 0, 0, false, (dm_render_desc){.blur_half_float = true}, n, w);
    snprintf(n, sizeof n, "%d reuse", B), snprintf(w, sizeof w, "%d, texture space reused (camera-only frames)", B);
    add(B, 0, 0, false, (dm_render_desc){.reuse_texture_space = true}, n, w);
    if (!quick) add(1024, 0, 0, false, (dm_render_desc){.reuse_texture_space = true}, "1024 reuse", "1024, texture space reused")
                    ->technique_row = true;
    /* the other techniques: frame error only (no texture-space diffusion to compare) */
    for (int i = 0, t; i < 3 && (t = (int[]){11, 17, 25}[i]); ++i) {
        snprintf(n, sizeof n, "screen %d", t), snprintf(w, sizeof w, "screen-space separable SSS, %d taps", t);
        setting *s = add(B, 0, 0, false, (dm_render_desc){0}, n, w);
        s->technique = DM_SSS_SCREEN_SPACE, s->screen_taps = t, s->technique_row = t >= 17; /* the default, or finer */
    }
    setting *p = add(B, 0, 0, false, (dm_render_desc){0}, "pre-integrated", "pre-integrated (Penner): the table by N.L and curvature");
    p->technique = DM_SSS_PRE_INTEGRATED, p->technique_row = true;
    add(256, 0, BURLEY_G, false, (dm_render_desc){0}, "256 Burley G6",
        "256, 6 Gaussians fitted to Burley (A 0.8/0.6/0.4, mfp 1/0.5/0.25 mm), vs Burley")
        ->burley = true;
    add(512, 0, SKIN_G, false, (dm_render_desc){0}, "512 skin G6",
        "512, 6 Gaussians fitted to the physical skin (Caucasian exemplar), vs the physical profile")
        ->skin = true;
    int T = quick ? 256 : 1024;
    snprintf(n, sizeof n, "%d + transl.", T), snprintf(w, sizeof w, "irradiance %d + translucency", T);
    setting *t = add(T, 0, 0, false, (dm_render_desc){0}, n, w);
    t->translucency = true, t->technique_row = T >= 1024;
    setting *s = add(B, 0, 0, false, (dm_render_desc){0}, "screen 17 + transl.", "screen-space 17 taps + translucency");
    s->technique = DM_SSS_SCREEN_SPACE, s->screen_taps = 17, s->translucency = s->technique_row = true;
}

/* The truth a row is compared with (NULL: the pack's own profile) and the pack it renders. */
static const char *row_truth(const setting *s)
{
    return s->burley ? BURLEY : s->skin ? SKIN : s->gaussians ? dipole : NULL;
}

static int row_pack(const setting *s)
{
    return s->technique == DM_SSS_PRE_INTEGRATED ? PACK_PREINT : s->burley ? PACK_BURLEY : s->skin ? PACK_SKIN
           : s->translucency                                 ? PACK_TRANSL
           : s->size == 2048 && !s->gaussians                ? PACK_2048
                                                              : s->gaussians;
}

/* The signed bias per region and channel, Σ a (render − ref) / Σ a ref over the texels both
 * cover (a: the texel's mm²), on stderr: whether a region's error is light missing (< 0) or
 * too much (> 0), which the mean |error| does not say. */
static void print_bias(const char *row, const float *ref, const float *px, const float *area, const uint8_t *label,
                       size_t n)
{
    static const char *const names[DM_REF_REGION_COUNT] = {"smooth", "seam", "thin"};
    for (int g = 0; g < DM_REF_REGION_COUNT; ++g) {
        double d[3] = {0, 0, 0}, t[3] = {0, 0, 0};
        for (size_t i = 0; i < n; ++i) {
            if (label[i] != g || !(ref[4 * i + 3] >= 0.5f && px[4 * i + 3] >= 0.5f) || !(area[i] > 0)) continue;
            for (int c = 0; c < 3; ++c) d[c] += area[i] * ((double)px[4 * i + c] - ref[4 * i + c]), t[c] += area[i] * ref[4 * i + c];
        }
        fprintf(stderr, "accuracy bench: %s: %s signed bias %+.2f / %+.2f / %+.2f %%\n", row, names[g],
                t[0] > 0 ? 100 * d[0] / t[0] : 0, t[1] > 0 ? 100 * d[1] / t[1] : 0, t[2] > 0 ? 100 * d[2] / t[2] : 0);
    }
}

/* Each region split by how far a texel lies inside its chart: ring 1 touches (8-neighbour) a
 * texel the reference does not cover (a chart's edge, a seam's gutter), ring 2 the next, 3 the
 * rest; mean red error (its own floor: 1 % of the ring's mean reference) and area, on stderr.
 * Where a region's error sits: along the charts' outlines (the blur's edge) or inside. */
static void print_rings(const char *row, const float *ref, const float *px, const float *area, const uint8_t *label,
                        int N)
{
    static const char *const names[DM_REF_REGION_COUNT] = {"smooth", "seam", "thin"};
    size_t n = (size_t)N * N;
    uint8_t *lab = malloc(n);
    if (!lab) return;
    for (size_t i = 0; i < n; ++i) {
        int x = (int)(i % (size_t)N), y = (int)(i / (size_t)N), ring = 3;
        for (int r = 1; r <= 2 && ring == 3; ++r)
            for (int dy = -r; dy <= r && ring == 3; ++dy)
                for (int dx = -r; dx <= r; ++dx) {
                    int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= N || yy >= N || !(ref[4 * ((size_t)yy * N + xx) + 3] >= 0.5f)) {
                        ring = r;
                        break;
                    }
                }
        lab[i] = label[i] < DM_REF_REGION_COUNT ? (uint8_t)(label[i] * 3 + ring - 1) : 255;
    }
    for (int g = 0; g < DM_REF_REGION_COUNT; ++g) {
        fprintf(stderr, "accuracy bench: %s: %s by ring from the chart's edge:", row, names[g]);
        for (int r = 0; r < 3; ++r) {
            dm_ref_error_stats st;
            dm_error err = {0};
            if (dm_ref_error_stats_compute(ref, px, area, lab, g * 3 + r, n, &st, &err) == DM_OK)
                fprintf(stderr, " %d%s %.2f %% red (%.0f mm2)", r + 1, r == 2 ? "+" : "", 100 * st.mean[0], st.weight_sum);
        }
        fprintf(stderr, "\n");
    }
    free(lab);
}

/* Per texel at size N: the region label and the area (mm²) of each of the reference's
 * own targets (common/atlas_regions.h). */
static int label_atlas(const dm_ref_regions *rg, const dm_mesh *m, sized *z)
{
    return atlas_regions(rg, m, z->N, z->ref.rgba, &z->label, &z->area, z->count, z->area_mm2);
}

static int open_pack(const char *path, packed *p)
{
    dm_error err = {0};
    if (dm_pack_open(path, &p->pack, &err) != DM_OK ||
        dm_render_assets_from_pack(&p->pack, &p->scene, &p->profile, &p->assets, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return 0;
    }
    p->open = true;
    return 1;
}

/* A constant RG32F stretch texture (malloc'd) at the chain's size: the median s_u, s_v
 * over the charts (mask > 0, else s_u > 0) of level 0. */
static float *flat_stretch(const dm_render_assets *a, float med[2])
{
    const dm_texture *t = &a->stretch[0];
    size_t n = (size_t)t->width * t->height;
    float *out = malloc(sizeof *out * 2 * n);
    if (!out || !dm_render_stretch_median(a, med)) return free(out), NULL;
    for (size_t i = 0; i < n; ++i) out[2 * i] = med[0], out[2 * i + 1] = med[1];
    return out;
}

int main(int argc, char **argv)
{
    const char *outdir = argc > 1 ? argv[1] : "bench/results";
    const char *bin = getenv("BUILD") ? getenv("BUILD") : "build/release";
    bool quick = getenv("DERMIS_BENCH_QUICK") && !strcmp(getenv("DERMIS_BENCH_QUICK"), "1");
    bool large = getenv("DERMIS_BENCH_LARGE") && !strcmp(getenv("DERMIS_BENCH_LARGE"), "1");
    texture_only = getenv("DERMIS_BENCH_TEXTURE_ONLY") && !strcmp(getenv("DERMIS_BENCH_TEXTURE_ONLY"), "1");
    int frames = getenv("DERMIS_BENCH_FRAMES") ? atoi(getenv("DERMIS_BENCH_FRAMES")) : quick ? 5 : 7;
    frames = frames < 5 ? 5 : frames > MAX_FRAMES ? MAX_FRAMES : frames;
    int B = quick ? 256 : 512;
    char dir[1024], pack_path[2048], cmd[4096];
    snprintf(cmd, sizeof cmd, "%s/bin/dermis-reference --help 2>/dev/null | grep -q -- --dipole", bin);
    dipole = system(cmd) == 0 ? "skin1" : NULL;
    add_rows(quick, large, B);
    snprintf(dir, sizeof dir, "%s/cache/accuracy", bin);
    snprintf(cmd, sizeof cmd, "mkdir -p %s %s", dir, outdir);
    if (system(cmd) != 0) return 4;
    snprintf(pack_path, sizeof pack_path, "%s/lps-sss.dpk", dir);
    snprintf(cmd, sizeof cmd, "%s/bin/dermis-pack %s -o %s --quiet", bin, SCENE, pack_path);
    if (argc > 2) snprintf(pack_path, sizeof pack_path, "%s", argv[2]); /* a pack of SCENE made before */
    else if (run(cmd) != 0) {
        fprintf(stderr, "error: '%s' failed (run from the repository root)\n", cmd);
        return 3;
    }
    static packed packs[NPACKS];
    dm_error err = {0};
    char hash[DM_HASH_HEX_SIZE];
    if (dm_hash_file_hex(pack_path, hash, &err) != DM_OK || !open_pack(pack_path, &packs[0])) {
        fprintf(stderr, "error: %s\n", err.detail);
        return 2;
    }
    for (int c = 0; c < nrows; ++c) {
        int g = rows_s[c].gaussians;
        char p[2048];
        if (fit_row(&rows_s[c]) && !packs[g].open &&
            (!pack_fit(bin, dir, hash, g, p, sizeof p) || !open_pack(p, &packs[g])))
            return 3;
        if (rows_s[c].burley && !packs[PACK_BURLEY].open &&
            (!pack_burley(bin, dir, hash, p, sizeof p) || !open_pack(p, &packs[PACK_BURLEY])))
            return 3;
        if (rows_s[c].skin && !packs[PACK_SKIN].open &&
            (!pack_skin(bin, dir, hash, p, sizeof p) || !open_pack(p, &packs[PACK_SKIN])))
            return 3;
        if (rows_s[c].skin && packs[PACK_SKIN].profile.count != SKIN_G) {
            fprintf(stderr, "error: the skin pack's profile has %d Gaussians, expected %d\n", packs[PACK_SKIN].profile.count, SKIN_G);
            return 3;
        }
        if (row_pack(&rows_s[c]) == PACK_TRANSL && !packs[PACK_TRANSL].open &&
            (!pack_transl(bin, dir, hash, p, sizeof p) || !open_pack(p, &packs[PACK_TRANSL])))
            return 3;
        if (row_pack(&rows_s[c]) == PACK_2048 && !packs[PACK_2048].open &&
            (!pack_2048(bin, dir, hash, p, sizeof p) || !open_pack(p, &packs[PACK_2048])))
            return 3;
        if (rows_s[c].technique == DM_SSS_PRE_INTEGRATED && !packs[PACK_PREINT].open &&
            (!pack_preint(bin, dir, hash, p, sizeof p) || !open_pack(p, &packs[PACK_PREINT])))
            return 3;
    }
    /* regions from the pack's mesh; references, labels and areas per size */
    dm_scene scene;
    dm_profile profile;
    dm_ref_surface_desc desc;
    dm_ref_surface *surf = NULL;
    dm_ref_regions *rg = NULL;
    if (dm_pack_scene(&packs[0].pack, &scene, &err) != DM_OK ||
        dm_ref_surface_desc_from_pack(&packs[0].pack, &scene, &profile, &desc, &err) != DM_OK ||
        dm_ref_surface_create(&desc, 0, &surf, &err) != DM_OK ||
        dm_ref_regions_create(&surf->mesh, surf->mm_per_unit, NULL, &rg, &err) != DM_OK) {
        fprintf(stderr, "error: regions: %s\n", err.detail);
        return 3;
    }
    dm_ref_regions_info ri;
    dm_ref_regions_get_info(rg, &ri);
    static sized z[MAX_SIZED];
    int nz = 0;
    for (int c = 0; c < nrows; ++c) {
        const char *truth = row_truth(&rows_s[c]);
        int i = 0;
        if (rows_s[c].technique != DM_SSS_TEXTURE_SPACE || rows_s[c].frame_only || rows_s[c].no_subsurface) continue;
        while (i < nz && !(z[i].N == rows_s[c].size && z[i].dipole == truth)) ++i;
        if (i < nz) continue;
        if (nz == MAX_SIZED) {
            fprintf(stderr, "error: more than %d texture-space references (MAX_SIZED)\n", MAX_SIZED);
            return 3;
        }
        z[nz].N = rows_s[c].size, z[nz].dipole = truth;
        if (!reference(bin, pack_path, hash, dir, z[nz].N, truth, NULL, -1, &z[nz].ref) || !label_atlas(rg, &surf->mesh, &z[nz]))
            return 3;
        ++nz;
    }
    /* the frame's truths: the scene's profile in every run, the dipole (Gaussian-count rows)
     * in the transport run where a row is compared with it; each with its flat (no-subsurface)
     * transport frame */
    static frame_truth ft[2];
    bool fits = false;
    for (int c = 0; c < nrows; ++c) fits |= dipole && fit_row(&rows_s[c]);
    for (int t = 0; t < (texture_only ? 0 : 1 + fits); ++t) {
        const char *truth = t ? dipole : NULL;
        for (int v = 0; v < (t ? 1 : FV_COUNT); ++v) {
            if (!reference(bin, pack_path, hash, dir, 0, truth, FV_WITHOUT[v], -1, &ft[t].ref[v])) return 3;
            ft[t].have[v] = true;
        }
        if (!reference(bin, pack_path, hash, dir, 0, truth, FV_FLAT, -1, &ft[t].flat)) return 3;
        /* each transport's steps: the margins' own bars (frame_truth.h, frame_rankings.h) */
        for (int k = 0; k < FT_STEP_COUNT; ++k) {
            if (!reference(bin, pack_path, hash, dir, 0, truth, FV_WITHOUT[FV_TRANSPORT], k, &ft[t].step[k][0]) ||
                !reference(bin, pack_path, hash, dir, 0, truth, FV_FLAT, k, &ft[t].step[k][1]))
                return 3;
            ft[t].have_step[k] = true;
        }
        ft[t].rays_left = t ? MARGIN_RAYS_LEFT_DIPOLE : MARGIN_RAYS_LEFT;
        ft[t].atlas_left = t ? MARGIN_ATLAS_LEFT_DIPOLE : MARGIN_ATLAS_LEFT;
        ft[t].fixed = t ? 0 : MARGIN_FIXED;
    }
    uint8_t *plabel = malloc((size_t)FW * FH);
    if (!plabel || (!texture_only && dm_ref_frame_labels(surf, rg, FW, FH, 0, plabel, &err) != DM_OK)) {
        fprintf(stderr, "error: frame labels: %s\n", err.detail);
        return 3;
    }

    dm_osmesa *ctx = NULL;
    if (dm_osmesa_create(&ctx, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return 3;
    }
    float med[2] = {1, 1};
    float *flat = flat_stretch(&packs[0].assets, med);
    if (!flat) {
        fprintf(stderr, "error: the stretch chain is not RG32F/RG16F\n");
        return 3;
    }
    static row rows[MAX_ROWS];
    static dm_render_assets as[MAX_ROWS];
    for (int c = 0; c < nrows; ++c) {
        const setting *s = &rows_s[c];
        rows[c].s = *s;
        int pk = row_pack(s);
        rows[c].scene = packs[pk].scene;
        if (s->taps) rows[c].scene.blur_taps = s->taps;
        rows[c].scene.effects[DM_EFFECT_GLOW] = false;
        rows[c].scene.effects[DM_EFFECT_TRANSLUCENCY] = s->translucency;
        rows[c].scene.sss_technique = s->technique;
        if (s->no_subsurface) rows[c].scene.effects[DM_EFFECT_SUBSURFACE] = false;
        if (s->screen_taps) rows[c].scene.screen_taps = s->screen_taps;
        rows[c].ft = s->burley || s->skin || texture_only ? NULL : &ft[s->gaussians && dipole]; /* Burley, skin: texture space only */
        as[c] = packs[pk].assets;
        as[c].scene = &rows[c].scene;
        if (s->no_seam) as[c].seam = (dm_texture){0};
        if (s->no_thin) as[c].thin = as[c].thin_half = (dm_texture){0};
        if (s->no_thin || s->no_gather)
            as[c].gather_index = as[c].gather_taps = as[c].gather_half_index = as[c].gather_half_taps = (dm_texture){0};
        if (s->flat_stretch) {
            as[c].stretch_level_count = 1;
            as[c].stretch[0] = (dm_texture){DM_TEX_RG32F, as[c].stretch[0].width, as[c].stretch[0].height, flat};
        }
        dm_render_desc d = s->knobs;
        d.width = W, d.height = H, d.irradiance_size = s->size, d.timings = true;
        fprintf(stderr, "accuracy bench: setting %s\n", s->name);
        if (dm_renderer_create(&as[c], &d, &rows[c].r, &err) != DM_OK ||
            dm_render_frame(rows[c].r, &(dm_frame_options){0}, &err) != DM_OK) {
            fprintf(stderr, "error: %s: %s\n", s->name, err.detail);
            return 3;
        }
    }
    for (int f = 0; f < frames; ++f)
        for (int c = 0; c < nrows; ++c) {
            if (dm_render_frame(rows[c].r, &(dm_frame_options){0}, &err) != DM_OK) {
                fprintf(stderr, "error: %s: %s\n", rows[c].s.name, err.detail);
                return 3;
            }
            dm_renderer_last_timings(rows[c].r, NULL, &rows[c].ms[f]);
        }
    float *default_px = NULL;
    bool pictured = false; /* the error pictures, of the first default row */
    for (int c = 0; c < nrows; ++c) {
        rows[c].frame_ms = bench_median(rows[c].ms, frames);
        const sized *zz = z;
        const char *truth = row_truth(&rows[c].s);
        while (zz < z + nz && !(zz->N == rows[c].s.size && zz->dipole == truth)) ++zz;
        bool is_default = !default_px && rows[c].s.size == (quick ? 256 : 1024) && !rows[c].s.taps &&
                          !rows[c].s.gaussians && !rows[c].s.flat_stretch && !rows[c].s.translucency &&
                          !rows[c].s.frame_only && !rows[c].s.no_subsurface && !rows[c].s.no_seam && !rows[c].s.no_thin && !rows[c].s.no_gather &&
                          rows[c].s.technique == DM_SSS_TEXTURE_SPACE && !memcmp(&rows[c].s.knobs, &(dm_render_desc){0}, sizeof(dm_render_desc));
        if (rows[c].s.technique == DM_SSS_TEXTURE_SPACE && !rows[c].s.frame_only && !rows[c].s.no_subsurface) {
            int w = 0, h = 0;
            float *px = NULL;
            if (dm_render_frame(rows[c].r, &(dm_frame_options){.view = DM_VIEW_DIFFUSION}, &err) == DM_OK) {
                dm_renderer_view_size(rows[c].r, &w, &h);
                px = w == zz->N && h == zz->N ? malloc(sizeof *px * 4 * (size_t)w * h) : NULL;
            }
            if (!px || dm_renderer_read_view(rows[c].r, px, &err) != DM_OK) {
                fprintf(stderr, "error: %s: the diffusion view (%dx%d): %s\n", rows[c].s.name, w, h, err.detail);
                return 3;
            }
            size_t n = (size_t)zz->N * zz->N;
            rows[c].ok[REG_ALL] = dm_ref_error_stats_compute(zz->ref.rgba, px, zz->area, NULL, -1, n, &rows[c].st[REG_ALL], &err) == DM_OK;
            for (int g = 0; g < DM_REF_REGION_COUNT; ++g)
                rows[c].ok[g] = dm_ref_error_stats_compute(zz->ref.rgba, px, zz->area, zz->label, g, n, &rows[c].st[g], &err) == DM_OK;
            print_bias(rows[c].s.name, zz->ref.rgba, px, zz->area, zz->label, n);
            print_rings(rows[c].s.name, zz->ref.rgba, px, zz->area, zz->label, zz->N);
            if (is_default && !pictured) {
                error_picture(outdir, zz, px, DM_REF_REGION_SEAM, rows[c].s.name);
                error_picture(outdir, zz, px, DM_REF_REGION_THIN, rows[c].s.name);
                pictured = true;
            }
            free(px);
        }
        dm_renderer_destroy(rows[c].r);
        if (rows[c].ft) {
            dm_render_desc d = rows[c].s.knobs;
            d.irradiance_size = rows[c].s.size;
            frame_measure(&as[c], &rows[c].scene, d, rows[c].ft, plabel, FW, FH, rows[c].s.name, &rows[c].fr,
                          is_default ? &default_px : NULL);
            rows[c].fok = rows[c].fr.trok[REG_ALL];
        }
        const dm_ref_error_stats *s = &rows[c].st[REG_ALL];
        const dm_ref_transport_stats *f = &rows[c].fr.tr[REG_ALL];
        printf("%-52s %7.1f ms", rows[c].s.what, rows[c].frame_ms);
        if (rows[c].ok[REG_ALL])
            printf("  TSD mean %5.2f/%5.2f/%5.2f %%  p95 %5.2f/%5.2f/%5.2f %%", 100 * s->mean[0], 100 * s->mean[1],
                   100 * s->mean[2], 100 * s->p95[0], 100 * s->p95[1], 100 * s->p95[2]);
        if (rows[c].fok)
            printf("  transport %5.2f/%5.2f/%5.2f %%", 100 * f->normalised[0], 100 * f->normalised[1], 100 * f->normalised[2]);
        printf("\n");
    }
    report(outdir, rows, z, nz, frames, packs[0].assets.index_count / 3, &ri, med, B);
    plot(outdir, dir, rows);
    if (default_px) frame_picture(outdir, &ft[0].ref[FV_FULL], default_px);
    for (int i = 0; i < nz; ++i)
        if (z[i].N == B && !z[i].dipole) regions_picture(outdir, &z[i]);
    free(default_px), free(flat);
    for (int i = 0; i < nz; ++i) dm_refcmp_ref_free(&z[i].ref), free(z[i].label), free(z[i].area);
    for (int t = 0; t < 2; ++t) {
        for (int v = 0; v < FV_COUNT; ++v) dm_refcmp_ref_free(&ft[t].ref[v]);
        dm_refcmp_ref_free(&ft[t].flat);
        for (int k = 0; k < FT_STEP_COUNT; ++k) dm_refcmp_ref_free(&ft[t].step[k][0]), dm_refcmp_ref_free(&ft[t].step[k][1]);
    }
    free(plabel);
    dm_ref_regions_destroy(rg), dm_ref_surface_destroy(surf);
    for (int g = 0; g < NPACKS; ++g)
        if (packs[g].open) dm_pack_close(&packs[g].pack);
    dm_osmesa_destroy(ctx);
    return 0;
}
