/* dm_render_legend.h — colour scales drawn into RGBA8 pictures on the CPU: the turbo colour
 * map and a colour bar with numbered ticks (the reference comparison's error scale, the
 * stretch and curvature views' scales). Top-down coordinates on bottom-up images, as
 * dm_render_font.h. */
#ifndef DM_RENDER_LEGEND_H
#define DM_RENDER_LEGEND_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Turbo colour map (Mikhailov 2019, polynomial fit; shaders/view.glsl has the same), t in
 * [0, 1] (clamped), as 8-bit sRGB. */
void dm_render_turbo(double t, uint8_t out[3]);

/* Writes the label of tick value v into out. */
typedef void (*dm_legend_format)(char *out, size_t size, double v);

/* A bar_w x bar_h turbo bar at (x, y), then below it ticks from lo to hi labelled by fmt
 * (as many as fit without overlapping, at most 4 intervals; "+" after the last when
 * open_top), at font scale s. Returns the y below the labels. */
int dm_render_colour_bar(uint8_t *rgba, int width, int height, int x, int y, int bar_w, int bar_h, int s, double lo,
                         double hi, dm_legend_format fmt, bool open_top);

/* A scalar view's picture with its legend: the top `height - dm_render_scalar_legend_height`
 * rows keep the picture (scaled to fit, left as drawn), the strip below gets the colour bar
 * from lo to hi, the quantity's name and where the range comes from (NULL: the 1st to 99th
 * percentile over the charts). */
int dm_render_scalar_legend_height(int width);
void dm_render_scalar_legend(uint8_t *rgba, int width, int height, double lo, double hi, const char *quantity,
                             const char *range);

#ifdef __cplusplus
}
#endif
#endif
