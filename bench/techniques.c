/* bench/techniques — the subsurface techniques side by side (issue 13): texture-space
 * diffusion, screen-space separable SSS at 11, 17 and 25 taps, and translucency added to
 * each, on the Lee Perry-Smith head packed from assets/scenes/lps.json (every effect),
 * 1280x720, irradiance 1024. Every renderer is created up front over the same assets and
 * the frames run round robin (frame f of every row, then f + 1), so a shared machine's load
 * hits every row alike; compare rows of one table, not across runs. The screen-space
 * kernels are fitted at create from the pack's profile by the function dermis-pack uses.
 *
 * Accuracy: with DERMIS_BENCH_REFERENCE=F.exr (a dermis-reference --frame of the same pack,
 * e.g. --size 320x180 --atlas 256; minutes), every row also renders at that size and is
 * compared with it through render/dm_render_refcmp.h (skin pixels, per channel mean and
 * p95 relative error). The reference has no translucency: the translucency rows' error
 * shows how much light they add, not an error of theirs.
 * Writes OUTDIR/techniques.md. DERMIS_BENCH_FRAMES overrides the frame count (default 7). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "common/bench_util.h"
#include "pack/dm_pack.h"
#include "core/dm_ssss_kernel.h"
#include "host/dm_osmesa.h"
#include "core/dm_cli.h"

/* the kernel row whose fit error the table shows: 0.32 mm per pixel, the demo face's 0.34 */
enum { FIT_ROW = 4 };
#include "core/dm_sort.h"
#include "render/dm_render.h"
#include "render/dm_render_pack.h"
#include "render/dm_render_refcmp.h"

enum { W = 1280, H = 720, IRR = 1024, MAX_FRAMES = 64 };

typedef struct row {
    const char *name;
    dm_sss_technique technique;
    int screen_taps;
    bool translucency;
    dm_scene scene;
    dm_renderer *r;
    double frame[MAX_FRAMES], cpu[MAX_FRAMES], sss[MAX_FRAMES];
    double frame_ms, cpu_ms, sss_ms, fit_error[3];
    bool has_err;
    dm_refcmp_stats st;
} row;

static row rows[] = {
    {.name = "texture-space", .technique = DM_SSS_TEXTURE_SPACE, .screen_taps = 17, .translucency = false},
    {.name = "screen-space 11", .technique = DM_SSS_SCREEN_SPACE, .screen_taps = 11, .translucency = false},
    {.name = "screen-space 17", .technique = DM_SSS_SCREEN_SPACE, .screen_taps = 17, .translucency = false},
    {.name = "screen-space 25", .technique = DM_SSS_SCREEN_SPACE, .screen_taps = 25, .translucency = false},
    {.name = "texture-space + translucency", .technique = DM_SSS_TEXTURE_SPACE, .screen_taps = 17, .translucency = true},
    {.name = "screen-space 17 + translucency", .technique = DM_SSS_SCREEN_SPACE, .screen_taps = 17, .translucency = true},
};
enum { NROWS = sizeof rows / sizeof rows[0] };

static dm_renderer *make(dm_render_assets *a, row *rw, int w, int h, bool timings)
{
    dm_error err = {0};
    dm_render_assets ra = *a;
    ra.scene = &rw->scene;
    ra.ss_kernel = NULL; /* fitted at create for the row's tap count */
    dm_render_desc d = {.width = w, .height = h, .irradiance_size = IRR, .timings = timings};
    dm_renderer *r = NULL;
    if (dm_renderer_create(&ra, &d, &r, &err) != DM_OK || dm_render_frame(r, &(dm_frame_options){0}, &err) != DM_OK) {
        fprintf(stderr, "error: %s: %s\n", rw->name, err.detail);
        dm_renderer_destroy(r);
        return NULL;
    }
    return r;
}

int main(int argc, char **argv)
{
    const char *outdir = argc > 1 ? argv[1] : "bench/results";
    int frames = getenv("DERMIS_BENCH_FRAMES") ? atoi(getenv("DERMIS_BENCH_FRAMES")) : 7;
    if (frames < 1) frames = 1;
    if (frames > MAX_FRAMES) frames = MAX_FRAMES;
    dm_error err = {0};
    dm_osmesa *ctx = NULL;
    if (dm_osmesa_create(&ctx, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return 3;
    }
    const char *bin = getenv("BUILD") ? getenv("BUILD") : "build/release";
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "%s/bin/dermis-pack assets/scenes/lps.json -o /tmp/dermis-bench-techniques.dpk --quiet",
             bin);
    if (system(cmd) != 0) {
        fprintf(stderr, "error: '%s' failed (run from the repository root)\n", cmd);
        return 3;
    }
    dm_pack pack;
    dm_scene scene;
    dm_profile profile;
    dm_render_assets assets;
    if (dm_pack_open("/tmp/dermis-bench-techniques.dpk", &pack, &err) != DM_OK ||
        dm_render_assets_from_pack(&pack, &scene, &profile, &assets, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return 3;
    }
    for (int i = 0; i < NROWS; ++i) {
        row *rw = &rows[i];
        rw->scene = scene;
        rw->scene.sss_technique = rw->technique;
        rw->scene.screen_taps = rw->screen_taps;
        rw->scene.effects[DM_EFFECT_TRANSLUCENCY] = rw->translucency;
        dm_ssss_kernel k;
        if (rw->technique == DM_SSS_SCREEN_SPACE && dm_ssss_kernel_fit(&profile, rw->screen_taps, &k, &err) == DM_OK)
            memcpy(rw->fit_error, k.fit_error[FIT_ROW], sizeof rw->fit_error);
        fprintf(stderr, "techniques bench: %s\n", rw->name);
        if (!(rw->r = make(&assets, rw, W, H, true))) return 3;
    }
    for (int f = 0; f < frames; ++f)
        for (int i = 0; i < NROWS; ++i) {
            row *rw = &rows[i];
            double c0 = dm_cpu_ms();
            if (dm_render_frame(rw->r, &(dm_frame_options){0}, &err) != DM_OK) fprintf(stderr, "error: %s\n", err.detail);
            rw->cpu[f] = dm_cpu_ms() - c0;
            double pass[DM_PLAN_MAX_PASSES];
            dm_renderer_last_timings(rw->r, pass, &rw->frame[f]);
            const dm_render_plan *p = dm_renderer_plan(rw->r);
            rw->sss[f] = 0;
            for (int k = 0; k < p->pass_count; ++k) {
                dm_pass_kind kind = p->passes[k].kind;
                if (kind == DM_PASS_IRRADIANCE || kind == DM_PASS_BLUR_U || kind == DM_PASS_BLUR_V ||
                    kind == DM_PASS_DIFFUSION || kind == DM_PASS_SS_BLUR_H || kind == DM_PASS_SS_BLUR_V)
                    rw->sss[f] += pass[k];
            }
        }
    for (int i = 0; i < NROWS; ++i) {
        rows[i].frame_ms = dm_median_doubles(rows[i].frame, (size_t)(frames));
        rows[i].cpu_ms = dm_median_doubles(rows[i].cpu, (size_t)(frames));
        rows[i].sss_ms = dm_median_doubles(rows[i].sss, (size_t)(frames));
        dm_renderer_destroy(rows[i].r);
        rows[i].r = NULL;
    }
    /* accuracy against a ground-truth frame, when one is given */
    const char *refpath = getenv("DERMIS_BENCH_REFERENCE");
    dm_refcmp_ref ref = {0};
    bool have_ref = refpath && dm_refcmp_load(refpath, &ref, &err) == DM_OK && ref.mode == DM_REFCMP_FRAME;
    if (refpath && !have_ref) fprintf(stderr, "warning: %s: %s (no accuracy columns)\n", refpath, err.detail);
    for (int i = 0; have_ref && i < NROWS; ++i) {
        row *rw = &rows[i];
        dm_renderer *r = make(&assets, rw, ref.width, ref.height, false);
        float *px = r ? malloc((size_t)ref.width * ref.height * 4 * sizeof *px) : NULL;
        if (px && dm_renderer_read_linear(r, px, &err) == DM_OK &&
            dm_refcmp_stats_compute(ref.rgba, px, ref.width, ref.height, &rw->st, NULL, &err) == DM_OK)
            rw->has_err = true;
        else
            fprintf(stderr, "warning: %s: %s\n", rw->name, err.detail);
        free(px);
        dm_renderer_destroy(r);
    }

    char path[1024], machine[512];
    snprintf(path, sizeof path, "%s/techniques.md", outdir);
    FILE *md = fopen(path, "w");
    if (!md) {
        fprintf(stderr, "error: %s: cannot write\n", path);
        return 4;
    }
    bench_machine(machine, sizeof machine);
    double load = -1;
    FILE *la = fopen("/proc/loadavg", "r");
    if (la) {
        if (fscanf(la, "%lf", &load) != 1) load = -1;
        fclose(la);
    }
    fprintf(md, "# Subsurface techniques and translucency (llvmpipe)\n\nMachine: %s; load average at the end %.2f "
                "(compare rows of this table, not across runs).\n",
            machine, load);
    fprintf(md, "The head (assets/scenes/lps.json, every effect), %dx%d, irradiance %d; median of %d frames, round "
                "robin, after one warm-up each. Subsurface ms: texture-space irradiance + 10 blur passes + the diffusion pass, or the two "
                "screen-space blur passes (the screen-space shading pass replaces the final pass and is not in it). "
                "Fit error: the separable kernel's relative Frobenius error against the profile, in its row "
                "for %g mm per pixel (the head's face at 1280x720; dermis-pack reports the largest over the "
                "rows).\n\n",
            W, H, IRR, frames, ldexp(DM_SSSS_ROW0_MM_PER_PX, FIT_ROW));
    fprintf(md, "| technique | frame ms | vs texture-space | CPU ms | subsurface ms | kernel fit error R/G/B |%s\n"
                "|---|---:|---:|---:|---:|---|%s\n",
            have_ref ? " frame error mean R/G/B | p95 R/G/B |" : "", have_ref ? "---|---|" : "");
    for (int i = 0; i < NROWS; ++i) {
        row *rw = &rows[i];
        double base = rw->translucency ? rows[rw->technique == DM_SSS_TEXTURE_SPACE ? 0 : 2].frame_ms : rows[0].frame_ms;
        char fit[64] = "—";
        if (rw->technique == DM_SSS_SCREEN_SPACE)
            snprintf(fit, sizeof fit, "%.1f / %.1f / %.1f %%", 100 * rw->fit_error[0], 100 * rw->fit_error[1],
                     100 * rw->fit_error[2]);
        fprintf(md, "| %s | **%.1f** | %s%.2fx | %.0f | %.1f | %s |", rw->name, rw->frame_ms,
                rw->translucency ? "(vs same technique) " : "", rw->frame_ms / base, rw->cpu_ms, rw->sss_ms, fit);
        if (have_ref && rw->has_err)
            fprintf(md, " %.2f / %.2f / %.2f %% | %.2f / %.2f / %.2f %% |", 100 * rw->st.mean[0], 100 * rw->st.mean[1],
                    100 * rw->st.mean[2], 100 * rw->st.p95[0], 100 * rw->st.p95[1], 100 * rw->st.p95[2]);
        else if (have_ref)
            fprintf(md, " — | — |");
        fprintf(md, "\n");
    }
    if (have_ref)
        fprintf(md, "\nReference: %s (%dx%d), error over skin pixels as `dermis-render --reference` reports it.\n",
                refpath, ref.width, ref.height);
    fclose(md);
    printf("techniques bench: wrote %s (texture-space %.1f ms, screen-space 17 %.1f ms)\n", path, rows[0].frame_ms,
           rows[2].frame_ms);
    dm_refcmp_ref_free(&ref);
    dm_pack_close(&pack);
    dm_osmesa_destroy(ctx);
    return 0;
}
