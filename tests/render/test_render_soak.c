/* The short soak (make test; the long one is bench/soak.c in make bench): memory stays flat
 * over a run of frames, in dermis-render and in the library, and the record of a run's
 * timings is resident before the first frame (issue #31: dermis-render --frames N --timings
 * grew 392 bytes a frame, its calloc'd timing record being filled a row a frame).
 *
 * Bounds: 64 KiB of growth after a warm-up quarter of the run. The old record grew 392 B a
 * frame, 350 KiB over the 900 frames after warm-up here; a page is 4 KiB, and what the
 * allocator keeps for itself is taken out in-process (malloc_trim before each sample). */
#define _GNU_SOURCE 1 /* malloc_trim */
#include <criterion/criterion.h>
#include <malloc.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "../common/render_fixture.h"
#include "render/dm_render_timing.h"

#define BIN DERMIS_BIN "/dermis-render"
enum { GROWTH_LIMIT_KIB = 64 };

/* Resident set of process pid in KiB (/proc/PID/statm), -1 when gone. */
static long rss_kib(pid_t pid)
{
    char path[64];
    snprintf(path, sizeof path, "/proc/%d/statm", (int)pid);
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    long size = 0, resident = -1;
    if (fscanf(f, "%ld %ld", &size, &resident) != 2) resident = -1;
    fclose(f);
    return resident < 0 ? -1 : resident * (sysconf(_SC_PAGESIZE) / 1024);
}

/* dermis-render --frames 1200 --timings on the small quad, its RSS sampled every 100 ms. */
Test(soak, dermis_render_rss_flat_over_a_run, .timeout = 60)
{
#ifdef __SANITIZE_ADDRESS__
    cr_skip_test("peak RSS means nothing under AddressSanitizer (shadow memory, quarantine): measured in release builds");
#endif
    pid_t pid = fork();
    cr_assert_geq(pid, 0);
    if (pid == 0) {
        FILE *q = freopen("/dev/null", "w", stdout);
        (void)q;
        execl(BIN, BIN, "--synthetic", "quad", "--size", "32x32", "--irradiance", "32", "--frames", "1200",
              "--timings", "--quiet", (char *)NULL);
        _exit(127);
    }
    enum { MAX = 4096 };
    static long kib[MAX];
    int n = 0, st = 0;
    while (waitpid(pid, &st, WNOHANG) == 0) {
        long v = rss_kib(pid);
        if (v > 0 && n < MAX) kib[n++] = v;
        nanosleep(&(struct timespec){0, 100 * 1000 * 1000}, NULL);
    }
    cr_assert(WIFEXITED(st) && WEXITSTATUS(st) == 0, "dermis-render failed");
    cr_assert_geq(n, 8, "only %d samples", n);
    long warm = kib[n / 4], last = kib[n - 1];
    cr_expect_leq(last - warm, GROWTH_LIMIT_KIB, "RSS grew %ld KiB after warm-up (%ld -> %ld KiB over %d samples)",
                  last - warm, warm, last, n - n / 4);
}

/* The library as the viewer drives it: camera moves (dm_renderer_set_scene), texture space
 * reused between them, read-backs; RSS after malloc_trim every 100 frames. */
Test(soak, renderer_rss_flat_over_frames, .timeout = 60)
{
#ifdef __SANITIZE_ADDRESS__
    cr_skip_test("peak RSS means nothing under AddressSanitizer (shadow memory, quarantine): measured in release builds");
#endif
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_QUAD});
    open_renderer_desc(&f, (dm_render_desc){.width = 32, .height = 32, .irradiance_size = 32, .shadow_size = 64,
                                            .reuse_texture_space = true});
    dm_error err = {0};
    dm_scene scene = f.synth->scene;
    uint8_t rgba[32 * 32 * 4];
    long kib[8];
    for (int s = 0, frame = 0; s < 8; ++s) {
        for (int k = 0; k < 100; ++k, ++frame) {
            if (frame % 10 == 0) {
                scene.camera_eye[0] += 0.01f;
                cr_assert_eq(dm_renderer_set_scene(f.r, &scene, &err), DM_OK, "%s", err.detail);
            }
            cr_assert_eq(dm_render_frame(f.r, &(dm_frame_options){.light_rotation_deg = (float)(frame / 10)}, &err), DM_OK,
                         "%s", err.detail);
            if (frame % 25 == 0) cr_assert_eq(dm_renderer_read_display(f.r, rgba, &err), DM_OK, "%s", err.detail);
        }
        malloc_trim(0);
        kib[s] = rss_kib(getpid());
    }
    cr_expect_leq(kib[7] - kib[2], GROWTH_LIMIT_KIB, "RSS grew %ld KiB from frame 300 to 800 (%ld -> %ld KiB)",
                  kib[7] - kib[2], kib[2], kib[7]);
    close_fixture(&f);
}

/* The timing record of 100,000 frames (37 MiB) is resident once init returns, and filling it
 * adds nothing. */
Test(soak, timing_record_resident_before_the_first_frame, .timeout = 60)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_QUAD});
    open_renderer_desc(&f, (dm_render_desc){.width = 16, .height = 16, .irradiance_size = 16, .shadow_size = 64,
                                            .timings = true});
    frame(&f, DM_VIEW_FINAL, 0);
    enum { FRAMES = 100000 };
    dm_error err = {0};
    dm_render_timing_log log;
    long before = rss_kib(getpid());
    cr_assert_eq(dm_render_timing_log_init(&log, FRAMES, true, &err), DM_OK, "%s", err.detail);
    long after_init = rss_kib(getpid());
    long record_kib = (long)((size_t)FRAMES * (DM_PLAN_MAX_PASSES + 2) * sizeof(double) / 1024);
    cr_expect_geq(after_init - before, record_kib * 9 / 10, "init made %ld KiB resident of the record's %ld KiB",
                  after_init - before, record_kib);
    for (int k = 0; k < FRAMES; ++k) dm_render_timing_log_add(&log, f.r);
    long filled = rss_kib(getpid());
    cr_expect_leq(filled - after_init, GROWTH_LIMIT_KIB, "filling the record grew RSS by %ld KiB", filled - after_init);
    cr_expect_eq(log.frame_count, FRAMES);
    cr_expect_geq(dm_render_timing_log_median(&log, -1), 0.0);
    dm_render_timing_log_free(&log);
    close_fixture(&f);
}
