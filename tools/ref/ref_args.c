/* ref_args.c — dermis-reference's command line (ref_args.h). */
#include "ref_args.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_cli.h"
#include "core/dm_diffusion.h"
#include "core/dm_output.h"

void ref_usage(FILE *f)
{
    fprintf(f,
            "Usage: dermis-reference PACK --texture-space N -o OUT.exr [options]\n"
            "       dermis-reference PACK --frame [--size WxH] -o OUT.exr [options]\n"
            "       dermis-reference --merge TILE.exr... -o OUT.exr\n"
            "The ground truth of subsurface diffusion: D(x) = sum_k w_k Int I(x') G(v_k, |P(x) - P(x')|) dA(x')\n"
            "over the whole mesh, 3-D distances in mm (light crosses UV seams and thin parts).\n"
            "\n"
            "  --texture-space N    the NxN atlas of D, I = the renderer's own level-0 irradiance at N\n"
            "                       (float RGBA EXR, A = 1 on covered texels; the layout of\n"
            "                       dermis-render --view irradiance --size NxN --irradiance N); 16..8192\n"
            "                       (~300 bytes a texel while I is rendered: 8192 needs ~20 GiB)\n"
            "  --irradiance FILE    take I from that EXR (R, G, B, A = coverage; NxN) instead of rendering it\n"
            "  --levels             also write each S_k as channels Sk.R, Sk.G, Sk.B\n"
            "  --frame              a ground-truth frame from the scene's camera: irradiance on the CPU\n"
            "                       (shadows by ray casting), diffused exactly, composed with the\n"
            "                       renderer's specular and environment; OUT.exr linear (A = 1 on skin),\n"
            "                       and OUT.png through the scene's tonemap\n"
            "  --size WxH           frame size, default the scene's; 1..16384 per side\n"
            "  --atlas N            frame: CPU irradiance atlas size, default 4096; 16..8192\n"
            "  --atlas-samples K    frame: KxK irradiance samples per atlas texel, default 4, fewer where\n"
            "                       atlas x K > 8192 (2 at 4096); 1..8\n"
            "  --pixel-samples K    frame: KxK sub-pixel rays per skin pixel (the surface terms and the\n"
            "                       diffusion at each ray's hit), default 3; 1..8\n"
"  --refine K           frame: pixels whose rays' radiance spreads by more than 2 %% of their\n"
            "                       mean (eyelids, lips, nostrils, ears) shaded again from KxK rays;\n"
            "                       default off; more than the pixel samples, at most 16\n"
            "  --diffusion-at-centre  frame: the diffusion at the pixel centre's hit only (cheaper; the\n"
            "                       behaviour before issue #27, for convergence studies)\n"
            "  --without LIST       frame: leave terms out, comma-separated: albedo (white), normal-map\n"
            "                       (the interpolated normal), shadows, subsurface (Lambert at the point):\n"
            "                       the decomposed comparison of bench/accuracy (docs/dermis-reference.md)\n"
            "  --dipole SPEC        diffuse by a dipole (Jensen 2001) instead of the pack's Gaussians: a medium\n"
            "                       (skin1, skin2, marble, ...) or 'sa,ss,eta' / 7 numbers (mm^-1), as in\n"
            "                       dermis-fit-profile; represented by dense Gaussians (error reported)\n"
            "  --multipole SPEC     the same for a slab (Donner & Jensen 2005); needs --thickness MM\n"
            "  --thickness MM       slab thickness, (0, 1e4]; --pairs N dipole pairs, default 20\n"
            "  --burley A/MFP       Burley normalized diffusion (Christensen & Burley 2015) as in dermis-fit-profile:\n"
            "                       albedo and mean free path (mm), 1 or 3 numbers each, e.g. 0.8,0.6,0.4/1,0.5,0.25\n"
            "  --skin SKIN          the physical skin as in dermis-fit-profile --skin (melanin=Cm,eumelanin=B,\n"
            "                       blood=Ch[,oxygenation=G,epidermis-mm=MM,dermis-mm=MM,eta=E]): its own\n"
            "                       R(r) per channel, not a fit of few Gaussians (docs/skin-model.md)\n"
            "  --skin-preset NAME   a named skin (dermis-fit-profile --list-presets)\n"
            "  --radial-gaussians N Gaussians representing --dipole/--multipole/--burley/--skin, default 12;\n"
            "                       2..32 (the residual error is printed)\n"
    );
    fprintf(f,
            "  --tile I/N           compute only slice I of N (1-based) of the texels; merge with --merge\n"
            "  --merge FILES        join tiles of one run into the file the one-shot run writes\n"
            "  --cut S              Gaussians cut at S sigma (the mass beyond is restored), default 4; 2..8\n"
            "  --spacing S          narrow Gaussians' sub-triangle edge in sigma, default 0.3; 1/32..1\n"
            "  --wide-texels T      Gaussians of sigma >= T texels use texel elements, default 4; >= 1\n"
            "  --threads T          worker threads, default all cores; 0..256 (results identical for any)\n"
            "  -o FILE              output (.exr)\n"
            "  -v                   more detail on stderr\n"
            "  --quiet              nothing on stdout\n"
            "  -h, --help           this text\n"
            "A run whose memory estimate (docs/dermis-reference.md, Memory) exceeds what is available\n"
            "is refused before any work, naming both; DERMIS_MEM_AVAILABLE_MB (MiB) overrides what is\n"
            "counted as available (default: MemAvailable, or a cgroup's limit when lower).\n"
            "Exit codes: 0 success, 1 usage error, 2 cannot load an input, 3 processing failed or\n"
            "            refused (memory), 4 cannot save the output.\n");
}

bool ref_radial(const ref_args *a)
{
    return a->medium || a->skin || a->skin_preset;
}

int ref_parse(int argc, char **argv, ref_args *a)
{
    memset(a, 0, sizeof *a);
    a->tile_index = a->tile_count = 1;
    for (int i = 1; i < argc; ++i) {
        const char *s = argv[i], *v;
        int64_t n;
        if (!strcmp(s, "-h") || !strcmp(s, "--help")) {
            ref_usage(stdout);
            return DM_EXIT_OK;
        } else if (dm_cli_version(s, "dermis-reference")) {
            return DM_EXIT_OK;
        } else if (!strcmp(s, "-o")) {
            if (!(a->out = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(s, "--texture-space")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 16, 8192, &n)) return DM_EXIT_USAGE;
            a->size = (int)n;
        } else if (!strcmp(s, "--atlas")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 16, 8192, &n)) return DM_EXIT_USAGE;
            a->atlas = (int)n;
        } else if (!strcmp(s, "--atlas-samples") || !strcmp(s, "--pixel-samples")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 1, 8, &n)) return DM_EXIT_USAGE;
            *(!strcmp(s, "--atlas-samples") ? &a->atlas_samples : &a->pixel_samples) = (int)n;
        } else if (!strcmp(s, "--irradiance")) {
            if (!(a->irradiance = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(s, "--frame")) {
            a->frame = true;
        } else if (!strcmp(s, "--refine")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 2, 16, &n)) return DM_EXIT_USAGE;
            a->refine = (int)n;
        } else if (!strcmp(s, "--diffusion-at-centre")) {
            a->at_centre = true;
        } else if (!strcmp(s, "--without")) {
            if (!(a->without = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            for (const char *t = a->without; *t;) {
                size_t len = strcspn(t, ",");
                bool *flag = len == 6 && !strncmp(t, "albedo", 6)       ? &a->no_albedo
                             : len == 10 && !strncmp(t, "normal-map", 10) ? &a->no_normal_map
                             : len == 7 && !strncmp(t, "shadows", 7)      ? &a->no_shadows
                             : len == 10 && !strncmp(t, "subsurface", 10) ? &a->no_subsurface
                                                                          : NULL;
                if (!flag) {
                    fprintf(stderr, "error: --without: '%.*s' is not one of albedo, normal-map, shadows, subsurface\n",
                            (int)len, t);
                    return DM_EXIT_USAGE;
                }
                *flag = true;
                t += len + (t[len] == ',');
            }
        } else if (!strcmp(s, "--size")) {
            char tail;
            if (!(v = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            if (sscanf(v, "%dx%d%c", &a->width, &a->height, &tail) != 2 || a->width < 1 || a->height < 1 ||
                a->width > 16384 || a->height > 16384) {
                fprintf(stderr, "error: --size: '%s' is not WxH with sides in [1, 16384]\n", v);
                return DM_EXIT_USAGE;
            }
        } else if (!strcmp(s, "--tile")) {
            char tail;
            if (!(v = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            if (sscanf(v, "%d/%d%c", &a->tile_index, &a->tile_count, &tail) != 2 || a->tile_count < 1 ||
                a->tile_count > MERGE_MAX || a->tile_index < 1 || a->tile_index > a->tile_count) {
                fprintf(stderr, "error: --tile: '%s' is not I/N with 1 <= I <= N <= %d\n", v, MERGE_MAX);
                return DM_EXIT_USAGE;
            }
        } else if (!strcmp(s, "--merge")) {
            while (i + 1 < argc && argv[i + 1][0] != '-') {
                if (a->merge_count == MERGE_MAX) {
                    fprintf(stderr, "error: --merge: more than %d files\n", MERGE_MAX);
                    return DM_EXIT_USAGE;
                }
                a->merge[a->merge_count++] = argv[++i];
            }
            if (!a->merge_count) {
                fprintf(stderr, "error: --merge needs the tile files\n");
                return DM_EXIT_USAGE;
            }
        } else if (!strcmp(s, "--dipole") || !strcmp(s, "--multipole") || !strcmp(s, "--burley")) {
            if (!(a->medium = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            a->multipole = !strcmp(s, "--multipole");
            a->burley = !strcmp(s, "--burley");
        } else if (!strcmp(s, "--skin")) {
            if (!(a->skin = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(s, "--skin-preset")) {
            if (!(a->skin_preset = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(s, "--thickness")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_double(s, v, 1e-9, DM_THICKNESS_MAX_MM, &a->thickness_mm))
                return DM_EXIT_USAGE;
        } else if (!strcmp(s, "--pairs")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 1, DM_MULTIPOLE_PAIRS_MAX, &n)) return DM_EXIT_USAGE;
            a->pairs = (int)n;
        } else if (!strcmp(s, "--radial-gaussians")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 2, DM_REFERENCE_GAUSSIANS_MAX, &n))
                return DM_EXIT_USAGE;
            a->radial_gaussians = (int)n;
        } else if (!strcmp(s, "--levels")) {
            a->levels = true;
        } else if (!strcmp(s, "--cut")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_double(s, v, 2, 8, &a->ropt.cut_sigma)) return DM_EXIT_USAGE;
        } else if (!strcmp(s, "--spacing")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_double(s, v, 1.0 / 32, 1, &a->ropt.spacing_sigma))
                return DM_EXIT_USAGE;
        } else if (!strcmp(s, "--wide-texels")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_double(s, v, 1, INFINITY, &a->ropt.wide_texels))
                return DM_EXIT_USAGE;
        } else if (!strcmp(s, "--threads")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 0, 256, &n)) return DM_EXIT_USAGE;
            a->threads = (int)n;
        } else if (!strcmp(s, "-v") || !strcmp(s, "--verbose")) {
            a->verbose = true;
        } else if (!strcmp(s, "--quiet")) {
            a->quiet = true;
        } else if (s[0] == '-' && s[1]) {
            fprintf(stderr, "error: unknown option '%s' (see --help)\n", s);
            return DM_EXIT_USAGE;
        } else if (!a->pack) {
            a->pack = s;
        } else {
            fprintf(stderr, "error: one PACK expected, got '%s' and '%s'\n", a->pack, s);
            return DM_EXIT_USAGE;
        }
    }
    const char *bad = !a->out                                     ? "no output given (-o OUT.exr)"
                      : a->merge_count && (a->pack || a->size || a->frame) ? "--merge takes tile files only"
                      : a->merge_count                            ? NULL
                      : !a->pack                                  ? "no PACK given"
                      : !a->frame == !a->size                     ? "give one of --texture-space N or --frame"
                      : a->frame && (a->irradiance || a->levels || a->tile_count > 1)
                          ? "--irradiance, --levels and --tile are texture-space options"
                      : !a->frame && (a->width || a->atlas || a->atlas_samples || a->pixel_samples || a->at_centre ||
                                      a->without || a->refine)
                          ? "--size, --atlas, the samples, --refine, --diffusion-at-centre and --without are --frame options"
                      : a->refine && a->refine <= (a->pixel_samples ? a->pixel_samples : 3)
                          ? "--refine K takes more rays than --pixel-samples"
                      : a->quiet && a->verbose             ? "--quiet conflicts with -v"
                                                           : NULL;
    if (!bad && a->multipole && !(a->thickness_mm > 0.0)) bad = "--multipole needs --thickness MM";
    if (!bad && !a->multipole && (a->thickness_mm > 0.0 || a->pairs)) bad = "--thickness and --pairs apply to --multipole";
    if (!bad && (!!a->medium + !!a->skin + !!a->skin_preset) > 1)
        bad = "--dipole/--multipole/--burley, --skin and --skin-preset exclude each other";
    if (!bad && !ref_radial(a) && a->radial_gaussians) bad = "--radial-gaussians applies to --dipole/--multipole/--burley/--skin";
    if (bad) {
        fprintf(stderr, "error: %s\n", bad);
        return DM_EXIT_USAGE;
    }
    a->ropt.thread_count = a->threads;
    if (!a->radial_gaussians) a->radial_gaussians = 12;
    return -1;
}
