/* gltf_write.h — a tiny glTF writer for tests: GLB containers from JSON + binary chunk,
 * base64 for data URIs, and a dm_mesh as a GLB (independent of the reader under test:
 * plain fwrite of the layout the glTF 2.0 spec gives). */
#ifndef TEST_GLTF_WRITE_H
#define TEST_GLTF_WRITE_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/dm_mesh.h"

static inline void glb_u32(FILE *f, uint32_t v)
{
    unsigned char b[4] = {(unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16), (unsigned char)(v >> 24)};
    fwrite(b, 1, 4, f);
}

/* Writes a GLB: 12-byte header, JSON chunk (padded with spaces), BIN chunk (zeros) when
 * bin_size > 0. Returns 0 on success. */
static inline int test_write_glb(const char *path, const char *json, const void *bin, size_t bin_size)
{
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    size_t jn = strlen(json), jp = (jn + 3) & ~(size_t)3, bp = (bin_size + 3) & ~(size_t)3;
    size_t total = 12 + 8 + jp + (bin_size ? 8 + bp : 0);
    fwrite("glTF", 1, 4, f);
    glb_u32(f, 2);
    glb_u32(f, (uint32_t)total);
    glb_u32(f, (uint32_t)jp);
    fwrite("JSON", 1, 4, f);
    fwrite(json, 1, jn, f);
    for (size_t i = jn; i < jp; ++i) fputc(' ', f);
    if (bin_size) {
        glb_u32(f, (uint32_t)bp);
        fwrite("BIN\0", 1, 4, f);
        fwrite(bin, 1, bin_size, f);
        for (size_t i = bin_size; i < bp; ++i) fputc(0, f);
    }
    return fclose(f) == 0 ? 0 : -1;
}

static inline int test_write_bytes(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    size_t n = fwrite(data, 1, size, f);
    return fclose(f) == 0 && n == size ? 0 : -1;
}

/* Standard base64 of data into a malloc'd string. */
static inline char *test_base64(const void *data, size_t size)
{
    static const char t[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const unsigned char *p = data;
    char *s = malloc((size + 2) / 3 * 4 + 1), *o = s;
    for (size_t i = 0; i < size; i += 3) {
        uint32_t v = (uint32_t)p[i] << 16 | (i + 1 < size ? (uint32_t)p[i + 1] << 8 : 0) | (i + 2 < size ? p[i + 2] : 0);
        *o++ = t[v >> 18 & 63];
        *o++ = t[v >> 12 & 63];
        *o++ = i + 1 < size ? t[v >> 6 & 63] : '=';
        *o++ = i + 2 < size ? t[v & 63] : '=';
    }
    *o = '\0';
    return s;
}

/* The mesh as a GLB: one vertex per (position index, corner UV, corner normal) —
 * glTF's split at seams —, POSITION, NORMAL, TEXCOORD_0 (v_glTF = 1 − v), u32
 * indices, one node, no transform. Returns 0 on success. */
static inline int test_glb_from_mesh(const dm_mesh *m, const char *path)
{
    size_t corners = (size_t)m->triangle_count * 3;
    float *pos = malloc(corners * 12), *nrm = malloc(corners * 12), *uv = malloc(corners * 8);
    uint32_t *idx = malloc(corners * 4);
    size_t nv = 0;
    /* split: a vertex is reused when the previous corner with the same position had
     * the same UV and normal (a per-position chain of candidates, linear scan) */
    int64_t *last = malloc((size_t)m->vertex_count * sizeof *last), *prev = malloc(corners * sizeof *prev);
    for (int32_t i = 0; i < m->vertex_count; ++i) last[i] = -1;
    for (size_t c = 0; c < corners; ++c) {
        uint32_t p = m->indices[c];
        float u = m->uvs[c * 2], v = 1.0f - m->uvs[c * 2 + 1];
        int64_t found = -1;
        for (int64_t k = last[p]; k >= 0; k = prev[k])
            if (uv[k * 2] == u && uv[k * 2 + 1] == v && !memcmp(nrm + k * 3, m->normals + c * 3, 12)) {
                found = k;
                break;
            }
        if (found < 0) {
            found = (int64_t)nv++;
            memcpy(pos + found * 3, m->positions + (size_t)p * 3, 12);
            memcpy(nrm + found * 3, m->normals + c * 3, 12);
            uv[found * 2] = u, uv[found * 2 + 1] = v;
            prev[found] = last[p];
            last[p] = found;
        }
        idx[c] = (uint32_t)found;
    }
    size_t bin_size = nv * 12 * 2 + nv * 8 + corners * 4;
    unsigned char *bin = malloc(bin_size);
    memcpy(bin, pos, nv * 12);
    memcpy(bin + nv * 12, nrm, nv * 12);
    memcpy(bin + nv * 24, uv, nv * 8);
    memcpy(bin + nv * 32, idx, corners * 4);
    char json[4096];
    snprintf(json, sizeof json,
             "{\"asset\":{\"version\":\"2.0\",\"generator\":\"dermis tests\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
             "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"name\":\"head\",\"primitives\":[{\"attributes\":"
             "{\"POSITION\":0,\"NORMAL\":1,\"TEXCOORD_0\":2},\"indices\":3}]}],"
             "\"buffers\":[{\"byteLength\":%zu}],\"bufferViews\":["
             "{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},"
             "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\"},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\"},"
             "{\"bufferView\":2,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC2\"},"
             "{\"bufferView\":3,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}]}",
             bin_size, nv * 12, nv * 12, nv * 12, nv * 24, nv * 8, nv * 32, corners * 4, nv, nv, nv, corners);
    int r = test_write_glb(path, json, bin, bin_size);
    free(pos), free(nrm), free(uv), free(idx), free(last), free(prev), free(bin);
    return r;
}

#endif
