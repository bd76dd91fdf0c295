/* bench/accuracy — what each renderer setting costs in time and in accuracy against the
 * ground truth (DESIGN.md promise 1): the exact surface convolution of dermis-reference.
 *
 * Scene: the packed head (assets/scenes/lps-sss.json: subsurface, shadows, tonemap), or
 * the pack given as argv[2]. One row per setting (irradiance size, blur taps through a
 * modified scene, dm_render_desc speed knobs). Columns:
 *   - frame ms: median of DERMIS_BENCH_FRAMES (default 7, at least 5) final frames at
 *     1280x720 after one warm-up, every row's renderer alive and the frames run round
 *     robin so the shared machine's load hits every row alike;
 *   - texture-space error: the renderer's `diffusion` view at irradiance N against
 *     `dermis-reference PACK --texture-space N` through dm_render_refcmp (per channel mean
 *     and p95 of |render − ref| / max(ref, 1 % of ref's mean), over the covered texels);
 *     also split into texels near a UV seam and the rest (see seam_mask).
 * References are expensive (minutes at 512² on 2 cores): each is computed once by the
 * dermis-reference tool and cached as BUILD/cache/accuracy/ref-<pack hash>-<N>.exr,
 * reused when its provenance (tool, input hash, size, one tile) matches.
 * DERMIS_BENCH_QUICK=1: irradiance 256 only, 5 frames.
 * Writes OUTDIR/accuracy.md, and OUTDIR/accuracy.png when gnuplot is installed. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bake/dm_ref_surface.h"
#include "bake/dm_reference.h"
#include "common/bench_util.h"
#include "core/dm_hash.h"
#include "core/dm_pack.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_pack.h"
#include "render/dm_render_refcmp.h"

enum { W = 1280, H = 720, MAX_FRAMES = 64, SEAM_MM = 3 };

typedef struct setting {
    const char *name, *what;
    int size, taps; /* irradiance size; blur taps (0 = the scene's) */
    dm_render_desc knobs;
} setting;

static const setting settings[] = {
    {"256", "irradiance 256, 7 taps", 256, 0, {0}},
    {"256 taps 5", "irradiance 256, 5 taps", 256, 5, {0}},
    {"256 taps 9", "irradiance 256, 9 taps", 256, 9, {0}},
    {"512", "irradiance 512, 7 taps", 512, 0, {0}},
    {"512 taps 5", "irradiance 512, 5 taps", 512, 5, {0}},
    {"512 taps 9", "irradiance 512, 9 taps", 512, 9, {0}},
    {"512 reduce3", "512, --blur-reduce-from 3 (levels 3..5 at 256)", 512, 0, {.blur_reduce_from = 3}},
    {"512 half-float", "512, --half-float (RGBA16F targets)", 512, 0, {.blur_half_float = true}},
    {"512 reuse", "512, texture space reused (camera-only frames)", 512, 0, {.reuse_texture_space = true}},
};
enum { NSET = sizeof settings / sizeof settings[0] };

/* Regions: all covered texels, near a seam, the rest. */
enum { REG_ALL, REG_SEAM, REG_REST, REG_COUNT };
static const char *region_names[REG_COUNT] = {"all", "seam", "rest"};

typedef struct sized {
    int N;
    dm_refcmp_ref ref;
    unsigned char *seam; /* N*N: 1 near a seam */
    long seam_count, covered;
} sized;

typedef struct row {
    dm_scene scene;
    dm_renderer *r;
    double ms[MAX_FRAMES], frame_ms;
    dm_refcmp_stats st[REG_COUNT];
    bool ok[REG_COUNT];
} row;

static int run(const char *cmd)
{
    fprintf(stderr, "accuracy bench: %s\n", cmd);
    return system(cmd);
}

/* The cached reference at N, computed by dermis-reference when missing or stale. */
static int reference(const char *bin, const char *pack, const char *hash, const char *dir, int N, dm_refcmp_ref *ref)
{
    const char *hex = strchr(hash, ':') ? strchr(hash, ':') + 1 : hash;
    char path[2048], cmd[8192];
    snprintf(path, sizeof path, "%s/ref-%.16s-%d.exr", dir, hex, N);
    dm_error err = {0};
    for (int attempt = 0; attempt < 2; ++attempt) {
        if (dm_refcmp_load(path, ref, &err) == DM_OK && ref->has_provenance &&
            !strcmp(ref->prov.tool, "dermis-reference") && !strcmp(ref->prov.input_hash, hash) &&
            ref->mode == DM_REFCMP_TEXTURE_SPACE && ref->width == N) {
            const dm_param *tc = dm_prov_find(&ref->prov, "tile_count");
            if (!tc || tc->i == 1) {
                fprintf(stderr, "accuracy bench: reference %s (%s)\n", path, attempt ? "computed" : "cached");
                return 1;
            }
        }
        dm_refcmp_ref_free(ref);
        if (attempt) break;
        snprintf(cmd, sizeof cmd, "%s/bin/dermis-reference %s --texture-space %d -o %s --quiet", bin, pack, N, path);
        if (run(cmd) != 0) break;
    }
    fprintf(stderr, "error: no usable reference %s: %s\n", path, err.detail);
    return 0;
}

/* Distance from p to segment ab. */
static double seg_dist(const double p[3], const double a[3], const double b[3])
{
    double ab[3], ap[3], t = 0, l2 = 0, d2 = 0;
    for (int c = 0; c < 3; ++c) ab[c] = b[c] - a[c], ap[c] = p[c] - a[c], t += ab[c] * ap[c], l2 += ab[c] * ab[c];
    t = l2 > 0 ? fmin(fmax(t / l2, 0), 1) : 0;
    for (int c = 0; c < 3; ++c) d2 += (ap[c] - t * ab[c]) * (ap[c] - t * ab[c]);
    return sqrt(d2);
}

typedef struct edge {
    uint32_t a, b; /* welded position ids, a < b */
    int32_t tri;
    float uva[2], uvb[2];
} edge;

static int edge_cmp(const void *x, const void *y)
{
    const edge *e = x, *f = y;
    if (e->a != f->a) return e->a < f->a ? -1 : 1;
    if (e->b != f->b) return e->b < f->b ? -1 : 1;
    return (e->tri > f->tri) - (e->tri < f->tri);
}

static const float *pos_key_base;
static int pos_cmp(const void *x, const void *y)
{
    const float *p = pos_key_base + 3 * (size_t)*(const uint32_t *)x, *q = pos_key_base + 3 * (size_t)*(const uint32_t *)y;
    int c = memcmp(p, q, 3 * sizeof *p);
    if (c) return c;
    return (*(const uint32_t *)x > *(const uint32_t *)y) - (*(const uint32_t *)x < *(const uint32_t *)y);
}

/* Seam texels at size N: the covered texels whose surface point (dm_reference_atlas_targets,
 * the reference's own targets) lies within SEAM_MM in 3-D of a seam edge: an edge whose
 * two triangles give its ends different UVs, or that only one triangle has (boundary; three
 * or more: non-manifold, counted as seam too). Positions are welded by exact value. */
static int seam_mask(const dm_pack *pack, sized *z)
{
    dm_error err = {0};
    dm_scene scene;
    dm_profile profile;
    dm_ref_surface_desc desc;
    dm_ref_surface *s = NULL;
    if (dm_pack_scene(pack, &scene, &err) != DM_OK || dm_ref_surface_desc_from_pack(pack, &scene, &profile, &desc, &err) != DM_OK ||
        dm_ref_surface_create(&desc, 0, &s, &err) != DM_OK) {
        fprintf(stderr, "error: seam mask: %s\n", err.detail);
        return 0;
    }
    const dm_mesh *m = &s->mesh;
    const double mm = s->mm_per_unit;
    /* weld */
    uint32_t *order = malloc(sizeof *order * (size_t)m->vertex_count), *weld = malloc(sizeof *weld * (size_t)m->vertex_count);
    for (int32_t i = 0; i < m->vertex_count; ++i) order[i] = (uint32_t)i;
    pos_key_base = m->positions;
    qsort(order, (size_t)m->vertex_count, sizeof *order, pos_cmp);
    for (int32_t i = 0; i < m->vertex_count; ++i)
        weld[order[i]] = i && !memcmp(m->positions + 3 * (size_t)order[i], m->positions + 3 * (size_t)order[i - 1], 12)
                             ? weld[order[i - 1]] : order[i];
    /* edges */
    size_t ec = 3 * (size_t)m->triangle_count;
    edge *e = malloc(sizeof *e * ec);
    for (int32_t t = 0; t < m->triangle_count; ++t)
        for (int c = 0; c < 3; ++c) {
            int c2 = (c + 1) % 3;
            uint32_t a = weld[m->indices[3 * t + c]], b = weld[m->indices[3 * t + c2]];
            const float *ua = m->uvs + (3 * (size_t)t + c) * 2, *ub = m->uvs + (3 * (size_t)t + c2) * 2;
            if (a > b) {
                uint32_t k = a; a = b; b = k;
                const float *u = ua; ua = ub; ub = u;
            }
            e[3 * t + c] = (edge){a, b, t, {ua[0], ua[1]}, {ub[0], ub[1]}};
        }
    qsort(e, ec, sizeof *e, edge_cmp);
    double (*seg)[2][3] = malloc(sizeof *seg * ec);
    size_t sc = 0;
    for (size_t i = 0; i < ec;) {
        size_t j = i + 1;
        while (j < ec && e[j].a == e[i].a && e[j].b == e[i].b) ++j;
        bool seam = j - i != 2 || memcmp(e[i].uva, e[i + 1].uva, 8) || memcmp(e[i].uvb, e[i + 1].uvb, 8);
        if (seam) {
            for (int c = 0; c < 3; ++c) {
                seg[sc][0][c] = m->positions[3 * (size_t)e[i].a + c] * mm;
                seg[sc][1][c] = m->positions[3 * (size_t)e[i].b + c] * mm;
            }
            ++sc;
        }
        i = j;
    }
    /* grid of SEAM_MM cells over the seam segments */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < sc; ++i)
        for (int k = 0; k < 2; ++k)
            for (int c = 0; c < 3; ++c) lo[c] = fmin(lo[c], seg[i][k][c]), hi[c] = fmax(hi[c], seg[i][k][c]);
    int dim[3];
    for (int c = 0; c < 3; ++c) dim[c] = sc ? (int)((hi[c] - lo[c]) / SEAM_MM) + 1 : 1;
    size_t cells = (size_t)dim[0] * dim[1] * dim[2];
    size_t *start = calloc(cells + 1, sizeof *start);
    uint32_t *items = NULL;
    for (int pass = 0; pass < 2; ++pass) {
        if (pass) {
            for (size_t c = 0; c < cells; ++c) start[c + 1] += start[c];
            items = malloc(sizeof *items * (start[cells] + 1));
        }
        size_t *fill = pass ? calloc(cells, sizeof *fill) : NULL;
        for (size_t i = 0; i < sc; ++i) {
            int a[3], b[3];
            for (int c = 0; c < 3; ++c) {
                a[c] = (int)((fmin(seg[i][0][c], seg[i][1][c]) - lo[c]) / SEAM_MM);
                b[c] = (int)((fmax(seg[i][0][c], seg[i][1][c]) - lo[c]) / SEAM_MM);
                if (b[c] >= dim[c]) b[c] = dim[c] - 1;
            }
            for (int x = a[0]; x <= b[0]; ++x)
                for (int y = a[1]; y <= b[1]; ++y)
                    for (int zz = a[2]; zz <= b[2]; ++zz) {
                        size_t c = ((size_t)zz * dim[1] + y) * dim[0] + x;
                        if (!pass) ++start[c + 1];
                        else items[start[c] + fill[c]++] = (uint32_t)i;
                    }
        }
        free(fill);
    }
    /* the reference's targets */
    dm_reference_atlas ra = {z->N, z->N, z->ref.rgba};
    dm_reference_target *tg = NULL;
    int64_t *texel_of = NULL;
    size_t count = 0;
    int ok = dm_reference_atlas_targets(m, &ra, 0, &tg, &texel_of, &count, &err) == DM_OK;
    if (!ok) fprintf(stderr, "error: seam mask: %s\n", err.detail);
    z->seam = calloc((size_t)z->N * z->N, 1);
    for (size_t i = 0; ok && i < count; ++i) {
        dm_ref_point p;
        dm_ref_surface_point(s, tg[i].triangle, tg[i].b1, tg[i].b2, &p);
        int g[3];
        bool inside = sc > 0;
        for (int c = 0; c < 3; ++c) g[c] = (int)floor((p.p_mm[c] - lo[c]) / SEAM_MM), inside &= g[c] >= -1 && g[c] <= dim[c];
        bool near = false;
        for (int dz = -1; inside && !near && dz <= 1; ++dz)
            for (int dy = -1; !near && dy <= 1; ++dy)
                for (int dx = -1; !near && dx <= 1; ++dx) {
                    int x = g[0] + dx, y = g[1] + dy, zz = g[2] + dz;
                    if (x < 0 || y < 0 || zz < 0 || x >= dim[0] || y >= dim[1] || zz >= dim[2]) continue;
                    size_t c = ((size_t)zz * dim[1] + y) * dim[0] + x;
                    for (size_t k = start[c]; !near && k < start[c + 1]; ++k)
                        near = seg_dist(p.p_mm, seg[items[k]][0], seg[items[k]][1]) <= SEAM_MM;
                }
        if (near) z->seam[texel_of[i]] = 1, ++z->seam_count;
    }
    z->covered = (long)count;
    fprintf(stderr, "accuracy bench: %zu seam edges; at %d: %ld of %ld covered texels within %d mm of one\n", sc, z->N,
            z->seam_count, z->covered, SEAM_MM);
    free(tg), free(texel_of), free(items), free(start), free(seg), free(e), free(order), free(weld);
    dm_ref_surface_destroy(s);
    return ok;
}

/* Stats of render against the reference over one region (alpha outside it zeroed in a copy;
 * the floor is 1 % of the region's own mean). */
static bool region_stats(const sized *z, const float *px, int region, dm_refcmp_stats *st)
{
    size_t n = (size_t)z->N * z->N;
    float *ref = malloc(sizeof *ref * 4 * n);
    memcpy(ref, z->ref.rgba, sizeof *ref * 4 * n);
    if (region != REG_ALL)
        for (size_t i = 0; i < n; ++i)
            if ((z->seam[i] != 0) != (region == REG_SEAM)) ref[4 * i + 3] = 0;
    dm_error err = {0};
    bool ok = dm_refcmp_stats_compute(ref, px, z->N, z->N, st, NULL, &err) == DM_OK;
    if (!ok) fprintf(stderr, "warning: %s region: %s\n", region_names[region], err.detail);
    free(ref);
    return ok;
}

static double mean3(const double v[3]) { return (v[0] + v[1] + v[2]) / 3; }

static void plot(const char *outdir, const char *bin, row *rows)
{
    if (system("command -v gnuplot >/dev/null 2>&1") != 0) return;
    char dat[1024], png[1024];
    snprintf(dat, sizeof dat, "%s/cache/accuracy/pareto.dat", bin);
    snprintf(png, sizeof png, "%s/accuracy.png", outdir);
    FILE *f = fopen(dat, "w");
    if (!f) return;
    for (int c = 0; c < NSET; ++c)
        if (rows[c].ok[REG_ALL])
            fprintf(f, "%.3f %.6f %.6f \"%s\"\n", rows[c].frame_ms, 100 * mean3(rows[c].st[REG_ALL].mean),
                    100 * mean3(rows[c].st[REG_ALL].p95), settings[c].name);
    fclose(f);
    FILE *g = popen("gnuplot", "w");
    if (!g) return;
    fprintf(g, "set terminal pngcairo size 1000,650 font ',11'\nset output '%s'\n"
               "set title 'dermis renderer settings on the head: texture-space error vs the exact convolution, and frame time'\n"
               "set xlabel 'frame ms (median, 1280x720, llvmpipe)'\nset ylabel 'relative error, %% (mean over R, G, B)'\n"
               "set grid\nset key top right\nset yrange [0:*]\nset offsets graph 0.05, graph 0.25, graph 0.1, graph 0.1\n"
               "plot '%s' using 1:2 with points pt 7 ps 1.5 title 'mean', '' using 1:2:4 with labels offset 1,0.7 left "
               "font ',9' notitle, '' using 1:3 with points pt 5 ps 1.2 title 'p95', '' using 1:3:4 with labels "
               "offset 1,-0.7 left font ',9' notitle\n",
            png, dat);
    if (pclose(g) == 0) printf("accuracy bench: wrote %s\n", png);
}

int main(int argc, char **argv)
{
    const char *outdir = argc > 1 ? argv[1] : "bench/results";
    const char *bin = getenv("BUILD") ? getenv("BUILD") : "build/release";
    bool quick = getenv("DERMIS_BENCH_QUICK") && !strcmp(getenv("DERMIS_BENCH_QUICK"), "1");
    int frames = getenv("DERMIS_BENCH_FRAMES") ? atoi(getenv("DERMIS_BENCH_FRAMES")) : quick ? 5 : 7;
    if (frames < 5) frames = 5;
    if (frames > MAX_FRAMES) frames = MAX_FRAMES;
    char dir[1024], pack_path[2048], cmd[4096];
    snprintf(dir, sizeof dir, "%s/cache/accuracy", bin);
    snprintf(cmd, sizeof cmd, "mkdir -p %s", dir);
    if (system(cmd) != 0) return 4;
    if (argc > 2) snprintf(pack_path, sizeof pack_path, "%s", argv[2]);
    else {
        snprintf(pack_path, sizeof pack_path, "%s/lps-sss.dpk", dir);
        snprintf(cmd, sizeof cmd, "%s/bin/dermis-pack assets/scenes/lps-sss.json -o %s --quiet", bin, pack_path);
        if (run(cmd) != 0) {
            fprintf(stderr, "error: '%s' failed (run from the repository root)\n", cmd);
            return 3;
        }
    }
    dm_error err = {0};
    char hash[DM_HASH_HEX_SIZE];
    dm_pack pack;
    if (dm_hash_file_hex(pack_path, hash, &err) != DM_OK || dm_pack_open(pack_path, &pack, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return 2;
    }
    /* references and seam masks */
    sized z[2] = {{.N = 256}, {.N = 512}};
    int nz = quick ? 1 : 2;
    for (int i = 0; i < nz; ++i)
        if (!reference(bin, pack_path, hash, dir, z[i].N, &z[i].ref) || !seam_mask(&pack, &z[i])) return 3;

    dm_osmesa *ctx = NULL;
    dm_scene scene;
    dm_profile profile;
    dm_render_assets assets;
    if (dm_osmesa_create(&ctx, &err) != DM_OK || dm_render_assets_from_pack(&pack, &scene, &profile, &assets, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return 3;
    }
    static row rows[NSET];
    bool use[NSET];
    for (int c = 0; c < NSET; ++c) {
        use[c] = settings[c].size == 256 || !quick;
        if (!use[c]) continue;
        rows[c].scene = scene;
        if (settings[c].taps) rows[c].scene.blur_taps = settings[c].taps;
        dm_render_assets a = assets;
        a.scene = &rows[c].scene;
        dm_render_desc d = settings[c].knobs;
        d.width = W, d.height = H, d.irradiance_size = settings[c].size, d.timings = true;
        fprintf(stderr, "accuracy bench: setting %s\n", settings[c].name);
        if (dm_renderer_create(&a, &d, &rows[c].r, &err) != DM_OK ||
            dm_render_frame(rows[c].r, &(dm_frame_options){0}, &err) != DM_OK) {
            fprintf(stderr, "error: %s: %s\n", settings[c].name, err.detail);
            return 3;
        }
    }
    for (int f = 0; f < frames; ++f)
        for (int c = 0; c < NSET; ++c) {
            if (!use[c]) continue;
            if (dm_render_frame(rows[c].r, &(dm_frame_options){0}, &err) != DM_OK) {
                fprintf(stderr, "error: %s: %s\n", settings[c].name, err.detail);
                return 3;
            }
            dm_renderer_last_timings(rows[c].r, NULL, &rows[c].ms[f]);
        }
    for (int c = 0; c < NSET; ++c) {
        if (!use[c]) continue;
        rows[c].frame_ms = bench_median(rows[c].ms, frames);
        const sized *zz = settings[c].size == 256 ? &z[0] : &z[1];
        int w = 0, h = 0;
        float *px = NULL;
        if (dm_render_frame(rows[c].r, &(dm_frame_options){.view = DM_VIEW_DIFFUSION}, &err) == DM_OK) {
            dm_renderer_view_size(rows[c].r, &w, &h);
            px = w == zz->N && h == zz->N ? malloc(sizeof *px * 4 * (size_t)w * h) : NULL;
        }
        if (!px || dm_renderer_read_view(rows[c].r, px, &err) != DM_OK) {
            fprintf(stderr, "error: %s: the diffusion view (%dx%d): %s\n", settings[c].name, w, h, err.detail);
            return 3;
        }
        for (int g = 0; g < REG_COUNT; ++g) rows[c].ok[g] = region_stats(zz, px, g, &rows[c].st[g]);
        free(px);
        dm_renderer_destroy(rows[c].r);
    }

    /* report */
    FILE *md = bench_open(outdir, "accuracy.md", "Renderer settings: texture-space accuracy against the ground truth, and time");
    if (!md) return 4;
    double load = -1;
    FILE *la = fopen("/proc/loadavg", "r");
    if (la) {
        if (fscanf(la, "%lf", &load) != 1) load = -1;
        fclose(la);
    }
    fprintf(md, "The Lee Perry-Smith head, `%s` (subsurface, shadows, tonemap), %d triangles. Frame ms: median of "
                "%d final frames at %dx%d after one warm-up (llvmpipe, CPU clock around glFinish; every row's "
                "renderer alive, frames round robin; load average %.2f at the end: compare rows, not runs).\n\n",
            argc > 2 ? pack_path : "assets/scenes/lps-sss.json", assets.index_count / 3, frames, W, H, load);
    fprintf(md, "Error: the renderer's `diffusion` view (Σ_k w_k L_k, texture space) at irradiance N against "
                "`dermis-reference PACK --texture-space N` (the exact surface convolution of the renderer's own "
                "level-0 irradiance, 3-D distances over the whole mesh), through `dm_render_refcmp`: per channel, "
                "|render − ref| / max(ref, 1 %% of ref's mean over the region), texel-weighted over the texels "
                "covered in both; mean and p95 in %%, R / G / B. The irradiance of the half-float row is itself "
                "rounded (its error includes that); reuse renders the same texture space as its base row.\n\n");
    fprintf(md, "| setting | frame ms | mean %% R / G / B | p95 %% R / G / B |\n|---|---:|---:|---:|\n");
    for (int c = 0; c < NSET; ++c) {
        if (!use[c]) continue;
        const dm_refcmp_stats *s = &rows[c].st[REG_ALL];
        fprintf(md, "| %s | **%.1f** | %.2f / %.2f / %.2f | %.2f / %.2f / %.2f |\n", settings[c].what, rows[c].frame_ms,
                100 * s->mean[0], 100 * s->mean[1], 100 * s->mean[2], 100 * s->p95[0], 100 * s->p95[1], 100 * s->p95[2]);
        printf("%-50s %7.1f ms  mean %5.2f/%5.2f/%5.2f %%  p95 %5.2f/%5.2f/%5.2f %%\n", settings[c].what,
               rows[c].frame_ms, 100 * s->mean[0], 100 * s->mean[1], 100 * s->mean[2], 100 * s->p95[0],
               100 * s->p95[1], 100 * s->p95[2]);
    }
    fprintf(md, "\n## By region: near a UV seam and the rest\n\n");
    fprintf(md, "Near a seam: covered texels whose surface point lies within %d mm (3-D) of a seam edge. Seam edges "
                "come from the pack's mesh with positions welded by exact value: an edge whose two triangles give "
                "its ends different UVs, or that one triangle alone has (boundary; three or more: non-manifold). A "
                "texel's point is the reference's own target for it (`dm_reference_atlas_targets`, the raster's "
                "triangle and barycentrics); distances to the edge segments through a %d mm grid. ",
            SEAM_MM, SEAM_MM);
    for (int i = 0; i < nz; ++i)
        fprintf(md, "At %d: %ld of %ld covered texels (%.1f %%) are near a seam. ", z[i].N, z[i].seam_count, z[i].covered,
                100.0 * z[i].seam_count / (z[i].covered ? z[i].covered : 1));
    fprintf(md, "Each region's floor is 1 %% of the reference's mean over that region.\n\n");
    fprintf(md, "| setting | seam mean %% R / G / B | seam p95 %% R / G / B | rest mean %% R / G / B | rest p95 %% R / G / B |\n"
                "|---|---:|---:|---:|---:|\n");
    for (int c = 0; c < NSET; ++c) {
        if (!use[c]) continue;
        fprintf(md, "| %s |", settings[c].what);
        for (int g = REG_SEAM; g <= REG_REST; ++g) {
            const dm_refcmp_stats *s = &rows[c].st[g];
            if (!rows[c].ok[g]) fprintf(md, " – | – |");
            else fprintf(md, " %.2f / %.2f / %.2f | %.2f / %.2f / %.2f |", 100 * s->mean[0], 100 * s->mean[1],
                         100 * s->mean[2], 100 * s->p95[0], 100 * s->p95[1], 100 * s->p95[2]);
        }
        fprintf(md, "\n");
    }
    fprintf(md, "\nReferences are cached under `BUILD/cache/accuracy/` by pack hash and size (computed once by "
                "`dermis-reference`); `DERMIS_BENCH_QUICK=1` runs the 256 rows only. Plot: `accuracy.png` "
                "(mean and p95 over R, G, B against frame ms).\n");
    fclose(md);
    printf("accuracy bench: wrote %s/accuracy.md\n", outdir);
    plot(outdir, bin, rows);
    for (int i = 0; i < nz; ++i) dm_refcmp_ref_free(&z[i].ref), free(z[i].seam);
    dm_pack_close(&pack);
    dm_osmesa_destroy(ctx);
    return 0;
}
