/* dm_pack_build_steps.c — the pack's steps for the scene, the surface maps, the LUTs, the
 * profile, the screen-space kernel and the mesh (dm_pack_build.h). */
#include "packer/dm_pack_build.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/dm_exr.h"
#include "mesh/dm_gltf_map.h"
#include "image/dm_image.h"
#include "bake/dm_lut.h"
#include "bake/dm_lut_prov.h"
#include "mesh/dm_mesh.h"
#include "core/dm_brdf.h"
#include "core/dm_input.h"
#include "core/dm_ssss_kernel.h"

#include "packer/dm_pack_build_impl.h"

/* --- steps -------------------------------------------------------------------------- */

dm_result dmpb_step_scene(dm_pack_build *j, dm_error *err)
{
    /* with albedo_from "skin" the albedo entry holds the skin's colour, and the pack's scene,
     * whose profile is no longer a skin (dmpb_fit_skin), takes that entry as its map */
    const dm_albedo_from from = j->scene.albedo_from;
    j->scene.albedo_from = DM_ALBEDO_FROM_MAP;
    char *text = NULL;
    dm_result r = dm_scene_to_json(&j->scene, &text, err);
    j->scene.albedo_from = from;
    if (r != DM_OK) return r;
    dm_provenance p;
    dm_prov_init(&p, DM_PACK_BUILD_TOOL);
    snprintf(p.input_hash, sizeof p.input_hash, "%s", j->scene_hash);
    dm_prov_add_string(&p, "scene", j->scene_path);
    dm_pack_entry d;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "scene");
    d.kind = DM_PACK_SCENE;
    r = dmpb_add(j, &d, text, strlen(text), &p, "normalised from the scene file", err);
    free(text);
    return r;
}

/* Changes a map's converted texels (RGBA8 when the format has 4 components) before they are
 * packed, adding to its provenance and report line (dmpb_albedo_from_skin). */
typedef dm_result (*map_change)(dm_pack_build *j, uint8_t *px, int w, int h, dm_provenance *p, char *src,
                                size_t src_size, dm_error *err);

/* A map from an image file: channels converted to the pack format, rows bottom-up, then
 * `change` (may be NULL) applied. */
static dm_result pack_map(dm_pack_build *j, const char *entry, const char *path, dm_tex_format f, map_change change,
                          dm_error *err)
{
    dm_image img;
    char gltf_src[300] = "";
    const bool gltf = dm_gltf_is_file(path) && (!strcmp(entry, "albedo") || !strcmp(entry, "normal"));
    dm_result r = gltf ? dm_gltf_map_read(path, j->scene.mesh_name, !strcmp(entry, "albedo") ? DM_GLTF_MAP_BASE_COLOR
                                                                                              : DM_GLTF_MAP_NORMAL,
                                          DM_PIXEL_U8, &img, gltf_src, sizeof gltf_src, err)
                       : dm_image_read(path, DM_PIXEL_U8, &img, err);
    if (r != DM_OK) {
        j->input_failed = true;
        dm_image_free(&img);
        return r;
    }
    const int out_c = dm_tex_format_get(f)->components;
    size_t n = (size_t)img.width * img.height;
    uint8_t *px = malloc(n * (size_t)out_c);
    if (!px) {
        dm_image_free(&img);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    const uint8_t *in = img.pixels;
    const int c = img.channels;
    for (size_t i = 0; i < n; ++i) {
        const uint8_t *s = in + i * (size_t)c;
        uint8_t *o = px + i * (size_t)out_c;
        if (out_c == 1) {
            /* grey maps: the mean of the colour channels (equal on a grey JPEG) */
            int sum = 0, cc = c >= 3 ? 3 : 1;
            for (int k = 0; k < cc; ++k) sum += s[k];
            o[0] = (uint8_t)((sum + cc / 2) / cc);
        } else {
            for (int k = 0; k < 3; ++k) o[k] = s[c >= 3 ? k : 0];
            o[3] = c == 4 ? s[3] : 255;
        }
    }
    dm_provenance p;
    dm_prov_init(&p, DM_PACK_BUILD_TOOL);
    r = dm_hash_file_hex(path, p.input_hash, err);
    dm_prov_add_string(&p, "source", path);
    if (gltf) dm_prov_add_string(&p, "gltf_image", gltf_src);
    dm_prov_add_string(&p, "conversion", out_c == 1 ? "u8 mean of colour channels" : "u8 rgb + alpha (255 if none)");
    dm_pack_entry d = dm_pack_texture_entry(entry, f, img.width, img.height);
    if (f == DM_TEX_RGBA8) {
        d.channel_count = 4;
        snprintf(d.channels[0], sizeof d.channels[0], "x");
        snprintf(d.channels[1], sizeof d.channels[1], "y");
        snprintf(d.channels[2], sizeof d.channels[2], "z");
        snprintf(d.channels[3], sizeof d.channels[3], "unused");
    }
    char src[160];
    snprintf(src, sizeof src, "from %.60s%s%.90s", dmpb_base_name(path), gltf ? " " : "", gltf ? gltf_src : "");
    if (r == DM_OK && change) r = change(j, px, img.width, img.height, &p, src, sizeof src, err);
    if (r == DM_OK) r = dmpb_add(j, &d, px, n * (size_t)out_c, &p, src, err);
    free(px);
    dm_image_free(&img);
    return r;
}

dm_result dmpb_step_albedo(dm_pack_build *j, dm_error *err)
{
    const bool from_skin = j->scene.albedo_from == DM_ALBEDO_FROM_SKIN;
    return pack_map(j, "albedo", j->scene.albedo, DM_TEX_RGBA8_SRGB, from_skin ? dmpb_albedo_from_skin : NULL, err);
}
dm_result dmpb_step_normal(dm_pack_build *j, dm_error *err)
{
    return pack_map(j, "normal", j->scene.normal_map, DM_TEX_RGBA8, NULL, err);
}
dm_result dmpb_step_specular(dm_pack_build *j, dm_error *err)
{
    return pack_map(j, "specular", j->scene.specular_map, DM_TEX_R8, NULL, err);
}
dm_result dmpb_step_roughness(dm_pack_build *j, dm_error *err)
{
    return pack_map(j, "roughness", j->scene.roughness_map, DM_TEX_R8, NULL, err);
}

dm_result dmpb_step_beckmann(dm_pack_build *j, dm_error *err)
{
    const int n = j->opt->beckmann_size;
    dm_provenance want;
    dm_lut_prov_beckmann(&want, DM_PACK_BUILD_TOOL, n, n);
    dm_pack_entry d = dm_pack_texture_entry("lut.beckmann", DM_TEX_R8, n, n);
    if (j->opt->beckmann) { /* already baked: provenance must match what we would bake */
        const char *f = j->opt->beckmann;
        dm_image img;
        dm_result r = dm_image_read(f, DM_PIXEL_U8, &img, err);
        if (r == DM_OK && !img.has_provenance)
            r = dm_fail(err, DM_ERR_MISMATCH, "%s: no dermis provenance, expected a LUT baked by dermis", f);
        if (r == DM_OK) r = dm_lut_prov_match(&img.prov, &want, f, err);
        if (r == DM_OK && (img.width != n || img.height != n || img.channels != 1))
            r = dm_fail(err, DM_ERR_MISMATCH, "%s: %dx%d with %d channels, expected %dx%d with 1", f, img.width,
                        img.height, img.channels, n, n);
        char src[160];
        snprintf(src, sizeof src, "from %s", dmpb_base_name(f));
        if (r == DM_OK) r = dmpb_add(j, &d, img.pixels, (size_t)n * n, &img.prov, src, err);
        dm_image_free(&img);
        return r;
    }
    dm_beckmann_lut lut;
    dm_result r = dm_lut_bake_beckmann(n, n, 0, j->opt->threads, &lut, err);
    if (r == DM_OK) r = dmpb_add(j, &d, lut.texels, (size_t)n * n, &want, "baked", err);
    dm_beckmann_lut_free(&lut);
    return r;
}

/* Loads an already-baked directional LUT into `out` (w*h*channels interleaved). */
static dm_result load_directional(dm_pack_build *j, const char *file, const char *table, const char *const *channels, int nch,
                                  float *out, dm_provenance *prov, dm_error *err)
{
    const int n = j->opt->lut_size;
    dm_provenance want;
    dm_lut_prov_directional(&want, DM_PACK_BUILD_TOOL, table, n, n, DM_SKIN_F0, j->opt->lut_nodes);
    dm_exr_image img;
    dm_result r = dm_exr_read(file, &img, err);
    if (r == DM_OK && !img.has_provenance)
        r = dm_fail(err, DM_ERR_MISMATCH, "%s: no dermis provenance, expected a LUT baked by dermis", file);
    if (r == DM_OK) r = dm_lut_prov_match(&img.prov, &want, file, err);
    if (r == DM_OK && (img.width != n || img.height != n))
        r = dm_fail(err, DM_ERR_MISMATCH, "%s: %dx%d, expected %dx%d", file, img.width, img.height, n, n);
    for (int c = 0; c < nch && r == DM_OK; ++c) {
        const float *plane = dm_exr_find(&img, channels[c]);
        if (!plane) {
            r = dm_fail(err, DM_ERR_FORMAT, "%s: no channel \"%s\", expected it", file, channels[c]);
            break;
        }
        for (size_t i = 0; i < (size_t)n * n; ++i) out[i * (size_t)nch + (size_t)c] = plane[i];
    }
    if (r == DM_OK) *prov = img.prov;
    dm_exr_free(&img);
    return r;
}

dm_result dmpb_step_directional(dm_pack_build *j, dm_error *err)
{
    const int n = j->opt->lut_size, nodes = j->opt->lut_nodes;
    const size_t count = (size_t)n * n;
    bool need_rho = dm_pack_build_wants(j, "lut.rho_dt"), need_env = dm_pack_build_wants(j, "lut.env_brdf");
    bool bake = (need_rho && !j->opt->rho_dt) || (need_env && !j->opt->env_brdf);
    dm_directional_lut lut;
    memset(&lut, 0, sizeof lut);
    float *rg = malloc(count * 2 * sizeof *rg), *r1 = malloc(count * sizeof *r1);
    dm_result r = rg && r1 ? DM_OK : dm_fail(err, DM_ERR_OUT_OF_MEMORY, "directional LUT: out of memory");
    if (r == DM_OK && bake) r = dm_lut_bake_directional(n, n, DM_SKIN_F0, nodes, j->opt->threads, &lut, err);
    if (r == DM_OK && need_rho) {
        dm_pack_entry d = dm_pack_texture_entry("lut.rho_dt", DM_TEX_R32F, n, n);
        d.channel_count = 1;
        snprintf(d.channels[0], sizeof d.channels[0], "rho_dt");
        dm_provenance p;
        char src[160] = "baked";
        if (j->opt->rho_dt) {
            static const char *const ch[] = {"rho_dt"};
            r = load_directional(j, j->opt->rho_dt, "rho_dt", ch, 1, r1, &p, err);
            snprintf(src, sizeof src, "from %s", dmpb_base_name(j->opt->rho_dt));
        } else {
            dm_lut_prov_directional(&p, DM_PACK_BUILD_TOOL, "rho_dt", n, n, DM_SKIN_F0, nodes);
            memcpy(r1, lut.rho_dt, count * sizeof *r1);
        }
        if (r == DM_OK) r = dmpb_add(j, &d, r1, count * sizeof *r1, &p, src, err);
    }
    if (r == DM_OK && need_env) {
        dm_pack_entry d = dm_pack_texture_entry("lut.env_brdf", DM_TEX_RG32F, n, n);
        d.channel_count = 2;
        snprintf(d.channels[0], sizeof d.channels[0], "scale");
        snprintf(d.channels[1], sizeof d.channels[1], "bias");
        dm_provenance p;
        char src[160] = "baked";
        if (j->opt->env_brdf) {
            static const char *const ch[] = {"scale", "bias"};
            r = load_directional(j, j->opt->env_brdf, "env_brdf", ch, 2, rg, &p, err);
            snprintf(src, sizeof src, "from %s", dmpb_base_name(j->opt->env_brdf));
        } else {
            dm_lut_prov_directional(&p, DM_PACK_BUILD_TOOL, "env_brdf", n, n, DM_SKIN_F0, nodes);
            for (size_t i = 0; i < count; ++i) {
                rg[2 * i] = lut.scale[i];
                rg[2 * i + 1] = lut.bias[i];
            }
        }
        if (r == DM_OK) r = dmpb_add(j, &d, rg, count * 2 * sizeof *rg, &p, src, err);
    }
    dm_directional_lut_free(&lut);
    free(rg);
    free(r1);
    return r;
}

dm_result dmpb_step_profile(dm_pack_build *j, dm_error *err)
{
    const dm_profile *pr = &j->scene.profile;
    dm_provenance p;
    dm_prov_init(&p, DM_PACK_BUILD_TOOL);
    dm_prov_add_string(&p, "source", j->skin.given ? "skin" : j->scene.profile_source);
    if (j->skin.given) { /* the parameters the profile was fitted to, exact, and how */
        dm_prov_add_string(&p, "skin", j->skin_spec);
        if (j->skin.preset[0]) dm_prov_add_string(&p, "skin_preset", j->skin.preset);
        dm_prov_add_string(&p, "skin_fit", "dermis-fit-profile --skin defaults: 6 Gaussians, normalised to white");
    }
    char *text = NULL;
    size_t size = 0;
    dm_result r = DM_OK;
    bool from_file = strcmp(j->scene.profile_source, "gems3-skin") != 0 && strcmp(j->scene.profile_source, "inline") != 0;
    if (from_file) { /* the file as it is: it keeps its fit error and its own provenance */
        r = dm_input_read(j->scene.profile_source, DM_INPUT_JSON, &text, &size, err);
        if (r == DM_OK) r = dm_hash_file_hex(j->scene.profile_source, p.input_hash, err);
    } else {
        r = dm_profile_to_json(pr, &text, err);
        if (r == DM_OK) size = strlen(text);
    }
    dm_pack_entry d;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "profile");
    d.kind = DM_PACK_PROFILE;
    char src[160];
    if (from_file)
        snprintf(src, sizeof src, "from %.150s", dmpb_base_name(j->scene.profile_source));
    else if (j->skin.given)
        snprintf(src, sizeof src, "fitted to the skin %s", j->skin.preset[0] ? j->skin.preset : "of the scene");
    else
        snprintf(src, sizeof src, "%s preset", pr->name);
    if (r == DM_OK) r = dmpb_add(j, &d, text, size, &p, src, err);
    free(text);
    return r;
}

/* The screen-space technique's separable kernels, one row per size of pixel, fitted to the
 * profile's line-spread function (core/dm_ssss_kernel.h); the largest edge error of the fit and
 * what the 2-D product loses of the profile (fit_error) over the rows go into the entry's
 * provenance and the report's source column. */
dm_result dmpb_step_ss_kernel(dm_pack_build *j, dm_error *err)
{
    dm_ssss_kernel k;
    dm_result r = dm_ssss_kernel_fit(&j->scene.profile, j->scene.screen_taps, &k, err);
    if (r != DM_OK) return r;
    float texels[DM_SSSS_MAX_ROWS * DM_SSSS_MAX_TAPS * 4];
    dm_ssss_kernel_texels(&k, texels);
    double edge = 0, fit[3] = {0, 0, 0};
    for (int row = 0; row < k.rows; ++row) {
        edge = fmax(edge, k.edge_error[row]);
        for (int c = 0; c < 3; ++c) fit[c] = fmax(fit[c], k.fit_error[row][c]);
    }
    dm_provenance p;
    dm_prov_init(&p, DM_PACK_BUILD_TOOL);
    dm_prov_add_string(&p, "source", j->scene.profile_source);
    dm_prov_add_string(&p, "product", "screen-space separable SSS kernels (Jimenez et al. 2015), one per size of pixel: "
                                      "the line-spread function's masses over bins of whole pixels");
    dm_prov_add_int(&p, "taps", k.taps);
    dm_prov_add_int(&p, "rows", k.rows);
    dm_prov_add_double(&p, "edge_error_max", edge);
    dm_prov_add_double(&p, "fit_error_max_r", fit[0]);
    dm_prov_add_double(&p, "fit_error_max_g", fit[1]);
    dm_prov_add_double(&p, "fit_error_max_b", fit[2]);
    char src[200];
    snprintf(src, sizeof src, "%d taps x %d sizes %g-%g mm/px, edge error <= %.2f %%, 2-D product error <= "
             "%.1f/%.1f/%.1f %% (R/G/B)", k.taps, k.rows, k.mm_per_px[0], k.mm_per_px[1], 100 * edge, 100 * fit[0],
             100 * fit[1], 100 * fit[2]);
    dm_pack_entry d = dm_pack_texture_entry("sss.kernel", DM_TEX_RGBA32F, k.taps, k.rows);
    d.has_t_range = true; /* the rows' mm per pixel: what the renderer needs of the layout */
    d.t_range[0] = (float)k.mm_per_px[0];
    d.t_range[1] = (float)k.mm_per_px[1];
    return dmpb_add(j, &d, texels, (size_t)k.taps * k.rows * 4 * sizeof(float), &p, src, err);
}

void dmpb_mesh_prov(const dm_pack_build *j, dm_provenance *p, const char *what)
{
    dm_prov_init(p, DM_PACK_BUILD_TOOL);
    snprintf(p->input_hash, sizeof p->input_hash, "%s", j->mesh_hash);
    dm_prov_add_string(p, "source", j->scene.mesh);
    dm_prov_add_string(p, "product", what);
    dm_prov_add_double(p, "mm_per_unit", j->scene.mm_per_unit);
    dm_prov_add_int(p, "triangles", j->mesh.triangle_count);
}

/* The GPU mesh: split at seams by (position, uv, normal), tangents with handedness,
 * interleaved in the dermis layout (pack/dm_pack.h DM_PACK_VERTEX_*). */
dm_result dmpb_step_mesh(dm_pack_build *j, dm_error *err)
{
    dm_result r = dmpb_ensure_mesh(j, err);
    if (r != DM_OK) return r;
    dm_gpu_mesh g;
    if ((r = dm_mesh_split_for_gpu(&j->mesh, &g, err)) != DM_OK) return r;
    const size_t vc = (size_t)g.vertex_count, floats = DM_PACK_VERTEX_STRIDE / 4;
    float *v = malloc(vc * floats * sizeof *v);
    if (!v) {
        dm_gpu_mesh_free(&g);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", j->scene.mesh);
    }
    for (size_t i = 0; i < vc; ++i) {
        float *o = v + i * floats;
        memcpy(o + DM_PACK_VERTEX_POSITION / 4, g.positions + 3 * i, 3 * sizeof *o);
        memcpy(o + DM_PACK_VERTEX_NORMAL / 4, g.normals + 3 * i, 3 * sizeof *o);
        memcpy(o + DM_PACK_VERTEX_UV / 4, g.uvs + 2 * i, 2 * sizeof *o);
        memcpy(o + DM_PACK_VERTEX_TANGENT / 4, g.tangents + 4 * i, 4 * sizeof *o);
    }
    dm_pack_entry d;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "mesh.vertices");
    d.kind = DM_PACK_MESH_VERTICES;
    d.vertex_count = (int64_t)vc;
    d.stride = DM_PACK_VERTEX_STRIDE;
    static const struct {
        const char *name;
        int offset, components;
    } attrs[4] = {{"position", DM_PACK_VERTEX_POSITION, 3},
                  {"normal", DM_PACK_VERTEX_NORMAL, 3},
                  {"uv", DM_PACK_VERTEX_UV, 2},
                  {"tangent", DM_PACK_VERTEX_TANGENT, 4}};
    d.attribute_count = 4;
    for (int k = 0; k < 4; ++k) {
        snprintf(d.attributes[k].name, sizeof d.attributes[k].name, "%s", attrs[k].name);
        d.attributes[k].offset = attrs[k].offset;
        d.attributes[k].components = attrs[k].components;
    }
    dm_provenance p;
    dmpb_mesh_prov(j, &p, "split by position, uv, normal; tangents with handedness");
    dm_prov_add_int(&p, "vertices", (int64_t)vc);
    char src[200];
    snprintf(src, sizeof src, "from %.150s", dmpb_base_name(j->scene.mesh));
    r = dmpb_add(j, &d, v, vc * floats * sizeof *v, &p, src, err);
    if (r == DM_OK) {
        memset(&d, 0, sizeof d);
        snprintf(d.name, sizeof d.name, "mesh.indices");
        d.kind = DM_PACK_MESH_INDICES;
        d.index_count = g.index_count;
        snprintf(d.vertices, sizeof d.vertices, "mesh.vertices");
        dmpb_mesh_prov(j, &p, "triangles, counter-clockwise");
        r = dmpb_add(j, &d, g.indices, (size_t)g.index_count * sizeof *g.indices, &p, src, err);
    }
    free(v);
    dm_gpu_mesh_free(&g);
    return r;
}

/* A dermis-bake-stretch EXR in place of the bake, when it was made from this mesh (content
 * hash), at this mm_per_unit and irradiance size, through this profile's variances. */
