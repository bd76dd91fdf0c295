/* dm_exr_read.h — a small, strict OpenEXR reader for the runtime side, which never links
 * OpenEXR (DESIGN.md). It reads what dermis writes: lib/image/dm_exr.c (ZIP) and
 * lib/render/picture/dm_render_image.c (NO_COMPRESSION), and the usual files of other tools
 * that keep to the same subset.
 *
 * Supported: single-part scanline files (version 2; the long-names flag is accepted),
 * compression NO_COMPRESSION, ZIPS (1 line per chunk) or ZIP (16 lines per chunk), HALF
 * and FLOAT channels with sampling 1×1, any data window up to DM_EXR_READ_MAX_SIDE per
 * side, any line order (each chunk states its first line). Attributes other than
 * "channels", "compression", "dataWindow" and "dermis.provenance" are skipped by size.
 * Everything else (tiled, deep, multi-part, UINT channels, subsampling, other
 * compressions) is refused with DM_ERR_UNSUPPORTED; every malformed input (truncated,
 * overlapping or missing chunks, bad sizes, zlib errors, a data window that disagrees
 * with the data, NaN or Inf samples, a provenance attribute that does not parse) fails
 * with DM_ERR_FORMAT or DM_ERR_NON_FINITE and a message naming the file (or "what"),
 * the value and what was expected. Never reads outside the buffer; allocation is
 * bounded by the input size (decoded bytes ≤ 1100 × input bytes + one chunk, zlib's
 * ratio limit is ~1032), so a tiny file cannot ask for gigabytes.
 *
 * Images in memory are planar float, rows bottom-up (row 0 is the last file line, as
 * image/dm_exr.h and the rest of dermis have it); files are top-down.
 */
#ifndef DM_EXR_READ_H
#define DM_EXR_READ_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/dm_prov.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    DM_EXR_READ_MAX_CHANNELS = 64,
    DM_EXR_READ_NAME_SIZE = 256,  /* channel names, NUL included (EXR long names) */
    DM_EXR_READ_MAX_SIDE = 32768, /* texels per side */
};

typedef struct dm_exr_file {
    int width, height; /* the data window's size */
    int channel_count;
    char names[DM_EXR_READ_MAX_CHANNELS][DM_EXR_READ_NAME_SIZE]; /* sorted, as in the file */
    int types[DM_EXR_READ_MAX_CHANNELS];  /* 1 HALF, 2 FLOAT: the storage type in the file */
    int compression;                      /* 0 none, 2 ZIPS, 3 ZIP */
    float *planes;            /* channel_count planes of width*height floats, rows bottom-up */
    bool has_provenance;      /* "dermis.provenance" was present (and parsed into prov) */
    dm_provenance prov;
} dm_exr_file;

/* Decodes `size` bytes of an EXR file. `what` names the source in messages (a path).
 * On success out->planes is allocated: free with dm_exr_file_free, also after a failure
 * (out is then empty). */
dm_result dm_exr_decode(const uint8_t *data, size_t size, const char *what, dm_exr_file *out, dm_error *err);
/* Reads and decodes a file (DM_ERR_FILE_OPEN / DM_ERR_FILE_READ when it cannot be read). */
dm_result dm_exr_load(const char *path, dm_exr_file *out, dm_error *err);
void dm_exr_file_free(dm_exr_file *f);
/* The plane of the named channel (width*height floats, bottom-up), or NULL. */
const float *dm_exr_file_channel(const dm_exr_file *f, const char *name);

#ifdef __cplusplus
}
#endif
#endif
