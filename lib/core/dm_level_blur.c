#include "core/dm_level_blur.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_parallel.h"

/* The stretch's component c at uv: bilinear, clamp to edge (GL_CLAMP_TO_EDGE, GL_LINEAR). */
static float stretch_at(const float *st, int sw, int sh, float u, float v, int c)
{
    float x = u * (float)sw - 0.5f, y = v * (float)sh - 0.5f;
    float fx0 = floorf(x), fy0 = floorf(y), fx = x - fx0, fy = y - fy0;
    int x0 = (int)fmaxf(fminf(fx0, (float)sw), -1.0f), y0 = (int)fmaxf(fminf(fy0, (float)sh), -1.0f);
    int x1 = x0 + 1, y1 = y0 + 1;
    x0 = x0 < 0 ? 0 : x0 >= sw ? sw - 1 : x0;
    x1 = x1 < 0 ? 0 : x1 >= sw ? sw - 1 : x1;
    y0 = y0 < 0 ? 0 : y0 >= sh ? sh - 1 : y0;
    y1 = y1 < 0 ? 0 : y1 >= sh ? sh - 1 : y1;
    size_t w = (size_t)sw;
    float a = st[2 * ((size_t)y0 * w + (size_t)x0) + c], b = st[2 * ((size_t)y0 * w + (size_t)x1) + c];
    float d = st[2 * ((size_t)y1 * w + (size_t)x0) + c], e = st[2 * ((size_t)y1 * w + (size_t)x1) + c];
    float top = a + fx * (b - a), bottom = d + fx * (e - d);
    return top + fy * (bottom - top);
}

bool dm_level_blur_step(const float *stretch, int sw, int sh, int dst_w, int dst_h, bool along_v, float *out)
{
    if (!stretch || !out || sw < 1 || sh < 1 || dst_w < 1 || dst_h < 1) return false;
    for (int y = 0; y < dst_h; ++y)
        for (int x = 0; x < dst_w; ++x) {
            float s = stretch_at(stretch, sw, sh, ((float)x + 0.5f) / (float)dst_w, ((float)y + 0.5f) / (float)dst_h,
                                 along_v ? 1 : 0);
            out[(size_t)y * (size_t)dst_w + (size_t)x] = isfinite(s) ? s : 0.0f;
        }
    return true;
}

/* Whether texel j along the pass's line (row y along u, column x along v) may be read for the
 * texel whose point is `me`: outside the image (the zero border), without a point, or within
 * reach of it in 3-D. */
static inline bool near(const dm_level_blur_pass *p, const float *me, int j, int x, int y, float reach)
{
    int n = p->along_v ? p->dst_h : p->dst_w;
    if (j < 0 || j >= n) return true;
    const float *q = p->points + 4 * (p->along_v ? (size_t)j * (size_t)p->dst_w + (size_t)x
                                                 : (size_t)y * (size_t)p->dst_w + (size_t)j);
    if (!(q[3] > 0.0f)) return true;
    float dx = q[0] - me[0], dy = q[1] - me[1], dz = q[2] - me[2];
    return dx * dx + dy * dy + dz * dz <= reach * reach;
}

/* Whether taps from texel coordinate lo to hi along the line read a texel across one of the
 * texel's two nearest cuts (c[0] on the left or below, c[1] on the right or above). */
static inline bool across(const int16_t *c, float lo, float hi)
{
    /* floor(lo) <= c0 − 1 and floor(hi) + 1 >= c1, for whole c0, c1 (lo <= hi: dt >= 0) */
    return lo < (float)c[0] || hi >= (float)c[1] - 1.0f;
}

/* A tap's texel coordinate clamped to [−2, n + 1] (NaN, from an infinite step times offset 0,
 * to −2): a tap beyond reads the zero border all the same. */
static inline float clamp_tap(float t, float nf)
{
    t = t >= -2.0f ? t : -2.0f;
    return t <= nf + 1.0f ? t : nf + 1.0f;
}

/* Rows [begin, end) of the destination. */
static inline __attribute__((always_inline)) void rows_taps(const dm_level_blur_pass *p, size_t begin, size_t end)
{
    const bool v = p->along_v;
    const int taps = p->taps;
    const float nf = (float)(v ? p->src_h : p->src_w); /* texels along the taps' axis */
    const long src_stride = dm_level_blur_stride(p->src_w), dst_stride = dm_level_blur_stride(p->dst_w);
    /* from one texel to the next along the axis, in floats */
    const ptrdiff_t step = v ? src_stride : 4;
    float off[DM_LEVEL_BLUR_MAX_TAPS], wt[DM_LEVEL_BLUR_MAX_TAPS], off_lo = 0.0f, off_hi = 0.0f;
    const float *pts = p->points && p->cuts && (v ? p->src_h == p->dst_h : p->src_w == p->dst_w) ? p->points : NULL;
    for (int i = 0; i < taps; ++i) {
        off[i] = p->offset_mm[i], wt[i] = p->weight[i];
        off_lo = off[i] < off_lo ? off[i] : off_lo;
        off_hi = off[i] > off_hi ? off[i] : off_hi;
    }
    for (size_t y = begin; y < end; ++y) {
        float vc = ((float)y + 0.5f) / (float)p->dst_h;
        float *out = p->dst + (ptrdiff_t)y * dst_stride;
        const float *srow = p->step + y * (size_t)p->dst_w;
        for (int x = 0; x < p->dst_w; ++x) {
            float c = v ? vc : ((float)x + 0.5f) / (float)p->dst_w;
            /* tap i at texel coordinate t0 + dt·offset_i along the line: row y (u) or column x (v) */
            float t0 = c * nf - 0.5f, dt = srow[x] * nf;
            const float *line = v ? p->src + 4 * (ptrdiff_t)x : p->src + (ptrdiff_t)y * src_stride;
            float sum[4] = {0, 0, 0, 0};
            float lo = t0 + dt * off_lo, hi = t0 + dt * off_hi;
            const int16_t *cut = pts ? p->cuts + 4 * (y * (size_t)p->dst_w + (size_t)x) + (v ? 2 : 0) : NULL;
            if (cut && across(cut, lo, hi)) { /* a texel without a point has no cuts */
                const float *me = pts + 4 * (y * (size_t)p->dst_w + (size_t)x);
                /* a texel between the two cuts is on this texel's side of both: only those beyond
                 * are measured */
                for (int i = 0; i < taps; ++i) {
                    float t = clamp_tap(t0 + dt * off[i], nf), fl = floorf(t), f = t - fl;
                    const float *a = line + (ptrdiff_t)fl * step, *b = a + step;
                    float reach = DM_LEVEL_BLUR_JUMP_FACTOR * fabsf(off[i]) + DM_LEVEL_BLUR_JUMP_MM;
                    bool ka = (fl >= (float)cut[0] && fl < (float)cut[1]) || near(p, me, (int)fl, x, y, reach);
                    bool kb = (fl + 1.0f >= (float)cut[0] && fl + 1.0f < (float)cut[1]) || near(p, me, (int)fl + 1, x, y, reach);
                    if (ka && kb) /* the unchecked sum's floats */
                        for (int k = 0; k < 4; ++k) sum[k] += wt[i] * (a[k] + f * (b[k] - a[k]));
                    else if (ka)
                        for (int k = 0; k < 4; ++k) sum[k] += wt[i] * (a[k] - f * a[k]);
                    else if (kb)
                        for (int k = 0; k < 4; ++k) sum[k] += wt[i] * (f * b[k]);
                }
            } else if (lo >= -2.0f && hi <= nf + 1.0f && lo <= hi) {
                /* every tap within the image and its zero border (the common case) */
                for (int i = 0; i < taps; ++i) {
                    float t = t0 + dt * off[i], fl = floorf(t), f = t - fl;
                    const float *a = line + (ptrdiff_t)fl * step, *b = a + step;
                    for (int k = 0; k < 4; ++k) sum[k] += wt[i] * (a[k] + f * (b[k] - a[k]));
                }
            } else {
                for (int i = 0; i < taps; ++i) {
                    float t = clamp_tap(t0 + dt * off[i], nf), fl = floorf(t), f = t - fl;
                    const float *a = line + (ptrdiff_t)fl * step, *b = a + step;
                    for (int k = 0; k < 4; ++k) sum[k] += wt[i] * (a[k] + f * (b[k] - a[k]));
                }
            }
            for (int k = 0; k < 4; ++k) out[4 * x + k] = sum[k];
        }
    }
}

/* x86-64: a clone for AVX2-class processors (SSE4.1's floor in one instruction, wider
 * registers), picked at load time; the same IEEE arithmetic, so the same floats. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
static void rows(void *ctx, size_t begin, size_t end)
{
    rows_taps(ctx, begin, end);
}

bool dm_level_blur(const dm_level_blur_pass *p)
{
    if (!p || !p->src || !p->dst || !p->step || !p->offset_mm || !p->weight || p->taps < 1 ||
        p->taps > DM_LEVEL_BLUR_MAX_TAPS)
        return false;
    if (p->src_w < 1 || p->src_h < 1 || p->dst_w < 1 || p->dst_h < 1)
        return false;
    if (p->along_v ? p->dst_w != p->src_w : p->dst_h != p->src_h) return false;
    dm_parallel_for((size_t)p->dst_h, 0, p->thread_count, rows, (void *)p);
    return true;
}

size_t dm_level_blur_floats(int w, int h)
{
    return w < 1 || h < 1 ? 0 : (size_t)dm_level_blur_stride(w) * (size_t)(h + 2 * DM_LEVEL_BLUR_PAD);
}

float *dm_level_blur_frame(float *buffer, int w, int h)
{
    if (!buffer || w < 1 || h < 1) return NULL;
    size_t stride = (size_t)dm_level_blur_stride(w), pad = DM_LEVEL_BLUR_PAD, side = 4 * pad;
    memset(buffer, 0, sizeof *buffer * stride * pad); /* the rows above */
    for (size_t y = pad; y < pad + (size_t)h; ++y) { /* each row's ends */
        memset(buffer + y * stride, 0, sizeof *buffer * side);
        memset(buffer + y * stride + stride - side, 0, sizeof *buffer * side);
    }
    memset(buffer + (pad + (size_t)h) * stride, 0, sizeof *buffer * stride * pad); /* and below */
    return buffer + pad * stride + side;
}

/* 3-D distance between the points of texels a and b, or −1 when either has none */
static float pair(const float *pts, size_t a, size_t b)
{
    const float *p = pts + 4 * a, *q = pts + 4 * b;
    if (!(p[3] > 0.0f) || !(q[3] > 0.0f)) return -1.0f;
    float dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
    return sqrtf(dx * dx + dy * dy + dz * dz);
}

long dm_level_blur_cuts(const float *points, int n, int16_t *cuts)
{
    if (!points || !cuts || n < 1) return 0;
    enum { BINS = 4096 };
    const float bin_mm = 0.005f; /* the histogram of neighbour distances: 5 µm bins to 20 mm */
    long *hist = calloc(BINS, sizeof *hist), pairs = 0, found = 0;
    if (!hist) return -1;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            size_t i = (size_t)y * (size_t)n + (size_t)x;
            float d[2] = {x + 1 < n ? pair(points, i, i + 1) : -1.0f, y + 1 < n ? pair(points, i, i + (size_t)n) : -1.0f};
            for (int k = 0; k < 2; ++k)
                if (d[k] >= 0.0f) {
                    int b = (int)(d[k] / bin_mm);
                    ++hist[b < BINS ? b : BINS - 1];
                    ++pairs;
                }
        }
    float median = 0.0f;
    for (long b = 0, run = 0; b < BINS && pairs > 0; ++b)
        if ((run += hist[b]) * 2 >= pairs) {
            median = ((float)b + 0.5f) * bin_mm;
            break;
        }
    free(hist);
    const float limit = fmaxf(DM_LEVEL_BLUR_CUT_STEPS * median, DM_LEVEL_BLUR_JUMP_MM);
    const int16_t none_lo = -1000, none_hi = (int16_t)(n + 1000);
    for (int axis = 0; axis < 2; ++axis) /* 0: rows (u), 1: columns (v) */
        for (int line = 0; line < n; ++line) {
            size_t s = axis ? (size_t)n : 1, l = axis ? 1 : (size_t)n, base = (size_t)line * l;
            int16_t last = none_lo; /* the nearest cut at or left of i */
            for (int i = 0; i < n; ++i) {
                size_t t = base + (size_t)i * s;
                if (i > 0 && pair(points, t - s, t) > limit) last = (int16_t)i, ++found;
                cuts[4 * t + 2 * axis] = points[4 * t + 3] > 0.0f ? last : none_lo;
            }
            int16_t next = none_hi; /* the nearest cut right of i */
            for (int i = n - 1; i >= 0; --i) {
                size_t t = base + (size_t)i * s;
                cuts[4 * t + 2 * axis + 1] = points[4 * t + 3] > 0.0f ? next : none_hi;
                if (i > 0 && pair(points, t - s, t) > limit) next = (int16_t)i;
            }
        }
    return found;
}
