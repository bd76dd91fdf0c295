/* dm_pack_write.h — builds a .dpk pack (format: pack/dm_pack.h) and writes it safely.
 *
 *   dm_pack_writer w;
 *   dm_pack_writer_init(&w);
 *   dm_pack_entry d = {.kind = DM_PACK_TEXTURE, .format = DM_TEX_R8, .width = 512, ...};
 *   snprintf(d.name, sizeof d.name, "lut.beckmann");
 *   dm_pack_writer_add(&w, &d, texels, &prov, &err);   // copies texels
 *   dm_pack_writer_write(&w, "head.dpk", &pack_prov, &err);
 *   dm_pack_writer_free(&w);
 *
 * Entries are written in the order added. Output is deterministic: the same entries,
 * data and provenance give the same bytes.
 */
#ifndef DM_PACK_WRITE_H
#define DM_PACK_WRITE_H

#include <stddef.h>
#include <stdint.h>

#include "pack/dm_pack.h"
#include "core/dm_prov.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_pack_blob {
    dm_pack_entry desc; /* desc.size is the blob's size; desc.data is unused */
    void *data;         /* owned copy */
    char *provenance_json;
} dm_pack_blob;

typedef struct dm_pack_writer {
    int count, capacity;
    dm_pack_blob *blobs;
} dm_pack_writer;

/* The descriptor of a single-level, single-layer texture entry. */
dm_pack_entry dm_pack_texture_entry(const char *name, dm_tex_format f, int w, int h);

void dm_pack_writer_init(dm_pack_writer *w);
/* Adds an entry: desc gives name, kind and the kind's fields; data is copied. For the
 * JSON kinds (profile, scene) data is the text and size its strlen; for the others size
 * must equal what the descriptor implies (dm_pack_entry_expected_size). Refuses a bad
 * descriptor, a duplicate name and non-finite floats, naming the entry. prov may not be NULL. */
dm_result dm_pack_writer_add(dm_pack_writer *w, const dm_pack_entry *desc, const void *data, size_t size,
                             const dm_provenance *prov, dm_error *err);
/* The whole pack in memory (malloc'd, 64-byte aligned; free with free()). */
dm_result dm_pack_writer_build(const dm_pack_writer *w, const dm_provenance *pack_prov, uint8_t **out,
                               size_t *out_size, dm_error *err);
/* Builds and writes to path through a temporary file, fsync and rename (core/dm_file.h). */
dm_result dm_pack_writer_write(const dm_pack_writer *w, const char *path, const dm_provenance *pack_prov,
                               size_t *written_size, dm_error *err);
void dm_pack_writer_free(dm_pack_writer *w);

#ifdef __cplusplus
}
#endif
#endif
