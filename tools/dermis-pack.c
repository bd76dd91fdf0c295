/* dermis-pack — scene + sources → one .dpk pack holding only what the scene's effects need.
 * parse → load scene → run the bake steps that apply → write. */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_curvature.h"
#include "bake/dm_exr.h"
#include "bake/dm_gltf_map.h"
#include "bake/dm_image.h"
#include "bake/dm_lut.h"
#include "bake/dm_lut_prov.h"
#include "bake/dm_mesh.h"
#include "bake/dm_mesh_plausible.h"
#include "bake/dm_stretch.h"
#include "bake/dm_pack_env.h"
#include "bake/dm_pack_write.h"
#include "bake/dm_preintegrated.h"
#include "core/dm_brdf.h"
#include "core/dm_cli.h"
#include "core/dm_file.h"
#include "core/dm_hash.h"
#include "core/dm_pack.h"
#include "core/dm_pack_needs.h"
#include "core/dm_scene.h"
#include "core/dm_ssss_kernel.h"
#include "core/dm_version.h"

#define TOOL "dermis-pack"

static void usage(FILE *f)
{
    fprintf(f,
            "Usage: dermis-pack SCENE.json -o FILE.dpk [options]\n"
            "       dermis-pack --explain SCENE.json\n"
            "Bakes what the scene's effects need and packs it, GPU-ready, into one .dpk file.\n"
            "\n"
            "Options:\n"
            "  -o, --output FILE      the pack to write (required unless --explain)\n"
            "  --explain              print which entries each enabled effect needs, and why; write nothing\n"
            "  --beckmann FILE.png    take this baked Beckmann LUT instead of baking (provenance must match)\n"
            "  --rho-dt FILE.exr      take this baked rho_dt LUT (channel \"rho_dt\"; provenance must match)\n"
            "  --env-brdf FILE.exr    take this baked env-BRDF LUT (channels \"scale\", \"bias\")\n"
            "  --stretch FILE.exr     take this dermis-bake-stretch output (same mesh, mm_per_unit,\n"
            "                         irradiance size and profile variances as the scene)\n"
            "  --env FILE.exr         take this dermis-bake-env output for the scene map it was baked\n"
            "                         from (matched by content hash; unrotated); repeat for several maps\n"
            "  --beckmann-size N      Beckmann LUT size, N x N (default %d, range 16..%d)\n"
            "  --lut-size N           rho_dt / env-BRDF LUT size, N x N (default %d, range 8..1024)\n"
            "  --lut-nodes N          Gauss-Legendre nodes for rho_dt (default %d, range 8..128)\n"
            "  --threads N            bake threads, 0 = all cores (default 0, range 0..256)\n"
            "  --assets DIR           look here for scene paths missing beside the scene, before\n"
            "                         DERMIS_ASSETS and the build's default (repeatable, up to 8)\n"
            "  -v, --verbose          print provenance of every entry\n"
            "  --quiet                print nothing but errors\n"
            "  -h, --help             this text\n"
            "\n"
            "Exit codes: 0 ok, 1 usage, 2 cannot load an input, 3 processing failed, 4 cannot save.\n",
            DM_LUT_BECKMANN_SIZE_DEFAULT, DM_LUT_SIZE_MAX, DM_LUT_DIRECTIONAL_SIZE_DEFAULT, DM_LUT_NODES_DEFAULT);
}

typedef struct options {
    const char *scene, *output, *beckmann, *rho_dt, *env_brdf;
    const char *env_files[8];
    int env_file_count;
    const char *stretch_file;
    const char *assets[8];
    int asset_count;
    bool explain, verbose, quiet;
    int beckmann_size, lut_size, lut_nodes, threads;
} options;

typedef struct report_row {
    char entry[DM_PACK_NAME_SIZE];
    char source[160];
    size_t size;
    double ms;
} report_row;

typedef struct job {
    const options *opt;
    dm_scene scene;
    char scene_hash[DM_HASH_HEX_SIZE];
    dm_pack_writer w;
    report_row rows[64];
    int row_count;
    double step_t0;
    bool env_file_used[8]; /* which --env files served a map */
    dm_mesh mesh; /* loaded once, for the mesh and stretch steps */
    bool mesh_loaded;
    char mesh_hash[DM_HASH_HEX_SIZE];
} job;

static void job_free(job *j)
{
    dm_pack_writer_free(&j->w);
    if (j->mesh_loaded) dm_mesh_free(&j->mesh);
    free(j);
}

/* --- helpers ------------------------------------------------------------------------ */

static bool wanted(const job *j, const char *entry)
{
    const dm_pack_need *n = dm_pack_need_find(entry);
    return n && dm_pack_entry_applies(entry, &j->scene);
}

static dm_result add(job *j, const dm_pack_entry *d, const void *data, size_t size, const dm_provenance *prov,
                     const char *source, dm_error *err)
{
    dm_result r = dm_pack_writer_add(&j->w, d, data, size, prov, err);
    if (r != DM_OK) return r;
    if (j->row_count < (int)(sizeof j->rows / sizeof j->rows[0])) {
        report_row *row = &j->rows[j->row_count++];
        snprintf(row->entry, sizeof row->entry, "%s", d->name);
        snprintf(row->source, sizeof row->source, "%s", source);
        row->size = size;
        row->ms = dm_now_ms() - j->step_t0;
    }
    return DM_OK;
}

static dm_pack_entry texture_desc(const char *name, dm_tex_format f, int w, int h)
{
    dm_pack_entry d;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "%s", name);
    d.kind = DM_PACK_TEXTURE;
    d.format = f;
    d.width = w;
    d.height = h;
    d.layers = 1;
    d.levels = 1;
    return d;
}

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

/* --- steps -------------------------------------------------------------------------- */

static dm_result step_scene(job *j, dm_error *err)
{
    char *text = NULL;
    dm_result r = dm_scene_to_json(&j->scene, &text, err);
    if (r != DM_OK) return r;
    dm_provenance p;
    dm_prov_init(&p, TOOL);
    snprintf(p.input_hash, sizeof p.input_hash, "%s", j->scene_hash);
    dm_prov_add_string(&p, "scene", j->opt->scene);
    dm_pack_entry d;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "scene");
    d.kind = DM_PACK_SCENE;
    r = add(j, &d, text, strlen(text), &p, "normalised from the scene file", err);
    free(text);
    return r;
}

/* A map from an image file: channels converted to the pack format, rows bottom-up. */
static dm_result pack_map(job *j, const char *entry, const char *path, dm_tex_format f, dm_error *err)
{
    dm_image img;
    char gltf_src[300] = "";
    const bool gltf = dm_gltf_is_file(path) && (!strcmp(entry, "albedo") || !strcmp(entry, "normal"));
    dm_result r = gltf ? dm_gltf_map_read(path, j->scene.mesh_name, !strcmp(entry, "albedo") ? DM_GLTF_MAP_BASE_COLOR
                                                                                              : DM_GLTF_MAP_NORMAL,
                                          DM_PIXEL_U8, &img, gltf_src, sizeof gltf_src, err)
                       : dm_image_read(path, DM_PIXEL_U8, &img, err);
    if (r != DM_OK) {
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
    dm_prov_init(&p, TOOL);
    r = dm_hash_file_hex(path, p.input_hash, err);
    dm_prov_add_string(&p, "source", path);
    if (gltf) dm_prov_add_string(&p, "gltf_image", gltf_src);
    dm_prov_add_string(&p, "conversion", out_c == 1 ? "u8 mean of colour channels" : "u8 rgb + alpha (255 if none)");
    dm_pack_entry d = texture_desc(entry, f, img.width, img.height);
    if (f == DM_TEX_RGBA8) {
        d.channel_count = 4;
        snprintf(d.channels[0], sizeof d.channels[0], "x");
        snprintf(d.channels[1], sizeof d.channels[1], "y");
        snprintf(d.channels[2], sizeof d.channels[2], "z");
        snprintf(d.channels[3], sizeof d.channels[3], "unused");
    }
    char src[160];
    snprintf(src, sizeof src, "from %.60s%s%.90s", base_name(path), gltf ? " " : "", gltf ? gltf_src : "");
    if (r == DM_OK) r = add(j, &d, px, n * (size_t)out_c, &p, src, err);
    free(px);
    dm_image_free(&img);
    return r;
}

static dm_result step_albedo(job *j, dm_error *err)
{
    return pack_map(j, "albedo", j->scene.albedo, DM_TEX_RGBA8_SRGB, err);
}
static dm_result step_normal(job *j, dm_error *err)
{
    return pack_map(j, "normal", j->scene.normal_map, DM_TEX_RGBA8, err);
}
static dm_result step_specular(job *j, dm_error *err)
{
    return pack_map(j, "specular", j->scene.specular_map, DM_TEX_R8, err);
}
static dm_result step_roughness(job *j, dm_error *err)
{
    return pack_map(j, "roughness", j->scene.roughness_map, DM_TEX_R8, err);
}

static dm_result step_beckmann(job *j, dm_error *err)
{
    const int n = j->opt->beckmann_size;
    dm_provenance want;
    dm_lut_prov_beckmann(&want, TOOL, n, n);
    dm_pack_entry d = texture_desc("lut.beckmann", DM_TEX_R8, n, n);
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
        snprintf(src, sizeof src, "from %s", base_name(f));
        if (r == DM_OK) r = add(j, &d, img.pixels, (size_t)n * n, &img.prov, src, err);
        dm_image_free(&img);
        return r;
    }
    dm_beckmann_lut lut;
    dm_result r = dm_lut_bake_beckmann(n, n, 0, j->opt->threads, &lut, err);
    if (r == DM_OK) r = add(j, &d, lut.texels, (size_t)n * n, &want, "baked", err);
    dm_beckmann_lut_free(&lut);
    return r;
}

/* Loads an already-baked directional LUT into `out` (w*h*channels interleaved). */
static dm_result load_directional(job *j, const char *file, const char *table, const char *const *channels, int nch,
                                  float *out, dm_provenance *prov, dm_error *err)
{
    const int n = j->opt->lut_size;
    dm_provenance want;
    dm_lut_prov_directional(&want, TOOL, table, n, n, DM_SKIN_F0, j->opt->lut_nodes);
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

static dm_result step_directional(job *j, dm_error *err)
{
    const int n = j->opt->lut_size, nodes = j->opt->lut_nodes;
    const size_t count = (size_t)n * n;
    bool need_rho = wanted(j, "lut.rho_dt"), need_env = wanted(j, "lut.env_brdf");
    bool bake = (need_rho && !j->opt->rho_dt) || (need_env && !j->opt->env_brdf);
    dm_directional_lut lut;
    memset(&lut, 0, sizeof lut);
    float *rg = malloc(count * 2 * sizeof *rg), *r1 = malloc(count * sizeof *r1);
    dm_result r = rg && r1 ? DM_OK : dm_fail(err, DM_ERR_OUT_OF_MEMORY, "directional LUT: out of memory");
    if (r == DM_OK && bake) r = dm_lut_bake_directional(n, n, DM_SKIN_F0, nodes, j->opt->threads, &lut, err);
    if (r == DM_OK && need_rho) {
        dm_pack_entry d = texture_desc("lut.rho_dt", DM_TEX_R32F, n, n);
        d.channel_count = 1;
        snprintf(d.channels[0], sizeof d.channels[0], "rho_dt");
        dm_provenance p;
        char src[160] = "baked";
        if (j->opt->rho_dt) {
            static const char *const ch[] = {"rho_dt"};
            r = load_directional(j, j->opt->rho_dt, "rho_dt", ch, 1, r1, &p, err);
            snprintf(src, sizeof src, "from %s", base_name(j->opt->rho_dt));
        } else {
            dm_lut_prov_directional(&p, TOOL, "rho_dt", n, n, DM_SKIN_F0, nodes);
            memcpy(r1, lut.rho_dt, count * sizeof *r1);
        }
        if (r == DM_OK) r = add(j, &d, r1, count * sizeof *r1, &p, src, err);
    }
    if (r == DM_OK && need_env) {
        dm_pack_entry d = texture_desc("lut.env_brdf", DM_TEX_RG32F, n, n);
        d.channel_count = 2;
        snprintf(d.channels[0], sizeof d.channels[0], "scale");
        snprintf(d.channels[1], sizeof d.channels[1], "bias");
        dm_provenance p;
        char src[160] = "baked";
        if (j->opt->env_brdf) {
            static const char *const ch[] = {"scale", "bias"};
            r = load_directional(j, j->opt->env_brdf, "env_brdf", ch, 2, rg, &p, err);
            snprintf(src, sizeof src, "from %s", base_name(j->opt->env_brdf));
        } else {
            dm_lut_prov_directional(&p, TOOL, "env_brdf", n, n, DM_SKIN_F0, nodes);
            for (size_t i = 0; i < count; ++i) {
                rg[2 * i] = lut.scale[i];
                rg[2 * i + 1] = lut.bias[i];
            }
        }
        if (r == DM_OK) r = add(j, &d, rg, count * 2 * sizeof *rg, &p, src, err);
    }
    dm_directional_lut_free(&lut);
    free(rg);
    free(r1);
    return r;
}

static dm_result step_profile(job *j, dm_error *err)
{
    const dm_profile *pr = &j->scene.profile;
    dm_provenance p;
    dm_prov_init(&p, TOOL);
    dm_prov_add_string(&p, "source", j->scene.profile_source);
    char *text = NULL;
    size_t size = 0;
    dm_result r = DM_OK;
    bool from_file = strcmp(j->scene.profile_source, "gems3-skin") != 0 && strcmp(j->scene.profile_source, "inline") != 0;
    if (from_file) { /* the file as it is: it keeps its fit error and its own provenance */
        r = dm_read_file(j->scene.profile_source, &text, &size, err);
        if (r == DM_OK) r = dm_hash_file_hex(j->scene.profile_source, p.input_hash, err);
    } else {
        size_t cap = 4096;
        text = malloc(cap);
        if (!text) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "profile: out of memory");
        size_t n = (size_t)snprintf(text, cap,
                                    "{\"format\": \"dermis-profile\", \"version\": 1, \"name\": \"%s\", \"gaussians\": [",
                                    pr->name);
        for (int k = 0; k < pr->count; ++k)
            n += (size_t)snprintf(text + n, cap - n, "%s\n  {\"variance_mm2\": %.17g, \"weights\": [%.17g, %.17g, %.17g]}",
                                  k ? "," : "", pr->variance_mm2[k], pr->weight[k][0], pr->weight[k][1], pr->weight[k][2]);
        n += (size_t)snprintf(text + n, cap - n, "\n]}\n");
        size = n;
    }
    dm_pack_entry d;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "profile");
    d.kind = DM_PACK_PROFILE;
    char src[160];
    if (from_file)
        snprintf(src, sizeof src, "from %.150s", base_name(j->scene.profile_source));
    else
        snprintf(src, sizeof src, "%s preset", pr->name);
    if (r == DM_OK) r = add(j, &d, text, size, &p, src, err);
    free(text);
    return r;
}

/* The screen-space technique's separable kernel, fitted to the profile (core/dm_ssss_kernel.h);
 * its fitting error goes into the entry's provenance and the report's source column. */
static dm_result step_ss_kernel(job *j, dm_error *err)
{
    dm_ssss_kernel k;
    dm_result r = dm_ssss_kernel_fit(&j->scene.profile, j->scene.screen_taps, &k, err);
    if (r != DM_OK) return r;
    float texels[DM_SSSS_MAX_TAPS * 4];
    dm_ssss_kernel_texels(&k, texels);
    dm_provenance p;
    dm_prov_init(&p, TOOL);
    dm_prov_add_string(&p, "source", j->scene.profile_source);
    dm_prov_add_string(&p, "product", "screen-space separable SSS kernel (Jimenez et al. 2015), rank-1 fit");
    dm_prov_add_int(&p, "taps", k.taps);
    dm_prov_add_double(&p, "range_mm", k.range_mm);
    dm_prov_add_double(&p, "fit_error_r", k.fit_error[0]);
    dm_prov_add_double(&p, "fit_error_g", k.fit_error[1]);
    dm_prov_add_double(&p, "fit_error_b", k.fit_error[2]);
    char src[160];
    snprintf(src, sizeof src, "%d taps, +-%.2f mm, fit error %.2f/%.2f/%.2f %% (R/G/B)", k.taps, k.range_mm,
             100 * k.fit_error[0], 100 * k.fit_error[1], 100 * k.fit_error[2]);
    dm_pack_entry d = texture_desc("sss.kernel", DM_TEX_RGBA32F, k.taps, 1);
    return add(j, &d, texels, (size_t)k.taps * 4 * sizeof(float), &p, src, err);
}

static dm_result ensure_mesh(job *j, dm_error *err)
{
    if (j->mesh_loaded) return DM_OK;
    dm_result r = dm_hash_file_hex(j->scene.mesh, j->mesh_hash, err);
    dm_mesh_load_options o = {.mesh_name = j->scene.mesh_name};
    if (r == DM_OK) r = dm_mesh_load(j->scene.mesh, &o, &j->mesh, err);
    j->mesh_loaded = r == DM_OK;
    char plausible[1024];
    if (r == DM_OK && dm_mesh_plausible(&j->mesh, j->scene.mm_per_unit, j->scene.mesh, plausible, sizeof plausible))
        fputs(plausible, stderr);
    return r;
}

static void mesh_prov(const job *j, dm_provenance *p, const char *what)
{
    dm_prov_init(p, TOOL);
    snprintf(p->input_hash, sizeof p->input_hash, "%s", j->mesh_hash);
    dm_prov_add_string(p, "source", j->scene.mesh);
    dm_prov_add_string(p, "product", what);
    dm_prov_add_double(p, "mm_per_unit", j->scene.mm_per_unit);
    dm_prov_add_int(p, "triangles", j->mesh.triangle_count);
}

/* The GPU mesh: split at seams by (position, uv, normal), tangents with handedness,
 * interleaved in the dermis layout (core/dm_pack.h DM_PACK_VERTEX_*). */
static dm_result step_mesh(job *j, dm_error *err)
{
    dm_result r = ensure_mesh(j, err);
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
    mesh_prov(j, &p, "split by position, uv, normal; tangents with handedness");
    dm_prov_add_int(&p, "vertices", (int64_t)vc);
    char src[200];
    snprintf(src, sizeof src, "from %.150s", base_name(j->scene.mesh));
    r = add(j, &d, v, vc * floats * sizeof *v, &p, src, err);
    if (r == DM_OK) {
        memset(&d, 0, sizeof d);
        snprintf(d.name, sizeof d.name, "mesh.indices");
        d.kind = DM_PACK_MESH_INDICES;
        d.index_count = g.index_count;
        snprintf(d.vertices, sizeof d.vertices, "mesh.vertices");
        mesh_prov(j, &p, "triangles, counter-clockwise");
        r = add(j, &d, g.indices, (size_t)g.index_count * sizeof *g.indices, &p, src, err);
    }
    free(v);
    dm_gpu_mesh_free(&g);
    return r;
}

/* A dermis-bake-stretch EXR in place of the bake, when it was made from this mesh (content
 * hash), at this mm_per_unit and irradiance size, through this profile's variances. */
static dm_result read_stretch(job *j, const char *file, dm_stretch_map *map, dm_error *err)
{
    dm_provenance p;
    dm_result r = dm_stretch_read(file, map, &p, err);
    if (r != DM_OK) return r;
    const dm_param *mm = dm_prov_find(&p, "mm_per_unit"), *name = dm_prov_find(&p, "mesh_name");
    const char *baked_name = name && name->type == DM_PARAM_STRING ? name->s : "";
    const int n = j->scene.irradiance_size;
    const dm_profile *pr = &j->scene.profile;
    if (strcmp(p.input_hash, j->mesh_hash) != 0)
        r = dm_fail(err, DM_ERR_MISMATCH, "%s: baked from a mesh with hash %s, %s has %s", file,
                    p.input_hash[0] ? p.input_hash : "(none)", j->scene.mesh, j->mesh_hash);
    else if (strcmp(baked_name, j->scene.mesh_name) != 0)
        r = dm_fail(err, DM_ERR_MISMATCH, "%s: baked from mesh name \"%s\", the scene's mesh.name is \"%s\"", file,
                    baked_name, j->scene.mesh_name);
    else if (!mm || mm->type == DM_PARAM_STRING || mm->d != j->scene.mm_per_unit)
        r = dm_fail(err, DM_ERR_MISMATCH, "%s: mm_per_unit is %g, the scene says %g", file, mm ? mm->d : 0.0,
                    j->scene.mm_per_unit);
    else if (map->width != n || map->height != n)
        r = dm_fail(err, DM_ERR_MISMATCH, "%s: %dx%d, the scene's irradiance size is %d (bake it with --size %d)",
                    file, map->width, map->height, n, n);
    else if (map->level_count != pr->count)
        r = dm_fail(err, DM_ERR_MISMATCH, "%s: %d levels, the scene's profile %s has %d Gaussians", file,
                    map->level_count, pr->name, pr->count);
    for (int k = 0; r == DM_OK && k < pr->count; ++k)
        if (map->variance_mm2[k] != pr->variance_mm2[k])
            r = dm_fail(err, DM_ERR_MISMATCH, "%s: level %d stands for %.17g mm^2, the scene's profile has %.17g",
                        file, k, map->variance_mm2[k], pr->variance_mm2[k]);
    if (r != DM_OK) dm_stretch_map_free(map);
    return r;
}

/* The stretch chain at the scene's irradiance size: one RG32F layer per Gaussian (u, v in
 * UV units per mm), and the chart mask as R8. */
static dm_result step_stretch(job *j, dm_error *err)
{
    dm_result r = ensure_mesh(j, err);
    if (r != DM_OK) return r;
    const int n = j->scene.irradiance_size;
    dm_stretch_options so = {.width = n,
                             .height = n,
                             .mm_per_unit = j->scene.mm_per_unit,
                             .profile = &j->scene.profile,
                             .thread_count = j->opt->threads};
    dm_stretch_map map;
    char src[200];
    snprintf(src, sizeof src, "baked from %.150s", base_name(j->scene.mesh));
    if (j->opt->stretch_file) {
        if ((r = read_stretch(j, j->opt->stretch_file, &map, err)) != DM_OK) return r;
        snprintf(src, sizeof src, "from %.150s", base_name(j->opt->stretch_file));
    } else if ((r = dm_stretch_bake(&j->mesh, &so, &map, err)) != DM_OK) {
        return r;
    }
    const size_t texels = (size_t)n * n;
    float *rg = malloc(texels * 2 * (size_t)map.level_count * sizeof *rg);
    uint8_t *mask = malloc(texels);
    if (!rg || !mask) r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "stretch %dx%d: out of memory", n, n);
    for (int k = 0; r == DM_OK && k < map.level_count; ++k)
        for (size_t i = 0; i < texels; ++i) {
            rg[((size_t)k * texels + i) * 2] = map.s_u[k][i];
            rg[((size_t)k * texels + i) * 2 + 1] = map.s_v[k][i];
        }
    for (size_t i = 0; r == DM_OK && i < texels; ++i) mask[i] = map.mask[i] > 0.5f ? 255 : 0;
    dm_provenance p;
    mesh_prov(j, &p, "stretch chain, UV units per mm, one layer per Gaussian");
    dm_prov_add_int(&p, "size", n);
    dm_prov_add_string(&p, "profile", j->scene.profile.name);
    for (int k = 0; k < map.level_count; ++k) {
        char name[32];
        snprintf(name, sizeof name, "variance%d_mm2", k);
        dm_prov_add_double(&p, name, map.variance_mm2[k]);
    }
    dm_prov_add_double(&p, "coverage", map.stats.coverage);
    if (j->opt->stretch_file) dm_prov_add_string(&p, "baked_file", j->opt->stretch_file);
    if (r == DM_OK) {
        dm_pack_entry d = texture_desc("stretch", DM_TEX_RG32F, n, n);
        d.layers = map.level_count;
        d.channel_count = 2;
        snprintf(d.channels[0], sizeof d.channels[0], "u");
        snprintf(d.channels[1], sizeof d.channels[1], "v");
        r = add(j, &d, rg, texels * 2 * (size_t)map.level_count * sizeof *rg, &p, src, err);
    }
    if (r == DM_OK) {
        dm_pack_entry d = texture_desc("stretch.mask", DM_TEX_R8, n, n);
        mesh_prov(j, &p, "chart coverage mask, 255 covered");
        dm_prov_add_int(&p, "size", n);
        r = add(j, &d, mask, texels, &p, src, err);
    }
    free(rg);
    free(mask);
    dm_stretch_map_free(&map);
    return r;
}

/* The pre-integrated technique's table (bake/dm_preintegrated.h) for the scene's profile:
 * 128 N.L x 64 curvature texels over 0..1 /mm, RGBA32F with a = 1; layout in the provenance. */
enum { PREINT_WIDTH = 128, PREINT_HEIGHT = 64 };
static dm_result step_preintegrated(job *j, dm_error *err)
{
    dm_preint_lut lut;
    dm_result r = dm_preint_bake(&j->scene.profile, PREINT_WIDTH, PREINT_HEIGHT, DM_PREINT_CURVATURE_MAX_DEFAULT,
                                 j->opt->threads, &lut, err);
    if (r != DM_OK) return r;
    size_t texels = (size_t)lut.width * lut.height;
    float *rgba = malloc(texels * 4 * sizeof *rgba);
    if (!rgba) {
        dm_preint_lut_free(&lut);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "pre-integrated table: out of memory");
    }
    for (size_t i = 0; i < texels; ++i) {
        for (int c = 0; c < 3; ++c) rgba[4 * i + c] = lut.rgb[c * texels + i];
        rgba[4 * i + 3] = 1.0f;
    }
    dm_provenance p;
    dm_prov_init(&p, TOOL);
    dm_prov_add_string(&p, "source", j->scene.profile_source);
    dm_prov_add_string(&p, "product", "pre-integrated skin diffuse D(N.L, curvature) (Penner 2011), rgb");
    dm_prov_add_string(&p, "s", "N.L = 2s-1 at texel centres");
    dm_prov_add_string(&p, "t", "curvature = curvature_max*j/(height-1) on row j");
    dm_prov_add_double(&p, "curvature_max_per_mm", lut.curvature_max_per_mm);
    char src[160];
    snprintf(src, sizeof src, "%dx%d, curvature 0..%g /mm, %.0f ms", lut.width, lut.height, lut.curvature_max_per_mm,
             lut.bake_ms);
    dm_pack_entry d = texture_desc("sss.preintegrated", DM_TEX_RGBA32F, lut.width, lut.height);
    r = add(j, &d, rgba, texels * 4 * sizeof *rgba, &p, src, err);
    free(rgba);
    dm_preint_lut_free(&lut);
    return r;
}

/* Mean curvature per texel at the irradiance size (bake/dm_curvature.h), smoothed over the
 * profile's RMS radius. */
static dm_result step_curvature(job *j, dm_error *err)
{
    dm_result r = ensure_mesh(j, err);
    if (r != DM_OK) return r;
    const int n = j->scene.irradiance_size;
    double smooth_mm = dm_curvature_profile_scale_mm(&j->scene.profile);
    dm_curvature_options o = {.width = n, .height = n, .mm_per_unit = j->scene.mm_per_unit, .smooth_mm = smooth_mm,
                              .thread_count = j->opt->threads};
    dm_curvature_map map;
    if ((r = dm_curvature_bake(&j->mesh, &o, &map, err)) != DM_OK) {
        dm_curvature_map_free(&map);
        return r;
    }
    dm_provenance p;
    mesh_prov(j, &p, "mean curvature, 1/mm, > 0 convex (cotangent Laplacian)");
    dm_prov_add_int(&p, "size", n);
    dm_prov_add_double(&p, "smooth_mm", smooth_mm);
    dm_prov_add_string(&p, "profile", j->scene.profile.name);
    char src[200];
    snprintf(src, sizeof src, "baked from %.120s, median %.3g /mm, smoothing %.2f mm", base_name(j->scene.mesh),
             map.stats.percentile[2], smooth_mm);
    dm_pack_entry d = texture_desc("sss.curvature", DM_TEX_R32F, n, n);
    r = add(j, &d, map.curvature, (size_t)n * n * sizeof(float), &p, src, err);
    dm_curvature_map_free(&map);
    return r;
}

/* One packed environment: k = 0 the main map (env.*), k > 0 alternative k (env<k>.*). */
static dm_result bake_environment(job *j, int k, dm_error *err)
{
    const dm_pack_need *sh_row = dm_pack_need_find("env.sh"), *spec_row = dm_pack_need_find("env.specular"),
                       *bg_row = dm_pack_need_find("env.background");
    char sh_name[DM_PACK_NAME_SIZE], spec_name[DM_PACK_NAME_SIZE], bg_name[DM_PACK_NAME_SIZE];
    dm_pack_need_entry_name(sh_row, k, sh_name);
    dm_pack_need_entry_name(spec_row, k, spec_name);
    dm_pack_need_entry_name(bg_row, k, bg_name);
    const char *path = k == 0 ? j->scene.environment : j->scene.env_alternatives[k - 1];
    bool lighting = wanted(j, sh_name) || wanted(j, spec_name);
    bool background = wanted(j, bg_name);
    if (!lighting && !background) return DM_OK;
    dm_pack_env env;
    dm_result r = DM_OK;
    char src[200];
    snprintf(src, sizeof src, "from %.150s", base_name(path));
    /* An already-baked file for this map (matched by content hash), else bake. A file for
     * another map is skipped; an unreadable file, or one for this map that cannot serve,
     * is an error that says why. */
    int used = -1;
    for (int f = 0; f < j->opt->env_file_count && used < 0; ++f) {
        bool same_map = false;
        r = dm_pack_env_from_file(j->opt->env_files[f], path, lighting, background, TOOL, &env, &same_map, err);
        if (r == DM_OK) {
            used = f;
            break;
        }
        dm_pack_env_free(&env);
        if (r != DM_ERR_MISMATCH || same_map) return r;
        r = DM_OK;
    }
    if (used >= 0) {
        j->env_file_used[used] = true;
        snprintf(src, sizeof src, "from %.150s", base_name(j->opt->env_files[used]));
    } else {
        r = dm_pack_env_bake(path, lighting, background, TOOL, j->opt->threads, &env, err);
    }
    if (r == DM_OK && lighting) {
        dm_pack_entry d;
        memset(&d, 0, sizeof d);
        snprintf(d.name, sizeof d.name, "%s", sh_name);
        d.kind = DM_PACK_ENV_SH;
        d.sh_order = 2;
        r = add(j, &d, env.sh, sizeof env.sh, &env.sh_prov, src, err);
        if (r == DM_OK) {
            d = texture_desc(spec_name, DM_TEX_RGBA32F, env.spec_width, env.spec_height);
            d.layers = env.spec_layers;
            r = add(j, &d, env.spec_rgba, (size_t)env.spec_width * env.spec_height * env.spec_layers * 4 * sizeof(float),
                    &env.spec_prov, src, err);
        }
    }
    if (r == DM_OK && background) {
        dm_pack_entry d = texture_desc(bg_name, DM_TEX_RGBA32F, env.background_width, env.background_height);
        r = add(j, &d, env.background_rgba, (size_t)env.background_width * env.background_height * 4 * sizeof(float),
                &env.background_prov, src, err);
    }
    dm_pack_env_free(&env);
    return r;
}

/* The main environment, then each alternative of environment.alternatives. */
static dm_result step_environment(job *j, dm_error *err)
{
    dm_result r = DM_OK;
    for (int k = 0; r == DM_OK && k <= j->scene.env_alternative_count; ++k) r = bake_environment(j, k, err);
    return r;
}

/* The bake steps, in pack order. A step runs when one of its entries applies to the scene
 * (dm_pack_needs.h); it adds only the entries that apply.
 */
typedef struct step {
    const char *name;
    const char *entries[3];
    dm_result (*run)(job *j, dm_error *err);
} step;

static const step steps[] = {
    {"scene", {"scene"}, step_scene},
    {"mesh", {"mesh.vertices", "mesh.indices"}, step_mesh},
    {"albedo map", {"albedo"}, step_albedo},
    {"normal map", {"normal"}, step_normal},
    {"specular map", {"specular"}, step_specular},
    {"roughness map", {"roughness"}, step_roughness},
    {"Beckmann LUT", {"lut.beckmann"}, step_beckmann},
    {"directional LUTs", {"lut.rho_dt", "lut.env_brdf"}, step_directional},
    {"profile", {"profile"}, step_profile},
    {"stretch", {"stretch", "stretch.mask"}, step_stretch},
    {"screen-space kernel", {"sss.kernel"}, step_ss_kernel},
    {"pre-integrated table", {"sss.preintegrated"}, step_preintegrated},
    {"curvature", {"sss.curvature"}, step_curvature},
    {"environment", {"env.sh", "env.specular", "env.background"}, step_environment},
};

/* --- explain ------------------------------------------------------------------------ */

static void explain(const dm_scene *s)
{
    printf("scene %s\neffects:", s->path);
    for (int e = 0; e < DM_EFFECT_COUNT; ++e)
        printf(" %s=%s", dm_effect_name((dm_effect)e), s->effects[e] ? "on" : "off");
    printf("\n\n%-8s %-15s %-19s %-52s %s\n", "status", "entry", "kind", "needed by", "what");
    int n;
    const dm_pack_need *needs = dm_pack_needs(&n);
    for (int k = 0; k < n; ++k) {
        const dm_pack_need *nd = &needs[k];
        bool applies = dm_pack_need_applies(nd, s);
        char kind[64], by[160] = "";
        snprintf(kind, sizeof kind, "%s%s%s", dm_pack_kind_name(nd->kind), nd->format >= 0 ? " " : "",
                 nd->format >= 0 ? dm_tex_format_get((dm_tex_format)nd->format)->name : "");
        size_t m = 0;
        if (!nd->effects) m += (size_t)snprintf(by, sizeof by, "always");
        for (int e = 0; e < DM_EFFECT_COUNT; ++e)
            if (nd->effects & DM_FX(e))
                m += (size_t)snprintf(by + m, m < sizeof by ? sizeof by - m : 0, "%s%s%s", m ? "|" : "",
                                      dm_effect_name((dm_effect)e), s->effects[e] ? "" : "(off)");
        if (nd->when && m < sizeof by)
            snprintf(by + m, sizeof by - m, " if %s", dm_need_when_text(nd->when));
        const char *status = applies ? "pack" : "skip";
        for (int c = 0; c < dm_pack_need_copies(nd, s); ++c) { /* env<k>.*: one per alternative map */
            char name[DM_PACK_NAME_SIZE], why[1200];
            if (c == 0)
                snprintf(why, sizeof why, "%s", nd->why);
            else
                snprintf(why, sizeof why, "%s (alternative %d: %s)", nd->why, c, base_name(s->env_alternatives[c - 1]));
            printf("%-8s %-15s %-19s %-52s %s\n", status, dm_pack_need_entry_name(nd, c, name), kind, by, why);
        }
    }
    printf("\npack = baked and packed; skip = no enabled effect or input needs it\n");
}

/* --- main --------------------------------------------------------------------------- */

static int parse_args(int argc, char **argv, options *o)
{
    *o = (options){.beckmann_size = DM_LUT_BECKMANN_SIZE_DEFAULT,
                   .lut_size = DM_LUT_DIRECTIONAL_SIZE_DEFAULT,
                   .lut_nodes = DM_LUT_NODES_DEFAULT};
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        int64_t v;
        if (dm_cli_version(a, "dermis-pack")) exit(0);
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            exit(DM_EXIT_OK);
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            if (!(o->output = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--explain")) {
            o->explain = true;
        } else if (!strcmp(a, "--beckmann")) {
            if (!(o->beckmann = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--rho-dt")) {
            if (!(o->rho_dt = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--env-brdf")) {
            if (!(o->env_brdf = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--stretch")) {
            if (!(o->stretch_file = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--env")) {
            if (o->env_file_count == 8) {
                fprintf(stderr, "error: --env: at most 8 files (one per environment map)\n");
                return DM_EXIT_USAGE;
            }
            if (!(o->env_files[o->env_file_count++] = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--beckmann-size")) {
            const char *t = dm_cli_value(argc, argv, &i);
            if (!t || !dm_cli_int(a, t, 16, DM_LUT_SIZE_MAX, &v)) return DM_EXIT_USAGE;
            o->beckmann_size = (int)v;
        } else if (!strcmp(a, "--lut-size")) {
            const char *t = dm_cli_value(argc, argv, &i);
            if (!t || !dm_cli_int(a, t, 8, 1024, &v)) return DM_EXIT_USAGE;
            o->lut_size = (int)v;
        } else if (!strcmp(a, "--lut-nodes")) {
            const char *t = dm_cli_value(argc, argv, &i);
            if (!t || !dm_cli_int(a, t, 8, 128, &v)) return DM_EXIT_USAGE;
            o->lut_nodes = (int)v;
        } else if (!strcmp(a, "--threads")) {
            const char *t = dm_cli_value(argc, argv, &i);
            if (!t || !dm_cli_int(a, t, 0, 256, &v)) return DM_EXIT_USAGE;
            o->threads = (int)v;
        } else if (!strcmp(a, "--assets")) {
            const char *v = dm_cli_value(argc, argv, &i);
            if (!v) return DM_EXIT_USAGE;
            if (o->asset_count == 8) {
                fprintf(stderr, "error: --assets: at most 8 folders\n");
                return DM_EXIT_USAGE;
            }
            o->assets[o->asset_count++] = v;
        } else if (!strcmp(a, "-v") || !strcmp(a, "--verbose")) {
            o->verbose = true;
        } else if (!strcmp(a, "--quiet")) {
            o->quiet = true;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "error: unknown option '%s' (see --help)\n", a);
            return DM_EXIT_USAGE;
        } else if (o->scene) {
            fprintf(stderr, "error: '%s': one scene only, '%s' already given\n", a, o->scene);
            return DM_EXIT_USAGE;
        } else {
            o->scene = a;
        }
    }
    if (!o->scene) {
        fprintf(stderr, "error: no scene given\n");
        usage(stderr);
        return DM_EXIT_USAGE;
    }
    if (o->explain && o->output) {
        fprintf(stderr, "error: --explain writes nothing: drop -o %s\n", o->output);
        return DM_EXIT_USAGE;
    }
    if (!o->explain && !o->output) {
        fprintf(stderr, "error: no output: give -o FILE.dpk (or --explain)\n");
        return DM_EXIT_USAGE;
    }
    if (o->verbose && o->quiet) {
        fprintf(stderr, "error: -v and --quiet conflict\n");
        return DM_EXIT_USAGE;
    }
    return DM_EXIT_OK;
}

static void print_size(char *out, size_t n, size_t bytes)
{
    if (bytes >= (1u << 20))
        snprintf(out, n, "%.2f MiB", bytes / 1048576.0);
    else if (bytes >= 1024)
        snprintf(out, n, "%.1f KiB", bytes / 1024.0);
    else
        snprintf(out, n, "%zu B", bytes);
}

/* A glTF mesh brings its material: where the scene names no albedo or normal map, the
 * material's baseColor / normal texture stands in (the map's path becomes the glTF file,
 * which pack_map reads through dm_gltf_map_read). */
static dm_result gltf_material_maps(job *j, dm_error *err)
{
    if (!dm_gltf_is_file(j->scene.mesh)) return DM_OK;
    struct { char *field; dm_gltf_map which; const char *what; } maps[2] = {
        {j->scene.albedo, DM_GLTF_MAP_BASE_COLOR, "albedo"}, {j->scene.normal_map, DM_GLTF_MAP_NORMAL, "normal_map"}};
    for (int k = 0; k < 2; ++k) {
        if (maps[k].field[0]) continue;
        int found = 0;
        char src[300];
        dm_result r = dm_gltf_map_find(j->scene.mesh, j->scene.mesh_name, maps[k].which, &found, src, sizeof src, err);
        if (r != DM_OK) return r;
        if (!found) continue;
        snprintf(maps[k].field, DM_SCENE_PATH_SIZE, "%s", j->scene.mesh);
        if (!j->opt->quiet)
            fprintf(stderr, "note: material.%s: the glTF material's %s, %s\n", maps[k].what,
                    maps[k].which == DM_GLTF_MAP_BASE_COLOR ? "baseColorTexture" : "normalTexture", src);
    }
    return DM_OK;
}

int main(int argc, char **argv)
{
    options opt;
    int rc = parse_args(argc, argv, &opt);
    if (rc != DM_EXIT_OK) return rc;

    job *j = calloc(1, sizeof *j);
    if (!j) return DM_EXIT_PROCESS;
    j->opt = &opt;
    dm_error err = {0};
    double t0 = dm_now_ms();
    if (dm_scene_read_assets(opt.scene, opt.assets, opt.asset_count, &j->scene, &err) != DM_OK ||
        dm_hash_file_hex(opt.scene, j->scene_hash, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        free(j);
        return DM_EXIT_LOAD;
    }
    if (gltf_material_maps(j, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        free(j);
        return DM_EXIT_LOAD;
    }
    if (j->scene.light_count == 0 && !j->scene.effects[DM_EFFECT_ENVIRONMENT_LIGHTING])
        fprintf(stderr,
                "warning: %s: no light and no environment lighting: every picture of this pack will be black; add a "
                "light to $.lights or turn on $.effects.environment_lighting with an $.environment.path\n",
                opt.scene);
    if (opt.explain) {
        explain(&j->scene);
        free(j);
        return DM_EXIT_OK;
    }
    /* Files given for entries the scene does not need are a mistake worth saying. */
    const struct { const char *file, *entry, *opt; } given[] = {
        {opt.beckmann, "lut.beckmann", "--beckmann"}, {opt.rho_dt, "lut.rho_dt", "--rho-dt"},
        {opt.env_brdf, "lut.env_brdf", "--env-brdf"}, {opt.stretch_file, "stretch", "--stretch"}};
    for (size_t k = 0; k < sizeof given / sizeof given[0]; ++k)
        if (given[k].file && !wanted(j, given[k].entry) && !opt.quiet)
            fprintf(stderr, "warning: %s %s: the scene's effects do not need %s; ignored\n", given[k].opt,
                    given[k].file, given[k].entry);

    dm_pack_writer_init(&j->w);
    /* a bar by step (a step's own work is not split) when stderr is a terminal */
    enum { STEP_COUNT = sizeof steps / sizeof steps[0] };
    bool will_run[STEP_COUNT];
    int run_count = 0, done = 0;
    for (size_t s = 0; s < STEP_COUNT; ++s) {
        will_run[s] = false;
        for (int e = 0; e < 3 && steps[s].entries[e]; ++e) will_run[s] = will_run[s] || wanted(j, steps[s].entries[e]);
        run_count += will_run[s];
    }
    dm_progress bar;
    dm_progress_begin(&bar, "pack", opt.quiet);
    for (size_t s = 0; s < STEP_COUNT; ++s) {
        if (!will_run[s]) continue;
        j->step_t0 = dm_now_ms();
        dm_error step_err = {0};
        dm_result step_r = steps[s].run(j, &step_err);
        dm_progress_update(&bar, (double)++done / (run_count + 1));
        if (step_r != DM_OK) {
            dm_progress_end(&bar);
            err = step_err;
            fprintf(stderr, "error: %s: %s\n", steps[s].name, err.detail);
            job_free(j);
            return err.code == DM_ERR_FILE_OPEN || err.code == DM_ERR_MISMATCH || err.code == DM_ERR_FORMAT
                       ? DM_EXIT_LOAD
                       : DM_EXIT_PROCESS;
        }
    }
    dm_progress_end(&bar);
    for (int f = 0; f < opt.env_file_count; ++f)
        if (!j->env_file_used[f] && !opt.quiet)
            fprintf(stderr, "warning: --env %s: baked from none of the scene's environment maps (or none is "
                            "needed); ignored\n", opt.env_files[f]);

    dm_provenance pp;
    dm_prov_init(&pp, TOOL);
    snprintf(pp.input_hash, sizeof pp.input_hash, "%s", j->scene_hash);
    dm_prov_add_string(&pp, "scene", opt.scene);
    dm_prov_add_int(&pp, "beckmann_size", opt.beckmann_size);
    dm_prov_add_int(&pp, "lut_size", opt.lut_size);
    dm_prov_add_int(&pp, "lut_nodes", opt.lut_nodes);
    dm_prov_add_double(&pp, "f0", DM_SKIN_F0);
    dm_prov_add_string(&pp, "beckmann_file", opt.beckmann ? opt.beckmann : "");
    dm_prov_add_string(&pp, "rho_dt_file", opt.rho_dt ? opt.rho_dt : "");
    dm_prov_add_string(&pp, "env_brdf_file", opt.env_brdf ? opt.env_brdf : "");
    size_t total = 0;
    double tw = dm_now_ms();
    dm_result r = dm_pack_writer_write(&j->w, opt.output, &pp, &total, &err);
    tw = dm_now_ms() - tw;
    if (r != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        job_free(j);
        return r == DM_ERR_FILE_WRITE ? DM_EXIT_SAVE : DM_EXIT_PROCESS;
    }
    if (!opt.quiet) {
        printf("%s -> %s\n", opt.scene, opt.output);
        printf("  %-14s %-20s %12s %9s  %s\n", "entry", "kind", "size", "ms", "source");
        for (int k = 0; k < j->row_count; ++k) {
            const dm_pack_blob *b = &j->w.blobs[k];
            char kind[48], sz[32];
            snprintf(kind, sizeof kind, "%s%s%s", dm_pack_kind_name(b->desc.kind),
                     b->desc.kind == DM_PACK_TEXTURE ? " " : "",
                     b->desc.kind == DM_PACK_TEXTURE ? dm_tex_format_get(b->desc.format)->name : "");
            print_size(sz, sizeof sz, j->rows[k].size);
            printf("  %-14s %-20s %12s %9.1f  %s\n", j->rows[k].entry, kind, sz, j->rows[k].ms, j->rows[k].source);
            if (opt.verbose) printf("      provenance %s\n", b->provenance_json);
        }
        char sz[32];
        print_size(sz, sizeof sz, total);
        printf("  %d entries, %s, written and verified in %.1f ms, total %.1f ms\n", j->row_count, sz, tw,
               dm_now_ms() - t0);
    }
    job_free(j);
    return DM_EXIT_OK;
}
