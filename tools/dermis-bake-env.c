/* dermis-bake-env — HDR equirectangular environment → diffuse SH9 + prefiltered specular
 * levels + background, in one EXR (layout in bake/dm_env_bake.h). */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_env_bake.h"
#include "core/dm_cli.h"
#include "core/dm_hash.h"
#include "core/dm_output.h"
#include "core/dm_version.h"

static const char *TOOL = "dermis-bake-env";

static void usage(FILE *f)
{
    fprintf(f, "Usage: %s ENV.hdr|ENV.exr -o OUT.exr [options]\n", TOOL);
}

static void help(void)
{
    usage(stdout);
    printf("\nBakes an equirectangular HDR environment (2:1, +Y up, centre looking along -Z) for the\n"
           "renderer: order-2 SH radiance (9 RGB coefficients, exact per-texel integrals), Beckmann\n"
           "prefiltered specular levels (filtered importance sampling, error measured against exact\n"
           "quadrature) and a background copy, all in one float EXR with provenance attributes.\n\n"
           "Options:\n"
           "  -o FILE                  output EXR (required)\n"
           "  --sh-order N             SH order; only 2 (9 coefficients) is implemented [2]\n"
           "  --levels N               specular levels, m evenly spaced over [%g, %g] [%d], 1..%d\n"
           "  --roughness M,M,...      explicit increasing m list instead of --levels, each %g..%g, 1..%d values\n"
           "  --samples N              importance samples per texel [%d], 1..%d\n"
           "  --spec-size W            width of the sharpest level (levels are 2:1, powers of two\n"
           "                           >= 4*pi/m, at most W and the source width) [%d], 4..%d\n"
           "  --background-size W      background width (height W/2), even [source width], 4..%d\n"
           "  --rotate DEG             rotate the environment about +Y (right-handed) [0], -3600..3600\n"
           "  --negative-tolerance T   set values in [-T, 0) to 0 with a warning (lossy EXR ringing);\n"
           "                           refuse anything lower [%g], 0..1\n"
           "  --check-texels N         texels per level compared with the exact reference [%d], 0..4096 (0: skip)\n"
           "  -j, --threads N          worker threads [0 = all cores], 0..64\n"
           "  -v                       more detail on stdout\n"
           "  --quiet                  no stats, no progress bar (errors and warnings still shown)\n"
           "  -h, --help               this text\n\n"
           "Exit codes: 0 success, 1 usage error, 2 cannot load the input (unreadable, not 2:1,\n"
           "NaN/Inf/negative texel: the message names its x, y from the top-left of the file),\n"
           "3 processing failed, 4 cannot save the output.\n\n"
           "Example: %s venice_sunset_1k.hdr -o venice.env.exr --samples 1024 --rotate 90\n",
           DM_ENV_M_FIRST, DM_ENV_M_LAST, DM_ENV_LEVELS_DEFAULT, DM_ENV_LEVEL_MAX, DM_ENV_M_MIN, DM_ENV_M_MAX,
           DM_ENV_LEVEL_MAX, DM_ENV_SAMPLES_DEFAULT, DM_ENV_SAMPLES_MAX, DM_ENV_SPEC_SIZE_DEFAULT, DM_ENVMAP_SIZE_MAX,
           DM_ENV_BACKGROUND_MAX, DM_ENVMAP_NEGATIVE_TOLERANCE_DEFAULT, DM_ENV_CHECK_TEXELS_DEFAULT, TOOL);
}

typedef struct args {
    const char *input, *output;
    dm_env_options opt;
    int levels_given, roughness_given, check_texels;
    double negative_tolerance;
    int verbose, quiet;
} args;

static int parse_roughness(const char *text, dm_env_options *o)
{
    char buf[512];
    snprintf(buf, sizeof buf, "%s", text);
    o->roughness_count = 0;
    for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        if (o->roughness_count == DM_ENV_LEVEL_MAX) {
            fprintf(stderr, "error: --roughness: more than %d values in '%s'\n", DM_ENV_LEVEL_MAX, text);
            return 0;
        }
        double m;
        if (!dm_cli_double("--roughness", tok, DM_ENV_M_MIN, DM_ENV_M_MAX, &m)) return 0;
        if (o->roughness_count > 0 && !(m > o->roughness[o->roughness_count - 1])) {
            fprintf(stderr, "error: --roughness: %g is not above the previous value %g (expected increasing m)\n", m,
                    o->roughness[o->roughness_count - 1]);
            return 0;
        }
        o->roughness[o->roughness_count++] = m;
    }
    if (o->roughness_count == 0) {
        fprintf(stderr, "error: --roughness: '%s' holds no value\n", text);
        return 0;
    }
    return 1;
}

static int parse(int argc, char **argv, args *a)
{
    memset(a, 0, sizeof *a);
    a->check_texels = DM_ENV_CHECK_TEXELS_DEFAULT;
    a->negative_tolerance = DM_ENVMAP_NEGATIVE_TOLERANCE_DEFAULT;
    for (int i = 1; i < argc; ++i) {
        const char *s = argv[i], *v;
        int64_t n;
        double d;
        if (dm_cli_version(s, "dermis-bake-env")) exit(0);
        if (!strcmp(s, "-h") || !strcmp(s, "--help")) {
            help();
            exit(DM_EXIT_OK);
        } else if (!strcmp(s, "-o")) {
            if (!(a->output = dm_cli_value(argc, argv, &i))) return 0;
        } else if (!strcmp(s, "--sh-order")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 2, 2, &n)) return 0;
        } else if (!strcmp(s, "--levels")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 1, DM_ENV_LEVEL_MAX, &n)) return 0;
            a->opt.level_count = (int)n;
            a->levels_given = 1;
        } else if (!strcmp(s, "--roughness")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !parse_roughness(v, &a->opt)) return 0;
            a->roughness_given = 1;
        } else if (!strcmp(s, "--samples")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 1, DM_ENV_SAMPLES_MAX, &n)) return 0;
            a->opt.samples = (int)n;
        } else if (!strcmp(s, "--spec-size")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 4, DM_ENVMAP_SIZE_MAX, &n)) return 0;
            a->opt.spec_size = (int)n;
        } else if (!strcmp(s, "--background-size")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 4, DM_ENV_BACKGROUND_MAX, &n)) return 0;
            if (n % 2) {
                fprintf(stderr, "error: --background-size: %" PRId64 " is odd: expected an even width (2:1)\n", n);
                return 0;
            }
            a->opt.background_width = (int)n;
        } else if (!strcmp(s, "--rotate")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_double(s, v, -3600, 3600, &d)) return 0;
            a->opt.rotate_deg = d;
        } else if (!strcmp(s, "--negative-tolerance")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_double(s, v, 0, 1, &d)) return 0;
            a->negative_tolerance = d;
        } else if (!strcmp(s, "--check-texels")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 0, 4096, &n)) return 0;
            a->check_texels = (int)n;
        } else if (!strcmp(s, "-j") || !strcmp(s, "--threads")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(s, v, 0, 64, &n)) return 0;
            a->opt.threads = (int)n;
        } else if (!strcmp(s, "-v")) {
            a->verbose = 1;
        } else if (!strcmp(s, "--quiet")) {
            a->quiet = 1;
        } else if (s[0] == '-' && s[1]) {
            fprintf(stderr, "error: unknown option '%s'\n", s);
            return 0;
        } else if (a->input) {
            fprintf(stderr, "error: a second input '%s' (already have '%s'): expected one environment map\n", s,
                    a->input);
            return 0;
        } else {
            a->input = s;
        }
    }
    if (!a->input || !a->output) {
        fprintf(stderr, "error: %s\n", !a->input ? "no input map given" : "no output given (-o FILE)");
        return 0;
    }
    if (a->levels_given && a->roughness_given) {
        fprintf(stderr, "error: --levels and --roughness conflict: give a count or a list, not both\n");
        return 0;
    }
    if (a->verbose && a->quiet) {
        fprintf(stderr, "error: -v and --quiet conflict\n");
        return 0;
    }
    a->opt.check_texels = a->check_texels > 0 ? a->check_texels : -1;
    if (a->opt.rotate_deg != 0.0)
        fprintf(stderr,
                "warning: --rotate %g: dermis-pack takes only unrotated bakes (a scene turns its environment at "
                "render time with environment.rotation_deg); for a pack, bake without --rotate and set "
                "rotation_deg %g in the scene\n",
                a->opt.rotate_deg, a->opt.rotate_deg);
    return 1;
}

static void on_progress(void *ctx, double fraction)
{
    dm_progress_update(ctx, fraction);
}

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

int main(int argc, char **argv)
{
    args a;
    if (!parse(argc, argv, &a)) {
        usage(stderr);
        return DM_EXIT_USAGE;
    }
    int rc = dm_output_check_cli("-o", a.output, (const char *const[]){".exr", NULL}, &a.input, 1, NULL);
    if (rc) return rc; /* before any work (core/dm_output.h) */

    dm_error err = {0};
    double t0 = dm_now_ms();
    dm_envmap map;
    if (dm_envmap_load(a.input, a.negative_tolerance, &map, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_envmap_free(&map);
        return DM_EXIT_LOAD;
    }
    char hash[DM_HASH_HEX_SIZE];
    if (dm_hash_file_hex(a.input, hash, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_envmap_free(&map);
        return DM_EXIT_LOAD;
    }
    if (map.clamped_texels)
        fprintf(stderr,
                "warning: %s: %" PRId64 " values in [-%g, 0) set to 0 (lowest %g at texel x=%d, y=%d from the top)\n",
                a.input, map.clamped_texels, a.negative_tolerance, map.most_negative, map.most_negative_x,
                map.most_negative_y);
    double load_ms = dm_now_ms() - t0;

    dm_progress bar;
    dm_progress_begin(&bar, TOOL, a.quiet);
    a.opt.progress = on_progress;
    a.opt.progress_ctx = &bar;
    dm_env_bake bake;
    dm_result r = dm_env_bake_run(&map, &a.opt, &bake, &err);
    dm_progress_end(&bar);
    if (r != DM_OK) {
        fprintf(stderr, "error: %s: %s\n", a.input, err.detail);
        dm_env_bake_free(&bake);
        dm_envmap_free(&map);
        return DM_EXIT_PROCESS;
    }

    dm_provenance prov;
    dm_prov_init(&prov, TOOL);
    snprintf(prov.input_hash, sizeof prov.input_hash, "%s", hash);
    dm_prov_add_string(&prov, "input", base_name(a.input));
    dm_prov_add_int(&prov, "source_width", map.width);
    dm_prov_add_int(&prov, "source_height", map.height);
    dm_prov_add_int(&prov, "sh_order", 2);
    dm_prov_add_int(&prov, "samples", bake.samples);
    dm_prov_add_double(&prov, "rotate_deg", a.opt.rotate_deg);
    dm_prov_add_double(&prov, "negative_tolerance", a.negative_tolerance);
    dm_prov_add_int(&prov, "spec_size", a.opt.spec_size ? a.opt.spec_size : DM_ENV_SPEC_SIZE_DEFAULT);
    dm_prov_add_int(&prov, "check_texels", a.check_texels);
    double tw = dm_now_ms();
    if (dm_env_write(a.output, &bake, &prov, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_env_bake_free(&bake);
        dm_envmap_free(&map);
        return DM_EXIT_SAVE;
    }
    double write_ms = dm_now_ms() - tw;

    if (!a.quiet) {
        printf("%s: %dx%d -> %s\n", a.input, map.width, map.height, a.output);
        if (map.clamped_texels) printf("negative values set to 0: %" PRId64 "\n", map.clamped_texels);
        printf("SH order 2 (radiance; E(n) = sum A_l L_k Y_k(n), A = pi, 2pi/3, pi/4):\n");
        for (int k = 0; k < DM_SH9_COUNT; ++k)
            printf("  L%d  % .6e % .6e % .6e\n", k, bake.sh[k][0], bake.sh[k][1], bake.sh[k][2]);
        printf("background %dx%d\n", bake.background_width, bake.background_height);
        printf("level  m      size      samples  err_rms   err_max   (relative, %d texels vs exact quadrature)\n",
               a.check_texels);
        for (int k = 0; k < bake.level_count; ++k) {
            const dm_env_level *lv = &bake.levels[k];
            if (lv->error.texels)
                printf("  %d    %.3f  %4dx%-4d %7d  %.2e  %.2e\n", k, lv->m, lv->width, lv->height, bake.samples,
                       lv->error.rms_rel, lv->error.max_rel);
            else
                printf("  %d    %.3f  %4dx%-4d %7d  -         -\n", k, lv->m, lv->width, lv->height, bake.samples);
        }
        printf("time: %.0f ms (load %.0f, SH %.0f, background %.0f, prefilter %.0f, check %.0f, write %.0f)\n",
               dm_now_ms() - t0, load_ms, bake.sh_ms, bake.background_ms, bake.prefilter_ms, bake.check_ms, write_ms);
        if (a.verbose)
            for (int k = 0; k < bake.level_count; ++k)
                printf("  level %d: prefilter %.1f ms, check %.1f ms, worst texel at (u, v) = (%.4f, %.4f)\n", k,
                       bake.levels[k].ms, bake.levels[k].error.ms, bake.levels[k].error.worst_u,
                       bake.levels[k].error.worst_v);
    }
    dm_env_bake_free(&bake);
    dm_envmap_free(&map);
    return DM_EXIT_OK;
}
