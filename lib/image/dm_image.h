/* dm_image.h — reading any image format through OpenImageIO (a thin C++ adapter,
 * dm_image_oiio.cpp, behind this C header), and the dm_image value type.
 *
 * Pixels in memory are interleaved, rows bottom-up (row 0 is v ≈ 0: the OBJ/OpenGL
 * convention); files are top-down, the flip happens here. Writing PNG goes through
 * core/dm_png.h (no OpenImageIO: it costs ~0.3 s of process start); dm_png_write is the
 * dm_image-shaped front of it.
 */
#ifndef DM_IMAGE_H
#define DM_IMAGE_H

#include <stddef.h>

#include "core/dm_prov.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum dm_pixel_type { DM_PIXEL_U8 = 1, DM_PIXEL_U16 = 2, DM_PIXEL_F32 = 4 } dm_pixel_type;

typedef struct dm_image {
    int width, height, channels; /* channels 1..4 */
    dm_pixel_type type;          /* bytes per channel value = the enum's value */
    void *pixels;                /* width*height*channels values, interleaved, bottom-up */
    int has_provenance;          /* set by dm_image_read when "dermis:provenance" parsed */
    dm_provenance prov;
} dm_image;

/* Bytes of one image's pixels. */
size_t dm_image_size(const dm_image *img);

/* Writes img (DM_PIXEL_U8 or DM_PIXEL_U16) as PNG with its provenance (core/dm_png.h),
 * through a temporary file renamed into place. prov may not be NULL. */
dm_result dm_png_write(const char *path, const dm_image *img, const dm_provenance *prov, dm_error *err);

/* Reads the first subimage of any format OpenImageIO knows, converted to `type`
 * (U8/U16 keep stored integers exactly when the file has that depth; F32 gives the
 * file's values, with integer formats scaled to [0, 1]; colour is NOT linearized: JPEG
 * albedo stays sRGB-encoded). PNG alpha is read unassociated. Free with dm_image_free,
 * also after a failure. */
dm_result dm_image_read(const char *path, dm_pixel_type type, dm_image *out, dm_error *err);
void dm_image_free(dm_image *img);

#ifdef __cplusplus
}
#endif
#endif
