#include "bake/dm_envmap.h"

#include <assert.h>
#include <stdbool.h>
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "image/dm_image.h"

void dm_envmap_free(dm_envmap *map)
{
    if (!map) return;
    for (int l = 0; l < DM_ENVMAP_LEVEL_MAX; ++l) free(map->level[l]);
    memset(map, 0, sizeof *map);
}

static void downsample(const float *src, int sw, int sh, float *dst, int dw, int dh)
{
    for (int j = 0; j < dh; ++j) {
        int j0 = 2 * j < sh ? 2 * j : sh - 1, j1 = 2 * j + 1 < sh ? 2 * j + 1 : sh - 1;
        for (int i = 0; i < dw; ++i) {
            int i0 = 2 * i < sw ? 2 * i : sw - 1, i1 = 2 * i + 1 < sw ? 2 * i + 1 : sw - 1;
            for (int c = 0; c < 3; ++c) {
                double s = (double)src[((size_t)j0 * sw + i0) * 3 + c] + src[((size_t)j0 * sw + i1) * 3 + c] +
                           src[((size_t)j1 * sw + i0) * 3 + c] + src[((size_t)j1 * sw + i1) * 3 + c];
                dst[((size_t)j * dw + i) * 3 + c] = (float)(0.25 * s);
            }
        }
    }
}

static const char *channel_name(int c)
{
    return c == 0 ? "R" : c == 1 ? "G" : "B";
}

dm_result dm_envmap_from_pixels(const float *pixels, int width, int height, int channels, double negative_tolerance,
                                const char *what, dm_envmap *out, dm_error *err)
{
    assert(pixels && out && what && channels >= 1 && negative_tolerance >= 0.0);
    memset(out, 0, sizeof *out);
    if (width != 2 * height || height < 2)
        return dm_fail(err, DM_ERR_FORMAT,
                       "%s: image is %dx%d: an equirectangular map must be twice as wide as high (2:1), at least 4x2",
                       what, width, height);
    if (width > DM_ENVMAP_SIZE_MAX)
        return dm_fail(err, DM_ERR_RANGE, "%s: image is %dx%d: expected at most %dx%d", what, width, height,
                       DM_ENVMAP_SIZE_MAX, DM_ENVMAP_SIZE_MAX / 2);
    size_t n = (size_t)width * height;
    out->level[0] = malloc(n * 3 * sizeof(float));
    if (!out->level[0]) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory for %dx%d", what, width, height);
    out->width = out->level_width[0] = width;
    out->height = out->level_height[0] = height;
    out->level_count = 1;
    float *dst = out->level[0];
    /* File order (top row first) so that the first refusal is the first bad texel a
     * viewer would show. */
    for (int y = 0; y < height; ++y) {
        int j = height - 1 - y;
        for (int x = 0; x < width; ++x) {
            size_t k = (size_t)j * width + x;
            for (int c = 0; c < 3; ++c) {
                float v = pixels[k * channels + (channels >= 3 ? c : 0)];
                const char *ch = channels >= 3 ? channel_name(c) : "grey";
                if (!isfinite(v)) {
                    dm_envmap_free(out);
                    return dm_fail(err, DM_ERR_NON_FINITE,
                                   "%s: texel (x=%d, y=%d) channel %s is %s: expected finite radiance "
                                   "(x from the left, y from the top of the file)",
                                   what, x, y, ch, isnan(v) ? "NaN" : "infinite");
                }
                if (v > DM_ENVMAP_RADIANCE_MAX) {
                    dm_envmap_free(out);
                    return dm_fail(err, DM_ERR_RANGE,
                                   "%s: texel (x=%d, y=%d) channel %s is %g: expected radiance at most %g "
                                   "(x from the left, y from the top of the file)",
                                   what, x, y, ch, v, DM_ENVMAP_RADIANCE_MAX);
                }
                if (v < 0.0f) {
                    if (v < -negative_tolerance) {
                        dm_envmap_free(out);
                        return dm_fail(err, DM_ERR_RANGE,
                                       "%s: texel (x=%d, y=%d) channel %s is %g: expected radiance >= 0 "
                                       "(tolerance %g; x from the left, y from the top of the file)",
                                       what, x, y, ch, v, negative_tolerance);
                    }
                    ++out->clamped_texels;
                    if (v < out->most_negative) {
                        out->most_negative = v;
                        out->most_negative_x = x;
                        out->most_negative_y = y;
                    }
                    v = 0.0f;
                }
                dst[k * 3 + c] = v;
            }
        }
    }
    while (out->level_count < DM_ENVMAP_LEVEL_MAX && out->level_height[out->level_count - 1] > 1) {
        int l = out->level_count;
        int sw = out->level_width[l - 1], sh = out->level_height[l - 1];
        int dw = sw / 2 > 1 ? sw / 2 : 1, dh = sh / 2 > 1 ? sh / 2 : 1;
        out->level[l] = malloc((size_t)dw * dh * 3 * sizeof(float));
        if (!out->level[l]) {
            dm_envmap_free(out);
            return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory for the mip pyramid", what);
        }
        downsample(out->level[l - 1], sw, sh, out->level[l], dw, dh);
        out->level_width[l] = dw;
        out->level_height[l] = dh;
        ++out->level_count;
    }
    return DM_OK;
}

/* True when path names an 8-bit display format (its values are sRGB-encoded, not radiance). */
static bool is_ldr_format(const char *path)
{
    static const char *const ext[] = {".png", ".jpg", ".jpeg", ".bmp", ".tga", ".gif", ".webp"};
    const char *dot = strrchr(path, '.');
    if (!dot || strchr(dot, '/')) return false;
    for (size_t k = 0; k < sizeof ext / sizeof ext[0]; ++k) {
        const char *a = dot, *b = ext[k];
        while (*a && *b && tolower((unsigned char)*a) == *b) ++a, ++b;
        if (!*a && !*b) return true;
    }
    return false;
}

dm_result dm_envmap_load(const char *path, double negative_tolerance, dm_envmap *out, dm_error *err)
{
    assert(path && out);
    memset(out, 0, sizeof *out);
    if (is_ldr_format(path))
        return dm_fail(err, DM_ERR_UNSUPPORTED,
                       "%s: an 8-bit image holds display (sRGB) values, not radiance, expected an HDR environment "
                       "(.hdr or .exr); to use it anyway, convert it to linear float (its brightness is then only "
                       "relative): oiiotool %s --colorconvert sRGB linear -d float -o ENV.exr",
                       path, path);
    dm_image img;
    dm_result r = dm_image_read(path, DM_PIXEL_F32, &img, err);
    if (r != DM_OK) {
        dm_image_free(&img);
        return r;
    }
    r = dm_envmap_from_pixels(img.pixels, img.width, img.height, img.channels, negative_tolerance, path, out, err);
    dm_image_free(&img);
    return r;
}

void dm_envmap_fetch(const dm_envmap *map, int level, double u, double v, double rgb[3])
{
    const int w = map->level_width[level], h = map->level_height[level];
    const float *p = map->level[level];
    double x = (u - floor(u)) * w - 0.5;
    double y = v * h - 0.5;
    if (!(y > 0.0)) y = 0.0; /* NaN too */
    if (y > h - 1) y = h - 1;
    double xf = floor(x);
    int i0 = (int)xf, j0 = (int)y;
    double fx = x - xf, fy = y - j0;
    if (i0 < 0) i0 += w;
    if (i0 >= w) i0 -= w;
    int i1 = i0 + 1 < w ? i0 + 1 : 0;
    int j1 = j0 + 1 < h ? j0 + 1 : j0;
    const float *a = p + ((size_t)j0 * w + i0) * 3, *b = p + ((size_t)j0 * w + i1) * 3;
    const float *c = p + ((size_t)j1 * w + i0) * 3, *d = p + ((size_t)j1 * w + i1) * 3;
    for (int k = 0; k < 3; ++k) {
        double top = a[k] + (b[k] - (double)a[k]) * fx;
        double bot = c[k] + (d[k] - (double)c[k]) * fx;
        rgb[k] = top + (bot - top) * fy;
    }
}

void dm_envmap_sample(const dm_envmap *map, double u, double v, double lod, double rgb[3])
{
    double top = map->level_count - 1;
    if (!(lod > 0.0)) lod = 0.0;
    if (lod > top) lod = top;
    int l0 = (int)lod;
    double f = lod - l0;
    dm_envmap_fetch(map, l0, u, v, rgb);
    if (f > 0.0 && l0 + 1 < map->level_count) {
        double b[3];
        dm_envmap_fetch(map, l0 + 1, u, v, b);
        for (int k = 0; k < 3; ++k) rgb[k] += (b[k] - rgb[k]) * f;
    }
}
