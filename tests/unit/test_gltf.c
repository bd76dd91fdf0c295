/* glTF 2.0 meshes through dm_mesh_load: the head as OBJ and as GLB bakes the same
 * stretch, and every hard case (transforms, several primitives and meshes, index types,
 * data URIs, external buffers, computed normals, each malformed input) has its test. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image/dm_image.h"
#include "mesh/dm_mesh.h"
#include "bake/dm_stretch.h"
#include "core/dm_file.h"
#include "pack/dm_pack.h"
#include "core/dm_png.h"
#include "core/dm_scene.h"
#include "../common/gltf_write.h"
#include "../common/tmpdir.h"

static char dir[512];

static void setup(void)
{
    cr_assert_not_null(test_tmpdir(dir, sizeof dir));
}

TestSuite(gltf, .init = setup, .timeout = 60);

static const char *in_dir(const char *name)
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

static const char *write_quad(const char *name, const quad_opts *o)
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

static void load_ok(const char *path, const dm_mesh_load_options *o, dm_mesh *m)
{
    dm_error err = {0};
    cr_assert_eq(dm_mesh_load(path, o, m, &err), DM_OK, "%s", err.detail);
}

/* Fails with `code`, and the message names the file and contains `what`. */
static void load_fails(const char *path, dm_result code, const char *what)
{
    dm_mesh m;
    dm_error err = {0};
    dm_result r = dm_mesh_load(path, NULL, &m, &err);
    cr_assert_eq(r, code, "%s: got %s (%s), expected %s", path, dm_result_name(r), err.detail, dm_result_name(code));
    cr_assert_not_null(strstr(err.detail, path), "message does not name the file: %s", err.detail);
    cr_assert_not_null(strstr(err.detail, what), "message lacks \"%s\": %s", what, err.detail);
    cr_assert_null(m.positions);
}

static void expect_quad(const dm_mesh *m)
{
    cr_assert_eq(m->vertex_count, 4);
    cr_assert_eq(m->triangle_count, 2);
    /* corner c's dermis UV equals its position's (x, y) */
    for (int k = 0; k < 6; ++k) {
        const float *p = m->positions + m->indices[k] * 3;
        cr_assert_eq(m->uvs[k * 2], p[0], "corner %d u", k);
        cr_assert_eq(m->uvs[k * 2 + 1], p[1], "corner %d v (flipped from glTF)", k);
        cr_assert_float_eq(m->normals[k * 3 + 2], 1.0f, 1e-6);
    }
}

Test(gltf, glb_quad_reads_with_v_flipped)
{
    quad_opts o = {0};
    dm_mesh m;
    load_ok(write_quad("quad.glb", &o), NULL, &m);
    expect_quad(&m);
    cr_assert_eq(m.normals_from_file, 1);
    cr_assert_null(m.tangents);
    dm_mesh_free(&m);
}

Test(gltf, index_types_u8_u16_u32)
{
    const int types[3] = {5121, 5123, 5125};
    for (int k = 0; k < 3; ++k) {
        quad_opts o = {.index_type = types[k]};
        char name[32];
        snprintf(name, sizeof name, "quad%d.glb", types[k]);
        dm_mesh m;
        load_ok(write_quad(name, &o), NULL, &m);
        expect_quad(&m);
        cr_assert_eq(m.indices[4], 2u);
        cr_assert_eq(m.indices[5], 3u);
        dm_mesh_free(&m);
    }
}

Test(gltf, data_uri_buffer)
{
    quad_opts o = {.buffer = "data"};
    dm_mesh m;
    load_ok(write_quad("quad-data.gltf", &o), NULL, &m);
    expect_quad(&m);
    dm_mesh_free(&m);
}

Test(gltf, external_bin_beside_the_gltf)
{
    quad_opts o = {.buffer = "file"};
    const char *path = write_quad("quad-file.gltf", &o);
    dm_mesh m;
    /* from another working directory: the .bin resolves against the .gltf's folder */
    char cwd[1024];
    cr_assert_not_null(getcwd(cwd, sizeof cwd));
    cr_assert_eq(chdir("/"), 0);
    load_ok(path, NULL, &m);
    cr_assert_eq(chdir(cwd), 0);
    expect_quad(&m);
    dm_mesh_free(&m);
    unlink(in_dir("quad.bin"));
    load_fails(path, DM_ERR_FORMAT, "quad.bin");
}

Test(gltf, no_normals_computed_smooth_across_uv_seams)
{
    /* Two triangles folded 90° along the edge (0,0,0)-(0,1,0), the edge a UV seam: glTF
     * stores its two ends twice (different UVs). Welded, both sides share the computed
     * normal there: the normalised sum of the two face normals, (1, 0, 1)/√2 ... up to
     * orientation; and the two copies of a seam vertex have the same normal. */
    const float pos[18] = {0, 0, 0, 0, 1, 0, 1, 0, 0, /* +z face */ 0, 0, 0, 0, 0, 1, 0, 1, 0 /* +x face */};
    const float uv[12] = {0.5f, 1, 0.5f, 0, 1, 1, 0.5f, 1, 0, 1, 0.4f, 0};
    unsigned char bin[120];
    memcpy(bin, pos, 72);
    memcpy(bin + 72, uv, 48);
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,"
        "\"TEXCOORD_0\":1}}]}],\"buffers\":[{\"byteLength\":120}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":72},"
        "{\"buffer\":0,\"byteOffset\":72,\"byteLength\":48}],\"accessors\":[{\"bufferView\":0,\"componentType\":5126,"
        "\"count\":6,\"type\":\"VEC3\"},{\"bufferView\":1,\"componentType\":5126,\"count\":6,\"type\":\"VEC2\"}]}";
    const char *path = in_dir("fold.glb");
    cr_assert_eq(test_write_glb(path, json, bin, sizeof bin), 0);
    dm_mesh m;
    load_ok(path, NULL, &m);
    cr_assert_eq(m.normals_from_file, 0);
    cr_assert_eq(m.vertex_count, 4, "the seam's two copies are welded: %d positions", m.vertex_count);
    cr_assert_eq(m.triangle_count, 2);
    /* corners 0 and 3 are (0,0,0) on either side of the seam: same smooth normal */
    for (int d = 0; d < 3; ++d) cr_assert_eq(m.normals[0 * 3 + d], m.normals[3 * 3 + d]);
    double n0 = m.normals[0], n2 = m.normals[2];
    cr_assert_float_eq(fabs(n0), 1 / sqrt(2.0), 1e-6, "smooth normal x %g", n0);
    cr_assert_float_eq(fabs(n2), 1 / sqrt(2.0), 1e-6, "smooth normal z %g", n2);
    dm_mesh_free(&m);
}

Test(gltf, node_transforms_applied)
{
    /* translation (10, 0, 0), 90° about +z (quaternion (0, 0, sin 45°, cos 45°)), scale 2:
     * (1, 0, 0) → (2, 0, 0) rotated → (0, 2, 0) → translated (10, 2, 0). Normal stays +z. */
    quad_opts o = {.node_extra = ",\"translation\":[10,0,0],\"rotation\":[0,0,0.7071067811865476,0.7071067811865476],"
                                 "\"scale\":[2,2,2]"};
    dm_mesh m;
    load_ok(write_quad("quad-trs.glb", &o), NULL, &m);
    cr_assert_float_eq(m.positions[3], 10.0f, 1e-5);
    cr_assert_float_eq(m.positions[4], 2.0f, 1e-5);
    cr_assert_float_eq(m.positions[5], 0.0f, 1e-5);
    cr_assert_float_eq(m.normals[2], 1.0f, 1e-6);
    dm_mesh_free(&m);
    /* 90° about +x: y → z, z → −y; the normal +z turns to −y, (1, 1, 0) goes to (1, 0, 1) */
    quad_opts rx = {.node_extra = ",\"rotation\":[0.7071067811865476,0,0,0.7071067811865476]"};
    load_ok(write_quad("quad-rx.glb", &rx), NULL, &m);
    cr_assert_float_eq(m.positions[2 * 3 + 0], 1.0f, 1e-6);
    cr_assert_float_eq(m.positions[2 * 3 + 1], 0.0f, 1e-6);
    cr_assert_float_eq(m.positions[2 * 3 + 2], 1.0f, 1e-6);
    for (int k = 0; k < 6; ++k) {
        cr_assert_float_eq(m.normals[k * 3 + 0], 0.0f, 1e-6);
        cr_assert_float_eq(m.normals[k * 3 + 1], -1.0f, 1e-6, "normal y %g", m.normals[k * 3 + 1]);
        cr_assert_float_eq(m.normals[k * 3 + 2], 0.0f, 1e-6);
    }
    dm_mesh_free(&m);
    /* a non-uniform scale (2, 1, 3): the file normal +z, through the inverse transpose
     * (∝ (0, 0, 1/3)) and renormalised, stays +z */
    quad_opts ns = {.node_extra = ",\"scale\":[2,1,3]"};
    load_ok(write_quad("quad-ns.glb", &ns), NULL, &m);
    cr_assert_float_eq(m.normals[2], 1.0f, 1e-6, "unit length after the inverse transpose");
    dm_mesh_free(&m);
    /* a mirror (scale x −1) keeps the
     * surface facing its normal by flipping the winding */
    quad_opts mir = {.node_extra = ",\"scale\":[-1,1,1]"};
    load_ok(write_quad("quad-mirror.glb", &mir), NULL, &m);
    cr_assert_eq(m.triangle_count, 2);
    double area_z = 0; /* the geometric normal of triangle 0 must agree with the file normal (+z) */
    const float *a = m.positions + m.indices[0] * 3, *b = m.positions + m.indices[1] * 3, *c = m.positions + m.indices[2] * 3;
    area_z = (double)(b[0] - a[0]) * (c[1] - a[1]) - (double)(b[1] - a[1]) * (c[0] - a[0]);
    cr_assert_gt(area_z, 0.0, "winding flipped back under a mirroring transform");
    cr_assert_float_eq(m.normals[2], 1.0f, 1e-6);
    dm_mesh_free(&m);
}

Test(gltf, parent_matrix_and_node_cycle)
{
    const char *fmt =
        "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"children\":[1],\"matrix\":"
        "[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,5,1]},{\"mesh\":0%s}],\"meshes\":[{\"primitives\":[{\"attributes\":"
        "{\"POSITION\":0,\"TEXCOORD_0\":1}}]}],\"buffers\":[{\"byteLength\":60}],\"bufferViews\":[{\"buffer\":0,"
        "\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":24}],\"accessors\":[{\"bufferView\":0,"
        "\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},{\"bufferView\":1,\"componentType\":5126,\"count\":3,"
        "\"type\":\"VEC2\"}]}";
    const float data[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1};
    char json[2048];
    snprintf(json, sizeof json, fmt, "");
    const char *path = in_dir("parent.glb");
    cr_assert_eq(test_write_glb(path, json, data, sizeof data), 0);
    dm_mesh m;
    load_ok(path, NULL, &m);
    for (int v = 0; v < 3; ++v) cr_assert_float_eq(m.positions[v * 3 + 2], 5.0f, 1e-6, "z of vertex %d", v);
    dm_mesh_free(&m);
    snprintf(json, sizeof json, fmt, ",\"children\":[0]");
    path = in_dir("cycle.glb");
    cr_assert_eq(test_write_glb(path, json, data, sizeof data), 0);
    load_fails(path, DM_ERR_FORMAT, "cycle");
}

Test(gltf, primitives_and_meshes_merged_or_selected)
{
    /* mesh "a": the quad twice (two primitives); mesh "b": the quad once, node moved +3 z */
    const char *prim = "{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"indices\":3}";
    /* write_quad has one node and one mesh: build the two-mesh file by editing its JSON */
    const char *base = write_quad("multi-base.gltf", &(quad_opts){.buffer = "data"});
    char *json = test_slurp(base);
    cr_assert_not_null(json);
    char *out = malloc(strlen(json) + 2048);
    const char *meshes = strstr(json, "\"meshes\":"), *buffers = strstr(json, ",\"buffers\":");
    cr_assert(meshes && buffers);
    int head = (int)(strstr(json, "\"scene\":0") - json);
    sprintf(out, "%.*s\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],\"nodes\":[{\"mesh\":0},{\"mesh\":1,"
                 "\"translation\":[0,0,3]}],\"meshes\":[{\"name\":\"a\",\"primitives\":[%s,%s]},{\"name\":\"b\","
                 "\"primitives\":[%s]}]%s",
            head, json, prim, prim, prim, buffers);
    const char *path = in_dir("multi.gltf");
    cr_assert_eq(test_write_bytes(path, out, strlen(out)), 0);
    free(json);
    free(out);
    dm_mesh m;
    load_ok(path, NULL, &m);
    cr_assert_eq(m.triangle_count, 6, "2 + 2 + 2 triangles merged, got %d", m.triangle_count);
    cr_assert_eq(m.vertex_count, 8, "mesh a's two primitives weld to 4 positions, b's 4 more: %d", m.vertex_count);
    dm_mesh_free(&m);
    dm_mesh_load_options lo = {.mesh_name = "b"};
    load_ok(path, &lo, &m);
    cr_assert_eq(m.triangle_count, 2);
    for (int v = 0; v < m.vertex_count; ++v) cr_assert_float_eq(m.positions[v * 3 + 2], 3.0f, 1e-6);
    dm_mesh_free(&m);
    dm_error err = {0};
    lo.mesh_name = "nose";
    cr_assert_eq(dm_mesh_load(path, &lo, &m, &err), DM_ERR_MISMATCH);
    cr_assert_not_null(strstr(err.detail, "\"nose\""), "%s", err.detail);
    cr_assert_not_null(strstr(err.detail, "\"a\", \"b\""), "lists the names: %s", err.detail);
}

Test(gltf, tangents_kept_when_given)
{
    /* accessor 4: tangent +x with w = −1 (an authored mirrored frame); the computed
     * frame of this quad would be +x with w = +1 */
    dm_mesh m;
    dm_error err = {0};
    load_ok(write_quad("quad-t.glb", &(quad_opts){.attributes = "\"POSITION\":0,\"TEXCOORD_0\":1,\"NORMAL\":2,"
                                                               "\"TANGENT\":4"}),
            NULL, &m);
    cr_assert_not_null(m.tangents);
    for (int k = 0; k < 6; ++k) cr_assert_eq(m.tangents[k * 4 + 3], -1.0f);
    dm_gpu_mesh g;
    cr_assert_eq(dm_mesh_split_for_gpu(&m, &g, &err), DM_OK, "%s", err.detail);
    for (int i = 0; i < g.vertex_count; ++i) {
        cr_assert_float_eq(g.tangents[i * 4], 1.0f, 1e-6);
        cr_assert_eq(g.tangents[i * 4 + 3], -1.0f, "the file's w, not the computed +1");
    }
    dm_gpu_mesh_free(&g);
    dm_mesh_free(&m);
    /* without NORMAL, tangents are dropped (they belong to the file's normals) */
    load_ok(write_quad("quad-tn.glb", &(quad_opts){.attributes = "\"POSITION\":0,\"TEXCOORD_0\":1,\"TANGENT\":4"}),
            NULL, &m);
    cr_assert_null(m.tangents);
    dm_mesh_free(&m);
}

/* ---- malformed input: each an error naming the file and what is wrong ----------- */

Test(gltf, truncated_glb)
{
    const char *path = write_quad("trunc.glb", &(quad_opts){0});
    char *bytes = NULL;
    FILE *f = fopen(path, "rb");
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    bytes = malloc((size_t)n);
    cr_assert_eq(fread(bytes, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    long cuts[] = {n - 7, n / 2, 20, 11, 3};
    for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; ++k) {
        cr_assert_eq(test_write_bytes(path, bytes, (size_t)cuts[k]), 0);
        load_fails(path, DM_ERR_FORMAT, "truncated");
    }
    free(bytes);
}

Test(gltf, accessor_out_of_its_buffer_view)
{
    load_fails(write_quad("range.glb", &(quad_opts){.position_count = 5}), DM_ERR_FORMAT, "runs past its buffer view");
    load_fails(write_quad("offset.glb", &(quad_opts){.accessor0_extra = ",\"byteOffset\":40"}), DM_ERR_FORMAT,
               "runs past its buffer view");
    load_fails(write_quad("view.glb", &(quad_opts){.attributes = "\"POSITION\":7,\"TEXCOORD_0\":1"}), DM_ERR_FORMAT,
               "accessor 7");
}

Test(gltf, index_out_of_bounds)
{
    quad_opts o = {.set_indices = 1, .index_value = {0, 1, 2, 0, 2, 4}};
    load_fails(write_quad("oob.glb", &o), DM_ERR_RANGE, "index 4");
    quad_opts big = {.index_type = 5125, .set_indices = 1, .index_value = {0, 1, 2, 0, 2, 0xffffffffu}};
    load_fails(write_quad("oob32.glb", &big), DM_ERR_RANGE, "index 4294967295");
}

Test(gltf, missing_texcoord_0)
{
    const char *path = write_quad("nouv.glb", &(quad_opts){.attributes = "\"POSITION\":0,\"NORMAL\":2"});
    load_fails(path, DM_ERR_FORMAT, "no TEXCOORD_0");
    dm_mesh m;
    load_ok(path, &(dm_mesh_load_options){.uvs_optional = 1}, &m);
    dm_mesh_free(&m);
}

Test(gltf, sparse_accessor_refused)
{
    quad_opts o = {.accessor0_extra = ",\"sparse\":{\"count\":1,\"indices\":{\"bufferView\":3,\"componentType\":5123},"
                                      "\"values\":{\"bufferView\":2}}"};
    load_fails(write_quad("sparse.glb", &o), DM_ERR_UNSUPPORTED, "sparse");
}

Test(gltf, draco_refused)
{
    quad_opts o = {.prim_extra = ",\"extensions\":{\"KHR_draco_mesh_compression\":{\"bufferView\":3,\"attributes\":"
                                 "{\"POSITION\":0}}}",
                   .top_extra = ",\"extensionsUsed\":[\"KHR_draco_mesh_compression\"]"};
    load_fails(write_quad("draco.glb", &o), DM_ERR_UNSUPPORTED, "KHR_draco_mesh_compression");
    o.top_extra = ",\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],\"extensionsRequired\":[\"KHR_draco_mesh_compression\"]";
    load_fails(write_quad("draco-req.glb", &o), DM_ERR_UNSUPPORTED, "Draco");
}

Test(gltf, garbage_and_empty)
{
    const char *path = in_dir("junk.gltf");
    cr_assert_eq(test_write_bytes(path, "{\"asset\":", 9), 0);
    load_fails(path, DM_ERR_FORMAT, "not a valid glTF");
    path = in_dir("nomesh.gltf");
    const char *none = "{\"asset\":{\"version\":\"2.0\"}}";
    cr_assert_eq(test_write_bytes(path, none, strlen(none)), 0);
    load_fails(path, DM_ERR_EMPTY, "no mesh");
}

/* ---- the head: OBJ and GLB bake the same stretch --------------------------------- */

Test(gltf, head_obj_and_glb_bake_identical_stretch, .timeout = 120)
{
    const char *obj = DERMIS_ASSETS "/lps/LeePerrySmith.obj";
    if (access(obj, R_OK) != 0) cr_skip_test("no head at %s", obj);
    dm_mesh a, b;
    load_ok(obj, NULL, &a);
    const char *glb = in_dir("head.glb");
    cr_assert_eq(test_glb_from_mesh(&a, glb), 0);
    load_ok(glb, NULL, &b);
    cr_assert_eq(b.triangle_count, a.triangle_count);
    /* Same shape: every corner's position and UV equal. glTF stores v' = 1 − v; the
     * round trip 1 − (1 − v) in float is exact for v ≥ 0.5 and within 2^-25 otherwise. */
    int64_t uv_exact = 0;
    for (int64_t k = 0; k < (int64_t)a.triangle_count * 3; ++k) {
        for (int d = 0; d < 3; ++d)
            cr_assert_eq(a.positions[a.indices[k] * 3 + d], b.positions[b.indices[k] * 3 + d], "corner %lld",
                         (long long)k);
        cr_assert_eq(a.uvs[k * 2], b.uvs[k * 2]);
        cr_assert_float_eq(a.uvs[k * 2 + 1], b.uvs[k * 2 + 1], 3e-8);
        uv_exact += a.uvs[k * 2 + 1] == b.uvs[k * 2 + 1];
    }
    dm_stretch_options so = {.width = 512, .height = 512, .mm_per_unit = 50, .thread_count = 2};
    dm_stretch_map sa, sb;
    dm_error err = {0};
    cr_assert_eq(dm_stretch_bake(&a, &so, &sa, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_stretch_bake(&b, &so, &sb, &err), DM_OK, "%s", err.detail);
    size_t n = (size_t)512 * 512;
    int64_t mask_diff = 0, value_diff = 0;
    double rel_max = 0;
    for (size_t i = 0; i < n; ++i) mask_diff += sa.mask[i] != sb.mask[i];
    for (int l = 0; l < sa.level_count; ++l)
        for (size_t i = 0; i < n; ++i) {
            value_diff += sa.s_u[l][i] != sb.s_u[l][i] || sa.s_v[l][i] != sb.s_v[l][i];
            double ru = fabs((double)sa.s_u[l][i] - sb.s_u[l][i]) / sa.s_u[l][i];
            double rv = fabs((double)sa.s_v[l][i] - sb.s_v[l][i]) / sa.s_v[l][i];
            if (ru > rel_max) rel_max = ru;
            if (rv > rel_max) rel_max = rv;
        }
    fprintf(stderr, "head: %lld/%lld v exact after the flip; %lld mask texels differ, %lld stretch values differ, max rel %.3g\n",
            (long long)uv_exact, (long long)a.triangle_count * 3, (long long)mask_diff, (long long)value_diff, rel_max);
    cr_assert_eq(mask_diff, 0);
    cr_assert_eq(value_diff, 0);
    dm_stretch_map_free(&sa);
    dm_stretch_map_free(&sb);
    dm_mesh_free(&a);
    dm_mesh_free(&b);
}

/* dermis-bake-stretch takes the GLB like the OBJ, and --mesh NAME selects (exit 2 when
 * no mesh has that name). */
Test(gltf, bake_stretch_tool_reads_glb, .timeout = 120)
{
    const char *obj = DERMIS_ASSETS "/lps/LeePerrySmith.obj";
    if (access(obj, R_OK) != 0) cr_skip_test("no head at %s", obj);
    dm_mesh a;
    load_ok(obj, NULL, &a);
    const char *glb = in_dir("head.glb");
    cr_assert_eq(test_glb_from_mesh(&a, glb), 0);
    dm_mesh_free(&a);
    char cmd[4096];
    const char *out_obj = in_dir("obj.exr"), *out_glb = in_dir("glb.exr"), *log = in_dir("log.txt");
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-bake-stretch %s -o %s --size 256 --quiet", obj, out_obj);
    cr_assert_eq(test_run(cmd, log), 0, "%s", cmd);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-bake-stretch %s --mesh head -o %s --size 256 --quiet", glb, out_glb);
    cr_assert_eq(test_run(cmd, log), 0, "%s", cmd);
    dm_stretch_map sa, sb;
    dm_provenance pa, pb;
    dm_error err = {0};
    cr_assert_eq(dm_stretch_read(out_obj, &sa, &pa, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_stretch_read(out_glb, &sb, &pb, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(sa.level_count, sb.level_count);
    size_t n = (size_t)sa.width * sa.height;
    cr_assert_eq(memcmp(sa.mask, sb.mask, n * sizeof(float)), 0);
    for (int l = 0; l < sa.level_count; ++l) {
        cr_assert_eq(memcmp(sa.s_u[l], sb.s_u[l], n * sizeof(float)), 0, "level %d u", l);
        cr_assert_eq(memcmp(sa.s_v[l], sb.s_v[l], n * sizeof(float)), 0, "level %d v", l);
    }
    dm_stretch_map_free(&sa);
    dm_stretch_map_free(&sb);
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-bake-stretch %s --mesh nose -o %s --size 256", glb, out_glb);
    cr_assert_eq(test_run(cmd, log), 2, "%s", cmd);
    char *text = test_slurp(log);
    cr_assert_not_null(strstr(text, "no mesh named \"nose\""), "%s", text);
    free(text);
}

/* A scene whose mesh is a GLB and that names no maps: dermis-pack packs the material's
 * embedded baseColor PNG as albedo and its external normal.png as the normal map, texel
 * for texel what dm_image_read gives for the same PNG files. */
Test(gltf, pack_takes_the_gltf_material_maps, .timeout = 120)
{
    /* 3×2 RGB test images (different, so albedo and normal cannot be swapped) */
    uint8_t colour[18], normal[18];
    for (int i = 0; i < 18; ++i) colour[i] = (uint8_t)(i * 13 + 7), normal[i] = (uint8_t)(250 - i * 11);
    const char *colour_png = in_dir("colour.png"), *normal_png = in_dir("normal.png");
    dm_error err = {0};
    cr_assert_eq(dm_png_write_pixels(colour_png, 3, 2, 3, 8, colour, NULL, NULL, 0, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_png_write_pixels(normal_png, 3, 2, 3, 8, normal, NULL, NULL, 0, &err), DM_OK, "%s", err.detail);
    char *png = NULL;
    size_t png_size = 0;
    cr_assert_eq(dm_read_file(colour_png, &png, &png_size, &err), DM_OK);
    write_quad("material.glb", &(quad_opts){.png = png, .png_size = png_size});
    free(png);
    const char *scene = in_dir("scene.json");
    const char *json = "{\"format\":\"dermis-scene\",\"version\":1,\"mesh\":{\"path\":\"material.glb\",\"name\":\"quad\"},"
                       "\"effects\":{\"specular\":false}}";
    cr_assert_eq(test_write_bytes(scene, json, strlen(json)), 0);
    char cmd[2048];
    const char *pack = in_dir("material.dpk"), *log = in_dir("pack.log");
    snprintf(cmd, sizeof cmd, DERMIS_BIN "/dermis-pack %s -o %s", scene, pack);
    int rc = test_run(cmd, log);
    char *text = test_slurp(log);
    cr_assert_eq(rc, 0, "%s\n%s", cmd, text);
    cr_assert_not_null(strstr(text, "baseColorTexture"), "%s", text);
    free(text);
    dm_pack pk;
    cr_assert_eq(dm_pack_open(pack, &pk, &err), DM_OK, "%s", err.detail);
    const char *entries[2] = {"albedo", "normal"}, *files[2] = {colour_png, normal_png};
    for (int k = 0; k < 2; ++k) {
        const dm_pack_entry *e = dm_pack_find(&pk, entries[k]);
        cr_assert_not_null(e, "no %s entry", entries[k]);
        cr_assert_eq(e->width, 3);
        cr_assert_eq(e->height, 2);
        dm_image ref;
        cr_assert_eq(dm_image_read(files[k], DM_PIXEL_U8, &ref, &err), DM_OK, "%s", err.detail);
        const uint8_t *got = e->data, *want = ref.pixels;
        for (int i = 0; i < 6; ++i)
            for (int c = 0; c < 3; ++c)
                cr_assert_eq(got[i * 4 + c], want[i * ref.channels + c], "%s texel %d channel %d", entries[k], i, c);
        dm_image_free(&ref);
    }
    dm_pack_close(&pk);
    /* a scene that names its own albedo keeps it */
    json = "{\"format\":\"dermis-scene\",\"version\":1,\"mesh\":{\"path\":\"material.glb\"},"
           "\"material\":{\"albedo\":\"normal.png\"},\"effects\":{\"specular\":false}}";
    cr_assert_eq(test_write_bytes(scene, json, strlen(json)), 0);
    cr_assert_eq(test_run(cmd, log), 0);
    cr_assert_eq(dm_pack_open(pack, &pk, &err), DM_OK, "%s", err.detail);
    const uint8_t *got = dm_pack_find(&pk, "albedo")->data;
    dm_image ref;
    cr_assert_eq(dm_image_read(normal_png, DM_PIXEL_U8, &ref, &err), DM_OK);
    cr_assert_eq(got[0], ((uint8_t *)ref.pixels)[0]);
    dm_image_free(&ref);
    dm_pack_close(&pk);
}

/* mesh.name in a scene: a string, kept through dm_scene_to_json; anything else refused. */
Test(gltf, scene_mesh_name)
{
    dm_scene *s = malloc(sizeof *s);
    dm_error err = {0};
    const char *ok = "{\"format\":\"dermis-scene\",\"version\":1,\"mesh\":{\"path\":\"h.glb\",\"name\":\"head\"},"
                     "\"effects\":{}}";
    cr_assert_eq(dm_scene_parse(ok, "/x/scene.json", s, &err), DM_OK, "%s", err.detail);
    cr_assert_str_eq(s->mesh_name, "head");
    char *json = NULL;
    cr_assert_eq(dm_scene_to_json(s, &json, &err), DM_OK);
    cr_assert_not_null(strstr(json, "\"name\":"), "%s", json);
    free(json);
    const char *bad = "{\"format\":\"dermis-scene\",\"version\":1,\"mesh\":{\"path\":\"h.glb\",\"name\":3},\"effects\":{}}";
    cr_assert_eq(dm_scene_parse(bad, "/x/scene.json", s, &err), DM_ERR_FORMAT);
    cr_assert_not_null(strstr(err.detail, "$.mesh.name"), "%s", err.detail);
    free(s);
}
