/* gltf_quad.h — the glTF tests' fixture: a folder per test (setup, in_dir) and a unit quad
 * written as GLB or glTF with the variation a test asks for (index type, data URI or
 * external buffer, extra node/primitive/accessor JSON, an embedded image) — test_gltf,
 * test_gltf_bake. */
#ifndef TEST_GLTF_QUAD_H
#define TEST_GLTF_QUAD_H

#include <criterion/criterion.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/dm_mesh.h"
#include "gltf_write.h"
#include "tmpdir.h"

static char dir[512]; /* the test's own folder (setup) */

static inline void setup(void)
{
    cr_assert_not_null(test_tmpdir(dir, sizeof dir));
}

static inline const char *in_dir(const char *name)
{
    static char path[16][768]; /* a ring: up to 16 paths in use at once */
    static int k;
    k = (k + 1) % 16;
    snprintf(path[k], sizeof path[k], "%s/%s", dir, name);
    return path[k];
}

/* ---- the unit quad fixture ----------------------------------------------------------
 * Positions (0,0,0) (1,0,0) (1,1,0) (0,1,0), dermis UVs equal to (x, y) — stored in
 * glTF as (x, 1 − y) —, normals +z, triangles 0 1 2 and 0 2 3. */
typedef struct quad_opts {
    int index_type;         /* 5121, 5123, 5125; 0 = 5123 */
    const char *attributes; /* NULL = POSITION, TEXCOORD_0, NORMAL */
    const char *node_extra, *prim_extra, *top_extra, *accessor0_extra;
    int position_count;     /* 0 = 4 */
    const char *buffer;     /* NULL: the GLB chunk; "data": a data URI (.gltf); "file": quad.bin beside */
    uint32_t index_value[6];
    int set_indices;
    const void *png;        /* embedded baseColor image (bufferView 5), with an external
                             * normal map "normal.png" beside the file: material 0 */
    size_t png_size;
} quad_opts;

static inline const char *write_quad(const char *name, const quad_opts *o)
{
    unsigned char bin[216 + 4096];
    memset(bin, 0, sizeof bin);
    cr_assert_leq(o->png_size, 4096);
    const float pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    const float nrm[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    if (o->set_indices) memcpy(idx, o->index_value, sizeof idx);
    memcpy(bin, pos, 48);
    memcpy(bin + 48, uv, 32);
    memcpy(bin + 80, nrm, 48);
    int type = o->index_type ? o->index_type : 5123, isize = type == 5121 ? 1 : type == 5123 ? 2 : 4;
    for (int i = 0; i < 6; ++i)
        for (int b = 0; b < isize; ++b) bin[128 + i * isize + b] = (unsigned char)(idx[i] >> (8 * b));
    const float tan[16] = {1, 0, 0, -1, 1, 0, 0, -1, 1, 0, 0, -1, 1, 0, 0, -1}; /* accessor 4 */
    memcpy(bin + 152, tan, 64);
    size_t bin_size = 220; /* bufferView 5: 4 zero bytes unless an image is embedded */
    char material[1024] = "", prim_material[32] = "";
    if (o->png) {
        memcpy(bin + 216, o->png, o->png_size);
        bin_size = 216 + ((o->png_size + 3) & ~(size_t)3);
        snprintf(material, sizeof material,
                 ",\"images\":[{\"bufferView\":5,\"mimeType\":\"image/png\"},{\"uri\":\"normal.png\"}],"
                 "\"textures\":[{\"source\":0},{\"source\":1}],\"materials\":[{\"pbrMetallicRoughness\":"
                 "{\"baseColorTexture\":{\"index\":0}},\"normalTexture\":{\"index\":1}}]");
        snprintf(prim_material, sizeof prim_material, ",\"material\":0");
    }
    char uri[1024] = "";
    char *b64 = NULL;
    const char *path = in_dir(name);
    if (o->buffer && !strcmp(o->buffer, "data")) {
        b64 = test_base64(bin, bin_size);
        snprintf(uri, sizeof uri, ",\"uri\":\"data:application/octet-stream;base64,%s\"", b64);
    } else if (o->buffer && !strcmp(o->buffer, "file")) {
        cr_assert_eq(test_write_bytes(in_dir("quad.bin"), bin, bin_size), 0);
        snprintf(uri, sizeof uri, ",\"uri\":\"quad.bin\"");
    }
    char json[4096];
    snprintf(json, sizeof json,
             "{\"asset\":{\"version\":\"2.0\"}%s,\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
             "\"nodes\":[{\"mesh\":0%s}],"
             "\"meshes\":[{\"name\":\"quad\",\"primitives\":[{\"attributes\":{%s},\"indices\":3%s%s}]}]%s,"
             "\"buffers\":[{\"byteLength\":%zu%s}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},"
             "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":32},{\"buffer\":0,\"byteOffset\":80,\"byteLength\":48},"
             "{\"buffer\":0,\"byteOffset\":128,\"byteLength\":%d},{\"buffer\":0,\"byteOffset\":152,\"byteLength\":64},"
             "{\"buffer\":0,\"byteOffset\":216,\"byteLength\":%zu}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%d,\"type\":\"VEC3\"%s},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"},"
             "{\"bufferView\":2,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
             "{\"bufferView\":3,\"componentType\":%d,\"count\":6,\"type\":\"SCALAR\"},"
             "{\"bufferView\":4,\"componentType\":5126,\"count\":4,\"type\":\"VEC4\"}]}",
             o->top_extra ? o->top_extra : "", o->node_extra ? o->node_extra : "",
             o->attributes ? o->attributes : "\"POSITION\":0,\"TEXCOORD_0\":1,\"NORMAL\":2",
             o->prim_extra ? o->prim_extra : "", prim_material, material, bin_size, uri, 6 * isize,
             o->png ? o->png_size : (size_t)4,
             o->position_count ? o->position_count : 4, o->accessor0_extra ? o->accessor0_extra : "", type);
    free(b64);
    if (o->buffer)
        cr_assert_eq(test_write_bytes(path, json, strlen(json)), 0);
    else
        cr_assert_eq(test_write_glb(path, json, bin, bin_size), 0);
    return path;
}

static inline void load_ok(const char *path, const dm_mesh_load_options *o, dm_mesh *m)
{
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(path, o, m, &err), DM_OK, "%s", err.detail);
}

#endif
