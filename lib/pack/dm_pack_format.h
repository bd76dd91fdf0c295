/* dm_pack_format.h — the .dpk pack format itself: its layout, the header's encoding, the
 * entry descriptor, the kinds and the texture format table, and the sizes a descriptor
 * implies. Depends on nothing else in lib/pack: the reader (pack/dm_pack.h), the verifier
 * and the writer (pack/dm_pack_write.h) stand on it.
 *
 * verified on open, handed out without copying.
 *
 * LAYOUT (all integers little-endian)
 *   [0, 64)      header
 *                  0  u8[8] magic  89 'D' 'P' 'K' 0D 0A 1A 0A   (DM_PACK_MAGIC)
 *                  8  u32   version                 DM_PACK_VERSION (1); what a reader accepts
 *                                                   and what bumps it: docs/dermis-dpk.5.md
 *                 12  u32   flags                   0; any set bit is refused (none defined)
 *                 16  u64   file_size               the whole file, bytes
 *                 24  u64   manifest_offset         64
 *                 32  u64   manifest_size           bytes of UTF-8 JSON, no NUL
 *                 40  u64   blobs_offset            align64(64 + manifest_size)
 *                 48  u64   reserved                0
 *                 56  u64   checksum                XXH3-64 of header bytes [0, 56) followed
 *                                                   by the manifest bytes
 *   [64, 64+manifest_size)   the manifest (JSON, below)
 *   then the blobs, in manifest order: the first at blobs_offset, each next one at
 *   align64(end of the previous), the file ending at the end of the last blob (or at
 *   blobs_offset when there is none). Every byte between is zero. So every byte of a valid
 *   file is covered by a checksum or must be zero: any single flipped bit is detected.
 *
 * MANIFEST
 *   { "format": "dermis-pack", "version": 1,
 *     "provenance": { ...dm_prov_to_json of the packer... },
 *     "entries": [ ENTRY, ... ] }
 *   ENTRY, common keys (all required):
 *     "name"   [a-z0-9._-], 1..63 chars, unique        "kind"   one of the kinds below
 *     "offset" bytes from the file start, multiple of 64 "size"  bytes
 *     "xxh3"   16 lowercase hex digits: XXH3-64 of the blob
 *     "provenance" { ...dm_prov_to_json of what made the blob... }
 *   Kinds and their extra keys (all required unless marked):
 *     "texture"   "format" (dm_tex_format names below), "width", "height" (1..16384),
 *                 "layers" (1..256), "levels" (1..1+log2(max(width, height))),
 *                 "channels" (optional: one name per component, e.g. ["scale", "bias"]),
 *                 "layer_values" (optional: one finite number per layer, at most 16: what
 *                 each layer stands for; env*.specular: the Beckmann m it is prefiltered
 *                 for), "t_range" (optional: [first, last], finite: the quantity the
 *                 rows span at their centres; sss.preintegrated: curvature in 1/mm).
 *                 Data the renderer needs comes from these keys, never from provenance.
 *                 Data: level-major, then layer, then rows bottom-up (row 0 is v ≈ 0, so
 *                 an upload of the bytes as they are gives texture(t, uv) = image(uv)),
 *                 texels tightly packed: set GL_UNPACK_ALIGNMENT to 1. Level l is
 *                 max(1, width>>l) × max(1, height>>l). Float formats hold finite values
 *                 only. 16f is IEEE half.
 *     "mesh.vertices"  "vertex_count" (≥ 1), "stride" (bytes, multiple of 4),
 *                 "attributes": [ {"name", "offset" (bytes), "components" (1..4),
 *                 "type": "float32"} ]. Data: interleaved float32, finite.
 *                 The dermis layout (DM_PACK_VERTEX_*): position xyz @0, normal xyz @12,
 *                 uv @24, tangent xyzw @32 (w = ±1 handedness), stride 48.
 *     "mesh.indices"   "index_count" (multiple of 3, ≥ 3), "type": "uint32",
 *                 "primitive": "triangles", "vertices": the mesh.vertices entry's name.
 *                 Every index < that entry's vertex_count.
 *     "env.sh"    "sh_order" (0..4). Data: (order+1)² × RGB float32, coefficients in the
 *                 order (l, m) = (0,0), (1,−1), (1,0), (1,1), (2,−2) ..., finite.
 *     "profile"   Data: a profile JSON (dm_profile.h form), the same Gaussians as the scene's
 *                 (DM_ERR_MISMATCH otherwise; renderers take the scene's).
 *     "scene"     Data: a complete scene JSON (dm_scene_to_json). Exactly one, named "scene".
 */
#ifndef DM_PACK_FORMAT_H
#define DM_PACK_FORMAT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define DM_PACK_MAGIC "\x89" "DPK\r\n\x1a\n"

enum {
    DM_PACK_VERSION = 1,
    DM_PACK_HEADER_SIZE = 64,
    DM_PACK_ALIGN = 64,
    DM_PACK_NAME_SIZE = 64,
    DM_PACK_MAX_ATTRIBUTES = 8,
    DM_PACK_MAX_CHANNELS = 4,
    DM_PACK_LAYER_VALUES_MAX = 16,
    DM_PACK_CHANNEL_NAME_SIZE = 24,
    DM_PACK_TEXTURE_SIZE_MAX = 16384,
    DM_PACK_LAYERS_MAX = 256,
    DM_PACK_SH_ORDER_MAX = 4,
    DM_PACK_MANIFEST_MAX = 16 << 20,
    DM_PACK_ENTRIES_MAX = 1024
};

/* The dermis vertex layout (DESIGN.md: split by position, uv, normal). */
enum {
    DM_PACK_VERTEX_STRIDE = 48,
    DM_PACK_VERTEX_POSITION = 0, /* xyz, mesh units */
    DM_PACK_VERTEX_NORMAL = 12,  /* xyz, unit */
    DM_PACK_VERTEX_UV = 24,      /* uv, v = 0 is the image's bottom row */
    DM_PACK_VERTEX_TANGENT = 32  /* xyz unit, w = ±1: bitangent = w · cross(normal, tangent) */
};

typedef enum dm_pack_kind {
    DM_PACK_TEXTURE = 0,
    DM_PACK_MESH_VERTICES,
    DM_PACK_MESH_INDICES,
    DM_PACK_ENV_SH,
    DM_PACK_PROFILE,
    DM_PACK_SCENE,
    DM_PACK_KIND_COUNT
} dm_pack_kind;

/* "texture", "mesh.vertices", ...; NULL for out-of-range values. */
const char *dm_pack_kind_name(dm_pack_kind k);
/* The kind with that name, or -1. */
int dm_pack_kind_from_name(const char *name);

typedef enum dm_tex_format {
    DM_TEX_R8 = 0,
    DM_TEX_RG8,
    DM_TEX_RGBA8,
    DM_TEX_RGBA8_SRGB, /* colour maps: the shader reads linear values through GL_SRGB8_ALPHA8 */
    DM_TEX_R16F,
    DM_TEX_RG16F,
    DM_TEX_RGBA16F,
    DM_TEX_R32F,
    DM_TEX_RG32F,
    DM_TEX_RGBA32F,
    DM_TEX_FORMAT_COUNT
} dm_tex_format;

typedef struct dm_tex_format_info {
    const char *name;      /* "r8", "rg8", "rgba8", "rgba8_srgb", "r16f", ... "rgba32f" */
    int components;        /* 1, 2 or 4 */
    int component_size;    /* bytes: 1, 2 or 4 */
    bool is_float;         /* 16f / 32f: must be finite */
    bool is_srgb;
} dm_tex_format_info;

/* Facts about a format; NULL for out-of-range values. */
const dm_tex_format_info *dm_tex_format_get(dm_tex_format f);
/* The format with that name, or -1. */
int dm_tex_format_from_name(const char *name);

typedef struct dm_vertex_attribute {
    char name[DM_PACK_CHANNEL_NAME_SIZE]; /* "position", "normal", "uv", "tangent", ... */
    int offset;                           /* bytes within the vertex */
    int components;                       /* float32 values, 1..4 */
} dm_vertex_attribute;

/* One entry. The reader fills it from the manifest; the writer takes one as the
 * descriptor of what it is given (offset, size, xxh3 and data are then ignored). */
typedef struct dm_pack_entry {
    char name[DM_PACK_NAME_SIZE];
    dm_pack_kind kind;
    uint64_t offset, size; /* bytes */
    uint64_t xxh3;
    const void *data;      /* reader: size bytes inside the mapping, 64-byte aligned */
    char *provenance_json; /* reader: owned by the pack, NUL-terminated */
    /* texture */
    dm_tex_format format;
    int width, height, layers, levels;
    int channel_count; /* 0 when the manifest names none */
    char channels[DM_PACK_MAX_CHANNELS][DM_PACK_CHANNEL_NAME_SIZE];
    int layer_value_count; /* 0, or layers: "layer_values" */
    float layer_values[DM_PACK_LAYER_VALUES_MAX];
    bool has_t_range;      /* "t_range" */
    float t_range[2];
    /* mesh.vertices */
    int64_t vertex_count;
    int stride;
    int attribute_count;
    dm_vertex_attribute attributes[DM_PACK_MAX_ATTRIBUTES];
    /* mesh.indices */
    int64_t index_count;
    char vertices[DM_PACK_NAME_SIZE];
    /* env.sh */
    int sh_order;
} dm_pack_entry;

/* Checks a descriptor's kind-specific fields and computes the blob size they imply
 * (textures: every level and layer; JSON kinds: any size ≥ 2). `what` prefixes messages. */
dm_result dm_pack_entry_expected_size(const dm_pack_entry *e, const char *what, uint64_t *size, dm_error *err);

/* Bytes of one level (all its layers) of a texture, and its offset from the blob start. */
uint64_t dm_pack_texture_level_size(const dm_pack_entry *e, int level);
uint64_t dm_pack_texture_level_offset(const dm_pack_entry *e, int level);

/* Header helpers shared with the writer: encode/decode the 64 bytes. */
typedef struct dm_pack_header {
    uint32_t version, flags;
    uint64_t file_size, manifest_offset, manifest_size, blobs_offset, reserved, checksum;
} dm_pack_header;
void dm_pack_header_encode(const dm_pack_header *h, uint8_t out[DM_PACK_HEADER_SIZE]);
/* The fields of the 64 bytes (magic not compared, values not checked: VERIFIED ON OPEN in pack/dm_pack.h does). */
void dm_pack_header_decode(const uint8_t in[DM_PACK_HEADER_SIZE], dm_pack_header *h);
/* The checksum field for a header (bytes [0, 56) used) and manifest. */
uint64_t dm_pack_header_checksum(const uint8_t header[DM_PACK_HEADER_SIZE], const void *manifest,
                                 size_t manifest_size);
/* 16 lowercase hex digits of v into out (17 bytes). */
void dm_pack_hex64(uint64_t v, char out[17]);

static inline uint64_t dm_pack_align(uint64_t x)
{
    return (x + (DM_PACK_ALIGN - 1)) & ~(uint64_t)(DM_PACK_ALIGN - 1);
}

/* Texels along one side at mip level `level` (at least 1). */
static inline uint64_t dm_pack_level_dim(int size, int level)
{
    uint64_t d = (uint64_t)size >> level;
    return d ? d : 1;
}

#ifdef __cplusplus
}
#endif
#endif
