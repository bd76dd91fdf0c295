/* dm_render_image.h — the runtime's image writers: 8-bit RGBA PNG (core/dm_png.h) and
 * an uncompressed float RGBA EXR written by hand, both with provenance. The runtime never links OpenImageIO
 * or OpenEXR (DESIGN.md); the offline side keeps image/dm_image.h and image/dm_exr.h.
 *
 * Pixels in memory are interleaved RGBA, rows bottom-up (OpenGL readback order); files
 * are top-down, the flip happens here. Both write through a temporary file renamed into
 * place (core/dm_file.h) and contain nothing time-dependent.
 * PNG: text chunks "Software" = "<tool> <version>" and "dermis:provenance" = the JSON of
 * dm_prov_to_json, as image/dm_image.h writes them, so either reader finds them.
 * EXR: scanline, NO_COMPRESSION, FLOAT channels A, B, G, R, and a string attribute
 * "dermis.provenance" (the same JSON) that image/dm_exr.h reads back.
 */
#ifndef DM_RENDER_IMAGE_H
#define DM_RENDER_IMAGE_H

#include <stdint.h>

#include "core/dm_prov.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* rgba: width*height*4 bytes. */
dm_result dm_render_write_png(const char *path, int width, int height, const uint8_t *rgba,
                              const dm_provenance *prov, dm_error *err);
/* rgba: width*height*4 floats, written as given; refused (DM_ERR_NON_FINITE, nothing
 * written) when one is NaN or infinite, the message naming the count and the first pixel. */
dm_result dm_render_write_exr(const char *path, int width, int height, const float *rgba,
                              const dm_provenance *prov, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
