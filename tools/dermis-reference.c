/* dermis-reference — the ground truth: the exact surface convolution of a pack's
 * irradiance in texture space, or a ground-truth frame from the scene's camera; tiles
 * for a farm and their merge. Straight pipeline: parse → load → irradiance → convolve →
 * write. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/dm_exr.h"
#include "bake/dm_profile_fit.h"
#include "bake/dm_skin_spec.h"
#include "reference/dm_ref_frame.h"
#include "reference/dm_ref_surface.h"
#include "reference/dm_reference.h"
#include "reference/dm_reference_tiles.h"
#include "core/dm_cli.h"
#include "core/dm_hash.h"
#include "core/dm_output.h"
#include "pack/dm_pack.h"
#include "core/dm_parallel.h"
#include "core/dm_png.h"
#include "core/dm_prov.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_memory.h"
#include "render/dm_render_pack.h"

#include "ref/ref_args.h"

static void on_progress(void *p, double f) { dm_progress_update(p, f); }

/* ---- texture space ----------------------------------------------------------------- */

/* I: the renderer's level-0 irradiance at N (headless), or an EXR of it. */
static int irradiance_atlas(const ref_args *a, const dm_pack *pack, float *rgba, char *source, size_t source_size)
{
    dm_error err = {0};
    const int N = a->size;
    if (a->irradiance) {
        dm_exr_image img;
        if (dm_exr_read(a->irradiance, &img, &err) != DM_OK) {
            fprintf(stderr, "error: %s\n", err.detail);
            dm_exr_free(&img);
            return DM_EXIT_LOAD;
        }
        const char *ch[4] = {"R", "G", "B", "A"};
        for (int c = 0; c < 4; ++c) {
            const float *p = dm_exr_find(&img, ch[c]);
            if (!p || img.width != N || img.height != N) {
                fprintf(stderr, "error: %s: expected an %dx%d RGBA EXR, found %dx%d%s\n", a->irradiance, N, N,
                        img.width, img.height, p ? "" : " without all of R, G, B, A");
                dm_exr_free(&img);
                return DM_EXIT_LOAD;
            }
            for (size_t i = 0; i < (size_t)N * N; ++i) rgba[4 * i + (size_t)c] = isfinite(p[i]) ? p[i] : 0.0f;
        }
        dm_exr_free(&img);
        char hex[DM_HASH_HEX_SIZE];
        if (dm_hash_file_hex(a->irradiance, hex, &err) != DM_OK) hex[0] = 0;
        snprintf(source, source_size, "file %s", hex);
        return -1;
    }
    dm_osmesa *gl = NULL;
    dm_renderer *r = NULL;
    dm_scene scene;
    dm_profile profile;
    dm_render_assets assets;
    int code = DM_EXIT_PROCESS;
    dm_render_desc desc = {.width = 64, .height = 64, .irradiance_size = N};
    dm_result loaded = dm_render_assets_from_pack(pack, &scene, &profile, &assets, &err);
    /* the charts' own light only: the seam map would light the gutters beyond them too (the
     * runtime's continuation), and the truth carries light across seams by its own 3-D sum */
    assets.seam = (dm_texture){0};
    if (loaded != DM_OK) code = DM_EXIT_LOAD;
    else if (!scene.effects[DM_EFFECT_SUBSURFACE])
        dm_fail(&err, DM_ERR_MISMATCH, "%.900s: the scene's subsurface effect is off: no irradiance to diffuse", pack->what);
    else if (dm_osmesa_create(&gl, &err) == DM_OK && dm_renderer_create(&assets, &desc, &r, &err) == DM_OK &&
             dm_render_frame(r, &(dm_frame_options){.view = DM_VIEW_IRRADIANCE}, &err) == DM_OK) {
        int t = dm_renderer_find_target(r, "irradiance");
        dm_target_info info;
        if (t >= 0) dm_renderer_target_info(r, t, &info);
        if (t < 0 || info.width != N || info.height != N || info.channels != 4)
            snprintf(err.detail, sizeof err.detail, "the renderer has no %dx%d RGBA irradiance target", N, N);
        else if (dm_renderer_read_target(r, t, rgba, &err) == DM_OK)
            code = -1;
    }
    if (code != -1) fprintf(stderr, "error: %s\n", err.detail);
    /* the shadow map's size in the source: the irradiance, and so the truth, depend on it */
    snprintf(source, source_size, "dermis-render irradiance %d, shadow map %d (%s)", N, DM_RENDER_SHADOW_SIZE_DEFAULT,
             gl && r ? dm_renderer_gl_name(r) : "");
    dm_renderer_destroy(r);
    dm_osmesa_destroy(gl);
    return code;
}

/* The pack's mesh (mesh units, per-corner UVs) and profile, through the frame's surface. */
static int load_surface(const ref_args *a, const dm_pack *pack, dm_scene *scene, dm_profile *profile,
                        dm_ref_surface **surface)
{
    dm_error err = {0};
    dm_ref_surface_desc desc;
    if (dm_pack_scene(pack, scene, &err) != DM_OK ||
        dm_ref_surface_desc_from_pack(pack, scene, profile, &desc, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return DM_EXIT_LOAD;
    }
    if (dm_ref_surface_create(&desc, a->threads, surface, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return DM_EXIT_PROCESS;
    }
    return -1;
}

/* The physical skin's own profile in a->radial_gaussians dense Gaussians (its residual printed). */
static int skin_kernel(const ref_args *a, dm_reference_kernel *k, char *name, size_t name_size)
{
    dm_error err = {0};
    dm_skin_params p;
    if ((a->skin ? dm_skin_spec_parse(a->skin, "--skin", &p, &err) : dm_skin_preset(a->skin_preset, &p, &err)) != DM_OK) {
        fprintf(stderr, "error: %s%s\n", a->skin ? "" : "--skin-preset: ", err.detail);
        return DM_EXIT_USAGE;
    }
    dm_profile_source src;
    double e[3];
    if (dm_profile_source_skin(&p, &src, &err) != DM_OK ||
        dm_reference_kernel_from_source(&src, a->radial_gaussians, k, e, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return DM_EXIT_PROCESS;
    }
    snprintf(name, name_size, "skin:%s", a->skin ? a->skin : a->skin_preset);
    if (!a->quiet)
        printf("%s %s in %d Gaussians (sigma %.3g..%.3g mm): relative L2 error %.2e %.2e %.2e (residual)\n",
               a->skin ? "--skin" : "--skin-preset", a->skin ? a->skin : a->skin_preset, k->count,
               sqrt(k->variance_mm2[0]), sqrt(k->variance_mm2[k->count - 1]), e[0], e[1], e[2]);
    return -1;
}

/* What is convolved: the profile's Gaussians, or --dipole/--multipole/--skin's representation. */
static int make_kernel(const ref_args *a, const dm_profile *profile, dm_reference_kernel *k, char *name, size_t name_size)
{
    dm_error err = {0};
    if (a->skin || a->skin_preset) return skin_kernel(a, k, name, name_size);
    if (!a->medium) {
        snprintf(name, name_size, "%s", profile->name);
        if (dm_reference_kernel_from_profile(profile, k, &err) == DM_OK) return -1;
        fprintf(stderr, "error: %s: %s\n", a->pack, err.detail);
        return DM_EXIT_PROCESS;
    }
    dm_profile_source src;
    double e[3];
    const char *opt = a->burley ? "--burley" : a->multipole ? "--multipole" : "--dipole";
    if (dm_profile_source_parse(a->medium, a->burley, a->multipole, a->thickness_mm, a->pairs, opt, &src, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return DM_EXIT_USAGE;
    }
    if (dm_reference_kernel_from_source(&src, a->radial_gaussians, k, e, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return DM_EXIT_PROCESS;
    }
    snprintf(name, name_size, "%s:%s", opt + 2, a->medium);
    if (!a->quiet)
        printf("%s %s in %d Gaussians (sigma %.3g..%.3g mm): relative L2 error %.2e %.2e %.2e\n", opt, a->medium, k->count,
               sqrt(k->variance_mm2[0]), sqrt(k->variance_mm2[k->count - 1]), e[0], e[1], e[2]);
    return -1;
}

static void base_provenance(const ref_args *a, const char *mode, dm_provenance *prov)
{
    dm_prov_init(prov, "dermis-reference");
    char hex[DM_HASH_HEX_SIZE];
    dm_error err = {0};
    if (a->pack && dm_hash_file_hex(a->pack, hex, &err) == DM_OK) snprintf(prov->input_hash, sizeof prov->input_hash, "%s", hex);
    dm_prov_add_string(prov, "mode", mode);
    dm_prov_add_double(prov, "cut_sigma", a->ropt.cut_sigma != 0.0 ? a->ropt.cut_sigma : 4.0);
    dm_prov_add_double(prov, "spacing_sigma", a->ropt.spacing_sigma != 0.0 ? a->ropt.spacing_sigma : 0.3);
    dm_prov_add_double(prov, "wide_texels", a->ropt.wide_texels != 0.0 ? a->ropt.wide_texels : 4.0);
    if (a->skin || a->skin_preset) {
        dm_skin_params p;
        char spec[512];
        if ((a->skin ? dm_skin_spec_parse(a->skin, "--skin", &p, NULL) : dm_skin_preset(a->skin_preset, &p, NULL)) == DM_OK) {
            dm_skin_spec_format(&p, 17, spec, sizeof spec);
            dm_prov_add_string(prov, "skin", spec);
        }
        if (a->skin_preset) dm_prov_add_string(prov, "skin_preset", a->skin_preset);
        dm_prov_add_int(prov, "radial_gaussians", a->radial_gaussians);
    }
    if (a->medium) {
        dm_prov_add_string(prov, a->burley ? "burley" : a->multipole ? "multipole" : "dipole", a->medium);
        if (a->multipole) dm_prov_add_double(prov, "thickness_mm", a->thickness_mm);
        if (a->multipole) dm_prov_add_int(prov, "pairs", a->pairs ? a->pairs : DM_MULTIPOLE_PAIRS_DEFAULT);
        dm_prov_add_int(prov, "radial_gaussians", a->radial_gaussians);
    }
}

static int texture_space(const ref_args *a, const dm_pack *pack)
{
    const int N = a->size;
    dm_error err = {0};
    dm_scene scene;
    dm_profile profile;
    dm_ref_surface *surface = NULL;
    int code = load_surface(a, pack, &scene, &profile, &surface);
    if (code != -1) return code;
    float *atlas = malloc(sizeof *atlas * 4 * (size_t)N * N);
    char source[256] = "";
    double t0 = dm_now_ms();
    if (!atlas) code = DM_EXIT_PROCESS;
    else code = irradiance_atlas(a, pack, atlas, source, sizeof source);
    double irr_ms = dm_now_ms() - t0;
    dm_reference_kernel kernel;
    dm_reference *ref = NULL;
    dm_reference_target *targets = NULL;
    int64_t *texel_of = NULL;
    size_t count = 0;
    dm_reference_atlas ra = {N, N, atlas};
    dm_progress bar;
    dm_progress_begin(&bar, "convolution", a->quiet);
    dm_reference_options ropt = a->ropt;
    ropt.progress = on_progress;
    ropt.progress_user = &bar;
    char kernel_name[256] = "";
    if (code == -1) code = make_kernel(a, &profile, &kernel, kernel_name, sizeof kernel_name);
    if (code == -1 && (dm_reference_atlas_targets(&surface->mesh, &ra, a->threads, &targets, &texel_of, &count, &err) != DM_OK ||
                       dm_reference_create(&surface->mesh, scene.mm_per_unit, &ra, &kernel, &ropt, &ref, &err) != DM_OK)) {
        fprintf(stderr, "error: %s: %s\n", a->pack, err.detail);
        code = DM_EXIT_PROCESS;
    }
    /* this tile's slice of the targets */
    size_t begin = (size_t)((double)count * (a->tile_index - 1) / a->tile_count);
    size_t end = (size_t)((double)count * a->tile_index / a->tile_count);
    int K = kernel.count;
    float *rgb = NULL, *levels = NULL, *planes = NULL;
    double eval_ms = 0.0;
    if (code == -1) {
        rgb = malloc(sizeof *rgb * 3 * (end - begin + 1));
        levels = a->levels ? malloc(sizeof *levels * 3 * (size_t)K * (end - begin + 1)) : NULL;
        planes = calloc((size_t)N * N * (4 + (a->levels ? 3 * (size_t)K : 0)), sizeof *planes);
        if (!rgb || !planes || (a->levels && !levels)) {
            fprintf(stderr, "error: cannot allocate the %dx%d result\n", N, N);
            code = DM_EXIT_PROCESS;
        }
    }
    if (code == -1) {
        t0 = dm_now_ms();
        dm_result r = dm_reference_eval(ref, targets + begin, end - begin, rgb, levels, &err);
        eval_ms = dm_now_ms() - t0;
        if (r != DM_OK) {
            fprintf(stderr, "error: %s\n", err.detail);
            code = DM_EXIT_PROCESS;
        }
    }
    if (code == -1) {
        size_t plane = (size_t)N * N;
        for (size_t i = begin; i < end; ++i) {
            size_t x = (size_t)texel_of[i];
            for (int c = 0; c < 3; ++c) planes[(size_t)c * plane + x] = rgb[3 * (i - begin) + (size_t)c];
            planes[3 * plane + x] = 1.0f;
            for (int k = 0; a->levels && k < K; ++k)
                for (int c = 0; c < 3; ++c)
                    planes[(4 + 3 * (size_t)k + (size_t)c) * plane + x] = levels[(3 * (i - begin) * (size_t)K) + 3 * (size_t)k + (size_t)c];
        }
        enum { CH_MAX = 4 + 3 * DM_REFERENCE_GAUSSIANS_MAX };
        static char names[CH_MAX][16];
        dm_exr_channel ch[CH_MAX];
        const char *rgba_names[4] = {"R", "G", "B", "A"};
        int nch = 4 + (a->levels ? 3 * K : 0);
        for (int c = 0; c < nch; ++c) {
            if (c < 4) snprintf(names[c], sizeof names[c], "%s", rgba_names[c]);
            else snprintf(names[c], sizeof names[c], "S%d.%s", (c - 4) / 3, rgba_names[(c - 4) % 3]);
            ch[c] = (dm_exr_channel){names[c], planes + (size_t)c * plane, DM_EXR_FLOAT};
        }
        dm_provenance prov;
        base_provenance(a, "texture-space", &prov);
        dm_reference_stats st;
        dm_reference_get_stats(ref, &st);
        dm_prov_add_int(&prov, "size", N);
        dm_prov_add_string(&prov, "irradiance", source);
        dm_prov_add_string(&prov, "profile", kernel_name);
        dm_prov_add_int(&prov, "gaussians", K);
        dm_prov_add_double(&prov, "mm_per_unit", scene.mm_per_unit);
        dm_prov_add_int(&prov, "covered_texels", (int64_t)count);
        dm_prov_add_int(&prov, "tile_index", a->tile_index);
        dm_prov_add_int(&prov, "tile_count", a->tile_count);
        dm_prov_add_int(&prov, "levels", a->levels);
        if (!dm_cli_finite(planes, (size_t)nch * plane, "the texture-space reference")) {
            code = DM_EXIT_PROCESS;
        } else if (dm_exr_write(a->out, N, N, ch, nch, &prov, &err) != DM_OK) {
            fprintf(stderr, "error: %s\n", err.detail);
            code = DM_EXIT_SAVE;
        } else {
            if (!a->quiet) {
                printf("%s: %dx%d texture-space reference, %zu of %zu covered texels (tile %d/%d)\n", a->out, N, N,
                       end - begin, count, a->tile_index, a->tile_count);
                printf("  irradiance %.0f ms (%s), elements %.0f ms (%lld), convolution %.1f s on %d threads\n", irr_ms,
                       source, st.build_ms, (long long)st.element_count, eval_ms / 1e3,
                       a->threads ? a->threads : dm_cpu_count());
                printf("  %d narrow + %d wide Gaussians, texel %.3f mm, surface %.0f mm^2, unlit %.3g mm^2\n",
                       st.narrow_gaussians, st.wide_gaussians, st.texel_mm, st.surface_area_mm2, st.unlit_area_mm2);
            }
            code = DM_EXIT_OK;
        }
    }
    dm_progress_end(&bar);
    free(planes);
    free(levels);
    free(rgb);
    free(targets);
    free(texel_of);
    dm_reference_destroy(ref);
    free(atlas);
    dm_ref_surface_destroy(surface);
    return code;
}

/* ---- frame ------------------------------------------------------------------------- */

static void on_stage(void *p, const char *stage, double f)
{
    dm_progress *bar = p;
    bar->label = stage;
    dm_progress_update(bar, f);
}

static int frame(const ref_args *a, const dm_pack *pack)
{
    dm_error err = {0};
    dm_scene scene;
    if (dm_pack_scene(pack, &scene, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return DM_EXIT_LOAD;
    }
    int W = a->width ? a->width : scene.width, H = a->height ? a->height : scene.height;
    float *rgba = malloc(sizeof *rgba * 4 * (size_t)W * H);
    uint8_t *display = malloc(4 * (size_t)W * H);
    if (!rgba || !display) {
        free(rgba);
        free(display);
        fprintf(stderr, "error: cannot allocate a %dx%d frame\n", W, H);
        return DM_EXIT_PROCESS;
    }
    dm_reference_kernel kernel;
    char kernel_name[256];
    dm_profile profile;
    dm_ref_surface_desc desc;
    /* --without: the decomposed comparison's variants (the same in the renderer: bench/accuracy) */
    if (a->no_shadows) scene.effects[DM_EFFECT_SHADOWS] = false;
    if (a->no_subsurface) scene.effects[DM_EFFECT_SUBSURFACE] = false;
    int code = DM_EXIT_LOAD;
    if (dm_ref_surface_desc_from_pack(pack, &scene, &profile, &desc, &err) == DM_OK) code = -1;
    if (a->no_albedo) desc.albedo = (dm_ref_texture){0};
    if (a->no_normal_map) desc.normal_map = (dm_ref_texture){0};
    if (code == -1) code = make_kernel(a, &profile, &kernel, kernel_name, sizeof kernel_name);
    if (code != -1) {
        if (code == DM_EXIT_LOAD) fprintf(stderr, "error: %s\n", err.detail);
        free(rgba);
        free(display);
        return code;
    }
    dm_progress bar;
    dm_progress_begin(&bar, "frame", a->quiet);
    dm_ref_frame_stats st = {0};
    dm_ref_frame_options fo = {.width = W, .height = H, .atlas_size = a->atlas, .thread_count = a->threads,
                               .atlas_samples = a->atlas_samples, .pixel_samples = a->pixel_samples,
                               .diffusion_at_centre = a->at_centre, .refine_samples = a->refine, .reference = &a->ropt, .kernel = &kernel, .progress = on_stage, .progress_user = &bar,
                               .stats = &st};
    dm_result r = dm_ref_frame_render_desc(&desc, &fo, rgba, &err);
    dm_progress_end(&bar);
    code = DM_EXIT_OK;
    if (r != DM_OK) {
        fprintf(stderr, "error: %s: %s\n", a->pack, err.detail);
        code = DM_EXIT_PROCESS;
    }
    if (code == DM_EXIT_OK) {
        size_t n = (size_t)W * H;
        float *planes = malloc(sizeof *planes * 4 * n);
        if (!planes) code = DM_EXIT_PROCESS;
        for (size_t i = 0; planes && i < n; ++i)
            for (int c = 0; c < 4; ++c) planes[(size_t)c * n + i] = rgba[4 * i + (size_t)c];
        dm_provenance prov;
        base_provenance(a, "frame", &prov);
        dm_prov_add_int(&prov, "width", W);
        dm_prov_add_int(&prov, "height", H);
        int atlas = a->atlas ? a->atlas : DM_REF_FRAME_ATLAS_DEFAULT;
        dm_prov_add_int(&prov, "atlas", atlas);
        dm_prov_add_int(&prov, "atlas_samples", dm_ref_frame_atlas_samples(atlas, a->atlas_samples));
        dm_prov_add_int(&prov, "pixel_samples", a->pixel_samples ? a->pixel_samples : 3);
        dm_prov_add_string(&prov, "diffusion", a->at_centre ? "centre" : "pixel");
        if (a->refine) dm_prov_add_int(&prov, "refine_samples", a->refine);
        dm_prov_add_string(&prov, "without", a->without ? a->without : "");
        dm_prov_add_double(&prov, "mm_per_unit", scene.mm_per_unit);
        dm_prov_add_string(&prov, "profile", kernel_name);
        dm_exr_channel ch[4] = {{"R", planes, DM_EXR_FLOAT}, {"G", planes + n, DM_EXR_FLOAT},
                                {"B", planes + 2 * n, DM_EXR_FLOAT}, {"A", planes + 3 * n, DM_EXR_FLOAT}};
        char png[4096];
        snprintf(png, sizeof png, "%.*s.png", (int)(strlen(a->out) - 4), a->out);
        dm_ref_frame_display(&scene, rgba, W, H, display);
        if (planes && !dm_cli_finite(planes, 4 * n, "the ground-truth frame")) {
            code = DM_EXIT_PROCESS;
        } else if (planes && (dm_exr_write(a->out, W, H, ch, 4, &prov, &err) != DM_OK ||
                       dm_png_write_pixels(png, W, H, 4, 8, display, &prov, NULL, 0, &err) != DM_OK)) {
            fprintf(stderr, "error: %s\n", err.detail);
            code = DM_EXIT_SAVE;
        } else if (planes && !a->quiet) {
            printf("%s, %s: %dx%d ground-truth frame, %lld skin pixels (%lld refined), atlas %d, %lld covered texels\n",
                   a->out, png, W, H, (long long)st.skin_pixels, (long long)st.refined_pixels, atlas,
                   (long long)st.covered_texels);
            printf("  setup %.0f ms, irradiance %.0f ms, elements %.0f ms, rays %.0f ms, convolution %.1f s, shading %.0f ms;"
                   " total %.1f s\n",
                   st.setup_ms, st.atlas_ms, st.reference_ms, st.rays_ms, st.convolution_ms / 1e3, st.compose_ms,
                   st.total_ms / 1e3);
        }
        free(planes);
    }
    free(rgba);
    free(display);
    return code;
}

/* ---- merge ------------------------------------------------------------------------- */

static int merge(const ref_args *a)
{
    dm_error err = {0};
    int64_t texels = 0;
    dm_result r = dm_reference_merge_tiles(a->merge, a->merge_count, a->out, &texels, &err);
    if (r != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return r == DM_ERR_FILE_WRITE ? DM_EXIT_SAVE : r == DM_ERR_OUT_OF_MEMORY ? DM_EXIT_PROCESS : DM_EXIT_LOAD;
    }
    if (!a->quiet) printf("%s: %d tiles merged, %lld texels\n", a->out, a->merge_count, (long long)texels);
    return DM_EXIT_OK;
}

int main(int argc, char **argv)
{
    ref_args a;
    int code = ref_parse(argc, argv, &a);
    if (code != -1) return code;
    /* the outputs before any work (core/dm_output.h): OUT.exr, and --frame's OUT.png beside it */
    const char *const exr[] = {".exr", NULL}, *const png[] = {".png", NULL}, *ins[2] = {a.pack, a.irradiance};
    char png_out[4096];
    snprintf(png_out, sizeof png_out, "%.*s.png", (int)strlen(a.out) - 4, a.out);
    if ((code = dm_output_check_cli("-o", a.out, exr, a.merge_count ? a.merge : ins, a.merge_count ? a.merge_count : 2,
                                    NULL)) || (a.frame && (code = dm_output_check_cli("-o", png_out, png, ins, 2, NULL))))
        return code;
    if (a.merge_count) return merge(&a);
    dm_pack pack;
    dm_error err = {0};
    if (dm_pack_open(a.pack, &pack, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_pack_close(&pack);
        return DM_EXIT_LOAD;
    }
    /* memory, before any work: the run's estimate (reference/dm_reference.h) with the renderer's for I */
    dm_render_memory rm = {0};
    if (!a.frame && !a.irradiance)
        dm_render_memory_estimate_pack(&pack, &(dm_render_desc){.width = 64, .height = 64, .irradiance_size = a.size},
                                       true, &rm, NULL);
    dm_reference_memory_options mo = {.texture_space = a.frame ? 0 : a.size, .irradiance_render_size = rm.total_size,
                                      .level_count = a.levels ? (a.medium ? a.radial_gaussians : DM_PROFILE_MAX_GAUSSIANS) : 0,
                                      .width = a.width, .height = a.height, .atlas_size = a.atlas, .atlas_samples = a.atlas_samples,
                                      .pixel_samples = a.pixel_samples, .refine_samples = a.refine};
    if (dm_reference_memory_check(&pack, &mo, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_pack_close(&pack);
        return DM_EXIT_PROCESS;
    }
    code = a.frame ? frame(&a, &pack) : texture_space(&a, &pack);
    dm_pack_close(&pack);
    return code;
}
