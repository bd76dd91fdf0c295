/* bench/render — the skin renderer on OSMesa (llvmpipe): what each speed/accuracy setting of
 * dm_render_desc costs in accuracy and buys in time (DESIGN.md promise 1), then median ms
 * per pass and per frame at irradiance 512/1024/2048 and each effect alone at 1024.
 * The Lee Perry-Smith head packed from assets/scenes/lps.json (17,684 triangles), 1280x720;
 * DERMIS_BENCH_SYNTHETIC=1 uses the synthetic UV sphere (18,240 triangles) instead.
 *
 * Settings table: every setting's renderer is created up front and the frames run round
 * robin (frame f of every setting, then frame f + 1), so a shared machine's load changes
 * hit every row alike. Error: against the exact path (9-tap PCF, RGBA32F, every level at
 * full resolution, texture space recomputed every frame), on the same frame:
 *   - output: the linear radiance before tonemapping ("screen"), max and mean |Δ| over the
 *     RGB values of every pixel, and the largest 8-bit step of the tonemapped display;
 *   - blur: the widest blur level (coverage-normalised rgb / alpha), where the reference has
 *     coverage, max and mean |Δ|; a reduced level is sampled bilinearly at full-resolution
 *     texel centres (as the final pass does).
 * Writes OUTDIR/render.md. DERMIS_BENCH_FRAMES overrides the frame count (default 7). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "common/bench_util.h"
#include "core/dm_cli.h"
#include "core/dm_sort.h"
#include "pack/dm_pack.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_compare.h"
#include "render/dm_render_pack.h"
#include "render/dm_render_synth.h"

/* What is rendered: the packed head, or the synthetic sphere. */
typedef struct bench_source {
    dm_render_assets assets;
    dm_scene scene;
    dm_profile profile;
    int triangle_count;
    const char *name;
    dm_pack pack;
    bool pack_open;
    dm_synth *synth;
} bench_source;

static int source_open(bench_source *s, dm_error *err)
{
    memset(s, 0, sizeof *s);
    const char *syn = getenv("DERMIS_BENCH_SYNTHETIC");
    if (syn && strcmp(syn, "1") == 0) {
        if (dm_synth_create(&(dm_synth_options){0}, &s->synth, err) != DM_OK) return 0;
        s->assets = s->synth->assets;
        s->scene = s->synth->scene;
        s->assets.scene = &s->scene;
        s->triangle_count = s->synth->triangle_count;
        s->name = "Synthetic UV sphere";
        return 1;
    }
    const char *bin = getenv("BUILD") ? getenv("BUILD") : "build/release";
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "%s/bin/dermis-pack assets/scenes/lps.json -o /tmp/dermis-bench-render.dpk --quiet", bin);
    if (system(cmd) != 0) {
        dm_fail(err, DM_ERR_FILE_READ, "'%s' failed (run from the repository root)", cmd);
        return 0;
    }
    if (dm_pack_open("/tmp/dermis-bench-render.dpk", &s->pack, err) != DM_OK) return 0;
    s->pack_open = true;
    if (dm_render_assets_from_pack(&s->pack, &s->scene, &s->profile, &s->assets, err) != DM_OK) return 0;
    s->triangle_count = s->assets.index_count / 3;
    s->name = "The Lee Perry-Smith head (assets/scenes/lps.json, every effect)";
    return 1;
}

static void source_close(bench_source *s)
{
    if (s->pack_open) dm_pack_close(&s->pack);
    dm_synth_free(s->synth);
}

enum { W = 1280, H = 720, MAX_FRAMES = 256 };

typedef struct setting {
    const char *name, *what;
    dm_render_desc knobs; /* only the quality fields are read */
} setting;

/* What each row changes from the default (row 1). Row 0 is the exact reference. */
static const setting settings[] = {
    {"exact", "reference: 9-tap PCF, RGBA32F, full-resolution levels summed per pixel", {.shadow_pcf_taps = 9, .diffusion_per_pixel = true}},
    {"default", "4-tap PCF (same filter), RGBA32F, full-resolution levels, their sum per texel (diffusion pass)", {0}},
    {"per-pixel", "default with the levels summed per pixel in the final pass (--diffusion-per-pixel)", {.diffusion_per_pixel = true}},
    {"gl-blur", "default with the blur passes (texture-space, glow) in GL, not on the CPU", {.blur_path = DM_BLUR_PATH_GL}},
    {"pcf1", "shadow: one bilinear compare", {.shadow_pcf_taps = 1}},
    {"half-float", "irradiance and blur targets RGBA16F", {.blur_half_float = true}},
    {"reduce4", "blur levels 4, 5 at 1/2 resolution", {.blur_reduce_from = 4}},
    {"reduce3", "blur levels 3..5 at 1/2 resolution", {.blur_reduce_from = 3}},
    {"reduce4q", "blur levels 4, 5 at 1/4 resolution", {.blur_reduce_from = 4, .blur_reduce_shift = 2}},
    {"fast", "reduce3 + half-float", {.blur_reduce_from = 3, .blur_half_float = true}},
    {"auto", "blur levels at the automatic resolution (4, 5 at 1/2, 1/4 on the head)", {.blur_auto_resolution = true}},
    {"reuse", "default, light unchanged: texture space reused (camera-only frames)", {.reuse_texture_space = true}},
};
enum { NSET = sizeof settings / sizeof settings[0] };

typedef struct run_state {
    dm_renderer *r;
    double *ms; /* frames x (DM_PLAN_MAX_PASSES + 1) */
    dm_render_plan plan;
    double pass_ms[DM_PLAN_MAX_PASSES], frame_ms;
    double cpu[MAX_FRAMES], cpu_ms; /* process CPU time (all llvmpipe threads) per frame */
} run_state;


static dm_renderer *make(bench_source *s, int irr, const dm_render_desc *knobs)
{
    dm_error err = {0};
    dm_renderer *r = NULL;
    dm_render_desc d = knobs ? *knobs : (dm_render_desc){0};
    d.width = W, d.height = H, d.irradiance_size = irr, d.timings = true;
    if (dm_renderer_create(&s->assets, &d, &r, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return NULL;
    }
    dm_frame_options fo = {0};
    if (dm_render_frame(r, &fo, &err) != DM_OK) { /* warm-up: shader JIT, first uploads */
        fprintf(stderr, "error: %s\n", err.detail);
        dm_renderer_destroy(r);
        return NULL;
    }
    return r;
}

static void one_frame(run_state *st, int f)
{
    dm_error err = {0};
    dm_frame_options fo = {0};
    double c0 = dm_cpu_ms();
    if (dm_render_frame(st->r, &fo, &err) != DM_OK) fprintf(stderr, "error: %s\n", err.detail);
    st->cpu[f] = dm_cpu_ms() - c0;
    double *row = st->ms + (size_t)f * (DM_PLAN_MAX_PASSES + 1);
    dm_renderer_last_timings(st->r, row, row + DM_PLAN_MAX_PASSES);
}

static void medians(run_state *st, int frames)
{
    st->plan = *dm_renderer_plan(st->r);
    st->cpu_ms = dm_median_doubles(st->cpu, (size_t)(frames));
    double col[MAX_FRAMES];
    for (int i = 0; i <= st->plan.pass_count; ++i) {
        int slot = i < st->plan.pass_count ? i : DM_PLAN_MAX_PASSES;
        for (int f = 0; f < frames; ++f) col[f] = st->ms[(size_t)f * (DM_PLAN_MAX_PASSES + 1) + slot];
        double m = dm_median_doubles(col, (size_t)(frames));
        if (i < st->plan.pass_count) st->pass_ms[i] = m;
        else st->frame_ms = m;
    }
}

/* One renderer alone: frames timed after a warm-up. */
static int run_alone(bench_source *s, int irr, int frames, run_state *st)
{
    memset(st, 0, sizeof *st);
    st->r = make(s, irr, NULL);
    if (!st->r) return 0;
    st->ms = calloc((size_t)frames * (DM_PLAN_MAX_PASSES + 1), sizeof *st->ms);
    for (int f = 0; f < frames; ++f) one_frame(st, f);
    medians(st, frames);
    free(st->ms);
    dm_renderer_destroy(st->r);
    return 1;
}

typedef dm_render_difference errors;

static void compare(dm_renderer *ref, dm_renderer *r, const char *level, errors *e)
{
    dm_error err = {0};
    if (dm_render_compare(ref, r, level, e, &err) != DM_OK) fprintf(stderr, "warning: %s\n", err.detail);
}

int main(int argc, char **argv)
{
    const char *outdir = argc > 1 ? argv[1] : "bench/results";
    int frames = getenv("DERMIS_BENCH_FRAMES") ? atoi(getenv("DERMIS_BENCH_FRAMES")) : 7;
    if (frames < 1) frames = 1;
    if (frames > MAX_FRAMES) frames = MAX_FRAMES;
    dm_error err = {0};
    dm_osmesa *ctx = NULL;
    bench_source src, *s = &src;
    if (dm_osmesa_create(&ctx, &err) != DM_OK || !source_open(s, &err)) {
        fprintf(stderr, "error: %s\n", err.detail);
        return 3;
    }
    char path[1024];
    snprintf(path, sizeof path, "%s/render.md", outdir);
    FILE *md = fopen(path, "w");
    if (!md) {
        fprintf(stderr, "error: %s: cannot write\n", path);
        return 4;
    }
    char machine[512];
    bench_machine(machine, sizeof machine);
    double load[3] = {0, 0, 0};
    FILE *la = fopen("/proc/loadavg", "r");
    if (la) {
        if (fscanf(la, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) load[0] = -1;
        fclose(la);
    }
    const char *lp = getenv("LP_NUM_THREADS");
    fprintf(md, "# Renderer timings (llvmpipe)\n\n");
    fprintf(md, "Machine: %s; LP_NUM_THREADS=%s, load average at start %.2f "
                "(compare rows of one table, not across runs).\n",
            machine, lp ? lp : "(default)", load[0]);
    fprintf(md, "%s, %d triangles, %dx%d, shadow map 1024, %d taps; median of %d frames after "
                "one warm-up; CPU clock around glFinish per pass (%s).\n\n",
            s->name, s->triangle_count, W, H, s->scene.blur_taps, frames, "llvmpipe's timer queries are wrong");

    /* ---- settings: time and error against the exact path, irradiance 1024 ---- */
    const int irr = 1024;
    run_state st[NSET];
    memset(st, 0, sizeof st);
    for (int c = 0; c < NSET; ++c) {
        fprintf(stderr, "render bench: setting %s\n", settings[c].name);
        st[c].r = make(s, irr, &settings[c].knobs);
        if (!st[c].r) return 3;
        st[c].ms = calloc((size_t)frames * (DM_PLAN_MAX_PASSES + 1), sizeof *st[c].ms);
    }
    for (int f = 0; f < frames; ++f)
        for (int c = 0; c < NSET; ++c) one_frame(&st[c], f);
    for (int c = 0; c < NSET; ++c) medians(&st[c], frames);
    char level[16];
    snprintf(level, sizeof level, "blur%d", st[0].plan.blur_levels - 1);
    errors e[NSET];
    for (int c = 0; c < NSET; ++c) compare(st[0].r, st[c].r, level, &e[c]);

    fprintf(md, "## Speed/accuracy settings (`dm_render_desc`), all effects, irradiance %d\n\n", irr);
    fprintf(md, "Error against `exact` on the same frame. Output: linear radiance before tonemapping, max / mean "
                "|Δ| over RGB (the reference's radiance peaks at %.2f); display: largest 8-bit step after "
                "tonemapping. Blur: %s (rgb / coverage) where the reference has coverage, max / mean |Δ| (its "
                "values peak at %.3f).\n\n",
            e[0].out_peak, level, e[0].level_peak);
    fprintf(md, "Frame ms: wall clock (what a viewer sees); CPU ms: process CPU time per frame, every llvmpipe "
                "thread summed (less sensitive to other users of the shared cores; 2 cores give at best half of "
                "it as wall time).\n\n");
    fprintf(md, "| setting | what | frame ms | CPU ms | irradiance | blur (10 passes) + diffusion | G-buffer + final | output max / mean |Δ| | "
                "display steps | blur max / mean |Δ| |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (int c = 0; c < NSET; ++c) {
        double irr_ms = 0, blur_ms = 0, final_ms = 0;
        for (int p = 0; p < st[c].plan.pass_count; ++p) {
            dm_pass_kind k = st[c].plan.passes[p].kind;
            if (k == DM_PASS_IRRADIANCE || k == DM_PASS_TS_GBUFFER) irr_ms += st[c].pass_ms[p];
            if (k == DM_PASS_BLUR_U || k == DM_PASS_BLUR_V || k == DM_PASS_DIFFUSION) blur_ms += st[c].pass_ms[p];
            if (k == DM_PASS_FINAL || k == DM_PASS_GBUFFER) final_ms += st[c].pass_ms[p];
        }
        fprintf(md, "| %s | %s | **%.1f** | %.0f | %.1f | %.1f | %.1f | %.2e / %.2e | %d | %.2e / %.2e |\n", settings[c].name,
                settings[c].what, st[c].frame_ms, st[c].cpu_ms, irr_ms, blur_ms, final_ms, e[c].out_max, e[c].out_mean,
                e[c].display_steps, e[c].level_max, e[c].level_mean);
    }
    fprintf(md, "\nPer pass, ms (same run):\n\n| pass |");
    for (int c = 0; c < NSET; ++c) fprintf(md, " %s |", settings[c].name);
    fprintf(md, "\n|---|");
    for (int c = 0; c < NSET; ++c) fprintf(md, "---:|");
    fprintf(md, "\n");
    /* the default's passes, each setting's by name ("–": not in its plan) */
    for (int p = 0; p < st[1].plan.pass_count; ++p) {
        const char *name = st[1].plan.passes[p].name;
        fprintf(md, "| %s |", name);
        for (int c = 0; c < NSET; ++c) {
            int q = dm_render_plan_find(&st[c].plan, name);
            if (q < 0) fprintf(md, " – |");
            else fprintf(md, " %.2f |", st[c].pass_ms[q]);
        }
        fprintf(md, "\n");
    }
    fprintf(md, "| **frame** |");
    for (int c = 0; c < NSET; ++c) fprintf(md, " **%.1f** |", st[c].frame_ms);
    fprintf(md, "\n\n");
    for (int c = 0; c < NSET; ++c) {
        free(st[c].ms);
        dm_renderer_destroy(st[c].r);
    }
    double default_1024 = st[1].frame_ms;

    /* ---- default settings, three irradiance sizes ---- */
    static const int sizes[3] = {512, 1024, 2048};
    run_state all[3];
    for (int i = 0; i < 3; ++i) {
        fprintf(stderr, "render bench: all effects, irradiance %d\n", sizes[i]);
        if (!run_alone(s, sizes[i], frames, &all[i])) return 3;
    }
    fprintf(md, "## Default settings, all effects: ms per pass\n\n| pass | 512 | 1024 | 2048 |\n|---|---:|---:|---:|\n");
    for (int p = 0; p < all[0].plan.pass_count; ++p)
        fprintf(md, "| %s | %.2f | %.2f | %.2f |\n", all[0].plan.passes[p].name, all[0].pass_ms[p], all[1].pass_ms[p],
                all[2].pass_ms[p]);
    fprintf(md, "| **frame** | **%.1f** | **%.1f** | **%.1f** |\n\n", all[0].frame_ms, all[1].frame_ms,
            all[2].frame_ms);

    /* ---- each effect alone, irradiance 1024 ---- */
    fprintf(md, "## Default settings, each effect alone (irradiance 1024)\n\n| effect | passes | frame ms | slowest pass |\n"
                "|---|---:|---:|---|\n");
    dm_scene keep = s->scene;
    for (int ef = 0; ef < DM_EFFECT_COUNT; ++ef) {
        for (int k = 0; k < DM_EFFECT_COUNT; ++k) s->scene.effects[k] = k == ef;
        fprintf(stderr, "render bench: %s alone\n", dm_effect_name((dm_effect)ef));
        run_state r1;
        if (!run_alone(s, 1024, frames, &r1)) return 3;
        int worst = 0;
        for (int p = 1; p < r1.plan.pass_count; ++p)
            if (r1.pass_ms[p] > r1.pass_ms[worst]) worst = p;
        fprintf(md, "| %s | %d | %.1f | %s %.1f |\n", dm_effect_name((dm_effect)ef), r1.plan.pass_count,
                r1.frame_ms, r1.plan.passes[worst].name, r1.pass_ms[worst]);
    }
    s->scene = keep;
    fclose(md);
    printf("render bench: wrote %s (default settings, all effects at 1024: %.1f ms/frame)\n", path, default_1024);
    source_close(s);
    dm_osmesa_destroy(ctx);
    return 0;
}
