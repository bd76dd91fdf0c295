/* dm_exr.h — OpenEXR through the OpenEXR Core C API: write and read float/half planes
 * with provenance.
 *
 * Images in memory are planar float, rows bottom-up (row 0 is v ≈ 0, as OpenGL and the
 * OBJ UV convention have it); files are top-down as EXR defines, the flip happens here.
 * Provenance is written twice: one attribute "dermis.provenance" holding the JSON of
 * dm_prov_to_json (read back by dm_exr_read), and one typed attribute per parameter,
 * "dm.<name>" (int, double or string), plus "dm.tool", "dm.version", "dm.input_hash",
 * so `exrheader` shows them. Compression is ZIP (lossless, deterministic).
 */
#ifndef DM_EXR_H
#define DM_EXR_H

#include "core/dm_prov.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum dm_exr_type { DM_EXR_HALF = 1, DM_EXR_FLOAT = 2 } dm_exr_type;

typedef struct dm_exr_channel {
    const char *name;  /* e.g. "R", "stretch0.u"; unique within the file */
    const float *data; /* width*height floats, rows bottom-up */
    dm_exr_type type;  /* storage type in the file */
} dm_exr_channel;

/* Writes an EXR through a temporary file renamed into place (dm_file.h). Values are
 * written as given: callers check finiteness where their format requires it. */
dm_result dm_exr_write(const char *path, int width, int height, const dm_exr_channel *channels,
                       int channel_count, const dm_provenance *prov, dm_error *err);

/* What dm_exr_read accepts: sides up to the largest texture dermis makes, at most 2^30
 * floats in all (an 8192² stretch chain of 13 channels is 0.87·2^30). */
enum { DM_EXR_NAME_SIZE = 256, DM_EXR_SIDE_MAX = 16384 };
#define DM_EXR_FLOATS_MAX ((int64_t)1 << 30)

typedef struct dm_exr_image {
    int width, height;
    int channel_count;
    char (*names)[DM_EXR_NAME_SIZE]; /* channel_count names, in the file's (sorted) order */
    float **planes;                  /* channel_count planes of width*height, rows bottom-up */
    int has_provenance;              /* 1 when "dermis.provenance" was present and parsed */
    dm_provenance prov;
} dm_exr_image;

/* Reads every channel of the first part of a scanline or tiled EXR as float. Free with
 * dm_exr_free, also after a failure (it is then empty). DM_ERR_FORMAT for a side beyond
 * DM_EXR_SIDE_MAX or more than DM_EXR_FLOATS_MAX values: OpenEXR allocates a chunk's
 * buffers from the header before it reads (a chunk claiming more bytes than the file holds
 * is refused by OpenEXR's own leader check). */
dm_result dm_exr_read(const char *path, dm_exr_image *out, dm_error *err);
void dm_exr_free(dm_exr_image *img);
/* The plane of the named channel, or NULL. */
const float *dm_exr_find(const dm_exr_image *img, const char *name);

#ifdef __cplusplus
}
#endif
#endif
