#include "render/dm_render_refcmp.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_exr_read.h"
#include "core/dm_sort.h"
#include "core/dm_srgb.h"
#include "render/dm_render_font.h"
#include "render/dm_render_legend.h"

/* ---- loading --------------------------------------------------------------------------- */

const char *dm_refcmp_mode_name(dm_refcmp_mode m)
{
    return m == DM_REFCMP_FRAME ? "frame" : "texture-space";
}

dm_result dm_refcmp_load(const char *path, dm_refcmp_ref *ref, dm_error *err)
{
    memset(ref, 0, sizeof *ref);
    dm_exr_file f;
    dm_result rc = dm_exr_load(path, &f, err);
    if (rc != DM_OK) return rc;
    static const char *names[4] = {"R", "G", "B", "A"};
    const float *ch[4];
    for (int c = 0; c < 4 && rc == DM_OK; ++c)
        if (!(ch[c] = dm_exr_file_channel(&f, names[c])))
            rc = dm_fail(err, DM_ERR_FORMAT, "%s: no channel %s; a reference has R, G, B and A", path, names[c]);
    const dm_param *mode = f.has_provenance ? dm_prov_find(&f.prov, "mode") : NULL;
    const dm_param *view = f.has_provenance ? dm_prov_find(&f.prov, "view") : NULL;
    if (rc == DM_OK) {
        if (mode && mode->type == DM_PARAM_STRING && !strcmp(mode->s, "texture-space")) ref->mode = DM_REFCMP_TEXTURE_SPACE;
        else if (mode && mode->type == DM_PARAM_STRING && !strcmp(mode->s, "frame")) ref->mode = DM_REFCMP_FRAME;
        else if (!mode && view && view->type == DM_PARAM_STRING && !strcmp(view->s, "diffusion"))
            ref->mode = DM_REFCMP_TEXTURE_SPACE;
        else if (!mode && view && view->type == DM_PARAM_STRING && !strcmp(view->s, "final"))
            ref->mode = DM_REFCMP_FRAME;
        else
            rc = dm_fail(err, DM_ERR_FORMAT,
                         "%s: provenance mode '%s': expected \"texture-space\" or \"frame\" (a dermis-reference "
                         "output, or dermis-render's diffusion or final view)",
                         path, mode && mode->type == DM_PARAM_STRING ? mode->s : "(none)");
    }
    if (rc == DM_OK && ref->mode == DM_REFCMP_TEXTURE_SPACE && (f.width != f.height || f.width < 8 || f.width > 8192))
        rc = dm_fail(err, DM_ERR_FORMAT, "%s: texture-space reference %dx%d, expected square, 8..8192", path, f.width,
                     f.height);
    if (rc == DM_OK && !(ref->rgba = malloc((size_t)f.width * f.height * 4 * sizeof(float))))
        rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: cannot allocate %dx%d", path, f.width, f.height);
    if (rc == DM_OK) {
        size_t n = (size_t)f.width * f.height;
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 4; ++c) ref->rgba[i * 4 + c] = ch[c][i];
        ref->width = f.width, ref->height = f.height;
        ref->has_provenance = f.has_provenance;
        ref->prov = f.prov;
    }
    dm_exr_file_free(&f);
    if (rc != DM_OK) dm_refcmp_ref_free(ref);
    return rc;
}

void dm_refcmp_ref_free(dm_refcmp_ref *ref)
{
    free(ref->rgba);
    memset(ref, 0, sizeof *ref);
}

/* ---- statistics ------------------------------------------------------------------------ */

dm_result dm_refcmp_stats_compute(const float *ref, const float *render, int width, int height, dm_refcmp_stats *st,
                                  float *rel, dm_error *err)
{
    memset(st, 0, sizeof *st);
    const size_t n = (size_t)width * height;
    double sum_ref[3] = {0, 0, 0};
    for (size_t i = 0; i < n; ++i) {
        bool a = ref[i * 4 + 3] >= 0.5f, b = render[i * 4 + 3] >= 0.5f;
        st->count += a && b;
        st->ref_only += a && !b;
        st->render_only += b && !a;
        if (a && b)
            for (int c = 0; c < 3; ++c) sum_ref[c] += ref[i * 4 + c];
    }
    if (st->count == 0)
        return dm_fail(err, DM_ERR_EMPTY, "comparison: no texel is covered in both the reference and the render (%ld "
                       "in the reference only, %ld in the render only)", st->ref_only, st->render_only);
    float *e = malloc((size_t)st->count * sizeof *e);
    if (!e) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "comparison: cannot allocate %ld values", st->count);
    for (int c = 0; c < 3; ++c) {
        double fl = DM_REFCMP_FLOOR_FRACTION * sum_ref[c] / (double)st->count;
        st->floor[c] = fl > 1e-30 ? fl : 1e-30;
    }
    if (rel)
        for (size_t i = 0; i < n; ++i) {
            bool a = ref[i * 4 + 3] >= 0.5f, b = render[i * 4 + 3] >= 0.5f;
            rel[i] = a && b ? 0.0f : a != b ? -2.0f : -1.0f;
        }
    for (int c = 0; c < 3; ++c) {
        long k = 0;
        double sum = 0;
        for (size_t i = 0; i < n; ++i) {
            if (ref[i * 4 + 3] < 0.5f || render[i * 4 + 3] < 0.5f) continue;
            double r = ref[i * 4 + c];
            double v = fabs((double)render[i * 4 + c] - r) / (r > st->floor[c] ? r : st->floor[c]);
            e[k++] = (float)v;
            sum += v;
            if (v > st->max[c]) st->max[c] = v;
            if (rel && (float)v > rel[i]) rel[i] = (float)v;
        }
        st->mean[c] = sum / (double)k;
        dm_sort_floats(e, (size_t)k);
        long rank = (long)ceil(0.95 * (double)k); /* nearest rank, 1-based */
        st->p95[c] = e[(rank > 0 ? rank : 1) - 1];
    }
    free(e);
    return DM_OK;
}

void dm_refcmp_stats_text(const dm_refcmp_stats *st, dm_refcmp_mode mode, char *out, int out_size)
{
    const char *unit = mode == DM_REFCMP_FRAME ? "pixels" : "texels";
    int n = snprintf(out, (size_t)out_size,
                     "compared %ld %s where both alphas are 1 (%ld covered in the reference only, %ld in the render "
                     "only)\nrelative error |render - ref| / max(ref, floor), floor = %g %% of the mean reference "
                     "(R %.4g, G %.4g, B %.4g)\n",
                     st->count, unit, st->ref_only, st->render_only, 100 * DM_REFCMP_FLOOR_FRACTION, st->floor[0],
                     st->floor[1], st->floor[2]);
    static const char ch[3] = {'R', 'G', 'B'};
    for (int c = 0; c < 3 && n >= 0 && n < out_size; ++c)
        n += snprintf(out + n, (size_t)(out_size - n), "  %c: mean %.4f %%, p95 %.4f %%, max %.4f %%\n", ch[c],
                      100 * st->mean[c], 100 * st->p95[c], 100 * st->max[c]);
}

/* ---- drawing --------------------------------------------------------------------------- */

const char *dm_refcmp_layout_name(dm_refcmp_layout l)
{
    static const char *names[DM_REFCMP_LAYOUT_COUNT] = {"side", "split", "error"};
    return (unsigned)l < DM_REFCMP_LAYOUT_COUNT ? names[l] : NULL;
}

bool dm_refcmp_layout_parse(const char *text, dm_refcmp_layout *l)
{
    for (int i = 0; i < DM_REFCMP_LAYOUT_COUNT; ++i)
        if (!strcmp(text, dm_refcmp_layout_name((dm_refcmp_layout)i))) {
            *l = (dm_refcmp_layout)i;
            return true;
        }
    return false;
}

static int font_scale(int out_width)
{
    return out_width >= 1100 ? 2 : 1;
}

int dm_refcmp_legend_height(int out_width)
{
    int s = font_scale(out_width);
    return 6 * s + 12 * s + 3 * (DM_FONT_H + 4) * s + 4 * (DM_FONT_H + 4) * s + 4 * s;
}

static const uint8_t c_bg[3] = {24, 24, 28}, c_text[3] = {235, 235, 235}, c_dim[3] = {150, 150, 155},
                     c_none[3] = {48, 48, 52}, c_mismatch[3] = {255, 0, 255}, c_label_bg[3] = {0, 0, 0};

/* The display white: the 99th percentile of the reference's largest channel where covered. */
static double display_white(const float *ref, int width, int height)
{
    size_t n = (size_t)width * height, k = 0;
    float *v = malloc(n * sizeof *v);
    if (!v) return 1.0;
    for (size_t i = 0; i < n; ++i) {
        if (ref[i * 4 + 3] < 0.5f) continue;
        float m = ref[i * 4] > ref[i * 4 + 1] ? ref[i * 4] : ref[i * 4 + 1];
        v[k++] = m > ref[i * 4 + 2] ? m : ref[i * 4 + 2];
    }
    double w = 1.0;
    if (k) {
        dm_sort_floats(v, k);
        w = v[(size_t)(0.99 * (double)(k - 1))];
    }
    free(v);
    return w > 1e-12 ? w : 1.0;
}

typedef enum source { SRC_REF, SRC_RENDER, SRC_ERROR, SRC_SPLIT } source;

/* One panel: the image fitted into (x0, y0, pw, ph) (top-down), nearest sample. */
static void draw_panel(uint8_t *out, int ow, int oh, int x0, int y0, int pw, int ph, source src, const float *ref,
                       const float *render, const float *rel, int w, int h, double white, double scale, float split,
                       const char *label)
{
    double f = fmin((double)pw / w, (double)ph / h);
    int dw = (int)(w * f), dh = (int)(h * f);
    int ox = x0 + (pw - dw) / 2, oy = y0 + (ph - dh) / 2;
    int split_x = (int)lrint(split * dw);
    for (int j = 0; j < dh; ++j) {
        int sy = h - 1 - (int)((j + 0.5) / f); /* image rows are bottom-up */
        if (sy < 0) sy = 0;
        for (int i = 0; i < dw; ++i) {
            int sx = (int)((i + 0.5) / f);
            if (sx >= w) sx = w - 1;
            size_t s = (size_t)sy * w + sx;
            uint8_t c[3];
            source use = src == SRC_SPLIT ? (i < split_x ? SRC_REF : SRC_RENDER) : src;
            if (use == SRC_ERROR) {
                if (rel[s] == -1.0f) memcpy(c, c_none, 3);
                else if (rel[s] < 0) memcpy(c, c_mismatch, 3);
                else dm_render_turbo(rel[s] / scale, c);
            } else {
                const float *p = (use == SRC_REF ? ref : render) + s * 4;
                if (p[3] < 0.5f) memcpy(c, c_none, 3);
                else
                    for (int k = 0; k < 3; ++k) c[k] = dm_srgb8_from_linear(p[k] / white);
            }
            if (src == SRC_SPLIT && (i == split_x || i == split_x - 1)) memset(c, 255, 3);
            dm_font_fill(out, ow, oh, ox + i, oy + j, 1, 1, c);
        }
    }
    int s = font_scale(ow);
    dm_font_fill(out, ow, oh, ox, oy, dm_font_width(label, s) + 6 * s, (DM_FONT_H + 6) * s, c_label_bg);
    dm_font_draw(out, ow, oh, ox + 3 * s, oy + 3 * s, s, c_text, label);
}

static void pct(char *out, size_t size, double v)
{
    snprintf(out, size, "%.3g%%", 100 * v);
}

void dm_refcmp_compose(const float *ref, const float *render, const float *rel, int width, int height,
                       const dm_refcmp_stats *st, const dm_refcmp_view *view, uint8_t *rgba, int out_width,
                       int out_height)
{
    const double scale = view->error_scale > 0 ? view->error_scale : DM_REFCMP_DEFAULT_ERROR_SCALE;
    /* the legend's width: clear of the right margin unless that leaves it too narrow */
    const int lw = out_width - view->margin_right_px >= 400 ? out_width - view->margin_right_px : out_width;
    const int s = font_scale(lw), legend = dm_refcmp_legend_height(lw) + view->margin_bottom_px;
    dm_font_fill(rgba, out_width, out_height, 0, 0, out_width, out_height, c_bg);
    const int ph = out_height - legend > 1 ? out_height - legend : 1;
    const double white = display_white(ref, width, height);
    char label[128];
    if (view->layout == DM_REFCMP_SIDE_BY_SIDE) {
        int pw = out_width / 3;
        draw_panel(rgba, out_width, out_height, 0, 0, pw, ph, SRC_REF, ref, render, rel, width, height, white, scale,
                   0, "REFERENCE");
        draw_panel(rgba, out_width, out_height, pw, 0, pw, ph, SRC_RENDER, ref, render, rel, width, height, white,
                   scale, 0, "RENDER");
        draw_panel(rgba, out_width, out_height, 2 * pw, 0, pw, ph, SRC_ERROR, ref, render, rel, width, height, white,
                   scale, 0, "RELATIVE ERROR");
    } else if (view->layout == DM_REFCMP_SPLIT) {
        float sp = view->split < 0 ? 0 : view->split > 1 ? 1 : view->split;
        snprintf(label, sizeof label, "REFERENCE | RENDER  (SPLIT AT %.0f%%)", 100.0 * sp);
        draw_panel(rgba, out_width, out_height, 0, 0, out_width, ph, SRC_SPLIT, ref, render, rel, width, height, white,
                   scale, sp, label);
    } else {
        draw_panel(rgba, out_width, out_height, 0, 0, out_width, ph, SRC_ERROR, ref, render, rel, width, height, white,
                   scale, 0, "RELATIVE ERROR");
    }

    /* legend: colour bar with its numbers, then the definition and the statistics */
    int x = 8 * s, y = ph + 6 * s;
    int bar_w = lw / 2 - 16 * s > 64 ? lw / 2 - 16 * s : 64, bar_h = 12 * s;
    int tx = x + bar_w + 8 * s;
    dm_font_fill(rgba, out_width, out_height, tx, y, 5 * s, bar_h, c_mismatch);
    tx = dm_font_draw(rgba, out_width, out_height, tx + 8 * s, y + 2 * s, s, c_dim, "COVERAGE DIFFERS  ");
    dm_font_fill(rgba, out_width, out_height, tx, y, 5 * s, bar_h, c_none);
    dm_font_draw(rgba, out_width, out_height, tx + 8 * s, y + 2 * s, s, c_dim, "NOT COMPARED");
    y = dm_render_colour_bar(rgba, out_width, out_height, x, y, bar_w, bar_h, s, 0.0, scale, pct, true);
    char line[256];
    snprintf(line, sizeof line, "ERROR = |RENDER - REF| / MAX(REF, FLOOR), FLOOR = %g%% OF MEAN REF", 100 * DM_REFCMP_FLOOR_FRACTION);
    dm_font_draw(rgba, out_width, out_height, x, y, s, c_dim, line);
    y += (DM_FONT_H + 4) * s;
    snprintf(line, sizeof line, "N = %ld (BOTH ALPHAS 1)   DISPLAY: VALUE / %.3g", st->count, white);
    dm_font_draw(rgba, out_width, out_height, x, y, s, c_dim, line);
    y += (DM_FONT_H + 4) * s;
    static const char chn[3] = {'R', 'G', 'B'};
    for (int c = 0; c < 3; ++c) {
        char m[32], p[32], mx[32];
        pct(m, sizeof m, st->mean[c]);
        pct(p, sizeof p, st->p95[c]);
        pct(mx, sizeof mx, st->max[c]);
        snprintf(line, sizeof line, "%c  MEAN %s  P95 %s  MAX %s", chn[c], m, p, mx);
        dm_font_draw(rgba, out_width, out_height, x, y, s, c_text, line);
        y += (DM_FONT_H + 4) * s;
    }
}
