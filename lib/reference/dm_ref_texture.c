#include "reference/dm_ref_texture.h"
#include "core/dm_half.h"
#include "core/dm_srgb.h"

#include <assert.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <string.h>

/* sRGB 8-bit → linear: 256 entries of the exact curve, made once. */
static double srgb_table[256];
static pthread_once_t srgb_once = PTHREAD_ONCE_INIT;
static void srgb_init(void)
{
    for (int i = 0; i < 256; ++i) srgb_table[i] = dm_srgb_to_linear(i / 255.0);
}
static double srgb8(uint8_t v)
{
    pthread_once(&srgb_once, srgb_init);
    return srgb_table[v];
}

void dm_ref_texel(const dm_ref_texture *t, int i, int j, double rgba[4])
{
    assert(t && t->texels);
    i = i < 0 ? 0 : i >= t->width ? t->width - 1 : i;
    j = j < 0 ? 0 : j >= t->height ? t->height - 1 : j;
    const dm_tex_format_info *f = dm_tex_format_get(t->format);
    assert(f);
    size_t at = ((size_t)j * (size_t)t->width + (size_t)i) * (size_t)f->components;
    double c[4] = {0, 0, 0, 1};
    for (int k = 0; k < f->components; ++k) {
        if (f->component_size == 1) {
            uint8_t v = ((const uint8_t *)t->texels)[at + k];
            c[k] = f->is_srgb && k < 3 ? srgb8(v) : v / 255.0;
        } else if (f->component_size == 2) {
            uint16_t h;
            memcpy(&h, (const uint8_t *)t->texels + (at + (size_t)k) * 2, sizeof h);
            c[k] = dm_half_to_float(h);
        } else {
            float v;
            memcpy(&v, (const uint8_t *)t->texels + (at + (size_t)k) * 4, sizeof v);
            c[k] = v;
        }
    }
    memcpy(rgba, c, sizeof c);
}

static int wrap(int i, int n, bool repeat)
{
    if (!repeat) return i < 0 ? 0 : i >= n ? n - 1 : i;
    int r = i % n;
    return r < 0 ? r + n : r;
}

void dm_ref_texture_sample(const dm_ref_texture *t, double u, double v, double rgba[4])
{
    assert(t && t->texels);
    /* keep the coordinates in a range where the integer conversions are exact */
    if (!(fabs(u) < 1e6)) u = 0;
    if (!(fabs(v) < 1e6)) v = 0;
    if (t->repeat_u) u -= floor(u);
    double x = u * t->width - 0.5, y = v * t->height - 0.5;
    double x0 = floor(x), y0 = floor(y), fx = x - x0, fy = y - y0;
    int i0 = (int)x0, j0 = (int)y0;
    int ia = wrap(i0, t->width, t->repeat_u), ib = wrap(i0 + 1, t->width, t->repeat_u);
    int ja = wrap(j0, t->height, false), jb = wrap(j0 + 1, t->height, false);
    double a[4], b[4], c[4], d[4];
    dm_ref_texel(t, ia, ja, a);
    dm_ref_texel(t, ib, ja, b);
    dm_ref_texel(t, ia, jb, c);
    dm_ref_texel(t, ib, jb, d);
    for (int k = 0; k < 4; ++k)
        rgba[k] = (1 - fy) * ((1 - fx) * a[k] + fx * b[k]) + fy * ((1 - fx) * c[k] + fx * d[k]);
}
