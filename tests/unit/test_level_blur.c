/* test_level_blur.c — core/dm_level_blur.h, the texture-space blur pass on the CPU, against
 * an independent double-precision evaluation of the shader's formula (shaders/blur.glsl:
 * bilinear taps with a zero border, the stretch read bilinearly with clamp-to-edge). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_level_blur.h"

/* image: w × h RGBA in a padded buffer, values from a fixed pseudo-random sequence */
typedef struct image {
    float *buf, *px;
    int w, h;
} image;

static image make(int w, int h, unsigned seed)
{
    image im = {calloc(dm_level_blur_floats(w, h), sizeof(float)), NULL, w, h};
    cr_assert_not_null(im.buf);
    im.px = dm_level_blur_frame(im.buf, w, h);
    long stride = dm_level_blur_stride(w);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < 4 * w; ++x) {
            seed = seed * 1664525u + 1013904223u;
            im.px[y * stride + x] = (float)(seed >> 8) / 16777216.0f * 3.0f;
        }
    return im;
}

static double texel(const image *im, int x, int y, int c)
{
    if (x < 0 || y < 0 || x >= im->w || y >= im->h) return 0.0;
    return im->px[y * dm_level_blur_stride(im->w) + 4 * x + c];
}

static double stretch_ref(const float *st, int sw, int sh, double u, double v, int c)
{
    double x = u * sw - 0.5, y = v * sh - 0.5, x0 = floor(x), y0 = floor(y), fx = x - x0, fy = y - y0;
    int xi[2] = {(int)x0, (int)x0 + 1}, yi[2] = {(int)y0, (int)y0 + 1};
    double sum = 0.0;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            int xx = xi[i] < 0 ? 0 : xi[i] >= sw ? sw - 1 : xi[i], yy = yi[j] < 0 ? 0 : yi[j] >= sh ? sh - 1 : yi[j];
            sum += (i ? fx : 1 - fx) * (j ? fy : 1 - fy) * st[2 * (yy * sw + xx) + c];
        }
    return sum;
}

/* the shader's sum at destination texel (x, y), in double */
static double reference(const image *src, int dw, int dh, bool along_v, const float *st, int sw, int sh,
                        const float *off, const float *w, int taps, int x, int y, int c)
{
    double u = (x + 0.5) / dw, v = (y + 0.5) / dh, s = stretch_ref(st, sw, sh, u, v, along_v), sum = 0.0;
    for (int i = 0; i < taps; ++i) {
        double t = (along_v ? v + s * off[i] : u + s * off[i]) * (along_v ? src->h : src->w) - 0.5;
        double t0 = floor(t), f = t - t0;
        int i0 = (int)t0;
        double a = along_v ? texel(src, x, i0, c) : texel(src, i0, y, c);
        double b = along_v ? texel(src, x, i0 + 1, c) : texel(src, i0 + 1, y, c);
        sum += w[i] * ((1 - f) * a + f * b);
    }
    return sum;
}

/* runs one pass: src → a new padded dst, the steps sampled from st */
static image run(const image *src, int dw, int dh, bool along_v, const float *st, int sw, int sh, const float *off,
                 const float *w, int taps, int threads)
{
    image dst = {calloc(dm_level_blur_floats(dw, dh), sizeof(float)), NULL, dw, dh};
    dst.px = dm_level_blur_frame(dst.buf, dw, dh);
    float *step = malloc(sizeof *step * (size_t)dw * (size_t)dh);
    cr_assert(dm_level_blur_step(st, sw, sh, dw, dh, along_v, step));
    dm_level_blur_pass p = {src->px, src->w, src->h, dst.px, dw, dh, along_v, step, off, w, taps, threads, NULL, false};
    cr_assert(dm_level_blur(&p));
    free(step);
    return dst;
}

static float *stretch_field(int sw, int sh, double base)
{
    float *st = malloc(sizeof *st * 2 * (size_t)sw * (size_t)sh);
    for (int y = 0; y < sh; ++y)
        for (int x = 0; x < sw; ++x) {
            st[2 * (y * sw + x)] = (float)(base * (1.0 + 0.5 * sin(0.37 * x + 0.11 * y)));
            st[2 * (y * sw + x) + 1] = (float)(base * (1.0 + 0.5 * cos(0.23 * x - 0.31 * y)));
        }
    return st;
}

static const float OFF[7] = {-3.1f, -2.0f, -0.9f, 0.0f, 0.9f, 2.0f, 3.1f}; /* mm */
static const float W[7] = {0.02f, 0.1f, 0.23f, 0.3f, 0.23f, 0.1f, 0.02f};

/* float against double: each tap's coordinate carries ~1e-6 texel of rounding, times the
 * texel differences (≤ 3) and the weights (sum 1): 1e-4 is far above that and far below a
 * wrong texel or weight (~1e-1). */
Test(level_blur, matches_the_shader_formula_in_double_along_u_and_v)
{
    const int w = 37, h = 29, sw = 16, sh = 20; /* the stretch at its own size, as a pack's */
    float *st = stretch_field(sw, sh, 0.05); /* ~2 texels per mm: taps reach past the border */
    image src = make(w, h, 1);
    for (int along_v = 0; along_v <= 1; ++along_v) {
        int dw = along_v ? w : 19, dh = along_v ? 15 : h; /* a reduced level: fewer texels across */
        image dst = run(&src, dw, dh, along_v, st, sw, sh, OFF, W, 7, 1);
        double worst = 0.0;
        for (int y = 0; y < dh; ++y)
            for (int x = 0; x < dw; ++x)
                for (int c = 0; c < 4; ++c) {
                    double ref = reference(&src, dw, dh, along_v, st, sw, sh, OFF, W, 7, x, y, c);
                    double got = dst.px[y * dm_level_blur_stride(dw) + 4 * x + c];
                    worst = fmax(worst, fabs(got - ref));
                }
        cr_expect_lt(worst, 1e-4, "along %s: max |cpu - double| %g", along_v ? "v" : "u", worst);
        free(dst.buf);
    }
    free(src.buf), free(st);
}

Test(level_blur, is_byte_identical_on_any_thread_count)
{
    float *st = stretch_field(64, 64, 0.02);
    image src = make(64, 48, 7);
    image one = run(&src, 64, 48, false, st, 64, 64, OFF, W, 7, 1);
    for (int threads = 2; threads <= 5; ++threads) {
        image many = run(&src, 64, 48, false, st, 64, 64, OFF, W, 7, threads);
        cr_expect(memcmp(one.buf, many.buf, sizeof(float) * dm_level_blur_floats(64, 48)) == 0, "%d threads differ",
                  threads);
        free(many.buf);
    }
    free(one.buf), free(src.buf), free(st);
}

/* a constant image of full coverage keeps its value where every tap lands inside, loses to
 * the zero border next to it, and a tap far outside (huge stretch) reads 0, not memory */
Test(level_blur, border_is_zero_and_far_taps_stay_in_bounds)
{
    const int n = 32;
    image src = make(n, n, 3);
    long stride = dm_level_blur_stride(n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < 4 * n; ++x) src.px[y * stride + x] = 2.0f;
    float st[2] = {0.01f, 0.01f}; /* one texel: 0.32 texels per mm everywhere */
    image dst = run(&src, n, n, false, st, 1, 1, OFF, W, 7, 1);
    cr_expect_float_eq(dst.px[16 * stride + 4 * 16], 2.0f, 1e-5); /* taps within ±1 texel */
    cr_expect_lt(dst.px[16 * stride], 2.0f - 1e-3);              /* texel 0: the first taps are outside */
    cr_expect_gt(dst.px[16 * stride], 1.0f);
    float huge[2] = {1e30f, 1e30f}, nan_st[2] = {NAN, NAN};
    image far = run(&src, n, n, true, huge, 1, 1, OFF, W, 7, 1);
    /* every tap but the centre one lands far outside: only the 0.3 weight remains */
    cr_expect_float_eq(far.px[5 * stride + 4 * 5], 0.6f, 1e-5);
    image bad = run(&src, n, n, true, nan_st, 1, 1, OFF, W, 7, 1); /* a NaN stretch reads as 0 */
    cr_expect_float_eq(bad.px[5 * stride + 4 * 5], 2.0f, 1e-5);
    free(dst.buf), free(far.buf), free(bad.buf), free(src.buf);
}

Test(level_blur, refuses_sizes_that_break_the_rules)
{
    float px[4] = {0}, step[4] = {0}, st[2] = {0};
    dm_level_blur_pass p = {px, 4, 4, px + 1, 4, 3, false, step, OFF, W, 7, 1, NULL, false}; /* u pass changes height */
    cr_expect_not(dm_level_blur(&p));
    p.along_v = true, p.dst_w = 3, p.dst_h = 4; /* v pass changes width */
    cr_expect_not(dm_level_blur(&p));
    p.dst_w = 4, p.taps = 0;
    cr_expect_not(dm_level_blur(&p));
    cr_expect_not(dm_level_blur_step(st, 0, 1, 4, 4, false, step));
    cr_expect_null(dm_level_blur_frame(NULL, 4, 4));
    cr_expect_eq(dm_level_blur_floats(0, 4), 0);
}

/* ---- the jump check (points) ------------------------------------------------------ */

/* cuts that put every tap across one (texel 0's left cut past every texel): each texel with a
 * point checks all its taps */
static const int16_t *everywhere(int texels)
{
    static int16_t c[4 * 256];
    cr_assert(texels <= 256);
    for (int i = 0; i < texels; ++i) c[4 * i] = c[4 * i + 2] = 30000, c[4 * i + 1] = c[4 * i + 3] = -30000;
    return c;
}

/* One row (or column) of 16 texels, 1 texel per mm (step 1/16 UV per mm), taps at −D, 0, +D mm
 * with weights ¼, ½, ¼, so each lands on a texel centre. Every texel's point lies on the x axis
 * 1 mm apart, except texel 9, put `d` mm from texel 8's point. Returns texel 8's red: the check
 * keeps texel 9 (when d ≤ reach) or leaves it out. */
static double jump_row(bool along_v, float D, double d, bool with_points)
{
    int w = along_v ? 1 : 16, h = along_v ? 16 : 1;
    image src = make(w, h, 7u);
    float st[2] = {1.0f / 16.0f, 1.0f / 16.0f}, off[3] = {-D, 0.0f, D}, wt[3] = {0.25f, 0.5f, 0.25f};
    float pts[16 * 4];
    for (int i = 0; i < 16; ++i) pts[4 * i] = (float)i, pts[4 * i + 1] = pts[4 * i + 2] = 0.0f, pts[4 * i + 3] = 1.0f;
    int j = 8 + (int)D; /* the tap's texel beyond 8 */
    pts[4 * j] = 8.0f, pts[4 * j + 1] = (float)d; /* d mm from texel 8 */
    image dst = {calloc(dm_level_blur_floats(w, h), sizeof(float)), NULL, w, h};
    dst.px = dm_level_blur_frame(dst.buf, w, h);
    float step[16];
    cr_assert(dm_level_blur_step(st, 1, 1, w, h, along_v, step));
    dm_level_blur_pass p = {src.px, w, h, dst.px, w, h, along_v, step, off, wt, 3, 1, with_points ? pts : NULL, everywhere(16)};
    cr_assert(dm_level_blur(&p));
    double r = along_v ? texel(&dst, 0, 8, 0) : texel(&dst, 8, 0, 0);
    double a = along_v ? texel(&src, 0, 8 - (int)D, 0) : texel(&src, 8 - (int)D, 0, 0);
    double m = along_v ? texel(&src, 0, 8, 0) : texel(&src, 8, 0, 0);
    double b = along_v ? texel(&src, 0, j, 0) : texel(&src, j, 0, 0);
    double kept = 0.25 * a + 0.5 * m + 0.25 * b, left_out = 0.25 * a + 0.5 * m;
    bool keep = d <= DM_LEVEL_BLUR_JUMP_FACTOR * D + DM_LEVEL_BLUR_JUMP_MM || !with_points;
    cr_expect_float_eq(r, keep ? kept : left_out, 1e-6, "D %g, d %g: %g, expected %g", D, d, r, keep ? kept : left_out);
    free(src.buf), free(dst.buf);
    return r;
}

/* The reach is 3 × the tap's offset + 3 mm: at offset 1 mm a point 6 mm away, at 3 mm one 12 mm
 * away. 2 % either side of it keeps or leaves out the tap's texel (a factor or margin 5 % off
 * moves the reach by 2.5 %, and these fail), along u and v alike. */
Test(level_blur, a_tap_that_jumps_farther_than_its_reach_is_left_out)
{
    for (int v = 0; v < 2; ++v) {
        double in1 = jump_row(v, 1.0f, 6.0 * 0.98, true), out1 = jump_row(v, 1.0f, 6.0 * 1.02, true);
        double in3 = jump_row(v, 3.0f, 12.0 * 0.98, true), out3 = jump_row(v, 3.0f, 12.0 * 1.02, true);
        cr_expect_neq(in1, out1);
        cr_expect_neq(in3, out3);
        cr_expect_float_eq(jump_row(v, 1.0f, 6.0 * 0.98, false), in1, 0.0, "kept: as without points");
        cr_expect_float_eq(jump_row(v, 1.0f, 6.0 * 1.02, false), in1, 0.0, "without points nothing is left out");
    }
    cr_expect_float_eq(DM_LEVEL_BLUR_JUMP_FACTOR, 3.0f, 0.0f);
    cr_expect_float_eq(DM_LEVEL_BLUR_JUMP_MM, 3.0f, 0.0f);
}

/* Points that never jump change nothing, bit for bit; texels without a point (w = 0) neither
 * refuse nor are refused. */
Test(level_blur, points_on_a_continuous_row_change_nothing)
{
    int w = 40, h = 3;
    image src = make(w, h, 11u);
    float st[2] = {0.02f, 0.03f}, off[5] = {-2.1f, -0.9f, 0.0f, 0.9f, 2.1f}, wt[5] = {0.1f, 0.2f, 0.4f, 0.2f, 0.1f};
    float *pts = calloc((size_t)w * h * 4, sizeof *pts);
    for (int i = 0; i < w * h; ++i)
        pts[4 * i] = (float)(i % w) * 0.7f, pts[4 * i + 1] = (float)(i / w) * 0.7f, pts[4 * i + 3] = i % 7 ? 1.0f : 0.0f;
    for (int v = 0; v < 2; ++v) {
        image a = {calloc(dm_level_blur_floats(w, h), sizeof(float)), NULL, w, h}, b = a;
        b.buf = calloc(dm_level_blur_floats(w, h), sizeof(float));
        a.px = dm_level_blur_frame(a.buf, w, h), b.px = dm_level_blur_frame(b.buf, w, h);
        float *step = malloc(sizeof *step * (size_t)w * h);
        cr_assert(dm_level_blur_step(st, 1, 1, w, h, v, step));
        dm_level_blur_pass p = {src.px, w, h, a.px, w, h, v, step, off, wt, 5, 1, NULL, everywhere(w * h)};
        cr_assert(dm_level_blur(&p));
        p.dst = b.px, p.points = pts;
        cr_assert(dm_level_blur(&p));
        cr_expect_eq(memcmp(a.buf, b.buf, sizeof(float) * dm_level_blur_floats(w, h)), 0, "along %s", v ? "v" : "u");
        free(a.buf), free(b.buf), free(step);
    }
    free(pts), free(src.buf);
}

/* The cuts: a 12 × 12 grid of points 0.5 mm apart, columns 7.. moved 40 mm away in z: one cut
 * along every row between x = 6 and 7, none along the columns; the texels' nearest cuts say so.
 * On a grid 1.5 mm apart a step of 2.4 × the median is no cut, 2.6 × is: the factor 2.5 pinned
 * (the 3 mm floor lies below both); on the 0.5 mm grid 2.6 × would be under the floor. A texel
 * without a point has no cut beside it. */
Test(level_blur, the_cuts_lie_where_the_atlas_jumps)
{
    enum { N = 12 };
    float pts[4 * N * N];
    int16_t cuts[4 * N * N];
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
            float *q = pts + 4 * (y * N + x);
            q[0] = 0.5f * (float)x, q[1] = 0.5f * (float)y, q[2] = x >= 7 ? 40.0f : 0.0f, q[3] = 1.0f;
        }
    cr_assert_eq(dm_level_blur_cuts(pts, N, cuts), N);
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
            const int16_t *c = cuts + 4 * (y * N + x);
            cr_expect_eq(c[0], x >= 7 ? 7 : -1000, "(%d, %d) left %d", x, y, c[0]);
            cr_expect_eq(c[1], x < 7 ? 7 : N + 1000, "(%d, %d) right %d", x, y, c[1]);
            cr_expect_eq(c[2], -1000);
            cr_expect_eq(c[3], N + 1000);
        }
    /* a smaller step: 2.4 and 2.6 × the median (1.5 mm), with the floor (3 mm) below them */
    for (int k = 0; k < 2; ++k) {
        for (int y = 0; y < N; ++y)
            for (int x = 0; x < N; ++x) {
                float *q = pts + 4 * (y * N + x);
                q[0] = 1.5f * (float)x + (x >= 7 ? (k ? 2.6f : 2.4f) * 1.5f - 1.5f : 0.0f), q[1] = 1.5f * (float)y, q[2] = 0.0f;
            }
        cr_expect_eq(dm_level_blur_cuts(pts, N, cuts), k ? N : 0, "step %.1f x the median", k ? 2.6 : 2.4);
    }
    /* a texel without a point: no cut beside it */
    for (int i = 0; i < N * N; ++i) pts[4 * i + 2] = (i % N) >= 7 ? 40.0f : 0.0f, pts[4 * i] = 0.5f * (float)(i % N);
    for (int y = 0; y < N; ++y) pts[4 * (y * N + 7) + 3] = 0.0f;
    cr_expect_eq(dm_level_blur_cuts(pts, N, cuts), 0);
}
