/* bench/render — median ms per pass and per frame of the skin renderer on OSMesa
 * (llvmpipe): irradiance 512/1024/2048 at 1280x720 with all effects, and each effect alone
 * at 1024. Synthetic UV sphere (18,240 triangles) until packs of the head exist.
 * Writes OUTDIR/render.md. DERMIS_BENCH_FRAMES overrides the frame count (default 5). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>
#include <unistd.h>

#include "core/dm_cli.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_synth.h"

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

typedef struct result {
    dm_render_plan plan;
    double pass_ms[DM_PLAN_MAX_PASSES], frame_ms;
} result;

static int run(dm_synth *s, int irr, int frames, result *out)
{
    dm_error err = {0};
    dm_renderer *r = NULL;
    dm_render_desc d = {.width = 1280, .height = 720, .irradiance_size = irr, .timings = true};
    if (dm_renderer_create(&s->assets, &d, &r, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return 0;
    }
    double *ms = calloc((size_t)frames * (DM_PLAN_MAX_PASSES + 1), sizeof *ms);
    dm_frame_options fo = {0};
    if (dm_render_frame(r, &fo, &err) != DM_OK) { /* warm-up: shader JIT, first uploads */
        fprintf(stderr, "error: %s\n", err.detail);
        free(ms);
        dm_renderer_destroy(r);
        return 0;
    }
    for (int f = 0; f < frames; ++f) {
        dm_render_frame(r, &fo, &err);
        dm_renderer_last_timings(r, ms + (size_t)f * (DM_PLAN_MAX_PASSES + 1),
                                 ms + (size_t)f * (DM_PLAN_MAX_PASSES + 1) + DM_PLAN_MAX_PASSES);
    }
    out->plan = *dm_renderer_plan(r);
    double col[1024];
    for (int i = 0; i <= out->plan.pass_count; ++i) {
        int slot = i < out->plan.pass_count ? i : DM_PLAN_MAX_PASSES;
        for (int f = 0; f < frames && f < 1024; ++f) col[f] = ms[(size_t)f * (DM_PLAN_MAX_PASSES + 1) + slot];
        double m = median(col, frames < 1024 ? frames : 1024);
        if (i < out->plan.pass_count) out->pass_ms[i] = m;
        else out->frame_ms = m;
    }
    free(ms);
    dm_renderer_destroy(r);
    return 1;
}

int main(int argc, char **argv)
{
    const char *outdir = argc > 1 ? argv[1] : "bench/results";
    int frames = getenv("DERMIS_BENCH_FRAMES") ? atoi(getenv("DERMIS_BENCH_FRAMES")) : 5;
    if (frames < 1) frames = 1;
    dm_error err = {0};
    dm_osmesa *ctx = NULL;
    dm_synth *s = NULL;
    if (dm_osmesa_create(&ctx, &err) != DM_OK || dm_synth_create(&(dm_synth_options){0}, &s, &err) != DM_OK) {
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
    struct utsname u;
    uname(&u);
    char cpu[256] = "unknown";
    FILE *ci = fopen("/proc/cpuinfo", "r");
    char line[512];
    while (ci && fgets(line, sizeof line, ci))
        if (!strncmp(line, "model name", 10)) {
            char *c = strchr(line, ':');
            if (c) snprintf(cpu, sizeof cpu, "%s", c + 2);
            cpu[strcspn(cpu, "\n")] = 0;
            break;
        }
    if (ci) fclose(ci);
    double load[3] = {0, 0, 0};
    FILE *la = fopen("/proc/loadavg", "r");
    if (la) {
        if (fscanf(la, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) load[0] = -1;
        fclose(la);
    }
    const char *lp = getenv("LP_NUM_THREADS");
    fprintf(md, "# Renderer timings (llvmpipe)\n\n");
    fprintf(md, "Machine: `%s %s %s %s`, CPU: %s, %ld cores online, LP_NUM_THREADS=%s, load average at start %.2f.\n",
            u.sysname, u.nodename, u.release, u.machine, cpu, sysconf(_SC_NPROCESSORS_ONLN), lp ? lp : "(default)",
            load[0]);
    fprintf(md, "Synthetic UV sphere, %d triangles, 1280x720, shadow map 1024, 7 taps; median of %d frames after "
                "one warm-up; CPU clock around glFinish per pass.\n\n", s->triangle_count, frames);

    /* all effects, three irradiance sizes */
    static const int sizes[3] = {512, 1024, 2048};
    result all[3];
    for (int i = 0; i < 3; ++i) {
        fprintf(stderr, "render bench: all effects, irradiance %d\n", sizes[i]);
        if (!run(s, sizes[i], frames, &all[i])) return 3;
    }
    fprintf(md, "## All effects: ms per pass\n\n| pass | 512 | 1024 | 2048 |\n|---|---:|---:|---:|\n");
    for (int p = 0; p < all[0].plan.pass_count; ++p)
        fprintf(md, "| %s | %.2f | %.2f | %.2f |\n", all[0].plan.passes[p].name, all[0].pass_ms[p], all[1].pass_ms[p],
                all[2].pass_ms[p]);
    fprintf(md, "| **frame** | **%.1f** | **%.1f** | **%.1f** |\n\n", all[0].frame_ms, all[1].frame_ms,
            all[2].frame_ms);

    /* each effect alone, irradiance 1024 */
    fprintf(md, "## Each effect alone (irradiance 1024)\n\n| effect | passes | frame ms | slowest pass |\n"
                "|---|---:|---:|---|\n");
    dm_scene keep = s->scene;
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) {
        for (int k = 0; k < DM_EFFECT_COUNT; ++k) s->scene.effects[k] = k == e;
        fprintf(stderr, "render bench: %s alone\n", dm_effect_name((dm_effect)e));
        result r;
        if (!run(s, 1024, frames, &r)) return 3;
        int worst = 0;
        for (int p = 1; p < r.plan.pass_count; ++p)
            if (r.pass_ms[p] > r.pass_ms[worst]) worst = p;
        fprintf(md, "| %s | %d | %.1f | %s %.1f |\n", dm_effect_name((dm_effect)e), r.plan.pass_count,
                r.frame_ms, r.plan.passes[worst].name, r.pass_ms[worst]);
    }
    s->scene = keep;
    fclose(md);
    printf("render bench: wrote %s (all effects at 1024: %.1f ms/frame)\n", path, all[1].frame_ms);
    dm_synth_free(s);
    dm_osmesa_destroy(ctx);
    return 0;
}
