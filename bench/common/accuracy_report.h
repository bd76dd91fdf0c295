/* bench/common/accuracy_report.h — what bench/accuracy writes from its rows: the
 * Markdown report (ending with the screen-space edge section of edge_table.h), the gnuplot
 * Pareto plot, the frame comparison and the region map.
 * Header-only like bench_util.h (benches are one .c each); included by bench/accuracy.c only. */
#ifndef BENCH_ACCURACY_REPORT_H
#define BENCH_ACCURACY_REPORT_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_prov.h"
#include "render/dm_render_image.h"
#include "common/bench_util.h"
#include "common/edge_table.h"
#include "common/frame_rankings.h"

static double mean3(const double v[3]) { return (v[0] + v[1] + v[2]) / 3; }

static void plot(const char *outdir, const char *dir, const row *rows)
{
    if (system("command -v gnuplot >/dev/null 2>&1") != 0) return;
    char dat[1100], front[1100], png[1100];
    snprintf(dat, sizeof dat, "%s/pareto.dat", dir), snprintf(front, sizeof front, "%s/front.dat", dir);
    snprintf(png, sizeof png, "%s/accuracy.png", outdir);
    FILE *f = fopen(dat, "w"), *fr = fopen(front, "w");
    if (!f || !fr) return;
    int order[MAX_ROWS], n = 0;
    double fmax_ = 1;
    bool frames = false; /* the right axis only when some row has a frame point (DERMIS_BENCH_TEXTURE_ONLY has none) */
    bool fits = false;   /* the dipole fits' series in the key only when it has points (DERMIS_BENCH_ROWS) */
    for (int c = 0; c < nrows; ++c) {
        /* another truth, never on the front: 1 the dipole fits (their own series), 2 Burley's and
         * the skin's fits (drawn with the texture-space points, labelled) */
        int fit = rows[c].s.burley || rows[c].s.skin ? 2 : rows[c].s.gaussians && dipole;
        if (!rows[c].ok[REG_ALL] && !rows[c].fok) continue;
        char tsd[32] = "?", fr_[32] = "?";
        if (rows[c].ok[REG_ALL]) snprintf(tsd, sizeof tsd, "%.6f", 100 * mean3(rows[c].st[REG_ALL].mean));
        if (rows[c].ok[REG_ALL] && !fit) order[n++] = c;
        fits |= fit == 1;
        double tr = 100 * frame_norm3(&rows[c].fr.tr[REG_ALL]);
        if (rows[c].fok) snprintf(fr_, sizeof fr_, "%.6f", tr), fmax_ = fmax(fmax_, tr), frames = true;
        fprintf(f, "%.3f %s %s \"%s\" \"%s\" %d\n", rows[c].frame_ms, tsd, fr_, rows[c].ok[REG_ALL] ? rows[c].s.name : "",
                rows[c].ok[REG_ALL] ? "" : rows[c].s.name, fit);
    }
    for (int i = 1; i < n; ++i) /* by ms, then error: the non-dominated points form the front */
        for (int j = i; j > 0 && (rows[order[j]].frame_ms < rows[order[j - 1]].frame_ms); --j) {
            int k = order[j];
            order[j] = order[j - 1], order[j - 1] = k;
        }
    double best = INFINITY;
    for (int i = 0; i < n; ++i) {
        double e = 100 * mean3(rows[order[i]].st[REG_ALL].mean);
        if (rows[order[i]].s.knobs.reuse_texture_space) continue; /* not a full frame */
        if (e < best) best = e, fprintf(fr, "%.3f %.6f\n", rows[order[i]].frame_ms, e);
    }
    fclose(f), fclose(fr);
    FILE *g = popen("gnuplot", "w");
    if (!g) return;
    fprintf(g, "set terminal pngcairo size 1100,700 font ',11'\nset output '%s'\n"
               "set title 'lps-sss: error against dermis-reference vs frame time, one point per setting%s'\n"
               "set xlabel 'frame ms (median, 1280x720, llvmpipe on 2 cores; log scale)'\nset logscale x\n"
               "set ylabel 'texture space: mean relative error, %% (R, G, B averaged; area-weighted)'\n",
            png, frames ? "" : " (texture space only)");
    if (frames)
        fprintf(g, "set y2label 'frame, transport run: error / no-subsurface error, %% (1280x720)' tc rgb '#d62728'\n"
                   "set y2tics tc rgb '#d62728'\nset ytics nomirror\nset y2range [0:%g]\n", 1.4 * fmax_);
    fprintf(g, "set grid\nset key top right\n"
               "set datafile missing '?'\nset yrange [0:*]\nset offsets graph 0.02, graph 0.25, graph 0.15, graph 0.05\n"
               "plot '%s' using 1:2 with lines lw 2 lc rgb '#999999' title 'Pareto front of the texture-space error (full frames)', "
               "'%s' using 1:($6 == 1 ? 1/0 : $2) with points pt 7 ps 1.4 lc rgb '#1f77b4' title 'texture space vs --texture-space N (gems3-skin), whole skin', "
               "'' using 1:($6 == 1 ? $2 : 1/0) with points pt 9 ps 1.4 lc rgb '#2ca02c' %s, "
               "'' using 1:2:4 with labels offset 0.6,0.4 left rotate by 40 font ',8' notitle%s\n",
            front, dat, fits ? "title 'N Gaussians fitted to the skin1 dipole, vs its reference'" : "notitle",
            frames ? ", '' using 1:3 axes x1y2 with points pt 5 ps 0.9 lc rgb '#d62728' title 'frame transport vs --frame, "
                     "normalised (right axis; 100 = no better than leaving subsurface out)', "
                     "'' using 1:3:5 axes x1y2 with labels offset 0.6,-0.4 left rotate by -30 font ',8' tc rgb '#d62728' notitle"
                   : "");
    if (pclose(g) == 0) printf("accuracy bench: wrote %s\n", png);
}

static void triple(FILE *md, const double v[3]) { fprintf(md, " %.2f / %.2f / %.2f |", 100 * v[0], 100 * v[1], 100 * v[2]); }

/* The transport run's normalised error: all channels, then R / G / B. */
static void transport_cell(FILE *md, const dm_ref_transport_stats *t)
{
    fprintf(md, " **%.1f** (%.1f / %.1f / %.1f) |", 100 * t->normalised_rgb, 100 * t->normalised[0], 100 * t->normalised[1],
            100 * t->normalised[2]);
}

/* The frame taken apart: per row the transport run by region, then what the surface terms
 * and the shadows add (mean relative error over the interior pixels of each run). */
static void frame_report(FILE *md, const row *rows)
{
    fprintf(md, "\n## The frame, taken apart\n\nEach run against its own reference at %dx%d. **Transport** "
                "(normalised %%: all channels' sums, then R / G / B) over the whole skin and per region — the labels of "
                "`dm_ref_regions.h` projected into the frame through each pixel's triangle (`dm_ref_frame_labels`); "
                "then the mean relative error over the interior skin pixels of each run: transport, **+ surface** "
                "(albedo and normal map: `--without shadows`), **+ shadows** (the scene as it is: ray-cast shadows "
                "against the shadow map). The Gaussian-count rows have their own truth (the skin1 dipole) in the "
                "transport run only.\n\n"
                "| setting | transport %% | smooth %% | seam %% | thin %% | transport mean %% | + surface mean %% | + shadows mean %% |\n"
                "|---|---:|---:|---:|---:|---:|---:|---:|\n", FW, FH);
    for (int c = 0; c < nrows; ++c) {
        const frame_result *f = &rows[c].fr;
        if (!rows[c].fok) continue;
        fprintf(md, "| %s |", rows[c].s.name);
        transport_cell(md, &f->tr[REG_ALL]);
        for (int g = 0; g < DM_REF_REGION_COUNT; ++g)
            if (f->trok[g]) transport_cell(md, &f->tr[g]);
            else fprintf(md, " – |");
        for (int v = 0; v < FV_COUNT; ++v)
            if (f->runok[v]) triple(md, f->run[v].mean);
            else fprintf(md, " – |");
        fprintf(md, "\n");
    }
    frame_rankings(md, rows);
}

static void report(const char *outdir, const row *rows, const sized *z, int nz, int frames, int tris,
                   const dm_ref_regions_info *ri, const float med[2], int B)
{
    FILE *md = bench_open(outdir, "accuracy.md", "Renderer settings: accuracy against the ground truth, and time");
    if (!md) return;
    int gsize = B; /* the size the Gaussian-count rows are checked at */
    for (int c = 0; c < nrows; ++c)
        if (rows[c].s.gaussians == 1) gsize = rows[c].s.size;
    double load = -1;
    FILE *la = fopen("/proc/loadavg", "r");
    if (la) {
        if (fscanf(la, "%lf", &load) != 1) load = -1;
        fclose(la);
    }
    fprintf(md, "The Lee Perry-Smith head, `%s` (subsurface, shadows, tonemap, no glow), %d triangles. Frame ms: "
                "median of %d final frames at %dx%d after one warm-up (llvmpipe, CPU clock around glFinish; every "
                "row's renderer alive, frames round robin; load average %.2f at the end: compare rows, not runs).\n\n",
            SCENE, tris, frames, W, H, load);
    if (getenv("DERMIS_BENCH_ROWS")) /* a partial run says so */
        fprintf(md, "**Rows**: only those `DERMIS_BENCH_ROWS` names (%d of them), so only their truths were computed: "
                    "`%s`.\n\n",
                nrows, getenv("DERMIS_BENCH_ROWS"));
    fprintf(md, "**Texture space (TSD)**: the renderer's `diffusion` view (Σ_k w_k L_k) at irradiance N against "
                "`dermis-reference PACK --texture-space N`: the exact surface convolution, with 3-D distances over the "
                "whole mesh, of the renderer's own level-0 irradiance by the scene's profile (gems3-skin's six "
                "Gaussians; the Gaussian-count rows: see the notes). Per channel rel = |render − ref| / max(ref, 1 %% of "
                "the reference's area-weighted mean over the region), over the texels covered in both; **area-"
                "weighted**: each texel counts the skin area it stands for, (3-D area / UV area of its triangle) / "
                "N² mm²; mean and p95 (the error below which 95 %% of the skin *area* lies), in %%, R / G / B.\n\n"
                "**Frame (transport)**: the final linear frame at %dx%d (`dermis-render`'s picture before the "
                "tonemap) of the *transport run* — white albedo, no normal map, no shadows, in the renderer and in "
                "`dermis-reference PACK --frame --without albedo,normal-map,shadows` alike (atlas %d, %dx%d samples a "
                "texel, %dx%d sub-pixel rays a pixel with the diffusion at each, `--refine %d`; the surface and full runs "
                "and the Gaussian-count rows' truth at atlas %d, %dx%d samples, without `--refine`) — over the interior skin pixels where "
                "subsurface changes the reference by more than 2 %% (against the same reference `--without ...,"
                "subsurface`): **normalised** = Σ|render − ref| / Σ|no-subsurface − ref| over them (100 %% = no "
                "better than leaving subsurface out) and the **mean** relative error there "
                "(`lib/reference/dm_ref_frame_compare.h`). What the surface terms and the shadows add: the next "
                "section.\n\n",
            FW, FH, TRANSPORT_ATLAS, TRANSPORT_AS, TRANSPORT_AS, FRAME_PS, FRAME_PS, FRAME_REFINE, FRAME_ATLAS, FRAME_AS,
            FRAME_AS);
    fprintf(md, "| setting | frame ms | TSD mean %% R / G / B | TSD p95 %% | frame transport, normalised %%: all (R / G / B) | frame transport mean %% |\n"
                "|---|---:|---:|---:|---:|---:|\n");
    for (int c = 0; c < nrows; ++c) {
        fprintf(md, "| %s | **%.1f** |", rows[c].s.what, rows[c].frame_ms);
        if (rows[c].ok[REG_ALL]) triple(md, rows[c].st[REG_ALL].mean), triple(md, rows[c].st[REG_ALL].p95);
        else fprintf(md, " – | – |");
        if (rows[c].fok) transport_cell(md, &rows[c].fr.tr[REG_ALL]), triple(md, rows[c].fr.tr[REG_ALL].mean);
        else fprintf(md, " – | – |");
        fprintf(md, "\n");
    }
    frame_report(md, rows);
    fprintf(md, "\n## Texture-space error by region\n\nLabels from the geometry (`lib/reference/dm_ref_regions.h`), per "
                "texel at the reference's own surface point for it (`dm_reference_atlas_targets`), first match wins: "
                "**seam**: within 3 mm (3-D) of a seam edge — an edge whose two triangles give it different UVs, or "
                "a mesh boundary (the atlas ends there too), positions welded by exact value (%lld edges on this "
                "head, %lld of them boundary); **thin** (thin parts and folds): some triangle facing the "
                "opposite way (n_x · n_y < 0) lies within 5 mm — the back of an ear or a nostril wall, the other lip, "
                "the eyelid over the eyeball; proximity rather than a ray along −n, because a ray finds only the "
                "back of a thin part, not the facing side of a fold; 5 mm is 1.8 σ of the widest Gaussian (σ = 2.7 "
                "mm); **smooth**: the rest. Skin area (%.0f cm² in all):",
            (long long)ri->seam_edges, (long long)ri->boundary_edges, ri->surface_area_mm2 / 100);
    for (int i = 0; i < nz; ++i) {
        double tot = 0;
        for (int g = 0; g < DM_REF_REGION_COUNT; ++g) tot += z[i].area_mm2[g];
        fprintf(md, " at %d,", z[i].N);
        for (int g = 0; g < DM_REF_REGION_COUNT; ++g)
            fprintf(md, " %s %.1f %% (%ld texels)%s", dm_ref_region_name(g), 100 * z[i].area_mm2[g] / tot, z[i].count[g],
                    g + 1 < DM_REF_REGION_COUNT ? "," : i + 1 < nz ? ";" : ".");
    }
    fprintf(md, " Each region's floor is 1 %% of the reference's area-weighted mean over that region.\n\n"
                "| setting | smooth mean %% | smooth p95 %% | seam mean %% | seam p95 %% | thin mean %% | thin p95 %% |\n"
                "|---|---:|---:|---:|---:|---:|---:|\n");
    for (int c = 0; c < nrows; ++c) {
        if (!rows[c].ok[REG_ALL]) continue;
        fprintf(md, "| %s |", rows[c].s.name);
        for (int g = 0; g < DM_REF_REGION_COUNT; ++g)
            if (rows[c].ok[g]) triple(md, rows[c].st[g].mean), triple(md, rows[c].st[g].p95);
            else fprintf(md, " – | – |");
        fprintf(md, "\n");
    }
    fprintf(md, "\nNotes. The half-float row's irradiance is itself rounded (its error includes that); reuse renders "
                "the same texture space as its base row (its frame ms is a camera-only frame). Stretch off: one "
                "constant stretch texture, the chart median s_u = %.4f, s_v = %.4f UV/mm, for every blur (the "
                "renderer unchanged). Gaussian rows at %d%s: `dermis-fit-profile %s -n N`, each packed with its own "
                "stretch chain, all compared with one reference of the profile they fit (%s), texture space and "
                "frame: they show each N's fitting cost on top of the diffusion's. The Burley row: the pack's profile "
                "is `dermis-fit-profile --burley --albedo 0.8,0.6,0.4 --mfp 1,0.5,0.25 -n 6`, compared in texture "
                "space with `dermis-reference --burley 0.8,0.6,0.4/1,0.5,0.25` (Burley represented by 12 Gaussians "
                "from d/40): what the 6-Gaussian fit loses. The skin row likewise: the pack's profile is "
                "`{\"skin\": {\"preset\": \"%s\"}}`, the physical skin model's exemplar fitted by dermis-pack "
                "(%d Gaussians), compared in texture space with `dermis-reference --skin-preset %s "
                "--radial-gaussians %d` (the model's own R(r) represented by %d Gaussians; 8 min at 512 on 2 cores); "
                "both normalise each channel's weights to sum 1 (white), so the row shows where the fit puts the "
                "light, not how much of it the skin returns. Screen-space rows (Jimenez's separable SSS, the kernel fitted from the profile at create) have no texture-space diffusion: "
                "frame error only, against the same frame references (they do not depend on the technique). The "
                "no-subsurface row is the renderer with subsurface off (Lambert × albedo): the floor. The 2048 row "
                "is measured on the frame only (its texture-space reference takes 15+ min), from the scene packed at "
                "2048 (its maps and thin gather baked at that size; the gather's texels share their taps in blocks of "
                "2 × 2). The fits' packs gather every level of σ ≥ 1 mm (up to four; in blocks of 2 × 2 where one run "
                "a texel would pass 2^25 taps). "
                "Translucency rows add light through thin parts (from the shadow map's thickness), which the reference "
                "carries by its 3-D convolution instead: their error shows what that adds. References are cached under `BUILD/cache/accuracy/` by pack hash and "
                "size (`DERMIS_BENCH_LARGE=1` adds 2048, whose reference takes 15+ min on 2 cores; "
                "`DERMIS_BENCH_QUICK=1` runs the 256 rows only). Plot: `accuracy.png` (mean error against frame ms, "
                "log scale, with the Pareto front of the texture-space points, and the transport run normalised on the "
                "right axis); `accuracy-frame.png`: the full run's reference, the default render (irradiance 1024) "
                "and the relative error, cropped to the head (pixel-weighted legend).\n",
            med[0], med[1], gsize,
            gsize != B ? " (the scene's irradiance size, where every map the pack bakes applies; 7 and 8 also at half "
                         "of it, with the pack's half-size maps and no seam map, listed under the rankings, not checked)"
                       : "",
            dipole ? "--dipole skin1" : "--preset gems3-skin",
            dipole ? "`dermis-reference --dipole skin1`, the dipole represented by 12 Gaussians" : "gems3-skin's six Gaussians",
            SKIN, SKIN_G, SKIN, SKIN_RADIAL, SKIN_RADIAL);
    edge_table(md); /* on failure the section stops short and stderr says why */
    fclose(md);
    printf("accuracy bench: wrote %s/accuracy.md\n", outdir);
}

/* The full run's reference | render | relative error, cropped to the head (its skin pixels'
 * box and a margin) at one pixel per frame pixel. */
static void frame_picture(const char *outdir, const dm_refcmp_ref *fref, const float *full)
{
    int x0 = FW, y0 = FH, x1 = -1, y1 = -1;
    for (int y = 0; y < FH; ++y)
        for (int x = 0; x < FW; ++x)
            if (fref->rgba[4 * ((size_t)y * FW + x) + 3] >= 0.5f)
                x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1, y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
    if (x1 < 0) return;
    x0 = x0 > 16 ? x0 - 16 : 0, y0 = y0 > 16 ? y0 - 16 : 0, x1 = x1 + 16 < FW ? x1 + 16 : FW - 1, y1 = y1 + 16 < FH ? y1 + 16 : FH - 1;
    int cw = x1 - x0 + 1, ch = y1 - y0 + 1;
    float *ref = malloc(sizeof *ref * 4 * (size_t)cw * ch), *px = malloc(sizeof *px * 4 * (size_t)cw * ch);
    for (int y = 0; ref && px && y < ch; ++y) {
        memcpy(ref + 4 * (size_t)y * cw, fref->rgba + 4 * ((size_t)(y0 + y) * FW + x0), sizeof *ref * 4 * cw);
        memcpy(px + 4 * (size_t)y * cw, full + 4 * ((size_t)(y0 + y) * FW + x0), sizeof *px * 4 * cw);
    }
    dm_refcmp_stats st;
    dm_error err = {0};
    float *rel = malloc(sizeof *rel * (size_t)cw * ch);
    int ow = 3 * cw, oh = ch + dm_refcmp_legend_height(ow);
    uint8_t *img = malloc((size_t)ow * oh * 4);
    char path[1024];
    snprintf(path, sizeof path, "%s/accuracy-frame.png", outdir);
    if (ref && px && rel && img && dm_refcmp_stats_compute(ref, px, cw, ch, &st, rel, &err) == DM_OK) {
        dm_refcmp_compose(ref, px, rel, cw, ch, &st, &(dm_refcmp_view){.layout = DM_REFCMP_SIDE_BY_SIDE}, img, ow, oh);
        dm_provenance prov;
        dm_prov_init(&prov, "bench/accuracy");
        dm_prov_add_string(&prov, "scene", SCENE);
        if (dm_render_write_png(path, ow, oh, img, &prov, &err) == DM_OK) printf("accuracy bench: wrote %s\n", path);
        else fprintf(stderr, "warning: %s\n", err.detail);
    }
    free(rel), free(img), free(ref), free(px);
}

/* The labels of one atlas as a picture: smooth grey, seam blue, thin orange, uncovered black. */
static void regions_picture(const char *outdir, const sized *z)
{
    static const uint8_t col[DM_REF_REGION_COUNT][3] = {{150, 150, 150}, {40, 90, 230}, {245, 140, 20}};
    size_t n = (size_t)z->N * z->N;
    uint8_t *img = calloc(n, 4);
    char path[1100];
    dm_error err = {0};
    if (!img) return;
    for (size_t i = 0; i < n; ++i) {
        if (z->area[i] > 0) memcpy(img + 4 * i, col[z->label[i] % DM_REF_REGION_COUNT], 3);
        img[4 * i + 3] = 255;
    }
    dm_provenance prov;
    dm_prov_init(&prov, "bench/accuracy");
    dm_prov_add_string(&prov, "legend", "smooth grey, seam (3 mm) blue, thin/fold (5 mm) orange");
    snprintf(path, sizeof path, "%s/accuracy-regions.png", outdir);
    if (dm_render_write_png(path, z->N, z->N, img, &prov, &err) == DM_OK) printf("accuracy bench: wrote %s\n", path);
    free(img);
}


/* One region's texels of the default row (texture space) by their signed red error against the
 * truth, floor as the bench's (DM_REF_ERROR_FLOOR of the region's mean): red where the render
 * is brighter, blue where darker, full colour at 20 %; the other skin dark grey, uncovered
 * black. OUTDIR/accuracy-seam-error.png and accuracy-thin-error.png (docs/seam-map.md,
 * docs/thin-map.md show them). */
static void error_picture(const char *outdir, const sized *z, const float *px, int region, const char *row)
{
    static const char *const names[DM_REF_REGION_COUNT] = {"smooth", "seam", "thin"};
    size_t n = (size_t)z->N * z->N;
    const float *ref = z->ref.rgba;
    double floor_ = 0, a = 0;
    for (size_t i = 0; i < n; ++i)
        if (z->label[i] == region && z->area[i] > 0) floor_ += z->area[i] * ref[4 * i], a += z->area[i];
    floor_ = a > 0 ? DM_REF_ERROR_FLOOR * floor_ / a : 0;
    uint8_t *img = calloc(n, 4);
    if (!img) return;
    for (size_t i = 0; i < n; ++i) {
        uint8_t *o = img + 4 * i;
        o[3] = 255;
        if (!(z->area[i] > 0) || ref[4 * i + 3] < 0.5f) continue;
        if (z->label[i] != region || px[4 * i + 3] < 0.5f) {
            o[0] = o[1] = o[2] = 60;
            continue;
        }
        double den = ref[4 * i] > floor_ ? ref[4 * i] : floor_, e = den > 0 ? (px[4 * i] - ref[4 * i]) / den : 0;
        double s = fabs(e) / 0.2 < 1 ? fabs(e) / 0.2 : 1;
        o[0] = (uint8_t)(e > 0 ? 120 + 135 * s : 120 * (1 - s));
        o[1] = (uint8_t)(120 * (1 - s));
        o[2] = (uint8_t)(e < 0 ? 120 + 135 * s : 120 * (1 - s));
    }
    char path[1100];
    dm_error err = {0};
    dm_provenance prov;
    dm_prov_init(&prov, "bench/accuracy");
    dm_prov_add_string(&prov, "scene", SCENE);
    dm_prov_add_string(&prov, "row", row);
    dm_prov_add_string(&prov, "region", names[region]);
    dm_prov_add_string(&prov, "legend", "signed red error (render - truth) / truth: red brighter, blue darker, "
                                        "full at 20 %; other skin grey");
    snprintf(path, sizeof path, "%s/accuracy-%s-error.png", outdir, names[region]);
    if (dm_render_write_png(path, z->N, z->N, img, &prov, &err) == DM_OK) printf("accuracy bench: wrote %s\n", path);
    else fprintf(stderr, "warning: %s\n", err.detail);
    free(img);
}


#endif
