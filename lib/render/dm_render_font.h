/* dm_render_font.h — a tiny built-in 5x7 bitmap font for labels and legends drawn into
 * RGBA8 images on the CPU (comparison panels, dm_render_refcmp.h). Digits, A–Z (lower
 * case is drawn as upper case), space and . , : % - + / | ( ) = [ ] _ ; anything else is
 * drawn as a small box. Coordinates are top-down (x right, y down from the top row) while
 * the image is bottom-up in memory, as every dermis image; drawing clips to the image. */
#ifndef DM_RENDER_FONT_H
#define DM_RENDER_FONT_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_FONT_W = 5, DM_FONT_H = 7, DM_FONT_ADVANCE = 6 }; /* pixels at scale 1 */

/* Draws text with its top-left corner at (x, y), each font pixel scale×scale. Returns the
 * x after the last glyph. */
int dm_font_draw(uint8_t *rgba, int width, int height, int x, int y, int scale, const uint8_t color[3],
                 const char *text);
/* Width in pixels of text at scale. */
int dm_font_width(const char *text, int scale);
/* Fills a rectangle (top-down coordinates, clipped). */
void dm_font_fill(uint8_t *rgba, int width, int height, int x, int y, int w, int h, const uint8_t color[3]);

#ifdef __cplusplus
}
#endif
#endif
