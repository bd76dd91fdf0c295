/* glTF 2.0 meshes through dm_mesh_load: every hard case (transforms, several primitives
 * and meshes, index types, data URIs, external buffers, computed normals, each malformed
 * input) has its test. The head as OBJ and as GLB: test_gltf_bake. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mesh/dm_mesh.h"
#include "../common/gltf_quad.h"
#include "../common/gltf_write.h"

TestSuite(gltf, .init = setup, .timeout = 60);

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
