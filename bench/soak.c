/* bench/soak — does the renderer stay flat over a long run? 10,000 headless frames of the
 * Lee Perry-Smith head (assets/scenes/lps.json, every effect) at a small size on OSMesa,
 * every MOVE_EVERY frames the camera steps round the head (dm_renderer_set_scene, the viewer's
 * path) and the lights turn, the frames between reuse the texture space (both the full frame
 * and the reused one run, as in the viewer), the display is read back every 50 frames; the resident set size
 * (/proc/self/statm) and glGetError sampled every SAMPLE frames.
 *
 * Writes OUTDIR/soak.md: RSS and frame time at each sample, the growth from the first
 * sample after warm-up to the last, GL errors. Exit 1 when a frame failed, a GL error was
 * seen, or the RSS grew by more than LIMIT_KIB after warm-up (the issue measured 128 KiB
 * over 600 frames at 640x360: allocator noise; a leak of even 64 bytes a frame is 625 KiB
 * over 10,000 frames and fails). DERMIS_SOAK_FRAMES overrides the frame count. */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/bench_util.h"
#include "core/dm_cli.h"
#include "core/dm_pack.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_pack.h"

enum { W = 160, H = 90, IRRADIANCE = 128, SHADOW = 256, SAMPLE = 500, WARMUP = 500, READBACK = 50, MOVE_EVERY = 20 };
enum { LIMIT_KIB = 512, MAX_SAMPLES = 1024 };

/* Resident set size in KiB (the second field of /proc/self/statm, in pages). */
static long rss_kib(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    if (!f) return -1;
    long size = 0, resident = 0;
    int got = fscanf(f, "%ld %ld", &size, &resident);
    fclose(f);
    return got == 2 ? resident * (sysconf(_SC_PAGESIZE) / 1024) : -1;
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
    unlink(pack_path); /* mapped: the file is no longer needed by name */
    if (dm_render_assets_from_pack(&pack, &scene, &profile, &assets, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return 3;
    }
    dm_render_desc d = {.width = W, .height = H, .irradiance_size = IRRADIANCE, .shadow_size = SHADOW,
                        .reuse_texture_space = true};
    dm_renderer *r = NULL;
    if (dm_renderer_create(&assets, &d, &r, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
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

    /* growth after warm-up: from the first sample at or after WARMUP frames to the last */
    int first = 0;
    while (first < sample_count - 1 && samples[first].frame < WARMUP) ++first;
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
    fclose(out);
    printf("soak: %d frames in %.1f s, RSS growth after frame %d: %+ld KiB (limit %d), GL errors %d, failed frames "
           "%d: %s\n",
           frames, total_s, samples[first].frame, growth, LIMIT_KIB, gl_errors, failed_frames,
           flat && !gl_errors && !failed_frames ? "ok" : "FAIL");
    return flat && !gl_errors && !failed_frames ? 0 : 1;
}
