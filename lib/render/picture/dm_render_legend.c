/* dm_render_legend.c — colour scales on the CPU (dm_render_legend.h). */
#include "render/dm_render_legend.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/dm_render_font.h"

static const uint8_t c_bg[3] = {24, 24, 28}, c_text[3] = {235, 235, 235};

void dm_render_turbo(double t, uint8_t out[3])
{
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    double r = 0.13572138 + t * (4.61539260 + t * (-42.66032258 + t * (132.13108234 + t * (-152.94239396 + t * 59.28637943))));
    double g = 0.09140261 + t * (2.19418839 + t * (4.84296658 + t * (-14.18503333 + t * (4.27729857 + t * 2.82956604))));
    double b = 0.10667330 + t * (12.64194608 + t * (-60.58204836 + t * (110.36276771 + t * (-89.90310912 + t * 27.34824973))));
    double v[3] = {r, g, b};
    for (int c = 0; c < 3; ++c) out[c] = (uint8_t)lrint(255.0 * (v[c] < 0 ? 0 : v[c] > 1 ? 1 : v[c]));
}

int dm_render_colour_bar(uint8_t *rgba, int width, int height, int x, int y, int bar_w, int bar_h, int s, double lo,
                         double hi, dm_legend_format fmt, bool open_top)
{
    for (int i = 0; i < bar_w; ++i) {
        uint8_t c[3];
        dm_render_turbo((i + 0.5) / bar_w, c);
        dm_font_fill(rgba, width, height, x + i, y, 1, bar_h, c);
    }
    y += bar_h + 2 * s;
    const int ticks = bar_w >= 240 * s ? 4 : bar_w >= 120 * s ? 2 : 1; /* labels never overlap */
    for (int t = 0; t <= ticks; ++t) {
        char num[32];
        fmt(num, sizeof num, lo + (hi - lo) * t / ticks);
        if (t == ticks && open_top) snprintf(num + strlen(num), sizeof num - strlen(num), "+");
        int px = x + (int)lrint((double)bar_w * t / ticks);
        dm_font_fill(rgba, width, height, px, y - 2 * s, s, 3 * s, c_text);
        int tw = dm_font_width(num, s);
        int lx = t == 0 ? px : t == ticks ? px - tw : px - tw / 2;
        dm_font_draw(rgba, width, height, lx, y + 2 * s, s, c_text, num);
    }
    return y + (DM_FONT_H + 6) * s;
}

static int legend_scale(int width)
{
    return width >= 1100 ? 2 : 1;
}

int dm_render_scalar_legend_height(int width)
{
    int s = legend_scale(width);
    return 6 * s + 12 * s + 2 * s + (DM_FONT_H + 6) * s + (DM_FONT_H + 4) * s + 4 * s;
}

static void general(char *out, size_t size, double v)
{
    snprintf(out, size, "%.3g", v);
}

void dm_render_scalar_legend(uint8_t *rgba, int width, int height, double lo, double hi, const char *quantity,
                             const char *range)
{
    int s = legend_scale(width), lh = dm_render_scalar_legend_height(width);
    if (lh > height) return;
    dm_font_fill(rgba, width, height, 0, height - lh, width, lh, c_bg);
    int x = 8 * s, y = height - lh + 6 * s, bar_w = width - 16 * s > 32 ? width - 16 * s : width;
    y = dm_render_colour_bar(rgba, width, height, x, y, bar_w, 12 * s, s, lo, hi, general, false);
    char line[160];
    snprintf(line, sizeof line, "%s (%s)", quantity ? quantity : "VALUE", range ? range : "1ST TO 99TH PERCENTILE OVER THE CHARTS");
    dm_font_draw(rgba, width, height, x, y, s, c_text, line);
}
