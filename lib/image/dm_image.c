#include "image/dm_image.h"

#include <assert.h>

#include "core/dm_png.h"

size_t dm_image_size(const dm_image *img)
{
    return (size_t)img->width * (size_t)img->height * (size_t)img->channels * (size_t)img->type;
}

dm_result dm_png_write(const char *path, const dm_image *img, const dm_provenance *prov, dm_error *err)
{
    assert(path && img && prov);
    if (img->type != DM_PIXEL_U8 && img->type != DM_PIXEL_U16)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: PNG holds 8 or 16 bits per channel only", path);
    return dm_png_write_pixels(path, img->width, img->height, img->channels, img->type == DM_PIXEL_U8 ? 8 : 16,
                               img->pixels, prov, NULL, 0, err);
}
