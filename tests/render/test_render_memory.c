/* The renderer's memory estimate (render/dm_render_memory.h) against the peak resident set
 * of dermis-render at a few sizes, the refusals of what does not fit (memory, the OpenGL's
 * limits) and the GL limits themselves (issue #31: --irradiance 8192 took 13 GB without a
 * word; --size 16384x16384 failed as "framebuffer incomplete"). */
#define _DEFAULT_SOURCE 1 /* wait4 */
#include <criterion/criterion.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "../common/tmpdir.h"
#include "core/dm_memory.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_memory.h"
#include "render/dm_render_synth.h"

#define BIN DERMIS_BIN "/dermis-render"

/* Runs argv to its end; returns its peak RSS in bytes (wait4's rusage), its exit code in *code. */
static uint64_t child_peak_rss(char *const argv[], int *code)
{
    pid_t pid = fork();
    cr_assert_geq(pid, 0);
    if (pid == 0) {
        FILE *q = freopen("/dev/null", "w", stdout);
        (void)q;
        execv(argv[0], argv);
        _exit(127);
    }
    int st = 0;
    struct rusage ru;
    cr_assert_eq(wait4(pid, &st, 0, &ru), pid);
    *code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return (uint64_t)ru.ru_maxrss * 1024u;
}

/* The estimate for dermis-render --synthetic SHAPE --size WxH --irradiance N (the tool's own
 * assets: dm_synth_create with its defaults), software OpenGL. */
static uint64_t estimate(dm_synth_shape shape, int w, int h, int n)
{
    dm_error err = {0};
    dm_synth *s = NULL;
    cr_assert_eq(dm_synth_create(&(dm_synth_options){.shape = shape}, &s, &err), DM_OK, "%s", err.detail);
    dm_render_memory m;
    dm_render_desc d = {.width = w, .height = h, .irradiance_size = n};
    cr_assert_eq(dm_render_memory_estimate(&s->assets, &d, true, &m, &err), DM_OK, "%s", err.detail);
    dm_synth_free(s);
    return m.total_size;
}

/* Within [0.8, 1.5] of the measured peak: the estimate counts every large buffer; what it
 * does not count (the allocator's slack, llvmpipe's per-thread tiles, PNG encoding) is small,
 * and the driver's constant was measured at the smallest size. */
static void check_size(const char *shape, int w, int h, int n)
{
    char dir[64], out[128], size[32], irr[16];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(out, sizeof out, "%s/o.png", dir);
    snprintf(size, sizeof size, "%dx%d", w, h);
    snprintf(irr, sizeof irr, "%d", n);
    char *argv[] = {BIN, "--synthetic", (char *)shape, "--size", size, "--irradiance", irr, "-o", out, "--quiet", NULL};
    int code = -1;
    uint64_t peak = child_peak_rss(argv, &code);
    cr_assert_eq(code, 0, "dermis-render --synthetic %s --size %s --irradiance %s", shape, size, irr);
    uint64_t est = estimate(strcmp(shape, "quad") ? DM_SYNTH_SPHERE : DM_SYNTH_QUAD, w, h, n);
    double ratio = (double)est / (double)peak;
    fprintf(stderr, "memory: %s %dx%d irradiance %d: estimate %.1f MiB, peak RSS %.1f MiB, ratio %.2f\n", shape, w, h,
            n, est / 1048576.0, peak / 1048576.0, ratio);
    cr_expect(ratio >= 0.8 && ratio <= 1.5, "%s %dx%d irradiance %d: estimate %.1f MiB, measured %.1f MiB (%.2f)",
              shape, w, h, n, est / 1048576.0, peak / 1048576.0, ratio);
}

Test(render_memory, estimate_within_its_factor_of_the_peak, .timeout = 240)
{
#ifdef __SANITIZE_ADDRESS__
    cr_skip_test("peak RSS means nothing under AddressSanitizer (shadow memory, quarantine): measured in release builds");
#endif
    check_size("quad", 64, 36, 64);
    check_size("sphere", 64, 36, 512);
    check_size("sphere", 64, 36, 1024);
    check_size("sphere", 1280, 720, 256);
    check_size("sphere", 2048, 2048, 64);
}

/* Runs a shell command; its exit code, its stderr in *text (malloc'd). */
static int run_text(const char *cmd, char **text)
{
    char dir[64], log[128];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(log, sizeof log, "%s/log", dir);
    int rc = test_run(cmd, log);
    *text = test_slurp(log);
    cr_assert(*text);
    return rc;
}

/* The reproduction: an 8192 irradiance where 8000 MiB are available is refused at
 * once, with the estimate, what is available, and what to lower. */
Test(render_memory, irradiance_8192_refused_with_both_numbers, .timeout = 60)
{
    char *text = NULL;
    int rc = run_text("DERMIS_MEM_AVAILABLE_MB=8000 " BIN " --synthetic sphere --size 64x36 --irradiance 8192 -o "
                      "/tmp/dermis-never-written.png",
                      &text);
    cr_expect_eq(rc, 3, "%s", text);
    cr_expect(strstr(text, "irradiance 8192 needs about ") && strstr(text, "GiB of memory"), "%s", text);
    cr_expect(strstr(text, "more than the 7.81 GiB available (DERMIS_MEM_AVAILABLE_MB)"), "%s", text);
    cr_expect(strstr(text, "lower the irradiance size (--irradiance)"), "%s", text);
    cr_expect(strstr(text, "texture space ") && strstr(text, "blur on the CPU "), "%s", text);
    cr_expect_neq(access("/tmp/dermis-never-written.png", F_OK), 0);
    free(text);
    /* what fits goes on */
    rc = run_text("DERMIS_MEM_AVAILABLE_MB=8000 " BIN " --synthetic sphere --size 64x36 --irradiance 256 --timings", &text);
    cr_expect_eq(rc, 0, "%s", text);
    free(text);
}

/* The estimate's numbers: 8192 on the sphere is ~19 GiB, and the library refuses it against
 * desc.memory_available_size before making anything (DM_ERR_OUT_OF_MEMORY). */
Test(render_memory, library_refuses_against_the_given_amount)
{
    uint64_t est = estimate(DM_SYNTH_SPHERE, 64, 36, 8192);
    cr_expect(est > ((uint64_t)17 << 30) && est < ((uint64_t)21 << 30), "%.2f GiB", est / 1073741824.0);
    dm_error err = {0};
    dm_osmesa *ctx = NULL;
    dm_synth *s = NULL;
    cr_assert_eq(dm_osmesa_create(&ctx, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_synth_create(&(dm_synth_options){0}, &s, &err), DM_OK, "%s", err.detail);
    dm_renderer *r = NULL;
    dm_render_desc d = {.width = 64, .height = 36, .irradiance_size = 1024, .memory_available_size = (uint64_t)200 << 20};
    cr_expect_eq(dm_renderer_create(&s->assets, &d, &r, &err), DM_ERR_OUT_OF_MEMORY);
    cr_expect(strstr(err.detail, "more than the 200 MiB available (dm_render_desc.memory_available_size)"), "%s",
              err.detail);
    cr_expect_null(r);
    d.memory_available_size = UINT64_MAX; /* no check */
    cr_expect_eq(dm_renderer_create(&s->assets, &d, &r, &err), DM_OK, "%s", err.detail);
    dm_renderer_destroy(r);
    dm_synth_free(s);
    dm_osmesa_destroy(ctx);
}

/* The OpenGL's limits, and the sizes beyond them refused by name (not "framebuffer
 * incomplete"): here llvmpipe makes RGBA32F textures of up to 16384 per side but not of more
 * than its bytes per texture, so 16384x16384 RGBA32F (4 GiB) is refused by the proxy test. */
Test(render_memory, sizes_beyond_the_gl_refused_by_name, .timeout = 60)
{
    dm_error err = {0};
    dm_osmesa *ctx = NULL;
    cr_assert_eq(dm_osmesa_create(&ctx, &err), DM_OK, "%s", err.detail);
    dm_render_gl_limits L;
    dm_render_gl_limits_get(&L);
    cr_expect_geq(L.max_texture_size, 4096);
    cr_expect_geq(L.max_renderbuffer_size, 4096);
    cr_expect(L.max_viewport[0] >= 4096 && L.max_viewport[1] >= 4096);
    cr_expect(dm_render_gl_can_make(GL_RGBA32F, 1024, 1024));
    cr_expect(!dm_render_gl_can_make(GL_RGBA32F, L.max_texture_size + 1, 16), "beyond GL_MAX_TEXTURE_SIZE");
    int sq = dm_render_gl_largest_square(GL_RGBA32F, L.max_texture_size);
    cr_expect(sq >= 1024 && sq <= L.max_texture_size, "%d", sq);
    cr_expect(dm_render_gl_can_make(GL_RGBA32F, sq, sq));
    if (sq < L.max_texture_size) cr_expect(!dm_render_gl_can_make(GL_RGBA32F, sq + 1, sq + 1));
    dm_osmesa_destroy(ctx);
    fprintf(stderr, "gl limits: GL_MAX_TEXTURE_SIZE %d, GL_MAX_RENDERBUFFER_SIZE %d, GL_MAX_VIEWPORT_DIMS %dx%d, "
                    "largest RGBA32F square %d\n",
            L.max_texture_size, L.max_renderbuffer_size, L.max_viewport[0], L.max_viewport[1], sq);
    if (sq == L.max_texture_size) return; /* a GL that makes any size: nothing to refuse */
    char cmd[256], *text = NULL;
    snprintf(cmd, sizeof cmd, BIN " --synthetic sphere --size %dx%d --irradiance 64 -o /tmp/dermis-never-written.png",
             L.max_texture_size, L.max_texture_size);
    int rc = run_text(cmd, &text);
    cr_expect_eq(rc, 3, "%s", text);
    cr_expect(strstr(text, "does not make its screen target") && strstr(text, "RGBA32F"), "%s", text);
    char want[64];
    snprintf(want, sizeof want, "the largest square it makes in that format is %dx%d", sq, sq);
    cr_expect(strstr(text, want), "'%s' not in: %s", want, text);
    cr_expect(!strstr(text, "framebuffer incomplete"), "%s", text);
    free(text);
}
