/* render_args.c — dermis-render's command line (render_args.h). */
#include "render_args.h"

#include <string.h>

#include "core/dm_cli.h"

void render_usage(FILE *f)
{
    fprintf(f,
            "Usage: dermis-render PACK -o OUT.png|OUT.exr [options]\n"
            "       dermis-render --synthetic sphere|quad [-o OUT] [options]\n"
            "Renders a scene headless (OSMesa, llvmpipe) through the texture-space skin pipeline.\n"
            "\n"
            "  -o FILE              output: .png (8-bit sRGB, tonemapped when the scene's tonemap\n"
            "                       effect is on) or .exr (linear float32 RGBA before tonemapping,\n"
            "                       alpha = coverage: 1 on the head, 0 elsewhere; texture views at\n"
            "                       their texture's own size, one pixel per texel, alpha = chart\n"
            "                       coverage); both carry the scene and parameters as provenance\n"
            "  --synthetic SHAPE    render the built-in synthetic scene (sphere: 18,240 triangles;\n"
            "                       quad: a 64 mm flat patch) instead of a pack\n"
            "  --size WxH           output size, default the scene's (1280x720); 1..16384 per side, and\n"
            "                       its RGBA32F screen target one texture this OpenGL makes (llvmpipe:\n"
            "                       under 1.5 GiB on a 24 GiB machine, up to 10032x10032 or 16384x6140)\n"
            "  --irradiance N       texture-space irradiance size, default the scene's (1024); 8..8192\n"
            "                       (~300 bytes a texel on llvmpipe: 4096 needs ~5 GiB, 8192 ~19 GiB)\n"
            "  --frames N           frames to render, default 1; 1..100000 (timings: median)\n"
            "  --view NAME          final (default), irradiance, blurK (1..5), stretchK (0..5),\n"
            "                       shadowK, specular, diffuse, uv, wireframe, diffusion (the\n"
            "                       texture-space sum of every level as the final pass weights it),\n"
            "                       curvature (pre-integrated packs), seam, thin and gather (the seam\n"
            "                       and thin-part maps: mm beyond the chart, mm across; the thin\n"
            "                       gather: taps a texel). PNGs of stretchK (as mm per texel),\n"
            "                       curvature (1/mm), seam, thin and gather use a colour scale with\n"
            "                       its legend\n"
            "  --view-scale X       multiplies debug texture views' values, default 1; (0, 1e6]\n"
            "  --light-azimuth DEG  turns every light about +Y, default 0; [-360, 360]\n"
            "  --timings            print the median ms per pass over the frames and per frame\n"
            "  --cpu-timings        the same in process CPU ms (every llvmpipe thread summed):\n"
            "                       steadier than wall time on a shared machine\n"
            "  --explain            print the pass list and why each pass is there (renders only\n"
            "                       when -o is given)\n"
            "  --shader-dir DIR     load shaders from DIR/*.glsl instead of the embedded copies\n"
            "  --reference REF.exr  compare with a ground truth (dermis-reference): texture-space\n"
            "                       references against the diffusion view at their size N (the\n"
            "                       irradiance size), frame references against the final linear\n"
            "                       image at their size; -o takes a PNG: [reference | render |\n"
            "                       relative error] with the colour scale; prints per channel mean,\n"
            "                       p95 and max of |render - ref| / max(ref, 1 %% of mean ref) over\n"
            "                       the texels/pixels where both alphas are 1\n"
            "  --error-scale X      relative error at the top of the colour scale, default 0.1;\n"
            "                       (0, 100]\n"
            );
    fprintf(f, "Speed/accuracy settings (their measured time and error: bench/results/render.md):\n"
            "  --shadow-size N      shadow map size, default 2048; 16..8192 (a cast shadow's edge\n"
            "                       moves with the lookup's offset, 1.5 texels: 4096 halves it,\n"
            "                       64 MiB a casting light; docs/crevices.md)\n"
            "  --pcf-taps N         shadow filter: 4 (default, the 3x3 PCF exactly), 9 (reference),\n"
            "                       1 (one bilinear compare: harder edges)\n"
            "  --blur-reduce-from K blur levels K and wider at reduced resolution, default off;\n"
            "                       1..7 (on the head at 1024, K = 3 at half resolution: -14 %%\n"
            "                       frame time, up to 25 display steps)\n"
            "  --blur-reduce-shift S  that resolution is irradiance >> S, default 1; 1..3\n"
            "  --blur-auto          each blur level at the lowest resolution (down to 1/8) where\n"
            "                       its Gaussian stays 1.2 texels wide at the median stretch (head\n"
            "                       at 1024: levels 4, 5 at 1/2, 1/4: -10 %% frame time, +0.5 %% mean\n"
            "                       red error against the ground truth)\n"
            "  --half-float         RGBA16F irradiance and blur targets (slower on llvmpipe)\n"
            "  --blur-on WHERE      auto (default: on the CPU when OpenGL is software, llvmpipe,\n"
            "                       and the targets are float; in GL otherwise), gl or cpu: where\n"
            "                       the blur passes (texture-space, glow) run; both give the same\n"
            "                       sums to float rounding\n"
            "  --diffusion-per-pixel  the final pass samples and sums every blur level per pixel\n"
            "                       instead of the diffusion pass's per-texel sum (slower; differs\n"
            "                       in the texel ring along chart edges)\n"
            "  --no-seam-map        leave the pack's seam map out: the blurs stop at UV seams, as\n"
            "                       before dermis baked one (to see what it changes); beside the\n"
            "                       thin gather, the gather alone carries the widest levels across\n"
            "                       them (the default before 2026-12-02, when the map is used\n"
            "                       beside it too; --seam-map-with-gather is still accepted)\n"
            "  --no-thin-map        leave the pack's thin-part map out: no light from across thin\n"
            "                       parts and folds (ears, lips, eyelids), as before dermis baked one\n"
            "  --no-thin-gather     leave the pack's thin gather out: the widest levels come from the\n"
            "                       atlas blur and the thin-part map alone (docs/thin-map.md)\n"

            "  --compare-exact      also render the exact path and print this setting's error\n"
            "                       against it (linear output, display steps, blur5) and both times\n"
            "  -v                   more detail on stderr\n"
            "  --quiet              nothing on stdout but requested output\n"
            "  -h, --help           this text\n"
            "Sizes beyond this OpenGL's limits, or whose memory estimate exceeds what is available\n"
            "(docs/dermis-render.md, Memory), are refused before anything is made, naming both.\n"
            "Environment: LP_NUM_THREADS sets llvmpipe's thread count (default: all cores);\n"
            "DERMIS_MEM_AVAILABLE_MB the memory (MiB) the check counts on (default: MemAvailable,\n"
            "or a cgroup's limit when lower).\n"
            "Exit codes: 0 success, 1 usage error, 2 cannot load the input, 3 rendering failed or\n"
            "            refused (limits, memory), 4 cannot save the output.\n");
}

int render_parse(int argc, char **argv, render_args *o)
{
    memset(o, 0, sizeof *o);
    o->frames = 1;
    o->view_scale = 1.0;
    o->view_text = "final";
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = NULL;
        int64_t n;
        double d;
        if (dm_cli_version(a, "dermis-render")) return DM_EXIT_OK;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            render_usage(stdout);
            return DM_EXIT_OK;
        } else if (!strcmp(a, "-o")) {
            if (!(o->out = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--synthetic")) {
            if (!(o->synthetic = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            if (strcmp(o->synthetic, "sphere") && strcmp(o->synthetic, "quad")) {
                fprintf(stderr, "error: --synthetic: '%s' is not sphere or quad\n", o->synthetic);
                return DM_EXIT_USAGE;
            }
        } else if (!strcmp(a, "--size")) {
            if (!(v = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            int w = 0, h = 0;
            char tail = 0;
            if (sscanf(v, "%dx%d%c", &w, &h, &tail) != 2 || w < 1 || h < 1 || w > 16384 || h > 16384) {
                fprintf(stderr, "error: --size: '%s' is not WxH with sides in [1, 16384]\n", v);
                return DM_EXIT_USAGE;
            }
            o->width = w, o->height = h;
        } else if (!strcmp(a, "--irradiance")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(a, v, 8, 8192, &n)) return DM_EXIT_USAGE;
            o->irradiance = (int)n;
        } else if (!strcmp(a, "--shadow-size")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(a, v, 16, 8192, &n)) return DM_EXIT_USAGE;
            o->speed.shadow_size = (int)n;
        } else if (!strcmp(a, "--pcf-taps")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(a, v, 1, 9, &n)) return DM_EXIT_USAGE;
            if (n != 1 && n != 4 && n != 9) {
                fprintf(stderr, "error: --pcf-taps: %lld is not 1, 4 or 9\n", (long long)n);
                return DM_EXIT_USAGE;
            }
            o->speed.shadow_pcf_taps = (int)n;
        } else if (!strcmp(a, "--blur-reduce-from")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(a, v, 1, 7, &n)) return DM_EXIT_USAGE;
            o->speed.blur_reduce_from = (int)n;
        } else if (!strcmp(a, "--blur-reduce-shift")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(a, v, 1, 3, &n)) return DM_EXIT_USAGE;
            o->speed.blur_reduce_shift = (int)n;
        } else if (!strcmp(a, "--blur-auto")) {
            o->speed.blur_auto_resolution = true;
        } else if (!strcmp(a, "--half-float")) {
            o->speed.blur_half_float = true;
        } else if (!strcmp(a, "--diffusion-per-pixel")) {
            o->speed.diffusion_per_pixel = true;
        } else if (!strcmp(a, "--no-seam-map")) {
            o->no_seam_map = true;
        } else if (!strcmp(a, "--seam-map-with-gather")) { /* the default since 2026-12-02 */
        } else if (!strcmp(a, "--no-thin-map")) {
            o->no_thin_map = true;
        } else if (!strcmp(a, "--no-thin-gather")) {
            o->no_thin_gather = true;
        } else if (!strcmp(a, "--blur-on")) {
            static const char *paths[] = {"auto", "gl", "cpu"}; /* dm_blur_path's order */
            int k = 0;
            if (!(v = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            while (k < 3 && strcmp(v, paths[k])) ++k;
            if (k == 3) {
                fprintf(stderr, "error: --blur-on: '%s' is not auto, gl or cpu\n", v);
                return DM_EXIT_USAGE;
            }
            o->speed.blur_path = (dm_blur_path)k;
        } else if (!strcmp(a, "--compare-exact")) {
            o->compare_exact = true;
        } else if (!strcmp(a, "--frames")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(a, v, 1, 100000, &n)) return DM_EXIT_USAGE;
            o->frames = (int)n;
        } else if (!strcmp(a, "--view")) {
            if (!(v = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            if (!dm_view_parse(v, &o->view, &o->view_index)) {
                fprintf(stderr, "error: --view: '%s' is not a view (see --help)\n", v);
                return DM_EXIT_USAGE;
            }
            o->view_text = v;
            o->view_given = true;
        } else if (!strcmp(a, "--view-scale")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_double(a, v, 1e-12, 1e6, &d)) return DM_EXIT_USAGE;
            o->view_scale = d;
            o->view_scale_given = true;
        } else if (!strcmp(a, "--light-azimuth")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_double(a, v, -360, 360, &d)) return DM_EXIT_USAGE;
            o->light_azimuth = d;
        } else if (!strcmp(a, "--reference")) {
            if (!(o->reference = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--error-scale")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_double(a, v, 1e-9, 100, &d)) return DM_EXIT_USAGE;
            o->error_scale = d;
        } else if (!strcmp(a, "--shader-dir")) {
            if (!(o->shader_dir = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--timings")) {
            o->timings = true;
        } else if (!strcmp(a, "--cpu-timings")) {
            o->timings = o->speed.timings_cpu = true;
        } else if (!strcmp(a, "--explain")) {
            o->explain = true;
        } else if (!strcmp(a, "-v")) {
            o->verbose = true;
        } else if (!strcmp(a, "--quiet")) {
            o->quiet = true;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "error: unknown option '%s'\n", a);
            return DM_EXIT_USAGE;
        } else if (!o->pack) {
            o->pack = a;
        } else {
            fprintf(stderr, "error: unexpected argument '%s' (one PACK only)\n", a);
            return DM_EXIT_USAGE;
        }
    }
    if (o->speed.blur_auto_resolution && o->speed.blur_reduce_from) {
        fprintf(stderr, "error: --blur-auto and --blur-reduce-from contradict each other\n");
        return DM_EXIT_USAGE;
    }
    if (o->speed.blur_path == DM_BLUR_PATH_CPU && o->speed.blur_half_float) {
        fprintf(stderr, "error: --blur-on cpu keeps float levels: it does not take --half-float\n");
        return DM_EXIT_USAGE;
    }
    if (o->speed.blur_reduce_shift && !o->speed.blur_reduce_from) {
        fprintf(stderr, "error: --blur-reduce-shift needs --blur-reduce-from\n");
        return DM_EXIT_USAGE;
    }
    if (!!o->pack == !!o->synthetic) {
        fprintf(stderr, "error: give either a PACK or --synthetic SHAPE\n");
        return DM_EXIT_USAGE;
    }
    if (o->verbose && o->quiet) {
        fprintf(stderr, "error: -v and --quiet conflict\n");
        return DM_EXIT_USAGE;
    }
    if (!o->out && !o->explain && !o->timings && !o->compare_exact && !o->reference) {
        fprintf(stderr, "error: nothing to do: give -o FILE, --reference, --timings, --compare-exact or --explain\n");
        return DM_EXIT_USAGE;
    }
    if (o->error_scale > 0 && !o->reference) {
        fprintf(stderr, "error: --error-scale needs --reference\n");
        return DM_EXIT_USAGE;
    }
    if (o->reference && (o->view_given || o->compare_exact || o->frames > 1)) {
        fprintf(stderr, "error: --reference chooses the view itself; it conflicts with --view, --frames and "
                        "--compare-exact\n");
        return DM_EXIT_USAGE;
    }
    return -1;
}
