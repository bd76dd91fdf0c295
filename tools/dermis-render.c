/* dermis-render — headless (OSMesa) renderer: scene → PNG/EXR, per-pass timings.
 * Straight pipeline: parse → load (assets) → context + renderer → frames → write. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_cli.h"
#include "core/dm_hash.h"
#include "core/dm_output.h"
#include "pack/dm_pack.h"
#include "core/dm_prov.h"
#include "core/dm_version.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_compare.h"
#include "render/dm_render_pack.h"
#include "render/dm_render_prov.h"
#include "render/dm_render_refcmp.h"
#include "render/dm_render_image.h"
#include "render/dm_render_synth.h"
#include "render/dm_render_timing.h"

#include "render/render_args.h"
#include "render/render_explain.h"

static void provenance(const render_args *o, const dm_scene *s, const char *input_hash, const dm_renderer *r,
                       dm_provenance *p)
{
    dm_render_provenance(p, "dermis-render", o->pack ? o->pack : o->synthetic, input_hash, s, r, o->view_text,
                         o->light_azimuth, o->frames);
    dm_render_settings_provenance(p, &o->speed, r);
}


/* What is rendered: a verified pack (mapped, nothing copied) or a synthetic scene. */
typedef struct source {
    dm_synth *synth;
    dm_pack pack;
    bool pack_open;
    dm_scene scene;
    dm_profile profile;
    dm_render_assets pack_assets;
    const dm_render_assets *assets;
    const dm_scene *s;
    char hash[DM_HASH_HEX_SIZE];
} source;

static int load(const render_args *o, source *src, dm_error *err)
{
    memset(src, 0, sizeof *src);
    if (o->pack) {
        size_t len = strlen(o->pack);
        if (len >= 5 && strcmp(o->pack + len - 5, ".json") == 0) { /* a scene: say how to pack it */
            const char *slash = strrchr(o->pack, '/');
            const char *base = slash ? slash + 1 : o->pack;
            int stem = (int)(len - 5 - (size_t)(base - o->pack));
            dm_fail(err, DM_ERR_FORMAT,
                    "%s: a scene file, not a pack: pack it first: dermis-pack %s -o %.*s.dpk, then dermis-render "
                    "%.*s.dpk",
                    o->pack, o->pack, stem, base, stem, base);
            return DM_EXIT_LOAD;
        }
        if (dm_pack_open(o->pack, &src->pack, err) != DM_OK) return DM_EXIT_LOAD; /* the input rules first */
        src->pack_open = true;
        if (dm_hash_file_hex(o->pack, src->hash, err) != DM_OK ||
            dm_render_assets_from_pack(&src->pack, &src->scene, &src->profile, &src->pack_assets, err) != DM_OK)
            return DM_EXIT_LOAD;
        if (o->no_seam_map) src->pack_assets.seam = (dm_texture){0};
        if (o->no_thin_map) src->pack_assets.thin = src->pack_assets.thin_half = (dm_texture){0};
        if (o->no_thin_gather)
            src->pack_assets.gather_index = src->pack_assets.gather_taps = src->pack_assets.gather_half_index =
                src->pack_assets.gather_half_taps = (dm_texture){0};
        src->assets = &src->pack_assets;
        src->s = &src->scene;
        if (src->scene.light_count == 0 && !src->scene.effects[DM_EFFECT_ENVIRONMENT_LIGHTING])
            fprintf(stderr, "warning: %s: the scene has no light and no environment lighting: the picture is black\n",
                    o->pack);
        return 0;
    }
    dm_synth_options so = {.shape = strcmp(o->synthetic, "quad") ? DM_SYNTH_SPHERE : DM_SYNTH_QUAD};
    if (dm_synth_create(&so, &src->synth, err) != DM_OK) return DM_EXIT_LOAD;
    src->assets = &src->synth->assets;
    src->s = &src->synth->scene;
    return 0;
}

static void unload(source *src)
{
    if (src->pack_open) dm_pack_close(&src->pack);
    dm_synth_free(src->synth);
}

/* --reference: the view's full-precision read-back against the reference, stats on
 * stdout, the side-by-side comparison as a PNG. Returns an exit code. */
static int compare_reference(const render_args *o, const dm_refcmp_ref *ref, dm_renderer *r, const dm_provenance *base)
{
    dm_error err = {0};
    int w, h;
    dm_renderer_view_size(r, &w, &h);
    if (w != ref->width || h != ref->height) {
        fprintf(stderr, "error: the render is %dx%d, the reference %dx%d\n", w, h, ref->width, ref->height);
        return DM_EXIT_PROCESS;
    }
    size_t n = (size_t)w * h;
    float *px = malloc(n * 4 * sizeof *px), *rel = malloc(n * sizeof *rel);
    dm_refcmp_stats st;
    int rc = DM_EXIT_OK;
    if (!px || !rel) {
        fprintf(stderr, "error: cannot allocate %dx%d\n", w, h);
        rc = DM_EXIT_PROCESS;
    } else if (dm_renderer_check_finite(r, &err) != DM_OK || dm_renderer_read_view(r, px, &err) != DM_OK ||
               dm_refcmp_stats_compute(ref->rgba, px, w, h, &st, rel, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        rc = DM_EXIT_PROCESS;
    }
    if (rc == DM_OK) {
        char text[2048];
        dm_refcmp_stats_text(&st, ref->mode, text, sizeof text);
        if (!o->quiet) printf("reference %s (%s, %dx%d) against %s:\n", o->reference, dm_refcmp_mode_name(ref->mode),
                              w, h, ref->mode == DM_REFCMP_FRAME ? "the final linear image" : "the diffusion view");
        fputs(text, stdout);
    }
    if (rc == DM_OK && o->out) {
        dm_refcmp_view view = {.layout = DM_REFCMP_SIDE_BY_SIDE, .error_scale = o->error_scale};
        int ow = 3 * w, oh = h + dm_refcmp_legend_height(3 * w);
        uint8_t *img = malloc((size_t)ow * oh * 4);
        dm_provenance prov = *base;
        dm_prov_add_string(&prov, "reference", o->reference);
        dm_prov_add_string(&prov, "reference_mode", dm_refcmp_mode_name(ref->mode));
        dm_prov_add_double(&prov, "error_scale", o->error_scale > 0 ? o->error_scale : DM_REFCMP_DEFAULT_ERROR_SCALE);
        dm_prov_add_double(&prov, "error_floor_fraction", DM_REFCMP_FLOOR_FRACTION);
        static const char *names[3][3] = {{"mean_r", "mean_g", "mean_b"}, {"p95_r", "p95_g", "p95_b"},
                                          {"max_r", "max_g", "max_b"}};
        for (int c = 0; c < 3; ++c) {
            dm_prov_add_double(&prov, names[0][c], st.mean[c]);
            dm_prov_add_double(&prov, names[1][c], st.p95[c]);
            dm_prov_add_double(&prov, names[2][c], st.max[c]);
        }
        if (!img) {
            fprintf(stderr, "error: cannot allocate the comparison image\n");
            rc = DM_EXIT_PROCESS;
        } else {
            dm_refcmp_compose(ref->rgba, px, rel, w, h, &st, &view, img, ow, oh);
            if (dm_render_write_png(o->out, ow, oh, img, &prov, &err) != DM_OK) {
                fprintf(stderr, "error: %s\n", err.detail);
                rc = DM_EXIT_SAVE;
            } else if (!o->quiet) {
                printf("wrote %s (%dx%d: reference | render | relative error)\n", o->out, ow, oh);
            }
        }
        free(img);
    }
    free(px);
    free(rel);
    return rc;
}

int main(int argc, char **argv)
{
    render_args o;
    int rc = render_parse(argc, argv, &o);
    if (rc == DM_EXIT_USAGE)
        fprintf(stderr, "Usage: dermis-render PACK -o OUT.png|OUT.exr [options] (--help for all)\n");
    if (rc != -1) return rc;
    dm_error err = {0};
    /* the output before any work (core/dm_output.h): the extension picks PNG or EXR; a comparison is a PNG */
    int format = 0;
    if (o.out && (rc = dm_output_check_cli("-o", o.out, (const char *const[]){".png", o.reference ? NULL : ".exr", NULL},
                                           (const char *const[]){o.pack, o.reference}, 2, &format)))
        return rc;

    /* load */
    source src;
    rc = load(&o, &src, &err);
    if (rc) {
        fprintf(stderr, "error: %s\n", err.detail);
        unload(&src);
        return rc;
    }

    /* --reference: the reference decides the view and its size */
    dm_refcmp_ref ref = {0};
    if (o.reference) {
        if (dm_refcmp_load(o.reference, &ref, &err) != DM_OK) {
            fprintf(stderr, "error: %s\n", err.detail);
            unload(&src);
            return DM_EXIT_LOAD;
        }
        bool ts = ref.mode == DM_REFCMP_TEXTURE_SPACE;
        if ((ts && o.irradiance && o.irradiance != ref.width) ||
            (!ts && o.width && (o.width != ref.width || o.height != ref.height))) {
            fprintf(stderr, "error: --reference %s is %dx%d (%s): %s disagrees\n", o.reference, ref.width, ref.height,
                    dm_refcmp_mode_name(ref.mode), ts ? "--irradiance" : "--size");
            dm_refcmp_ref_free(&ref);
            unload(&src);
            return DM_EXIT_USAGE;
        }
        if (ts) o.irradiance = ref.width;
        else o.width = ref.width, o.height = ref.height;
        o.view = ts ? DM_VIEW_DIFFUSION : DM_VIEW_FINAL;
        o.view_index = 0;
        o.view_text = ts ? "diffusion" : "final";
    }

    /* a texture-space view is square: without --size, the scene's height on both sides
     * (not the texture squashed into the scene's 16:9 frame) */
    if (!o.width && dm_view_is_texture(o.view)) o.width = o.height = src.s->height;
    /* context + renderer */
    dm_osmesa *ctx = NULL;
    dm_renderer *r = NULL, *exact = NULL;
    dm_render_timing_log log = {0}, exact_log = {0}; /* the run's timings (render/dm_render_timing.h) */
    dm_render_desc desc = o.speed;
    desc.shader_dir = o.shader_dir;
    desc.width = o.width;
    desc.height = o.height;
    desc.irradiance_size = o.irradiance;
    desc.timings = o.timings || o.compare_exact;
    if (dm_osmesa_create(&ctx, &err) != DM_OK || dm_renderer_create(src.assets, &desc, &r, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        rc = DM_EXIT_PROCESS;
        goto done;
    }
    if (o.verbose) fprintf(stderr, "renderer: %s\n", dm_renderer_gl_name(r));
    /* --compare-exact: the reference renderer, the exact path at the same sizes (9 PCF taps,
     * the levels summed per pixel: bench/render.c's `exact` row) */
    if (o.compare_exact) {
        dm_render_desc ed = {.shader_dir = o.shader_dir, .width = o.width, .height = o.height,
                             .irradiance_size = o.irradiance, .timings = true, .shadow_pcf_taps = 9,
                             .diffusion_per_pixel = true};
        if (dm_renderer_create(src.assets, &ed, &exact, &err) != DM_OK) {
            fprintf(stderr, "error: the exact path: %s\n", err.detail);
            rc = DM_EXIT_PROCESS;
            goto done;
        }
    }

    dm_frame_options fo = {.view = o.view, .view_index = o.view_index, .view_scale = (float)o.view_scale,
                           .light_rotation_deg = (float)o.light_azimuth};
    if (o.explain) {
        dm_render_plan plan;
        if (dm_render_plan_build(src.s, o.view, o.view_index, &plan, &err) != DM_OK) {
            fprintf(stderr, "error: %s\n", err.detail);
            rc = DM_EXIT_USAGE;
            goto done;
        }
        if (dm_renderer_thin_map(r)) dm_render_plan_thin_map(&plan); /* as the renderer's: no translucency on top */
        char text[8192];
        dm_render_plan_explain(&plan, text, sizeof text);
        fputs(text, stdout);
        if (plan.blur_levels > 1) render_explain_maps(r, src.assets, desc.irradiance_size ? desc.irradiance_size : src.s->irradiance_size);
        if (!o.out && !o.timings && !o.compare_exact) goto done;
    }

    /* frames; their timings' record is taken before the first frame */
    if (desc.timings && (dm_render_timing_log_init(&log, o.frames, true, &err) != DM_OK ||
                         (exact && dm_render_timing_log_init(&exact_log, o.frames, false, &err) != DM_OK))) {
        fprintf(stderr, "error: %s\n", err.detail);
        rc = DM_EXIT_PROCESS;
        goto done;
    }
    /* --compare-exact times warm frames: one untimed frame on each renderer first (shader
     * compilation on first use, first uploads), then the medians of o.frames frames */
    if (exact && (dm_render_frame(r, &fo, &err) != DM_OK || dm_render_frame(exact, &fo, &err) != DM_OK)) {
        fprintf(stderr, "error: warm-up frame: %s\n", err.detail);
        rc = err.code == DM_ERR_INVALID_ARGUMENT ? DM_EXIT_USAGE : DM_EXIT_PROCESS;
        goto done;
    }
    dm_progress prog;
    dm_progress_begin(&prog, "rendering", o.quiet || o.frames < 4);
    for (int f = 0; f < o.frames; ++f) {
        if (dm_render_frame(r, &fo, &err) != DM_OK) {
            fprintf(stderr, "error: frame %d: %s\n", f, err.detail);
            rc = err.code == DM_ERR_INVALID_ARGUMENT ? DM_EXIT_USAGE : DM_EXIT_PROCESS;
            goto done;
        }
        dm_render_timing_log_add(&log, r);
        if (exact && dm_render_frame(exact, &fo, &err) != DM_OK) {
            fprintf(stderr, "error: the exact path, frame %d: %s\n", f, err.detail);
            rc = DM_EXIT_PROCESS;
            goto done;
        }
        if (exact) dm_render_timing_log_add(&exact_log, exact);
        dm_progress_update(&prog, (f + 1.0) / o.frames);
    }
    dm_progress_end(&prog);
    if (exact) {
        dm_render_difference d;
        const char *level = dm_renderer_find_target(exact, "blur5") >= 0 ? "blur5" : NULL;
        if (dm_render_compare(exact, r, level, &d, &err) != DM_OK) {
            fprintf(stderr, "error: %s\n", err.detail);
            rc = DM_EXIT_PROCESS;
            goto done;
        }
        printf("compare-exact: this setting %.1f ms, exact path %.1f ms per frame (median of %d warm frames, after "
               "one warm-up frame each)\n",
               dm_render_timing_log_median(&log, -1), dm_render_timing_log_median(&exact_log, -1), o.frames);
        printf("  output (linear, RGB): max |d| %.3e, mean %.3e (peak %.3g); display: %d steps of 255\n", d.out_max,
               d.out_mean, d.out_peak, d.display_steps);
        if (level)
            printf("  %s (coverage-normalised): max |d| %.3e, mean %.3e (peak %.3g)\n", level, d.level_max,
                   d.level_mean, d.level_peak);
    }
    if (o.timings)
        dm_render_timing_log_print(&log, r,
                                   !dm_renderer_timing_on_cpu(r) ? "GL timer queries"
                                   : o.speed.timings_cpu        ? "process CPU time around glFinish, every thread"
                                                                : "wall clock around glFinish",
                                   stdout);

    if (o.reference) {
        dm_provenance prov;
        provenance(&o, src.s, src.hash, r, &prov);
        rc = compare_reference(&o, &ref, r, &prov);
        goto done;
    }

    /* write */
    if (o.out) {
        /* EXR: the view at full precision (texture views at their texture's size); PNG: the
         * display at the output size */
        int w, h;
        bool exr = format == 1;
        if (exr) dm_renderer_view_size(r, &w, &h);
        else dm_renderer_size(r, &w, &h, NULL);
        dm_provenance prov;
        provenance(&o, src.s, src.hash, r, &prov);
        void *px = malloc((size_t)w * h * 4 * (exr ? sizeof(float) : 1));
        dm_result res = px ? dm_renderer_check_finite(r, &err) /* NaN or Inf: exit 3, nothing written */
                           : dm_fail(&err, DM_ERR_OUT_OF_MEMORY, "%s: cannot allocate the image", o.out);
        if (res == DM_OK) res = exr ? dm_renderer_read_view(r, px, &err) : dm_renderer_read_display(r, px, &err);
        if (res != DM_OK) {
            rc = DM_EXIT_PROCESS;
        } else {
            if (!exr) res = dm_render_view_with_legend(r, &px, w, &h, &err);
            if (res == DM_OK)
                res = exr ? dm_render_write_exr(o.out, w, h, px, &prov, &err)
                          : dm_render_write_png(o.out, w, h, px, &prov, &err);
            if (res != DM_OK) rc = DM_EXIT_SAVE;
            else if (!o.quiet) printf("wrote %s (%dx%d, view %s)\n", o.out, w, h, o.view_text);
            if (res == DM_OK && !o.quiet && o.view == DM_VIEW_SPECULAR)
                printf("specular view: the head x %.3g (its 99th percentile to near white)\n", dm_renderer_view_gain(r));
        }
        if (res != DM_OK) fprintf(stderr, "error: %s\n", err.detail);
        free(px);
    }
done:
    dm_render_timing_log_free(&log);
    dm_render_timing_log_free(&exact_log);
    dm_refcmp_ref_free(&ref);
    dm_renderer_destroy(exact);
    dm_renderer_destroy(r);
    dm_osmesa_destroy(ctx);
    unload(&src);
    return rc;
}
