/* bench/soak — does the renderer stay flat over a long run? Two runs on OSMesa (llvmpipe):
 *
 * 1. The library: 10,000 headless frames of the Lee Perry-Smith head
 *    (assets/scenes/lps.json, every effect) at a small size; every MOVE_EVERY frames the camera
 *    steps round the head (dm_renderer_set_scene, the viewer's path) and the lights turn, the
 *    frames between reuse the texture space (both the full frame and the reused one run, as in
 *    the viewer), the display is read back every 50 frames; the resident set size
 *    (/proc/self/statm) and glGetError sampled every SAMPLE frames.
 * 2. The tool: dermis-render on the same pack, --frames TOOL_FRAMES --timings (issue #31: its
 *    calloc'd timing record, filled a row of 392 bytes a frame, grew the RSS without plateau),
 *    its RSS sampled from /proc/PID/statm every 200 ms.
 *
 * Writes OUTDIR/soak.md: RSS and frame time at each sample, the growth over the second half,
 * GL errors, and the tool's RSS. Exit 1 when a frame failed, a GL error was seen, or either RSS
 * grew by more than LIMIT_KIB once warm (the library: over the second half of its frames,
 * 5,000 by default; the tool: from a third of its run to its end). glibc's heap settles in
 * the first ~3,000 frames (+0.1..0.8 MiB of free chunks it keeps, then flat:
 * docs/dermis-render.md, Memory and sizes); a leak of 32 bytes a frame is 156 KiB over 5,000
 * frames and fails, as the tool's old 392 bytes a frame (+484 KiB over its last 2,000) did.
 * DERMIS_SOAK_FRAMES overrides the frame count of
 * run 1. tests/render/test_render_soak.c is the short version make test runs. */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "common/bench_util.h"
#include "core/dm_cli.h"
#include "pack/dm_pack.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_pack.h"

enum { W = 160, H = 90, IRRADIANCE = 128, SHADOW = 256, SAMPLE = 500, READBACK = 50, MOVE_EVERY = 20 };
enum { LIMIT_KIB = 128, MAX_SAMPLES = 1024, TOOL_FRAMES = 3000, TOOL_SAMPLES_MAX = 8192 };

/* Resident set size in KiB of a process (the second field of /proc/PID/statm, in pages). */
static long rss_kib_of(const char *statm)
{
    FILE *f = fopen(statm, "r");
    if (!f) return -1;
    long size = 0, resident = 0;
    int got = fscanf(f, "%ld %ld", &size, &resident);
    fclose(f);
    return got == 2 ? resident * (sysconf(_SC_PAGESIZE) / 1024) : -1;
}

static long rss_kib(void)
{
    return rss_kib_of("/proc/self/statm");
}

/* Run 2: dermis-render PACK --frames TOOL_FRAMES --timings, its RSS every 200 ms. Returns the
 * growth from a third of the samples to the last (KiB); *first_kib, *last_kib, *samples say
 * what was seen; -1 when the tool failed. */
static long tool_soak(const char *bin, const char *pack, long *first_kib, long *last_kib, int *samples)
{
    char exe[512], frames[16], size[32], irr[16];
    snprintf(exe, sizeof exe, "%s/bin/dermis-render", bin);
    snprintf(frames, sizeof frames, "%d", TOOL_FRAMES);
    snprintf(size, sizeof size, "%dx%d", W, H);
    snprintf(irr, sizeof irr, "%d", IRRADIANCE);
    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        FILE *q = freopen("/dev/null", "w", stdout);
        (void)q;
        execl(exe, exe, pack, "--size", size, "--irradiance", irr, "--frames", frames, "--timings", "--quiet",
              (char *)NULL);
        _exit(127);
    }
    static long kib[TOOL_SAMPLES_MAX];
    char statm[64];
    snprintf(statm, sizeof statm, "/proc/%d/statm", (int)pid);
    int n = 0, st = 0;
    while (waitpid(pid, &st, WNOHANG) == 0) {
        long v = rss_kib_of(statm);
        if (v > 0 && n < TOOL_SAMPLES_MAX) kib[n++] = v;
        nanosleep(&(struct timespec){0, 200 * 1000 * 1000}, NULL);
        fprintf(stderr, "\rsoak: dermis-render --frames %d, RSS %ld KiB", TOOL_FRAMES, n ? kib[n - 1] : 0L);
    }
    fprintf(stderr, "\n");
    *samples = n;
    if (!WIFEXITED(st) || WEXITSTATUS(st) != 0 || n < 6) return -1;
    *first_kib = kib[n / 3], *last_kib = kib[n - 1];
    return kib[n - 1] - kib[n / 3];
}

typedef struct sample {
    int frame;
    long rss_kib;
    double ms_per_frame;
    int gl_errors;
} sample;

int main(int argc, char **argv)
{
    const char *outdir = argc > 1 ? argv[1] : "bench/results";
    int frames = 10000;
    const char *fe = getenv("DERMIS_SOAK_FRAMES");
    if (fe && atoi(fe) > 0) frames = atoi(fe);

    const char *bin = getenv("BUILD") ? getenv("BUILD") : "build/release";
    char pack_path[256], cmd[1024];
    snprintf(pack_path, sizeof pack_path, "/tmp/dermis-bench-soak-%ld.dpk", (long)getpid());
    snprintf(cmd, sizeof cmd, "%s/bin/dermis-pack assets/scenes/lps.json -o %s --quiet", bin, pack_path);
    if (system(cmd) != 0) {
        fprintf(stderr, "error: '%s' failed (run from the repository root)\n", cmd);
        return 3;
    }
    dm_error err = {0};
    dm_osmesa *ctx = NULL;
    dm_pack pack;
    dm_scene scene;
    dm_profile profile;
    dm_render_assets assets;
    if (dm_osmesa_create(&ctx, &err) != DM_OK || dm_pack_open(pack_path, &pack, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        unlink(pack_path);
        return 3;
    }
    if (dm_render_assets_from_pack(&pack, &scene, &profile, &assets, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        unlink(pack_path);
        return 3;
    }
    dm_render_desc d = {.width = W, .height = H, .irradiance_size = IRRADIANCE, .shadow_size = SHADOW,
                        .reuse_texture_space = true};
    dm_renderer *r = NULL;
    if (dm_renderer_create(&assets, &d, &r, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        unlink(pack_path);
        return 3;
    }
    uint8_t *rgba = malloc((size_t)W * H * 4);
    static sample samples[MAX_SAMPLES];
    int sample_count = 0, failed_frames = 0, gl_errors = 0;
    const dm_scene base = scene;
    double t_sample = dm_now_ms(), t0 = t_sample;
    for (int f = 1; f <= frames; ++f) {
        /* every MOVE_EVERY frames the camera steps round the head (radius and height kept)
         * and the lights turn; between, the texture space is reused */
        int step = f / MOVE_EVERY;
        if (f % MOVE_EVERY == 0) {
            double a = 2.0 * 3.14159265358979323846 * step / 72.0;
            float ex = base.camera_eye[0] - base.camera_target[0], ez = base.camera_eye[2] - base.camera_target[2];
            float rad = sqrtf(ex * ex + ez * ez);
            scene.camera_eye[0] = base.camera_target[0] + rad * (float)sin(a);
            scene.camera_eye[2] = base.camera_target[2] + rad * (float)cos(a);
            if (dm_renderer_set_scene(r, &scene, &err) != DM_OK) {
                fprintf(stderr, "error: frame %d: %s\n", f, err.detail);
                ++failed_frames;
                break;
            }
        }
        dm_frame_options fo = {.light_rotation_deg = (float)(step % 360)};
        if (dm_render_frame(r, &fo, &err) != DM_OK) {
            if (failed_frames++ < 5) fprintf(stderr, "error: frame %d: %s\n", f, err.detail);
        }
        if (f % READBACK == 0 && dm_renderer_read_display(r, rgba, &err) != DM_OK) {
            if (failed_frames++ < 5) fprintf(stderr, "error: frame %d readback: %s\n", f, err.detail);
        }
        if (f % SAMPLE == 0 || f == frames) {
            int e = 0;
            for (GLenum g = glGetError(); g != GL_NO_ERROR && e < 64; g = glGetError()) ++e;
            gl_errors += e;
            double now = dm_now_ms();
            if (sample_count < MAX_SAMPLES) {
                int since = sample_count ? f - samples[sample_count - 1].frame : f;
                samples[sample_count++] = (sample){f, rss_kib(), (now - t_sample) / since, e};
            }
            t_sample = now;
            fprintf(stderr, "\rsoak: frame %d/%d, RSS %ld KiB", f, frames, samples[sample_count - 1].rss_kib);
        }
    }
    double total_s = (dm_now_ms() - t0) / 1e3;
    fprintf(stderr, "\n");
    free(rgba);
    dm_renderer_destroy(r);
    dm_pack_close(&pack);
    dm_osmesa_destroy(ctx);
    long tool_first = 0, tool_last = 0;
    int tool_samples = 0;
    long tool_growth = tool_soak(bin, pack_path, &tool_first, &tool_last, &tool_samples);
    unlink(pack_path);
    bool tool_flat = tool_growth >= 0 && tool_growth <= LIMIT_KIB;

    /* growth once warm: from the first sample at or after half the frames to the last */
    int first = 0;
    while (first < sample_count - 1 && samples[first].frame < frames / 2) ++first;
    long growth = sample_count ? samples[sample_count - 1].rss_kib - samples[first].rss_kib : 0;
    long peak = 0;
    for (int k = 0; k < sample_count; ++k)
        if (samples[k].rss_kib > peak) peak = samples[k].rss_kib;
    bool flat = growth <= LIMIT_KIB;

    FILE *out = bench_open(outdir, "soak.md", "Soak: 10,000 headless frames, memory and GL errors");
    if (!out) return 4;
    fprintf(out,
            "The head (`assets/scenes/lps.json`, every effect) at %dx%d, irradiance %d², shadow maps %d², on "
            "OSMesa (llvmpipe); every %d frames the camera steps round the head (`dm_renderer_set_scene`, the "
            "viewer's path) and the lights turn, the frames between reuse the texture space; the display is read "
            "back every %d frames. RSS from `/proc/self/statm`, "
            "`glGetError` drained at each sample. `bench/soak.c`.\n\n",
            W, H, IRRADIANCE, SHADOW, MOVE_EVERY, READBACK);
    fprintf(out, "| frame | RSS (KiB) | ms per frame since the last sample | GL errors |\n|---:|---:|---:|---:|\n");
    for (int k = 0; k < sample_count; ++k)
        fprintf(out, "| %d | %ld | %.2f | %d |\n", samples[k].frame, samples[k].rss_kib, samples[k].ms_per_frame,
                samples[k].gl_errors);
    fprintf(out,
            "\n%d frames in %.1f s; failed frames %d; GL errors %d; RSS peak %ld KiB, growth after frame %d: "
            "%+ld KiB (limit %d KiB): %s.\n",
            frames, total_s, failed_frames, gl_errors, peak, samples[first].frame, growth, LIMIT_KIB,
            flat ? "flat" : "GROWING");
    if (tool_growth >= 0)
        fprintf(out,
                "\n`dermis-render` on the same pack, `--size %dx%d --irradiance %d --frames %d --timings`: RSS %ld KiB "
                "at a third of its run, %ld KiB at its end (%d samples, every 200 ms): %+ld KiB (limit %d KiB): %s.\n",
                W, H, IRRADIANCE, TOOL_FRAMES, tool_first, tool_last, tool_samples, tool_growth, LIMIT_KIB,
                tool_flat ? "flat" : "GROWING");
    else
        fprintf(out, "\n`dermis-render --frames %d --timings` failed.\n", TOOL_FRAMES);
    fclose(out);
    bool ok = flat && tool_flat && !gl_errors && !failed_frames;
    printf("soak: %d frames in %.1f s, RSS growth after frame %d: %+ld KiB (limit %d), GL errors %d, failed frames "
           "%d; dermis-render --frames %d --timings: RSS growth %+ld KiB: %s\n",
           frames, total_s, samples[first].frame, growth, LIMIT_KIB, gl_errors, failed_frames, TOOL_FRAMES, tool_growth,
           ok ? "ok" : "FAIL");
    if (!ok)
        fprintf(stderr, "error: soak: %s\n",
                !flat        ? "the library's RSS grew beyond the limit after warm-up (a leak: see soak.md)"
                : !tool_flat ? "dermis-render's RSS grew beyond the limit over its run (a leak: see soak.md)"
                             : "GL errors or failed frames");
    return ok ? 0 : 1;
}
