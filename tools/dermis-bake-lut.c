/* dermis-bake-lut — bakes the specular lookup tables: the 8-bit Beckmann table, rho_dt
 * and the split-sum environment-BRDF table, with their error against the exact functions;
 * and on request Penner's pre-integrated diffuse table for a profile.
 * Pipeline: parse options → bake → (report) → write. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/dm_exr.h"
#include "image/dm_image.h"
#include "bake/dm_lut.h"
#include "bake/dm_lut_prov.h"
#include "bake/dm_preintegrated.h"
#include "core/dm_brdf.h"
#include "core/dm_cli.h"
#include "core/dm_hash.h"
#include "core/dm_output.h"
#include "core/dm_parallel.h"
#include "core/dm_prov.h"
#include "core/dm_version.h"

#define TOOL "dermis-bake-lut"

typedef struct options {
    const char *out_dir;
    const char *beckmann_path, *float_path, *rho_dt_path, *env_brdf_path;
    int want_beckmann, want_rho_dt, want_env_brdf;
    const char *preint_path, *profile; /* --preintegrated, --profile */
    int want_preint, preint_w, preint_h;
    double curvature_max;
    int beckmann_w, beckmann_h, dir_w, dir_h, nodes, threads;
    double f0;
    int report, verbose, quiet;
} options;

static void usage(FILE *f)
{
    fprintf(f,
            "Usage: " TOOL " [options]\n"
            "Bakes the specular lookup tables of the skin model (GPU Gems 3 ch. 14).\n"
            "\n"
            "Tables (all three unless --tables says otherwise):\n"
            "  beckmann  8-bit PNG, s = N.H, t = m, texel centres, value round(255*0.5*D^0.1),\n"
            "            decoded (2*v)^10; D >= 1024 saturates (counted and reported).\n"
            "  rho_dt    float EXR channel \"rho_dt\": integral of f_KS (N.V) over V, rho_s = 1,\n"
            "            s = N.L, t = m. True values (they exceed 1 toward grazing).\n"
            "  env_brdf  float EXR channels \"scale\", \"bias\": integral of f_KS cos = F0*scale + bias,\n"
            "            s = N.V, t = m (split-sum image-based specular).\n"
            "  preintegrated  (only when named) float EXR channels R, G, B: Penner's pre-integrated\n"
            "            skin diffuse D = int max(0, cos(theta+x)) R(2r sin(x/2)) dx / int R(2r sin(x/2)) dx\n"
            "            over the whole circle; s = N.L from -1 to 1 (texel centres), t = curvature 1/r,\n"
            "            row j = curvature_max*j/(height-1) (row 0 is flat: max(0, N.L)).\n"
            "\n"
            "Options:\n"
            "  -o, --out-dir DIR       folder for the default file names (default .)\n"
            "  --tables LIST           comma list of beckmann,rho_dt,env_brdf,preintegrated\n"
            "                          (default beckmann,rho_dt,env_brdf)\n"
            "  --beckmann FILE         Beckmann PNG path (default DIR/beckmann.png)\n"
            "  --float FILE            also write the exact Beckmann D as float EXR (default off)\n"
            "  --rho-dt FILE           rho_dt EXR path (default DIR/rho_dt.exr)\n"
            "  --env-brdf FILE         env-BRDF EXR path (default DIR/env_brdf.exr)\n"
            "  --size N|WxH            Beckmann size (default %d, range 1..%d)\n"
            "  --rho-dt-size N|WxH     rho_dt and env-BRDF size (default %d, range 2..%d)\n"
            "  --nodes N               Gauss-Legendre nodes per axis for rho_dt (default %d, 8..128)\n"
            "  --preintegrated FILE    pre-integrated EXR path (default DIR/preintegrated.exr)\n"
            "  --profile FILE|gems3-skin  profile JSON (dermis-fit-profile) for preintegrated\n"
            "                          (default gems3-skin; Burley: fit it with --burley first)\n"
            "  --preint-size N|WxH     pre-integrated size, N.L x curvature (default %dx%d, 2..%d)\n"
            "  --curvature-max K       largest curvature, 1/mm (default %g, range (0, %g])\n"
            "  --f0 X                  Schlick F0 for rho_dt (default %.3f, 0..1)\n"
            "  --threads N             worker threads (default 0 = all cores, 0..64)\n"
            "  --report                print each table's error against the exact function and times\n"
            "  -v, --verbose           more detail   --quiet   only errors\n"
            "  -h, --help              this text     --version\n"
            "\n"
            "Exit codes: 0 ok, 1 usage error, 2 cannot load --profile, 3 bake failed, 4 cannot write an output.\n"
            "Example: " TOOL " -o build/luts --report\n"
            "         " TOOL " --tables preintegrated --profile skin.json -o build/luts --report\n",
            DM_LUT_BECKMANN_SIZE_DEFAULT, DM_LUT_SIZE_MAX, DM_LUT_DIRECTIONAL_SIZE_DEFAULT, DM_LUT_SIZE_MAX,
            DM_LUT_NODES_DEFAULT, DM_PREINT_WIDTH_DEFAULT, DM_PREINT_HEIGHT_DEFAULT, DM_PREINT_SIZE_MAX,
            DM_PREINT_CURVATURE_MAX_DEFAULT, DM_PREINT_CURVATURE_MAX_LIMIT, DM_SKIN_F0);
}

static int parse_size(const char *opt, const char *text, int min, int *w, int *h)
{
    int64_t a, b;
    const char *x = text ? strchr(text, 'x') : NULL;
    if (!x) {
        if (!dm_cli_int(opt, text, min, DM_LUT_SIZE_MAX, &a)) return 0;
        *w = *h = (int)a;
        return 1;
    }
    char first[32];
    snprintf(first, sizeof first, "%.*s", (int)(x - text), text);
    if (!dm_cli_int(opt, first, min, DM_LUT_SIZE_MAX, &a) || !dm_cli_int(opt, x + 1, min, DM_LUT_SIZE_MAX, &b))
        return 0;
    *w = (int)a;
    *h = (int)b;
    return 1;
}

static int parse_tables(const char *text, options *o)
{
    o->want_beckmann = o->want_rho_dt = o->want_env_brdf = o->want_preint = 0;
    char buf[256];
    snprintf(buf, sizeof buf, "%s", text);
    for (char *save = NULL, *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
        if (strcmp(t, "beckmann") == 0) o->want_beckmann = 1;
        else if (strcmp(t, "rho_dt") == 0) o->want_rho_dt = 1;
        else if (strcmp(t, "env_brdf") == 0) o->want_env_brdf = 1;
        else if (strcmp(t, "preintegrated") == 0) o->want_preint = 1;
        else {
            fprintf(stderr, "error: --tables: unknown table '%s' (expected beckmann, rho_dt, env_brdf, preintegrated)\n",
                    t);
            return 0;
        }
    }
    if (!o->want_beckmann && !o->want_rho_dt && !o->want_env_brdf && !o->want_preint) {
        fprintf(stderr, "error: --tables: no table named\n");
        return 0;
    }
    return 1;
}

/* Returns 0 on success, else the exit code. */
static int parse_args(int argc, char **argv, options *o)
{
    *o = (options){.out_dir = ".", .want_beckmann = 1, .want_rho_dt = 1, .want_env_brdf = 1,
                   .beckmann_w = DM_LUT_BECKMANN_SIZE_DEFAULT, .beckmann_h = DM_LUT_BECKMANN_SIZE_DEFAULT,
                   .dir_w = DM_LUT_DIRECTIONAL_SIZE_DEFAULT, .dir_h = DM_LUT_DIRECTIONAL_SIZE_DEFAULT,
                   .nodes = DM_LUT_NODES_DEFAULT, .f0 = DM_SKIN_F0, .preint_w = DM_PREINT_WIDTH_DEFAULT,
                   .preint_h = DM_PREINT_HEIGHT_DEFAULT, .curvature_max = DM_PREINT_CURVATURE_MAX_DEFAULT};
    int preint_option = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v;
        int64_t n;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            exit(DM_EXIT_OK);
        } else if (dm_cli_version(a, TOOL)) {
            exit(DM_EXIT_OK);
        } else if (!strcmp(a, "-o") || !strcmp(a, "--out-dir")) {
            if (!(o->out_dir = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--tables")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !parse_tables(v, o)) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--beckmann")) {
            if (!(o->beckmann_path = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--float")) {
            if (!(o->float_path = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--rho-dt")) {
            if (!(o->rho_dt_path = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--env-brdf")) {
            if (!(o->env_brdf_path = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--preintegrated")) {
            if (!(o->preint_path = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            preint_option = 1;
        } else if (!strcmp(a, "--profile")) {
            if (!(o->profile = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            preint_option = 1;
        } else if (!strcmp(a, "--preint-size")) {
            if (!parse_size(a, dm_cli_value(argc, argv, &i), 2, &o->preint_w, &o->preint_h)) return DM_EXIT_USAGE;
            if (o->preint_w > DM_PREINT_SIZE_MAX || o->preint_h > DM_PREINT_SIZE_MAX) {
                fprintf(stderr, "error: --preint-size: at most %d per side\n", DM_PREINT_SIZE_MAX);
                return DM_EXIT_USAGE;
            }
            preint_option = 1;
        } else if (!strcmp(a, "--curvature-max")) {
            if (!dm_cli_double(a, dm_cli_value(argc, argv, &i), 0.0, DM_PREINT_CURVATURE_MAX_LIMIT, &o->curvature_max))
                return DM_EXIT_USAGE;
            if (!(o->curvature_max > 0.0)) {
                fprintf(stderr, "error: --curvature-max: must be more than 0 /mm\n");
                return DM_EXIT_USAGE;
            }
            preint_option = 1;
        } else if (!strcmp(a, "--size")) {
            if (!parse_size(a, dm_cli_value(argc, argv, &i), 1, &o->beckmann_w, &o->beckmann_h)) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--rho-dt-size")) {
            if (!parse_size(a, dm_cli_value(argc, argv, &i), 2, &o->dir_w, &o->dir_h)) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--nodes")) {
            if (!dm_cli_int(a, dm_cli_value(argc, argv, &i), 8, 128, &n)) return DM_EXIT_USAGE;
            o->nodes = (int)n;
        } else if (!strcmp(a, "--threads")) {
            if (!dm_cli_int(a, dm_cli_value(argc, argv, &i), 0, 64, &n)) return DM_EXIT_USAGE;
            o->threads = (int)n;
        } else if (!strcmp(a, "--f0")) {
            if (!dm_cli_double(a, dm_cli_value(argc, argv, &i), 0.0, 1.0, &o->f0)) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--report")) {
            o->report = 1;
        } else if (!strcmp(a, "-v") || !strcmp(a, "--verbose")) {
            o->verbose = 1;
        } else if (!strcmp(a, "--quiet")) {
            o->quiet = 1;
        } else {
            fprintf(stderr, "error: unknown option '%s' (see --help)\n", a);
            return DM_EXIT_USAGE;
        }
    }
    if (o->verbose && o->quiet) {
        fprintf(stderr, "error: -v and --quiet contradict each other\n");
        return DM_EXIT_USAGE;
    }
    if (preint_option && !o->want_preint) {
        fprintf(stderr, "error: --preintegrated, --profile, --preint-size and --curvature-max need "
                        "--tables preintegrated\n");
        return DM_EXIT_USAGE;
    }
    if (o->float_path && !o->want_beckmann) {
        fprintf(stderr, "error: --float needs the beckmann table (see --tables)\n");
        return DM_EXIT_USAGE;
    }
    return 0;
}

static const char *out_path(char *buf, size_t size, const char *given, const char *dir, const char *name)
{
    if (given) return given;
    snprintf(buf, size, "%s/%s", dir, name);
    return buf;
}

/* Every output this run writes, checked before any work (core/dm_output.h). */
static int check_outputs(const options *o)
{
    static const char *const png[] = {".png", NULL}, *const exr[] = {".exr", NULL};
    const struct { int want; const char *opt, *given, *name; const char *const *ext; } outs[] = {
        {o->want_beckmann, "--beckmann", o->beckmann_path, "beckmann.png", png},
        {o->float_path != NULL, "--float", o->float_path, "", exr},
        {o->want_rho_dt, "--rho-dt", o->rho_dt_path, "rho_dt.exr", exr},
        {o->want_env_brdf, "--env-brdf", o->env_brdf_path, "env_brdf.exr", exr},
        {o->want_preint, "--preintegrated", o->preint_path, "preintegrated.exr", exr}};
    for (size_t k = 0; k < sizeof outs / sizeof outs[0]; ++k) {
        char buf[4200];
        const char *p = out_path(buf, sizeof buf, outs[k].given, o->out_dir, outs[k].name);
        const char *opt = outs[k].given ? outs[k].opt : "-o";
        int rc = outs[k].want ? dm_output_check_cli(opt, p, outs[k].ext, &o->profile, 1, NULL) : 0;
        if (rc) return rc;
    }
    return 0;
}

/* The shared contract (bake/dm_lut_prov.h), so dermis-pack can take these files as they
 * are; the descriptive parameters after it are for people. */
static void beckmann_prov(dm_provenance *p, int exact, const options *o)
{
    if (exact) dm_lut_prov_beckmann_exact(p, TOOL, o->beckmann_w, o->beckmann_h);
    else dm_lut_prov_beckmann(p, TOOL, o->beckmann_w, o->beckmann_h);
    dm_prov_add_string(p, "s", "N.H, texel centres");
    dm_prov_add_string(p, "t", "m, texel centres");
    dm_prov_add_double(p, "d_max", DM_BECKMANN_LUT_D_MAX);
}

static void directional_prov(dm_provenance *p, const char *table, const options *o)
{
    dm_lut_prov_directional(p, TOOL, table, o->dir_w, o->dir_h, o->f0, o->nodes);
    dm_prov_add_string(p, "s", strcmp(table, "rho_dt") == 0 ? "N.L, texel centres" : "N.V, texel centres");
    dm_prov_add_string(p, "t", "m, texel centres");
    dm_prov_add_string(p, "integrator", "Gauss-Legendre in half-vector space, u = tan^2(theta_h)/m^2, horizon cut");
}

/* Roughness bands of the report: all m, then the issue's accuracy floor m = 0.05 and the
 * range skin uses (spec maps down to about 0.1, the chapter's m ≈ 0.3). */
enum { BANDS = 4 };
static const double report_m_min[BANDS] = {0.0, 0.05, 0.1, 0.2};

static void print_report(const options *o, const dm_beckmann_lut *bl, const dm_directional_lut *dl)
{
    if (bl) {
        printf("beckmann %dx%d: relative error of (2*bilinear(v))^10 against exact D over the lobe\n"
               "(D > 1%% of its row peak, D < 1024), 4x4 samples per texel; bake %.1f ms\n",
               bl->width, bl->height, bl->bake_ms);
        printf("  %-8s %12s %12s %12s %10s\n", "m >=", "max rel", "rms rel", "samples", "check ms");
        dm_lut_error e[BANDS];
        dm_lut_beckmann_error(bl, 4, report_m_min, BANDS, o->threads, e);
        for (int b = 0; b < BANDS; ++b) {
            printf("  %-8.2f %11.3e%% %11.3e%% %12" PRId64 " %10.1f", report_m_min[b], 100.0 * e[b].max_rel,
                   100.0 * e[b].rms_rel, e[b].samples, e[b].ms);
            if (o->verbose) printf("   worst at N.H=%.4f m=%.4f", e[b].worst_s, e[b].worst_t);
            printf("\n");
        }
        if (bl->clipped_rows)
            printf("  clipping: %d rows (m <= %.5f) hold texels with D >= 1024 (%" PRId64 " texels saturate)\n",
                   bl->clipped_rows, bl->max_clipped_m, bl->saturated_texels);
        else
            printf("  clipping: no texel centre reaches D = 1024 (D(1, m) = 1/m^2 exceeds it for m < 1/32,\n"
                   "  but only within %.1e of N.H = 1 at this size)\n", 0.5 / bl->width);
    }
    if (dl) {
        static const char *names[3] = {"rho_dt", "env.scale", "env.bias"};
        printf("rho_dt + env-BRDF %dx%d (%d nodes): absolute error against a %d-node reference at texel\n"
               "centres, midpoints and borders, bilinear as sampled; 'centres' is the integral's own error,\n"
               "'N.L-weighted' is max N.L*|error|, what reaches lit irradiance; bake %.1f ms\n",
               dl->width, dl->height, dl->nodes, DM_LUT_REFERENCE_NODES, dl->bake_ms);
        printf("  %-10s %-8s %12s %12s %12s %10s\n", "table", "m >=", "max abs", "centres", "N.L-weighted",
               "check ms");
        dm_lut_error e[3 * BANDS];
        dm_lut_directional_error(dl, report_m_min, BANDS, o->threads, e);
        for (int b = 0; b < BANDS; ++b)
            for (int c = 0; c < 3; ++c) {
                const dm_lut_error *q = &e[3 * b + c];
                if ((c == 0 && !o->want_rho_dt) || (c > 0 && !o->want_env_brdf)) continue;
                printf("  %-10s %-8.2f %12.3e %12.3e %12.3e %10.1f", names[c], report_m_min[b], q->max_abs,
                       q->max_abs_centres, q->max_abs_weighted, q->ms);
                if (o->verbose) printf("   worst at N.L=%.4f m=%.4f", q->worst_s, q->worst_t);
                printf("\n");
            }
    }
}

/* The profile of --profile (a JSON or the gems3-skin preset) and a hash of its numbers. */
static int load_profile(const options *o, dm_profile *p, char hash[DM_HASH_HEX_SIZE])
{
    dm_error err = {0};
    if (!o->profile || strcmp(o->profile, "gems3-skin") == 0) {
        dm_profile_gems3_skin(p);
    } else if (dm_profile_read(o->profile, p, &err) != DM_OK) {
        fprintf(stderr, "error: --profile: %s\n", err.detail);
        return DM_EXIT_LOAD;
    }
    double numbers[4 * DM_PROFILE_MAX_GAUSSIANS];
    for (int k = 0; k < p->count; ++k) {
        numbers[4 * k] = p->variance_mm2[k];
        for (int c = 0; c < 3; ++c) numbers[4 * k + 1 + c] = p->weight[k][c];
    }
    dm_hash_hex(numbers, sizeof(double) * 4 * (size_t)p->count, hash);
    return 0;
}

static void preint_report(const options *o, const dm_profile *p, const dm_preint_lut *l)
{
    enum { BRUTE = 1 << 16 };
    int stride = l->width / 32 > 1 ? l->width / 32 : 1;
    dm_preint_error e;
    dm_preint_lut_error(p, l, stride, BRUTE, o->threads, &e);
    printf("preintegrated %dx%d (curvature 0..%g /mm, profile %s): absolute error against a %d-point\n"
           "brute-force midpoint rule over the circle, every %d-th row and column; bake %.1f ms\n",
           l->width, l->height, l->curvature_max_per_mm, p->name, BRUTE, stride, l->bake_ms);
    printf("  centres %.3e (the integral's own error and float rounding), bilinear midpoints %.3e\n"
           "  (worst at N.L=%.4f curvature=%.4f /mm), %ld samples, check %.1f ms\n",
           e.max_abs_centres, e.max_abs_bilinear, e.worst_cos, e.worst_curvature, e.samples, e.ms);
}

int main(int argc, char **argv)
{
    options o;
    int code = parse_args(argc, argv, &o);
    if (code || (code = check_outputs(&o))) return code;
    double t_start = dm_now_ms();
    dm_error err = {0};
    dm_profile profile;
    char profile_hash[DM_HASH_HEX_SIZE] = "";
    if (o.want_preint && (code = load_profile(&o, &profile, profile_hash))) return code;

    /* bake: a bar by stage (each table, then the files) when stderr is a terminal */
    dm_progress bar;
    dm_progress_begin(&bar, "bake-lut", o.quiet);
    const double stages =
        (o.want_beckmann ? 1 : 0) + (o.want_rho_dt || o.want_env_brdf ? 1 : 0) + (o.want_preint ? 1 : 0) + 1;
    double stage = 0;
    dm_beckmann_lut bl = {0};
    dm_directional_lut dl = {0};
    if (o.want_beckmann &&
        dm_lut_bake_beckmann(o.beckmann_w, o.beckmann_h, o.float_path != NULL, o.threads, &bl, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return DM_EXIT_PROCESS;
    }
    if (o.want_beckmann) dm_progress_update(&bar, ++stage / stages);
    if ((o.want_rho_dt || o.want_env_brdf) &&
        dm_lut_bake_directional(o.dir_w, o.dir_h, o.f0, o.nodes, o.threads, &dl, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_beckmann_lut_free(&bl);
        return DM_EXIT_PROCESS;
    }
    if (o.want_rho_dt || o.want_env_brdf) dm_progress_update(&bar, ++stage / stages);
    dm_preint_lut pl = {0};
    if (o.want_preint &&
        dm_preint_bake(&profile, o.preint_w, o.preint_h, o.curvature_max, o.threads, &pl, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_beckmann_lut_free(&bl);
        dm_directional_lut_free(&dl);
        return DM_EXIT_PROCESS;
    }
    double t_baked = dm_now_ms();

    if (o.want_preint) dm_progress_update(&bar, ++stage / stages);
    dm_progress_end(&bar);
    /* write */
    char b1[4200], b2[4200], b3[4200], b4[4200];
    dm_provenance prov;
    dm_result r = DM_OK;
    if (o.want_beckmann) {
        beckmann_prov(&prov, 0, &o);
        dm_image img = {.width = bl.width, .height = bl.height, .channels = 1, .type = DM_PIXEL_U8, .pixels = bl.texels};
        const char *p = out_path(b1, sizeof b1, o.beckmann_path, o.out_dir, "beckmann.png");
        r = dm_png_write(p, &img, &prov, &err);
        if (r == DM_OK && !o.quiet) printf("wrote %s (%dx%d, 8-bit)\n", p, bl.width, bl.height);
        if (r == DM_OK && o.float_path) {
            beckmann_prov(&prov, 1, &o);
            dm_exr_channel ch = {"D", bl.exact, DM_EXR_FLOAT};
            r = dm_exr_write(o.float_path, bl.width, bl.height, &ch, 1, &prov, &err);
            if (r == DM_OK && !o.quiet) printf("wrote %s (%dx%d, float D)\n", o.float_path, bl.width, bl.height);
        }
    }
    if (r == DM_OK && o.want_rho_dt) {
        directional_prov(&prov, "rho_dt", &o);
        dm_exr_channel ch = {"rho_dt", dl.rho_dt, DM_EXR_FLOAT};
        const char *p = out_path(b2, sizeof b2, o.rho_dt_path, o.out_dir, "rho_dt.exr");
        r = dm_exr_write(p, dl.width, dl.height, &ch, 1, &prov, &err);
        if (r == DM_OK && !o.quiet) printf("wrote %s (%dx%d, float)\n", p, dl.width, dl.height);
    }
    if (r == DM_OK && o.want_env_brdf) {
        directional_prov(&prov, "env_brdf", &o);
        dm_exr_channel ch[2] = {{"scale", dl.scale, DM_EXR_FLOAT}, {"bias", dl.bias, DM_EXR_FLOAT}};
        const char *p = out_path(b3, sizeof b3, o.env_brdf_path, o.out_dir, "env_brdf.exr");
        r = dm_exr_write(p, dl.width, dl.height, ch, 2, &prov, &err);
        if (r == DM_OK && !o.quiet) printf("wrote %s (%dx%d, float scale+bias)\n", p, dl.width, dl.height);
    }
    if (r == DM_OK && o.want_preint) {
        dm_lut_prov_preintegrated(&prov, TOOL, pl.width, pl.height, pl.curvature_max_per_mm, profile.name,
                                  profile_hash);
        dm_prov_add_string(&prov, "s", "N.L = 2s-1 at texel centres, -1..1");
        dm_prov_add_string(&prov, "t", "curvature = curvature_max*j/(height-1) on row j: row 0 flat (max(0, N.L))");
        dm_prov_add_string(&prov, "integral", "int_-pi^pi max(0,cos(theta+x)) R(2r sin(x/2)) dx / int R(2r sin(x/2)) dx");
        dm_prov_add_string(&prov, "integrator", "per Gaussian, Gauss-Legendre 24 on pieces cut at kinks and sigma chords");
        size_t plane = (size_t)pl.width * pl.height;
        dm_exr_channel ch[3] = {{"B", pl.rgb + 2 * plane, DM_EXR_FLOAT},
                                {"G", pl.rgb + plane, DM_EXR_FLOAT},
                                {"R", pl.rgb, DM_EXR_FLOAT}};
        const char *p = out_path(b4, sizeof b4, o.preint_path, o.out_dir, "preintegrated.exr");
        r = dm_exr_write(p, pl.width, pl.height, ch, 3, &prov, &err);
        if (r == DM_OK && !o.quiet) printf("wrote %s (%dx%d, float RGB)\n", p, pl.width, pl.height);
    }
    if (r != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_beckmann_lut_free(&bl);
        dm_directional_lut_free(&dl);
        dm_preint_lut_free(&pl);
        return DM_EXIT_SAVE;
    }
    double t_written = dm_now_ms();

    if (!o.quiet && o.want_beckmann && bl.clipped_rows && !o.report)
        fprintf(stderr, "warning: beckmann: %" PRId64 " texels in %d rows (m <= %.5f) exceed D = 1024 and saturate\n",
                bl.saturated_texels, bl.clipped_rows, bl.max_clipped_m);
    if (o.report) print_report(&o, o.want_beckmann ? &bl : NULL, (o.want_rho_dt || o.want_env_brdf) ? &dl : NULL);
    if (o.report && o.want_preint) preint_report(&o, &profile, &pl);
    if (!o.quiet)
        printf("time: bake %.1f ms (beckmann %.1f, rho_dt+env_brdf %.1f, preintegrated %.1f), write %.1f ms, "
               "%d threads\n",
               t_baked - t_start, bl.bake_ms, dl.bake_ms, pl.bake_ms, t_written - t_baked,
               o.threads ? o.threads : dm_cpu_count());
    dm_beckmann_lut_free(&bl);
    dm_directional_lut_free(&dl);
    dm_preint_lut_free(&pl);
    return DM_EXIT_OK;
}
