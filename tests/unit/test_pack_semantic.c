/* The physical ranges of every pack entry (pack/dm_pack_semantic.h), checked by dm_pack_open
 * for every reader: each reproduction of issue #31 point 1 (finite but absurd values, every
 * checksum recomputed, tests/common/pack_absurd.h) is refused with a message naming the
 * entry, where, the value and the range; values at the edges of the ranges, and the real
 * packs dermis-pack makes, are taken. */
#include <criterion/criterion.h>
#include <criterion/parameterized.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/pack_absurd.h"
#include "bake/dm_stretch.h"
#include "pack/dm_pack.h"
#include "pack/dm_pack_semantic.h"

/* The base pack of `technique` in memory (free it). */
static uint8_t *base(const char *technique, size_t *size)
{
    char dir[256], path[512];
    cr_assert(test_tmpdir(dir, sizeof dir));
    cr_assert(absurd_base_pack(dir, technique, path, sizeof path), "dermis-pack %s in %s", technique, dir);
    uint8_t *buf = test_pack_load(path, size);
    cr_assert_not_null(buf, "%s", path);
    return buf;
}

static dm_result open_copy(const uint8_t *buf, size_t size, dm_error *err)
{
    uint8_t *copy = aligned_alloc(64, (size + 63) / 64 * 64);
    memcpy(copy, buf, size);
    dm_pack pack;
    dm_result r = dm_pack_open_memory(copy, size, "t.dpk", &pack, err);
    dm_pack_close(&pack);
    free(copy);
    return r;
}

Test(pack_semantic, real_packs_open, .timeout = 60)
{
    static const char *const techniques[] = {"texture-space", "screen-space", "pre-integrated"};
    for (int k = 0; k < 3; ++k) {
        size_t size;
        uint8_t *buf = base(techniques[k], &size);
        dm_error err = {0};
        cr_expect_eq(open_copy(buf, size, &err), DM_OK, "%s: %s", techniques[k], err.detail);
        free(buf);
    }
}

/* Parameters are indices: a worker may not share the table's addresses. */
ParameterizedTestParameters(pack_semantic, absurd_values_refused)
{
    static int index[ABSURD_CASE_COUNT];
    for (int k = 0; k < ABSURD_CASE_COUNT; ++k) index[k] = k;
    return cr_make_param_array(int, index, ABSURD_CASE_COUNT);
}

ParameterizedTest(int *k, pack_semantic, absurd_values_refused, .timeout = 60)
{
    const absurd_case *c = &absurd_cases[*k];
    size_t size;
    uint8_t *buf = base(c->technique, &size);
    dm_error err = {0};
    cr_assert_eq(open_copy(buf, size, &err), DM_OK, "%s: the base pack: %s", c->name, err.detail);
    cr_assert(absurd_apply(c, buf, size), "%s: the edit did not apply", c->name);
    dm_result r = open_copy(buf, size, &err);
    cr_assert_neq(r, DM_OK, "%s: accepted", c->name);
    cr_expect(r == DM_ERR_RANGE || r == DM_ERR_FORMAT, "%s: %s", c->name, dm_result_name(r));
    cr_expect(strncmp(err.detail, "t.dpk", 5) == 0, "%s: does not name the file: %s", c->name, err.detail);
    cr_expect(strstr(err.detail, c->expect), "%s: '%s' not in: %s", c->name, c->expect, err.detail);
    free(buf);
}

/* Values at the edges of the ranges, and plausible ones, are taken: the bounds refuse what
 * no real data holds, not what some data might. */
typedef struct edge {
    const char *name, *technique, *entry;
    uint64_t index;
    float value;
} edge;

static const edge edges[] = {
    {"rho_dt zero", "texture-space", "lut.rho_dt", 0, 0.0f},
    {"rho_dt at pi", "texture-space", "lut.rho_dt", 3, 3.14159265f},
    {"env_brdf -0", "texture-space", "lut.env_brdf", 1, -0.0f},
    {"stretch at the bound", "texture-space", "stretch", 7, (float)DM_PACK_STRETCH_MAX_PER_MM},
    {"stretch tiny", "texture-space", "stretch", 8, 1e-30f},
    {"env texel at the bound", "texture-space", "env.specular", 2, (float)DM_PACK_RADIANCE_MAX},
    {"a sun of 1.6e9", "texture-space", "env.background", 0, 1.6e9f},
    {"sh negative band 1", "texture-space", "env.sh", 3, -5.0f},
    {"vertex at 199 units (9.95 m)", "texture-space", "mesh.vertices", 0, 199.0f},
    {"normal 1.0005 long", "texture-space", "mesh.vertices", DM_PACK_VERTEX_NORMAL / 4, 0.0f}, /* see below */
    {"preintegrated 1", "pre-integrated", "sss.preintegrated", 0, 1.0f},
    {"curvature -50 per mm", "pre-integrated", "sss.curvature", 0, -50.0f},
};

Test(pack_semantic, edges_taken, .timeout = 60)
{
    static const char *const techniques[] = {"texture-space", "pre-integrated"};
    for (int t = 0; t < 2; ++t) {
        size_t size;
        uint8_t *buf = base(techniques[t], &size);
        for (size_t k = 0; k < sizeof edges / sizeof edges[0]; ++k) {
            const edge *g = &edges[k];
            if (strcmp(g->technique, techniques[t]) != 0) continue;
            uint8_t *copy = malloc(size);
            memcpy(copy, buf, size);
            float value = g->value;
            if (!strncmp(g->name, "normal", 6)) { /* vertex 0's normal scaled to length 1.0005 */
                uint64_t off, bytes;
                cr_assert(test_pack_blob(copy, "mesh.vertices", &off, &bytes));
                float n[3];
                memcpy(n, copy + off + DM_PACK_VERTEX_NORMAL, sizeof n);
                for (int d = 0; d < 3; ++d) n[d] *= 1.0005f;
                memcpy(copy + off + DM_PACK_VERTEX_NORMAL, n, sizeof n);
                value = n[0];
            }
            cr_assert(test_pack_set_floats(copy, size, g->entry, g->index, 1, 1, value), "%s", g->name);
            dm_error err = {0};
            cr_expect_eq(open_copy(copy, size, &err), DM_OK, "%s: %s", g->name, err.detail);
            free(copy);
        }
        free(buf);
    }
}

/* What the renderer could not take is refused for every reader too: a tangent that is not
 * unit or without its handedness, a negative mean radiance, a known entry in another format. */
Test(pack_semantic, shapes_refused, .timeout = 60)
{
    size_t size;
    uint8_t *buf = base("texture-space", &size);
    struct {
        const char *entry;
        uint64_t index;
        float value;
        const char *expect;
    } cases[] = {
        {"mesh.vertices", DM_PACK_VERTEX_TANGENT / 4 + 3, 0.5f, "vertex 0: tangent w = 0.5, expected +1 or -1"},
        {"mesh.vertices", DM_PACK_VERTEX_TANGENT / 4, 0.0f, "vertex 0: tangent ("},
        {"env.sh", 0, -1.0f, "entry \"env.sh\": coefficient 0 channel 0 is -1, expected [0, "},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        uint8_t *copy = malloc(size);
        memcpy(copy, buf, size);
        cr_assert(test_pack_set_floats(copy, size, cases[k].entry, cases[k].index, 1, 1, cases[k].value));
        dm_error err = {0};
        cr_expect_eq(open_copy(copy, size, &err), DM_ERR_RANGE, "%s", err.detail);
        cr_expect(strstr(err.detail, cases[k].expect), "'%s' not in: %s", cases[k].expect, err.detail);
        free(copy);
    }
    /* a known name in another format of the same size: rho_dt's 8 x 8 floats as rgba8 */
    uint8_t *copy = malloc(size);
    memcpy(copy, buf, size);
    cr_assert(test_pack_replace_manifest(copy, size, "\"format\":\t\"r32f\"", "\"format\":\t\"rgba8\""));
    cr_assert(test_pack_replace_manifest(copy, size, "[\"rho_dt\"]", "[\"r\",\"g\",\"b\",\"a\"]"));
    dm_error err = {0};
    cr_expect_eq(open_copy(copy, size, &err), DM_ERR_FORMAT, "%s", err.detail);
    cr_expect(strstr(err.detail, "t.dpk: entry \"lut.rho_dt\" is texture rgba8, expected texture r32f"), "%s",
              err.detail);
    free(copy);
    free(buf);
}

/* The stretch baker never writes what the reader refuses: a triangle whose stretch passes
 * DM_PACK_STRETCH_MAX_PER_MM (UV [0, 1] over a micrometre at mm_per_unit 1e-3) is counted
 * degenerate and covers nothing; one just under it is an ordinary triangle. */
Test(pack_semantic, stretch_baker_keeps_the_bound)
{
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_alloc(3, 1, &m, &err), DM_OK);
    float p[9] = {0, 0, 0, 1e-3f, 0, 0, 0, 1e-3f, 0}, uv[6] = {0, 0, 1, 0, 0, 1};
    memcpy(m.positions, p, sizeof p);
    memcpy(m.uvs, uv, sizeof uv);
    for (int k = 0; k < 3; ++k) m.indices[k] = (uint32_t)k;
    dm_triangle_stretch ts;
    dm_triangle_stretch_of(&m, 0, 1e-3, &ts); /* sides of 1e-6 mm: 1e6 UV per mm, the bound */
    cr_expect_eq(ts.kind, DM_TRIANGLE_OK);
    cr_expect(dm_pack_stretch_ok((float)ts.s_u), "%g", ts.s_u);
    dm_triangle_stretch_of(&m, 0, 0.5e-3, &ts); /* 2e6 UV per mm */
    cr_expect_eq(ts.kind, DM_TRIANGLE_ZERO_AREA);
    cr_expect_eq(ts.s_u, 0.0);
    dm_mesh_free(&m);
}
