/* pack_absurd.h — the reproductions of issue #31 point 1: pack data that is finite but
 * absurd, every checksum made right again (pack_edit.h), and the small real packs they are
 * made from (dermis-pack on the pack-v1 fixture's sphere, one pack per subsurface technique,
 * with environment lighting and its background). test_pack_semantic opens each with the
 * library; test_pack_agreement gives each to dermis-check and dermis-render. */
#ifndef TEST_PACK_ABSURD_H
#define TEST_PACK_ABSURD_H

#include <limits.h>
#include <stdlib.h>
#include <unistd.h>

#include "pack_edit.h"
#include "tmpdir.h"

typedef enum absurd_edit {
    EDIT_ONE,        /* float `index` of the entry := value */
    EDIT_ALL,        /* every float of the entry := value */
    EDIT_UPPER_HALF, /* the second half of the entry's floats := value */
    EDIT_NORMALS,    /* every vertex normal := (0, 0, 0) */
    EDIT_TEXT,       /* `from` := `to` (padded with spaces) in the scene and profile JSON blobs */
    EDIT_MANIFEST    /* `from` := `to` in the manifest */
} absurd_edit;

typedef struct absurd_case {
    const char *name;
    const char *technique; /* the base pack: texture-space, screen-space or pre-integrated */
    absurd_edit edit;
    const char *entry;
    uint64_t index;
    float value;
    const char *from, *to;
    const char *expect; /* in dm_pack_open's message (the renderer and dermis-check print it) */
} absurd_case;

static const absurd_case absurd_cases[] = {
    {"zero_normals", "texture-space", EDIT_NORMALS, "mesh.vertices", 0, 0, NULL, NULL,
     "entry \"mesh.vertices\": vertex 0: normal (0, 0, 0) has length 0, expected 1 +- 0.001"},
    {"rho_dt_minus_1e38", "texture-space", EDIT_ONE, "lut.rho_dt", 9, -1e38f, NULL, NULL,
     "entry \"lut.rho_dt\": texel (1, 1) of layer 0, component 0 is -1e+38, expected [0, 3.14"},
    {"env_sh_1e38", "texture-space", EDIT_ONE, "env.sh", 4, 1e38f, NULL, NULL,
     "entry \"env.sh\": coefficient 1 channel 1 is 1e+38, expected within +-3.5"},
    {"preintegrated_1e38", "pre-integrated", EDIT_ONE, "sss.preintegrated", 2, 1e38f, NULL, NULL,
     "entry \"sss.preintegrated\": texel (0, 0) of layer 0, component 2 is 1e+38, expected [0, 1.001]"},
    {"stretch_texel_1e38", "texture-space", EDIT_ONE, "stretch", 1, 1e38f, NULL, NULL,
     "entry \"stretch\": texel (0, 0) of layer 0, component 1 is 1e+38, expected (0, 1e+06]"},
    {"env_specular_texel_1e38", "texture-space", EDIT_ONE, "env.specular", 0, 1e38f, NULL, NULL,
     "entry \"env.specular\": texel (0, 0) of layer 0, component 0 is 1e+38, expected [0, 1e+18]"},
    {"env_background_texel_1e38", "texture-space", EDIT_ONE, "env.background", 5, 1e38f, NULL, NULL,
     "entry \"env.background\": texel (1, 0) of layer 0, component 1 is 1e+38, expected [0, 1e+18]"},
    {"profile_variance_1e38", "texture-space", EDIT_TEXT, "scene", 0, 0, "7.4100000000000001", "1e38",
     "gaussians[5].variance_mm2 = 1e+38, expected a value in (0, 1e+08] mm^2"},
    {"vertex_x_1e6", "texture-space", EDIT_ONE, "mesh.vertices", 12, 1e6f, NULL, NULL,
     "entry \"mesh.vertices\": vertex 1: position x = 1e+06 (5e+07 mm at mm_per_unit 50), expected within +-200"},
    {"kernel_plus_1e38", "screen-space", EDIT_ONE, "sss.kernel", 4, 1e38f, NULL, NULL,
     "entry \"sss.kernel\": row 0 channel 0 weights sum to"},
    {"kernel_minus_1e38", "screen-space", EDIT_ONE, "sss.kernel", 4, -1e38f, NULL, NULL,
     "entry \"sss.kernel\": row 0 tap 1 weight 0 is -1e+38, expected >= 0"},
    {"t_range_3e38", "pre-integrated", EDIT_MANIFEST, "sss.preintegrated", 0, 0, "\"t_range\":\t[0, 1]",
     "\"t_range\":[0,3e38]",
     "entry \"sss.preintegrated\": t_range [0, 3e+38], expected [0, max] with max in (0, 1000]"},
    {"rho_dt_all_minus_1e38", "texture-space", EDIT_ALL, "lut.rho_dt", 0, -1e38f, NULL, NULL,
     "entry \"lut.rho_dt\": texel (0, 0) of layer 0, component 0 is -1e+38"},
    {"env_brdf_all_minus_1e38", "texture-space", EDIT_ALL, "lut.env_brdf", 0, -1e38f, NULL, NULL,
     "entry \"lut.env_brdf\": texel (0, 0) of layer 0, component 0 is -1e+38"},
    {"stretch_upper_half_minus_1e38", "texture-space", EDIT_UPPER_HALF, "stretch", 0, -1e38f, NULL, NULL,
     "entry \"stretch\": texel (0, 0) of layer 3, component 0 is -1e+38, expected (0, 1e+06]"},
    {"thin_mm_1e38", "texture-space", EDIT_ONE, "thin", 2, 1e38f, NULL, NULL,
     "entry \"thin\": texel (0, 0) of layer 0, component 2 is 1e+38, expected [0, 8.16"},
    {"thin_candidate_half", "texture-space", EDIT_ONE, "thin", 3, 0.5f, NULL, NULL,
     "entry \"thin\": texel (0, 0) is (0, 0, 0, 0.5), expected a candidate (u, v, mm, 1) or none (0, 0, 0, 0)"},
    {"env_specular_layer_m_absurd", "texture-space", EDIT_MANIFEST, "env.specular", 0, 0,
     "\"layer_values\":\t[0.10000000149011612",
     "\"layer_values\":[9e9", "entry \"env.specular\": layer_values[0] = 9e+09, expected a Beckmann m in [0.01, 2]"},
};
enum { ABSURD_CASE_COUNT = (int)(sizeof absurd_cases / sizeof absurd_cases[0]) };

/* Replaces `from` by `to` (no longer) in entry `name`'s JSON text, padding with spaces. */
static inline bool test_pack_replace_text(uint8_t *buf, size_t size, const char *name, const char *from, const char *to)
{
    uint64_t off, bytes;
    if (!test_pack_blob(buf, name, &off, &bytes) || strlen(to) > strlen(from)) return false;
    char *text = malloc(bytes + 1);
    memcpy(text, buf + off, bytes);
    text[bytes] = '\0';
    char *at = strstr(text, from);
    if (at) {
        memset(buf + off + (at - text), ' ', strlen(from));
        memcpy(buf + off + (at - text), to, strlen(to));
    }
    free(text);
    test_pack_fix_checksums(buf, size);
    return at != NULL;
}

/* Applies a case to a loaded base pack; false when its entry or text is not there. */
static inline bool absurd_apply(const absurd_case *c, uint8_t *buf, size_t size)
{
    uint64_t off, bytes;
    if (!test_pack_blob(buf, c->entry, &off, &bytes)) return false;
    uint64_t floats = bytes / 4;
    switch (c->edit) {
    case EDIT_ONE: return test_pack_set_floats(buf, size, c->entry, c->index, 1, 1, c->value);
    case EDIT_ALL: return test_pack_set_floats(buf, size, c->entry, 0, floats, 1, c->value);
    case EDIT_UPPER_HALF:
        return test_pack_set_floats(buf, size, c->entry, floats / 2, floats - floats / 2, 1, c->value);
    case EDIT_NORMALS:
        for (int d = 0; d < 3; ++d)
            if (!test_pack_set_floats(buf, size, c->entry, (uint64_t)(DM_PACK_VERTEX_NORMAL / 4 + d),
                                      bytes / DM_PACK_VERTEX_STRIDE, DM_PACK_VERTEX_STRIDE / 4, 0.0f))
                return false;
        return true;
    case EDIT_TEXT: /* the scene's profile and the profile entry stay equal */
        return test_pack_replace_text(buf, size, "scene", c->from, c->to) &&
               test_pack_replace_text(buf, size, "profile", c->from, c->to);
    case EDIT_MANIFEST: return test_pack_replace_manifest(buf, size, c->from, c->to);
    }
    return false;
}

/* Packs the fixture's sphere with `technique` into dir/base-TECHNIQUE.dpk (written to path):
 * specular, energy conservation, subsurface, shadows, environment lighting with background
 * (baked small), a 32 × 24 output. Run from the repository root, as make test does. */
static inline bool absurd_base_pack(const char *dir, const char *technique, char *path, size_t path_size)
{
    char sphere[PATH_MAX], scene[512], cmd[4096];
    if (!getcwd(sphere, sizeof sphere - 64)) return false;
    strcat(sphere, "/tests/fixtures/pack-v1/sphere.obj");
    snprintf(scene, sizeof scene, "%s/%s.json", dir, technique);
    snprintf(path, path_size, "%s/base-%s.dpk", dir, technique);
    FILE *f = fopen(scene, "w");
    if (!f) return false;
    fprintf(f,
            "{\"mesh\": {\"path\": \"%s\", \"mm_per_unit\": 50},\n"
            " \"material\": {\"roughness\": 0.3, \"rho_s\": 0.18},\n"
            " \"environment\": {\"path\": \"%s/env/venice_sunset_1k.hdr\", \"background\": true},\n"
            " \"lights\": [{\"type\": \"directional\", \"direction\": [0.5, 0.4, 0.8], \"intensity\": 2,"
            " \"casts_shadow\": true}],\n"
            " \"effects\": {\"specular\": true, \"energy_conservation\": true, \"environment_lighting\": true,\n"
            "   \"subsurface\": {\"profile\": \"gems3-skin\", \"technique\": \"%s\", \"irradiance_size\": 64},\n"
            "   \"shadows\": true, \"tonemap\": {}},\n"
            " \"camera\": {\"eye\": [0, 0, 8], \"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fov_y_deg\": 30},\n"
            " \"output\": {\"width\": 32, \"height\": 24}}\n",
            sphere, DERMIS_ASSETS, technique);
    if (fclose(f) != 0) return false;
    snprintf(cmd, sizeof cmd,
             "cd '%s' && " DERMIS_BIN "/dermis-bake-env " DERMIS_ASSETS "/env/venice_sunset_1k.hdr -o env.exr "
             "--samples 16 --levels 2 --spec-size 32 --background-size 64 --check-texels 0 --quiet && " DERMIS_BIN
             "/dermis-pack %s.json -o base-%s.dpk --env env.exr --beckmann-size 16 --lut-size 8 --threads 1 --quiet",
             dir, technique, technique);
    return test_run(cmd, NULL) == 0;
}

#endif
