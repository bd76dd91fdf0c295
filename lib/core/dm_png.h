/* dm_png.h — a small, deterministic PNG encoder over zlib, for 8/16-bit grey, grey+alpha,
 * RGB and RGBA. Used by the bakes and by the runtime, which must not link OpenImageIO
 * (DESIGN.md); OpenImageIO alone adds ~0.3 s to a process's start (measured, Debian 12).
 * Reading PNG (and every other format) goes through image/dm_image.h.
 *
 * Pixels are interleaved, rows bottom-up (row 0 is v ≈ 0), 16-bit values in host order;
 * the encoder flips and byte-swaps. Text chunks (tEXt, Latin-1 keys of 1..79 bytes) carry
 * provenance: "Software" = "<tool> <version>" and "dermis:provenance" = the JSON of
 * dm_prov_to_json. No time chunk: the same pixels and text give the same bytes.
 */
#ifndef DM_PNG_H
#define DM_PNG_H

#include <stdint.h>

#include "core/dm_prov.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_png_text {
    const char *key;
    const char *value;
} dm_png_text;

/* Writes through a temporary file renamed into place (core/dm_file.h). bits is 8 or 16,
 * channels 1..4. prov (may be NULL) adds the two provenance chunks; extra text chunks
 * (text_count of them, may be 0) follow. */
dm_result dm_png_write_pixels(const char *path, int width, int height, int channels, int bits, const void *pixels,
                              const dm_provenance *prov, const dm_png_text *text, int text_count, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
