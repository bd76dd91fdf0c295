/* dm_renderer_blit_display: the display picture in the caller's framebuffer, byte for byte
 * at the output size (tonemapped: from the display target; otherwise built on the CPU),
 * only inside the rectangle, scaled with linear filtering, and the caller's GL state back. */
#include <criterion/criterion.h>
#include <stdlib.h>
#include <string.h>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "../common/render_fixture.h"
#include "render/dm_render.h"

enum { W = 96, H = 64 };

/* The caller's own framebuffer: one RGBA8 colour renderbuffer, cleared to a colour no
 * picture pixel has (alpha 0: the display's alpha is 255 everywhere). */
typedef struct caller_fbo {
    GLuint fbo, rb;
    int width, height;
} caller_fbo;

static const uint8_t clear_rgba[4] = {64, 128, 191, 0};

static caller_fbo make_fbo(int width, int height)
{
    caller_fbo c = {0, 0, width, height};
    glGenRenderbuffers(1, &c.rb);
    glBindRenderbuffer(GL_RENDERBUFFER, c.rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glGenFramebuffers(1, &c.fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, c.fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, c.rb);
    cr_assert_eq(glCheckFramebufferStatus(GL_FRAMEBUFFER), GL_FRAMEBUFFER_COMPLETE);
    glClearColor(clear_rgba[0] / 255.0f, clear_rgba[1] / 255.0f, clear_rgba[2] / 255.0f, clear_rgba[3] / 255.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    cr_assert_eq(glGetError(), GL_NO_ERROR);
    return c;
}

static void free_fbo(caller_fbo *c)
{
    glDeleteFramebuffers(1, &c->fbo);
    glDeleteRenderbuffers(1, &c->rb);
}

static uint8_t *read_fbo(const caller_fbo *c)
{
    uint8_t *px = malloc((size_t)c->width * c->height * 4);
    glBindFramebuffer(GL_FRAMEBUFFER, c->fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, c->width, c->height, GL_RGBA, GL_UNSIGNED_BYTE, px);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    cr_assert_eq(glGetError(), GL_NO_ERROR);
    return px;
}

static uint8_t *read_display(fixture *f)
{
    uint8_t *px = malloc((size_t)W * H * 4);
    dm_error err = {0};
    cr_assert_eq(dm_renderer_read_display(f->r, px, &err), DM_OK, "%s", err.detail);
    return px;
}

static void open_scene(fixture *f, bool tonemap)
{
    open_synth(f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 32, .sphere_rings = 24});
    f->synth->scene.effects[DM_EFFECT_TONEMAP] = tonemap;
    /* bright enough that the untonemapped picture is not clamped to white everywhere */
    f->synth->scene.lights[0].intensity = 0.7f;
    open_renderer(f, W, H, 128);
    frame(f, DM_VIEW_FINAL, 0);
    bool has_tonemap = dm_render_plan_find(dm_renderer_plan(f->r), "tonemap") >= 0;
    cr_assert_eq(has_tonemap, tonemap, "the plan %s a tonemap pass", has_tonemap ? "has" : "lacks");
}

/* A same-size blit with other framebuffers bound for reading and drawing and a 1x1 scissor
 * box on: the picture arrives whole, byte for byte, and the bindings and enables are back. */
static void expect_exact_copy(fixture *f, const char *what)
{
    caller_fbo dst = make_fbo(W, H), other_read = make_fbo(4, 4), other_draw = make_fbo(4, 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, other_read.fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, other_draw.fbo);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, 1, 1);
    dm_error err = {0};
    cr_assert_eq(dm_renderer_blit_display(f->r, dst.fbo, 0, 0, W, H, &err), DM_OK, "%s: %s", what, err.detail);
    GLint read_bound = -1, draw_bound = -1;
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_bound);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_bound);
    cr_expect_eq((GLuint)read_bound, other_read.fbo, "%s: read framebuffer %d after the blit, expected %u", what,
                 read_bound, other_read.fbo);
    cr_expect_eq((GLuint)draw_bound, other_draw.fbo, "%s: draw framebuffer %d after the blit, expected %u", what,
                 draw_bound, other_draw.fbo);
    cr_expect(glIsEnabled(GL_SCISSOR_TEST), "%s: the scissor test was left off", what);
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    uint8_t *got = read_fbo(&dst), *want = read_display(f);
    size_t diff = 0, first = 0;
    for (size_t i = 0; i < (size_t)W * H * 4; ++i)
        if (got[i] != want[i] && diff++ == 0) first = i;
    cr_expect_eq(diff, 0, "%s: %zu bytes differ from dm_renderer_read_display (first: byte %zu, %u, expected %u)",
                 what, diff, first, got[first], want[first]);
    size_t lit = 0; /* the comparison means something: the head is there */
    for (size_t i = 0; i < (size_t)W * H; ++i) lit += want[i * 4] > 8;
    cr_expect_gt(lit, (size_t)W * H / 10, "%s: only %zu pixels lit", what, lit);
    free(got), free(want);
    free_fbo(&dst), free_fbo(&other_read), free_fbo(&other_draw);
}

Test(render_blit, tonemapped_copy_equals_read_display)
{
    fixture f;
    open_scene(&f, true);
    expect_exact_copy(&f, "tonemapped");
    close_fixture(&f);
}

/* Not tonemapped: built on the CPU into the renderer's texture, which a later frame refills. */
Test(render_blit, untonemapped_copy_equals_read_display_frame_after_frame)
{
    fixture f;
    open_scene(&f, false);
    expect_exact_copy(&f, "linear, first frame");
    dm_error err = {0};
    cr_assert_eq(dm_render_frame(f.r, &(dm_frame_options){.light_rotation_deg = 90}, &err), DM_OK, "%s", err.detail);
    expect_exact_copy(&f, "linear, light turned");
    close_fixture(&f);
}

/* Into a rectangle inside a larger framebuffer: at the output size at an offset (exact
 * there), and halved (each pixel the mean of a 2x2 block: linear filtering with the sample
 * point on the block's centre; ±1 for rounding). Every pixel outside keeps the clear colour. */
static void rectangle_case(bool tonemap)
{
    fixture f;
    open_scene(&f, tonemap);
    uint8_t *want = read_display(&f);
    static const struct {
        int x, y, w, h;
    } rects[] = {{7, 5, W, H}, {3, 11, W / 2, H / 2}};
    for (int k = 0; k < 2; ++k) {
        int x0 = rects[k].x, y0 = rects[k].y, w = rects[k].w, h = rects[k].h;
        caller_fbo dst = make_fbo(W + 20, H + 20);
        dm_error err = {0};
        cr_assert_eq(dm_renderer_blit_display(f.r, dst.fbo, x0, y0, w, h, &err), DM_OK, "%s", err.detail);
        uint8_t *got = read_fbo(&dst);
        size_t outside_changed = 0, inside_off = 0;
        for (int j = 0; j < dst.height; ++j)
            for (int i = 0; i < dst.width; ++i) {
                const uint8_t *p = got + ((size_t)j * dst.width + i) * 4;
                bool inside = i >= x0 && i < x0 + w && j >= y0 && j < y0 + h;
                if (!inside) {
                    outside_changed += memcmp(p, clear_rgba, 4) != 0;
                    continue;
                }
                int si = i - x0, sj = j - y0;
                for (int c = 0; c < 4; ++c) {
                    int ref;
                    if (w == W) {
                        ref = want[((size_t)sj * W + si) * 4 + c];
                    } else {
                        int sum = 0;
                        for (int dj = 0; dj < 2; ++dj)
                            for (int di = 0; di < 2; ++di)
                                sum += want[((size_t)(2 * sj + dj) * W + 2 * si + di) * 4 + c];
                        ref = sum / 4;
                    }
                    int tol = w == W ? 0 : 1;
                    inside_off += abs(p[c] - ref) > tol;
                }
            }
        cr_expect_eq(outside_changed, 0, "%s, %dx%d at (%d, %d): %zu pixels outside the rectangle changed",
                     tonemap ? "tonemapped" : "linear", w, h, x0, y0, outside_changed);
        cr_expect_eq(inside_off, 0, "%s, %dx%d at (%d, %d): %zu values inside differ from the %s picture",
                     tonemap ? "tonemapped" : "linear", w, h, x0, y0, inside_off,
                     w == W ? "displayed" : "2x2-averaged");
        free(got);
        free_fbo(&dst);
    }
    free(want);
    close_fixture(&f);
}

Test(render_blit, rectangle_inside_larger_fbo_tonemapped)
{
    rectangle_case(true);
}

Test(render_blit, rectangle_inside_larger_fbo_linear)
{
    rectangle_case(false);
}

Test(render_blit, bad_arguments_refused)
{
    fixture f;
    open_synth(&f, (dm_synth_options){.shape = DM_SYNTH_SPHERE, .sphere_segments = 16, .sphere_rings = 12});
    open_renderer(&f, W, H, 64);
    caller_fbo dst = make_fbo(W, H);
    dm_error err = {0};
    cr_expect_eq(dm_renderer_blit_display(f.r, dst.fbo, 0, 0, W, H, &err), DM_ERR_INVALID_ARGUMENT,
                 "a blit before any frame was accepted");
    cr_expect(strstr(err.detail, "no frame"), "message: %s", err.detail);
    frame(&f, DM_VIEW_FINAL, 0);
    static const struct {
        int w, h;
        const char *name;
    } bad[] = {{0, H, "width 0"}, {W, -3, "height -3"}};
    for (int k = 0; k < 2; ++k) {
        err = (dm_error){0};
        cr_expect_eq(dm_renderer_blit_display(f.r, dst.fbo, 0, 0, bad[k].w, bad[k].h, &err), DM_ERR_INVALID_ARGUMENT,
                     "%s was accepted", bad[k].name);
        cr_expect(strstr(err.detail, bad[k].name), "message for %s: %s", bad[k].name, err.detail);
    }
    err = (dm_error){0};
    cr_expect_eq(dm_renderer_blit_display(f.r, 1, INT32_MAX - 8, 0, 16, 16, &err), DM_ERR_INVALID_ARGUMENT,
                 "a rectangle ending past INT_MAX was accepted");
    err = (dm_error){0};
    cr_expect_eq(dm_renderer_blit_display(f.r, dst.fbo + 1000, 0, 0, W, H, &err), DM_ERR_INVALID_ARGUMENT,
                 "framebuffer %u (never made) was accepted", dst.fbo + 1000);
    cr_expect(strstr(err.detail, "not a framebuffer"), "message: %s", err.detail);
    /* nothing was written by the refused calls */
    uint8_t *got = read_fbo(&dst);
    size_t changed = 0;
    for (size_t i = 0; i < (size_t)W * H; ++i) changed += memcmp(got + i * 4, clear_rgba, 4) != 0;
    cr_expect_eq(changed, 0, "refused calls changed %zu pixels", changed);
    free(got);
    cr_expect_eq(glGetError(), GL_NO_ERROR, "refused calls left a GL error");
    free_fbo(&dst);
    close_fixture(&f);
}
