/* bench/ref_convergence — the ground-truth frame's own error bar (issue #27): how far
 * `dermis-reference --frame` moves when each of its discretisations is refined, at the size
 * and in the runs bench/accuracy compares against (1280x720; the transport run and the full
 * scene), on assets/scenes/lps-sss.json.
 *
 * Factors, one at a time from a base: the irradiance atlas (512, 1024, 2048 texels a side),
 * its samples per texel (2², 4², 8²), the convolution's quadrature (--cut 4 --spacing 0.3
 * against --cut 6 --spacing 0.15), the sub-pixel rays (1², 2², 3², 4² for the surface terms)
 * and where the diffusion is taken (the pixel centre against each sub-pixel ray's hit); at
 * 640x360 (cheaper) the rays with D at each, 2², 3², 6², and 3² refined to 6² where a pixel
 * needs it (--refine 6) against 6² everywhere; in texture space (per region: smooth, seams,
 * thin parts) the quadrature at 256², and the irradiance's own resolution — the renderer's I
 * at 256² and 1024² against I at twice that, D read at the coarse texels' centres. Each
 * step is reported in the unit the accuracy bench uses for that run: the transport run as
 * Σ|a − b| / Σ|no-subsurface − b| over the signal pixels (dm_ref_frame_compare.h; so it reads
 * directly against the bench's normalised column), the full run as the mean relative
 * difference over the interior skin pixels.
 * Frames are cached under BUILD/cache/convergence/ (name = the setting) and reused when their
 * provenance names this pack (DERMIS_BENCH_CACHED=1: only what is cached, nothing computed).
 * Writes OUTDIR/ref_convergence.md. argv[2], optional: the pack. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/atlas_regions.h"
#include "common/bench_util.h"
#include "core/dm_hash.h"
#include "reference/dm_ref_frame_compare.h"
#include "reference/dm_ref_surface.h"
#include "pack/dm_pack.h"
#include "render/dm_render_refcmp.h"

enum { FW = 1280, FH = 720, QW = 640, QH = 360 };
static const char *SCENE = "assets/scenes/lps-sss.json";
static const char *TRANSPORT = "--without albedo,normal-map,shadows";

typedef struct frame {
    const char *name, *options; /* options after --frame --size, or after --texture-space ts */
    bool transport;
    int ts;       /* texture space at ts² (--texture-space ts), else 0: a frame */
    bool quarter; /* at QW x QH (the rays' convergence, cheaper) */
} frame;

static const frame frames[] = {
    {"T-flat", "--without albedo,normal-map,shadows,subsurface --atlas 1024 --pixel-samples 1", true, 0, false},
    {"T-a512-s4-p1c", "--atlas 512 --atlas-samples 4 --pixel-samples 1", true, 0, false},
    {"T-a1024-s4-p1c", "--atlas 1024 --atlas-samples 4 --pixel-samples 1", true, 0, false},
    {"T-a2048-s4-p1c", "--atlas 2048 --atlas-samples 4 --pixel-samples 1", true, 0, false},
    {"T-a4096-s2-p1c", "--atlas 4096 --atlas-samples 2 --pixel-samples 1", true, 0, false},
    {"T-a1024-s2-p1c", "--atlas 1024 --atlas-samples 2 --pixel-samples 1", true, 0, false},
    {"T-a1024-s8-p1c", "--atlas 1024 --atlas-samples 8 --pixel-samples 1", true, 0, false},
    {"T-a4096-s1-p1c", "--atlas 4096 --atlas-samples 1 --pixel-samples 1", true, 0, false},
    {"T-a8192-s1-p1c", "--atlas 8192 --atlas-samples 1 --pixel-samples 1", true, 0, false},
    {"T-a1024-s4-p1c-q", "--atlas 1024 --atlas-samples 4 --pixel-samples 1 --cut 6 --spacing 0.15", true, 0, false},
    {"T-a4096-s2-p3c", "--atlas 4096 --atlas-samples 2 --pixel-samples 3 --diffusion-at-centre", true, 0, false},
    {"T-a4096-s2-p2p", "--atlas 4096 --atlas-samples 2 --pixel-samples 2", true, 0, false},
    {"T-a4096-s2-p3p", "--atlas 4096 --atlas-samples 2 --pixel-samples 3", true, 0, false},
    {"F-a2048-s4-p1c", "--atlas 2048 --atlas-samples 4 --pixel-samples 1", false, 0, false},
    {"F-a4096-s2-p1c", "--atlas 4096 --atlas-samples 2 --pixel-samples 1", false, 0, false},
    {"F-a4096-s2-p2c", "--atlas 4096 --atlas-samples 2 --pixel-samples 2 --diffusion-at-centre", false, 0, false},
    {"F-a4096-s2-p3c", "--atlas 4096 --atlas-samples 2 --pixel-samples 3 --diffusion-at-centre", false, 0, false},
    {"F-a4096-s2-p4c", "--atlas 4096 --atlas-samples 2 --pixel-samples 4 --diffusion-at-centre", false, 0, false},
    {"F-a4096-s2-p3p", "--atlas 4096 --atlas-samples 2 --pixel-samples 3", false, 0, false},
    {"Q-flat", "--without albedo,normal-map,shadows,subsurface --atlas 1024 --pixel-samples 1", true, 0, true},
    {"Q-a1024-s2-p2p", "--atlas 1024 --atlas-samples 2 --pixel-samples 2", true, 0, true},
    {"Q-a1024-s2-p3p", "--atlas 1024 --atlas-samples 2 --pixel-samples 3", true, 0, true},
    {"Q-a1024-s2-p6p", "--atlas 1024 --atlas-samples 2 --pixel-samples 6", true, 0, true},
    {"Q-a1024-s2-p3r6", "--atlas 1024 --atlas-samples 2 --pixel-samples 3 --refine 6", true, 0, true},
    {"TS-256", "", false, 256, false},
    {"TS-256-q", "--cut 6 --spacing 0.15", false, 256, false},
    {"TS-512", "", false, 512, false},
    {"TS-1024", "", false, 1024, false},
    {"TS-2048", "", false, 2048, false},
};
enum { NF = sizeof frames / sizeof frames[0] };
static dm_refcmp_ref refs[NF];

/* One refinement step: coarse against fine, what it varies. */
typedef struct step {
    const char *coarse, *fine, *what;
} step;

static const step steps[] = {
    {"T-a512-s4-p1c", "T-a1024-s4-p1c", "transport: atlas 512 → 1024"},
    {"T-a1024-s4-p1c", "T-a2048-s4-p1c", "transport: atlas 1024 → 2048"},
    {"T-a2048-s4-p1c", "T-a4096-s2-p1c", "transport: atlas 2048 → 4096 (both 8192² irradiance points)"},
    {"T-a1024-s2-p1c", "T-a1024-s4-p1c", "transport: atlas 1024, samples 2² → 4²"},
    {"T-a1024-s4-p1c", "T-a1024-s8-p1c", "transport: atlas 1024, samples 4² → 8²"},
    {"T-a4096-s1-p1c", "T-a8192-s1-p1c", "transport: atlas 4096 → 8192 (one sample a texel)"},
    {"T-a4096-s1-p1c", "T-a4096-s2-p1c", "transport: atlas 4096, samples 1 → 2²"},
    {"T-a1024-s4-p1c", "T-a1024-s4-p1c-q", "transport: quadrature cut 4 σ, spacing 0.3 σ → 6 σ, 0.15 σ"},
    {"T-a4096-s2-p3c", "T-a4096-s2-p3p", "transport: 3² rays, diffusion at the centre → at each ray"},
    {"T-a4096-s2-p2p", "T-a4096-s2-p3p", "transport: 2² → 3² rays, diffusion at each"},
    {"Q-a1024-s2-p2p", "Q-a1024-s2-p3p", "transport at 640x360, atlas 1024: 2² → 3² rays"},
    {"Q-a1024-s2-p3p", "Q-a1024-s2-p6p", "transport at 640x360, atlas 1024: 3² → 6² rays"},
    {"Q-a1024-s2-p3r6", "Q-a1024-s2-p6p", "transport at 640x360, atlas 1024: 3² with `--refine 6` → 6² everywhere"},
    {"F-a2048-s4-p1c", "F-a4096-s2-p1c", "full: atlas 2048 → 4096"},
    {"F-a4096-s2-p2c", "F-a4096-s2-p3c", "full: 2² → 3² sub-pixel rays (diffusion at the centre)"},
    {"F-a4096-s2-p3c", "F-a4096-s2-p4c", "full: 3² → 4² sub-pixel rays (diffusion at the centre)"},
    {"F-a4096-s2-p3c", "F-a4096-s2-p3p", "full: 3² rays, diffusion at the centre → at each ray"},
    {"TS-256", "TS-256-q", "texture space 256: quadrature cut 4 σ, spacing 0.3 σ → 6 σ, 0.15 σ"},
    {"TS-256", "TS-512", "texture space 256: irradiance 256² → 512² (D read at 256's texel centres)"},
    {"TS-1024", "TS-2048", "texture space 1024: irradiance 1024² → 2048² (D read at 1024's texel centres)"},
};
enum { NS = sizeof steps / sizeof steps[0] };

/* The frame of that name (index into frames and refs). */
static int named(const char *name)
{
    for (int i = 0; i < NF; ++i)
        if (!strcmp(frames[i].name, name)) return i;
    return 0;
}

static bool load(const char *bin, const char *dir, const char *pack, const char *hash, const frame *f, dm_refcmp_ref *ref)
{
    char path[2048], cmd[8192];
    snprintf(path, sizeof path, "%s/%s.exr", dir, f->name);
    dm_error err = {0};
    for (int attempt = 0; attempt < 2; ++attempt) {
        int w = f->ts ? f->ts : f->quarter ? QW : FW, h = f->ts ? f->ts : f->quarter ? QH : FH;
        if (dm_refcmp_load(path, ref, &err) == DM_OK && ref->has_provenance && !strcmp(ref->prov.input_hash, hash) &&
            ref->width == w && ref->height == h) {
            fprintf(stderr, "ref_convergence: %s (%s)\n", path, attempt ? "computed" : "cached");
            return true;
        }
        dm_refcmp_ref_free(ref);
        if (attempt || getenv("DERMIS_BENCH_CACHED")) break;
        if (f->ts)
            snprintf(cmd, sizeof cmd, "%s/bin/dermis-reference %s --texture-space %d %s -o %s --quiet", bin, pack, f->ts,
                     f->options, path);
        else
            snprintf(cmd, sizeof cmd, "%s/bin/dermis-reference %s --frame --size %dx%d %s %s -o %s --quiet", bin, pack, w,
                     h, f->transport && !strstr(f->name, "-flat") ? TRANSPORT : "", f->options, path);
        fprintf(stderr, "ref_convergence: %s\n", cmd);
        if (system(cmd) != 0) break;
    }
    fprintf(stderr, "error: %s: %s\n", path, err.detail);
    return false;
}

/* fine (N² RGBA) read at the texel centres of an M² atlas (M < N, bilinear): out (M² RGBA),
 * alpha 0 where a read would take in a texel fine does not cover. */
static void read_at(const float *fine, int N, int M, float *out)
{
    for (int j = 0; j < M; ++j)
        for (int i = 0; i < M; ++i) {
            double x = (i + 0.5) * N / M - 0.5, y = (j + 0.5) * N / M - 0.5;
            int x0 = (int)floor(x), y0 = (int)floor(y);
            double fx = x - x0, fy = y - y0, v[3] = {0};
            bool ok = x0 >= 0 && y0 >= 0 && x0 + 1 < N && y0 + 1 < N;
            for (int k = 0; ok && k < 4; ++k) {
                const float *t = fine + 4 * ((size_t)(y0 + k / 2) * N + x0 + k % 2);
                double w = (k % 2 ? fx : 1 - fx) * (k / 2 ? fy : 1 - fy);
                ok = t[3] >= 0.5f;
                for (int c = 0; c < 3; ++c) v[c] += w * t[c];
            }
            float *o = out + 4 * ((size_t)j * M + i);
            for (int c = 0; c < 3; ++c) o[c] = ok ? (float)v[c] : 0.0f;
            o[3] = ok ? 1.0f : 0.0f;
        }
}

/* The texture-space steps per region: area-weighted mean |coarse − fine| / fine over the
 * texels of each label (dm_ref_regions.h) at the coarse step's size, as accuracy.md's region
 * table weighs them; a finer irradiance's D is read at the coarse texels' centres. */
static int texture_space_table(FILE *md, const char *pack_path)
{
    dm_pack pack;
    dm_scene scene;
    dm_profile profile;
    dm_ref_surface_desc desc;
    dm_ref_surface *surf = NULL;
    dm_ref_regions *rg = NULL;
    dm_error err = {0};
    if (dm_pack_open(pack_path, &pack, &err) != DM_OK || dm_pack_scene(&pack, &scene, &err) != DM_OK ||
        dm_ref_surface_desc_from_pack(&pack, &scene, &profile, &desc, &err) != DM_OK ||
        dm_ref_surface_create(&desc, 0, &surf, &err) != DM_OK ||
        dm_ref_regions_create(&surf->mesh, surf->mm_per_unit, NULL, &rg, &err) != DM_OK) {
        fprintf(stderr, "error: regions: %s\n", err.detail);
        return 0;
    }
    fprintf(md, "\nThe texture-space reference (`--texture-space N`), area-weighted mean |coarse − fine| / fine "
                "per region at the coarse size (the labels and areas of accuracy.md's region table), %%, R / G / B:\n\n"
                "| refinement | smooth | seam | thin |\n|---|---:|---:|---:|\n");
    int ok = 1;
    for (int s = 0; ok && s < NS; ++s) {
        const frame *fa = &frames[named(steps[s].coarse)], *fb = &frames[named(steps[s].fine)];
        const dm_refcmp_ref *a = &refs[named(steps[s].coarse)], *b = &refs[named(steps[s].fine)];
        if (!fb->ts || !a->rgba || !b->rgba) continue;
        uint8_t *label = NULL;
        float *area = NULL, *fine = b->rgba;
        long count[DM_REF_REGION_COUNT] = {0};
        double area_mm2[DM_REF_REGION_COUNT] = {0};
        size_t n = (size_t)fa->ts * fa->ts;
        ok = atlas_regions(rg, &surf->mesh, fa->ts, a->rgba, &label, &area, count, area_mm2);
        if (ok && fb->ts != fa->ts) ok = (fine = malloc(sizeof *fine * 4 * n)) != NULL;
        if (ok && fb->ts != fa->ts) read_at(b->rgba, fb->ts, fa->ts, fine);
        if (ok) fprintf(md, "| %s |", steps[s].what);
        for (int g = 0; ok && g < DM_REF_REGION_COUNT; ++g) {
            dm_ref_error_stats st;
            if (dm_ref_error_stats_compute(fine, a->rgba, area, label, g, n, &st, &err) == DM_OK)
                fprintf(md, " %.3f / %.3f / %.3f |", 100 * st.mean[0], 100 * st.mean[1], 100 * st.mean[2]);
            else fprintf(md, " – |");
        }
        if (ok) fprintf(md, "\n");
        if (fine != b->rgba) free(fine);
        free(label), free(area);
    }
    dm_ref_regions_destroy(rg), dm_ref_surface_destroy(surf), dm_pack_close(&pack);
    return ok;
}

int main(int argc, char **argv)
{
    const char *outdir = argc > 1 ? argv[1] : "bench/results";
    const char *bin = getenv("BUILD") ? getenv("BUILD") : "build/release";
    char dir[1024], pack[2048], cmd[4096], hash[DM_HASH_HEX_SIZE];
    snprintf(dir, sizeof dir, "%s/cache/convergence", bin);
    snprintf(cmd, sizeof cmd, "mkdir -p %s %s/cache/accuracy %s", dir, bin, outdir);
    if (system(cmd) != 0) return 4;
    if (argc > 2) snprintf(pack, sizeof pack, "%s", argv[2]);
    else {
        snprintf(pack, sizeof pack, "%s/cache/accuracy/lps-sss.dpk", bin);
        snprintf(cmd, sizeof cmd, "%s/bin/dermis-pack %s -o %s --quiet", bin, SCENE, pack);
        if (system(cmd) != 0) {
            fprintf(stderr, "error: '%s' failed (run from the repository root)\n", cmd);
            return 3;
        }
    }
    dm_error err = {0};
    if (dm_hash_file_hex(pack, hash, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return 2;
    }
    bool cached_only = getenv("DERMIS_BENCH_CACHED") != NULL; /* a partial table from what is cached */
    for (int i = 0; i < NF; ++i)
        if (!load(bin, dir, pack, hash, &frames[i], &refs[i]) && !cached_only) return 3;
    FILE *md = bench_open(outdir, "ref_convergence.md", "The ground-truth frame's error bar: dermis-reference --frame refined");
    if (!md) return 4;
    fprintf(md, "`%s` at %dx%d, one factor refined at a time (`bench/ref_convergence.c`). **Transport** rows: the "
                "run bench/accuracy normalises (`--without albedo,normal-map,shadows`), the step's difference "
                "Σ|coarse − fine| / Σ|no-subsurface − fine| over the pixels where subsurface changes the fine frame by "
                "more than 2 %% — the unit of accuracy.md's *normalised* column. **Full** rows: the scene as it is, "
                "mean |coarse − fine| / fine over the interior skin pixels (the unit of its *+ shadows* column). "
                "All channels (transport: the sums over R, G and B; the bench's ranking number), then R / G / B, %%.\n\n"
                "| refinement | normalised, all %% | normalised or mean %% R / G / B | signal (red) or interior pixels |\n"
                "|---|---:|---:|---:|\n",
            SCENE, FW, FH);
    float *w = malloc(sizeof *w * (size_t)FW * FH);
    for (int s = 0; w && s < NS; ++s) {
        const dm_refcmp_ref *a = &refs[named(steps[s].coarse)], *b = &refs[named(steps[s].fine)];
        bool quarter = frames[named(steps[s].fine)].quarter;
        const dm_refcmp_ref *flat = &refs[named(quarter ? "Q-flat" : "T-flat")];
        size_t n = quarter ? (size_t)QW * QH : (size_t)FW * FH;
        if (frames[named(steps[s].fine)].ts || !a->rgba || !b->rgba || !flat->rgba) continue;
        dm_ref_frame_interior(b->rgba, a->rgba, quarter ? QW : FW, quarter ? QH : FH, w);
        double v[3], all = -1;
        long count;
        if (frames[named(steps[s].fine)].transport) {
            dm_ref_transport_stats st;
            if (dm_ref_transport_compute(b->rgba, flat->rgba, a->rgba, w, NULL, -1, n, 0, &st, &err) != DM_OK)
                continue;
            for (int c = 0; c < 3; ++c) v[c] = st.normalised[c];
            count = st.signal[0], all = st.normalised_rgb;
        } else {
            dm_ref_error_stats st;
            if (dm_ref_error_stats_compute(b->rgba, a->rgba, w, NULL, -1, n, &st, &err) != DM_OK) continue;
            for (int c = 0; c < 3; ++c) v[c] = st.mean[c];
            count = st.count;
        }
        char a3[32] = "–";
        if (all >= 0) snprintf(a3, sizeof a3, "**%.2f**", 100 * all);
        fprintf(md, "| %s | %s | %.3f / %.3f / %.3f | %ld |\n", steps[s].what, a3, 100 * v[0], 100 * v[1], 100 * v[2], count);
        printf("%-70s %7.3f %7.3f %7.3f %%\n", steps[s].what, 100 * v[0], 100 * v[1], 100 * v[2]);
    }
    if (!texture_space_table(md, pack) && !cached_only) return 3;
    fprintf(md, "\nTimes: see `docs/dermis-reference.md` (Convergence).\n");
    fclose(md);
    free(w);
    for (int i = 0; i < NF; ++i) dm_refcmp_ref_free(&refs[i]);
    printf("ref_convergence: wrote %s/ref_convergence.md\n", outdir);
    return 0;
}
