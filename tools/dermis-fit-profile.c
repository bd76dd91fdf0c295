/* dermis-fit-profile — fits N Gaussians (shared variances, per-channel weights) to a
 * diffusion profile: the GPU Gems 3 table, a dipole / multipole from optical parameters,
 * Burley's normalized diffusion from albedo and mean free path, or the physical skin from
 * melanin, blood and layers; writes the profile JSON and prints what each N costs. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_profile_fit.h"
#include "bake/dm_profile_json.h"
#include "bake/dm_profile_tsv.h"
#include "bake/dm_skin_spec.h"
#include "core/dm_cli.h"
#include "core/dm_diffusion.h"
#include "core/dm_output.h"
#include "core/dm_prov.h"
#include "core/dm_version.h"

#define TOOL "dermis-fit-profile"

typedef struct options {
    const char *preset;    /* --preset */
    const char *spec;      /* --dipole / --multipole value */
    bool burley;           /* --burley */
    const char *skin;      /* --skin SPEC */
    const char *skin_preset; /* --skin-preset NAME */
    bool list_presets;     /* --list-presets */
    const char *albedo, *mfp; /* --albedo, --mfp (Burley) */
    int source_count;      /* how many source options were given */
    bool multipole;
    double thickness_mm;   /* 0 = not given */
    int pairs;             /* 0 = not given */
    int gaussians;
    int nodes;
    bool normalize;
    bool table;
    const char *output;
    const char *radial;    /* --radial FILE.tsv */
    const char *spectrum;  /* --spectrum FILE.tsv (skin sources) */
    const char *name;
    bool verbose, quiet;
} options;

static void usage(FILE *f)
{
    fprintf(f, "Usage: " TOOL " (--preset gems3-skin | --dipole SPEC | --multipole SPEC --thickness MM |\n"
               "                          --burley --albedo R,G,B --mfp R,G,B | --skin SKIN | --skin-preset NAME)\n"
               "                          [-n N] [--table] [-o profile.json] [--radial R.tsv] [--spectrum S.tsv] [options]\n");
}

static void help(void)
{
    usage(stdout);
    const char *const *names = dm_medium_preset_names();
    printf("\nFits N Gaussians G(v, r) = exp(-r^2/2v)/(2 pi v), variances v (mm^2) shared by R, G, B and\n"
           "weights >= 0 per channel, minimising integral r (R(r) - sum G)^2 dr, and writes the profile\n"
           "JSON that dermis-bake-stretch --profile and the renderer read.\n\n"
           "Source (exactly one):\n"
           "  --preset gems3-skin    the six-Gaussian skin profile of GPU Gems 3 ch. 14 (DESIGN.md)\n"
           "  --dipole SPEC          Jensen et al. 2001 dipole, semi-infinite medium\n"
           "  --multipole SPEC       Donner & Jensen 2005 multipole, slab of --thickness MM\n"
           "  SPEC is a measured medium (Jensen et al. 2001, eta 1.3):");
    for (int i = 0; names[i]; ++i) printf(" %s", names[i]);
    printf("\n"
           "       or 'sa,ss,eta' (grey: sigma_a, sigma_s' in 1/mm, same for R, G, B)\n"
           "       or 'saR,saG,saB,ssR,ssG,ssB,eta'.\n"
           "       sigma_a in [0, %g], sigma_s' in (0, %g], eta in [%g, %g].\n"
           "  --thickness MM         slab thickness, (0, %g] mm; multipole only, required there\n"
           "  --pairs N              dipole pairs i = -N..N of the multipole, 1..%d (default %d)\n"
           "  --burley               Christensen & Burley 2015 normalized diffusion,\n"
           "                         R(r) = A s (exp(-s r) + exp(-s r/3)) / (8 pi r), s = S(A) / mfp,\n"
           "                         S(A) = 1.85 - A + 7|A - 0.8|^3 (their searchlight fit for the mfp)\n"
           "                         (R ~ 1/r at 0: its fit and errors weigh by r^2, not r)\n"
           "  --albedo A|R,G,B       Burley albedo A per channel, [0, 1]; required with --burley\n"
           "  --mfp MM|R,G,B         Burley mean free path per channel, (0, %g] mm; required there\n"
           "  --skin SKIN            the physical two-layer skin (docs/skin-model.md): spectral multipole\n"
           "                         layers, CIE D65 to linear sRGB, its R(r) per channel. SKIN is\n"
           "                         melanin=Cm,eumelanin=B,blood=Ch[,oxygenation=G][,epidermis-mm=MM]\n"
           "                         [,dermis-mm=MM][,eta=E]: Cm melanosome fraction [0, %g],\n"
           "                         B eumelanin share [0, 1], Ch dermal blood fraction [0, %g],\n"
           "                         G HbO2 share [0, 1] (0.75), epidermis [%g, %g] mm (0.25),\n"
           "                         dermis 0 (semi-infinite, default) or [%g, %g] mm, E [%g, %g] (1.4)\n"
           "  --skin-preset NAME     a named skin: caucasian, asian, african (Donner & Jensen 2006) or\n"
           "                         fitzpatrick-1 ... fitzpatrick-6 (our mapping onto Jacques' melanosome\n"
           "                         bands); --list-presets prints their parameters\n"
           "  --list-presets         print the skin presets and exit\n\n"
           "Fit:\n"
           "  -n, --gaussians N      Gaussians, 1..%d (default %d); the runtime blurs 2(N-1) passes\n"
           "  --nodes N              radial quadrature nodes in ln r, odd, %d..%d (default %d)\n"
           "  --no-normalize         keep the source's reflectance; default: each channel's weights\n"
           "                         sum to 1 (white; the colour comes from the albedo map)\n"
           "  --table                print error, blur passes and fit time for N = 1..%d\n\n"
           "Output:\n"
           "  -o, --output FILE      profile JSON (required unless --table, --radial or --spectrum)\n"
           "  --radial FILE.tsv      the source's R(r) and the fit's (before normalising) per channel,\n"
           "                         1/mm^2, at %d radii log-spaced %g..%g mm, tab-separated (for plots)\n"
           "  --spectrum FILE.tsv    --skin / --skin-preset only: the total diffuse reflectance per\n"
           "                         wavelength, 400..700 nm every 10 nm, tab-separated\n"
           "  --name NAME            profile name (default: the source's, e.g. skin1-dipole)\n"
           "  -v                     also print the Gaussians\n"
           "  --quiet                print nothing but errors\n"
           "  -h, --help             this text\n\n"
           "Exit codes: 0 ok, 1 usage (bad option or parameter), 2 cannot load input,\n"
           "            3 fit failed, 4 cannot save output.\n",
           DM_SIGMA_MAX_PER_MM, DM_SIGMA_MAX_PER_MM, DM_ETA_MIN, DM_ETA_MAX, DM_THICKNESS_MAX_MM,
           DM_MULTIPOLE_PAIRS_MAX, DM_MULTIPOLE_PAIRS_DEFAULT, DM_MFP_MAX_MM, DM_SKIN_MELANIN_MAX, DM_SKIN_BLOOD_MAX,
           DM_SKIN_EPIDERMIS_MIN_MM, DM_SKIN_EPIDERMIS_MAX_MM, DM_SKIN_DERMIS_MIN_MM, DM_SKIN_DERMIS_MAX_MM,
           DM_SKIN_ETA_MIN, DM_SKIN_ETA_MAX, DM_PROFILE_MAX_GAUSSIANS, DM_FIT_GAUSSIANS_DEFAULT,
           DM_FIT_NODES_MIN, DM_FIT_NODES_MAX, DM_FIT_NODES_DEFAULT, DM_PROFILE_MAX_GAUSSIANS,
           DM_PROFILE_TSV_RADIAL_ROWS, DM_PROFILE_TSV_R_MIN_MM, DM_PROFILE_TSV_R_MAX_MM);
}

/* 0 = ok, otherwise the exit code. */
static int parse(int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    o->gaussians = DM_FIT_GAUSSIANS_DEFAULT;
    o->nodes = DM_FIT_NODES_DEFAULT;
    o->normalize = true;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v;
        int64_t n;
        if (dm_cli_version(a, "dermis-fit-profile")) exit(0);
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            help();
            exit(DM_EXIT_OK);
        } else if (!strcmp(a, "--preset")) {
            if (!(v = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            o->preset = v;
            ++o->source_count;
        } else if (!strcmp(a, "--dipole") || !strcmp(a, "--multipole")) {
            if (!(v = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            o->spec = v;
            o->multipole = !strcmp(a, "--multipole");
            ++o->source_count;
        } else if (!strcmp(a, "--burley")) {
            o->burley = true;
            ++o->source_count;
        } else if (!strcmp(a, "--skin")) {
            if (!(o->skin = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            ++o->source_count;
        } else if (!strcmp(a, "--skin-preset")) {
            if (!(o->skin_preset = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            ++o->source_count;
        } else if (!strcmp(a, "--list-presets")) {
            o->list_presets = true;
        } else if (!strcmp(a, "--albedo")) {
            if (!(o->albedo = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--mfp")) {
            if (!(o->mfp = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--thickness")) {
            if (!(v = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
            if (!dm_cli_double(a, v, 0.0, DM_THICKNESS_MAX_MM, &o->thickness_mm)) return DM_EXIT_USAGE;
            if (!(o->thickness_mm > 0.0)) {
                fprintf(stderr, "error: --thickness: '%s' must be more than 0 mm\n", v);
                return DM_EXIT_USAGE;
            }
        } else if (!strcmp(a, "--pairs")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(a, v, 1, DM_MULTIPOLE_PAIRS_MAX, &n))
                return DM_EXIT_USAGE;
            o->pairs = (int)n;
        } else if (!strcmp(a, "-n") || !strcmp(a, "--gaussians")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(a, v, 1, DM_PROFILE_MAX_GAUSSIANS, &n))
                return DM_EXIT_USAGE;
            o->gaussians = (int)n;
        } else if (!strcmp(a, "--nodes")) {
            if (!(v = dm_cli_value(argc, argv, &i)) || !dm_cli_int(a, v, DM_FIT_NODES_MIN, DM_FIT_NODES_MAX, &n))
                return DM_EXIT_USAGE;
            if (n % 2 == 0) {
                fprintf(stderr, "error: --nodes: '%s' must be odd (Simpson's rule)\n", v);
                return DM_EXIT_USAGE;
            }
            o->nodes = (int)n;
        } else if (!strcmp(a, "--no-normalize")) {
            o->normalize = false;
        } else if (!strcmp(a, "--table")) {
            o->table = true;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            if (!(o->output = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--radial")) {
            if (!(o->radial = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--spectrum")) {
            if (!(o->spectrum = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--name")) {
            if (!(o->name = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "-v")) {
            o->verbose = true;
        } else if (!strcmp(a, "--quiet")) {
            o->quiet = true;
        } else {
            fprintf(stderr, "error: unknown option '%s'\n", a);
            usage(stderr);
            return DM_EXIT_USAGE;
        }
    }
    const char *why = NULL;
    if (o->list_presets)
        why = o->source_count || o->output || o->table || o->radial || o->spectrum ? "--list-presets takes no other option"
                                                                                  : NULL;
    else if (o->source_count == 0)
        why = "give a source: --preset, --dipole, --multipole, --burley, --skin or --skin-preset";
    else if (o->source_count > 1)
        why = "--preset, --dipole, --multipole, --burley, --skin and --skin-preset exclude each other";
    else if (o->burley && (!o->albedo || !o->mfp))
        why = "--burley needs --albedo and --mfp";
    else if (!o->burley && (o->albedo || o->mfp))
        why = "--albedo and --mfp apply to --burley only";
    else if (o->multipole && o->thickness_mm == 0.0)
        why = "--multipole needs --thickness MM";
    else if (!o->multipole && o->thickness_mm != 0.0)
        why = "--thickness applies to --multipole only";
    else if (!o->multipole && o->pairs)
        why = "--pairs applies to --multipole only";
    else if (o->spectrum && !o->skin && !o->skin_preset)
        why = "--spectrum applies to --skin and --skin-preset only";
    else if (!o->output && !o->table && !o->radial && !o->spectrum)
        why = "give -o FILE (or --table to only print the table, --radial or --spectrum to only write those)";
    else if (o->verbose && o->quiet)
        why = "-v and --quiet exclude each other";
    if (why) {
        fprintf(stderr, "error: %s\n", why);
        usage(stderr);
        return DM_EXIT_USAGE;
    }
    return 0;
}

/* Parses SPEC (preset name, 3 or 7 numbers) into a validated medium; 0 or DM_EXIT_USAGE. */
static int parse_medium(const options *o, dm_medium *m)
{
    dm_error err = {0};
    if (dm_medium_parse(o->spec, o->multipole ? DM_MODEL_MULTIPOLE : DM_MODEL_DIPOLE, o->thickness_mm, o->pairs,
                        o->multipole ? "--multipole" : "--dipole", m, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return DM_EXIT_USAGE;
    }
    return 0;
}

/* The skin presets and their parameters, as --skin would take them. */
static void list_presets(void)
{
    for (int i = 0; dm_skin_preset_name(i); ++i) {
        dm_skin_params p;
        char spec[512];
        dm_skin_preset(dm_skin_preset_name(i), &p, NULL);
        dm_skin_spec_format(&p, 6, spec, sizeof spec);
        printf("%-14s %s\n", dm_skin_preset_name(i), spec);
    }
}

static void provenance(const options *o, const dm_profile_source *s, dm_provenance *p)
{
    dm_prov_init(p, TOOL);
    if (s->kind == DM_SOURCE_SKIN) {
        dm_prov_add_string(p, "source", "skin");
        if (o->skin_preset) dm_prov_add_string(p, "skin_preset", o->skin_preset);
        char spec[512];
        dm_skin_spec_format(&s->skin, 17, spec, sizeof spec);
        dm_prov_add_string(p, "skin", spec);
        dm_prov_add_string(p, "skin_model", "two layers, spectral multipole 400-700 nm (Donner & Jensen 2005/2006), "
                                            "CIE D65 to linear sRGB (docs/skin-model.md)");
        double total[3];
        dm_profile_source_total(s, total);
        static const char *const t[3] = {"skin_total_reflectance_r", "skin_total_reflectance_g",
                                         "skin_total_reflectance_b"};
        for (int c = 0; c < 3; ++c) dm_prov_add_double(p, t[c], total[c]);
    } else if (s->kind == DM_SOURCE_GAUSSIANS) {
        dm_prov_add_string(p, "source", "preset");
        dm_prov_add_string(p, "preset", o->preset);
    } else if (s->kind == DM_SOURCE_BURLEY) {
        dm_prov_add_string(p, "source", "burley");
        dm_prov_add_string(p, "burley_shape", "S(A)=1.85-A+7|A-0.8|^3 (Christensen & Burley 2015, searchlight, mfp)");
        static const char *const a[3] = {"albedo_r", "albedo_g", "albedo_b"};
        static const char *const l[3] = {"mfp_mm_r", "mfp_mm_g", "mfp_mm_b"};
        for (int c = 0; c < 3; ++c) dm_prov_add_double(p, a[c], s->burley.albedo[c]);
        for (int c = 0; c < 3; ++c) dm_prov_add_double(p, l[c], s->burley.mfp_mm[c]);
    } else {
        const dm_medium *m = &s->medium;
        dm_prov_add_string(p, "source", o->multipole ? "multipole" : "dipole");
        dm_prov_add_string(p, "medium", o->spec);
        static const char *const a[3] = {"sigma_a_r", "sigma_a_g", "sigma_a_b"};
        static const char *const ss[3] = {"sigma_s_prime_r", "sigma_s_prime_g", "sigma_s_prime_b"};
        for (int c = 0; c < 3; ++c) dm_prov_add_double(p, a[c], m->sigma_a_per_mm[c]);
        for (int c = 0; c < 3; ++c) dm_prov_add_double(p, ss[c], m->sigma_s_prime_per_mm[c]);
        dm_prov_add_double(p, "eta", m->eta);
        if (o->multipole) {
            dm_prov_add_double(p, "thickness_mm", m->thickness_mm);
            dm_prov_add_int(p, "pairs", m->pair_count ? m->pair_count : DM_MULTIPOLE_PAIRS_DEFAULT);
        }
    }
    dm_prov_add_int(p, "gaussians", o->gaussians);
    dm_prov_add_int(p, "nodes", o->nodes);
    dm_prov_add_int(p, "normalize", o->normalize);
}

static void print_table(const dm_profile_source *s, const options *o, const char *name)
{
    printf("%-3s %-7s %-11s %-11s %-11s %-11s %s\n", "N", "passes", "err_R", "err_G", "err_B", "err_max",
           "fit_ms");
    for (int n = 1; n <= DM_PROFILE_MAX_GAUSSIANS; ++n) {
        dm_fit_options fo = {.gaussian_count = n, .node_count = o->nodes};
        dm_fit_result fr;
        dm_error err = {0};
        double t0 = dm_now_ms();
        if (dm_profile_fit(s, &fo, name, &fr, &err) != DM_OK) {
            printf("%-3d error: %s\n", n, err.detail);
            continue;
        }
        double ms = dm_now_ms() - t0;
        printf("%-3d %-7d %-11.3e %-11.3e %-11.3e %-11.3e %.1f%s\n", n, dm_profile_blur_passes(n),
               fr.error_relative[0], fr.error_relative[1], fr.error_relative[2], fr.error_relative_max, ms,
               n == o->gaussians ? "  <- -n" : "");
    }
}

/* --radial and --spectrum (bake/dm_profile_tsv.h); 0 or the exit code. */
static int write_tsv(const options *o, const dm_profile_source *src, const char *name)
{
    dm_provenance prov;
    provenance(o, src, &prov);
    dm_error err = {0};
    if (o->radial) {
        dm_fit_options fo = {.gaussian_count = o->gaussians, .node_count = o->nodes};
        dm_fit_result fr;
        if (dm_profile_fit(src, &fo, name, &fr, &err) != DM_OK) {
            fprintf(stderr, "error: %s\n", err.detail);
            return DM_EXIT_PROCESS;
        }
        if (dm_profile_tsv_radial(o->radial, src, &fr.profile, &prov, &err) != DM_OK) {
            fprintf(stderr, "error: %s\n", err.detail);
            return DM_EXIT_SAVE;
        }
    }
    if (o->spectrum && dm_profile_tsv_spectrum(o->spectrum, &src->skin, &prov, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return DM_EXIT_SAVE;
    }
    return 0;
}

int main(int argc, char **argv)
{
    options o;
    int rc = parse(argc, argv, &o);
    if (rc) return rc;
    if (o.list_presets) {
        list_presets();
        return DM_EXIT_OK;
    }
    if (o.output && (rc = dm_output_check_cli("-o", o.output, (const char *const[]){".json", NULL}, NULL, 0, NULL)))
        return rc; /* before any work (core/dm_output.h) */
    if (o.radial && (rc = dm_output_check_cli("--radial", o.radial, (const char *const[]){".tsv", NULL}, NULL, 0, NULL)))
        return rc;
    if (o.spectrum &&
        (rc = dm_output_check_cli("--spectrum", o.spectrum, (const char *const[]){".tsv", NULL}, NULL, 0, NULL)))
        return rc;

    /* Load: build the source. */
    dm_profile_source src;
    memset(&src, 0, sizeof src);
    char name[DM_PROFILE_NAME_SIZE];
    if (o.preset) {
        if (strcmp(o.preset, "gems3-skin") != 0) {
            fprintf(stderr, "error: --preset: '%s' is unknown, expected gems3-skin (media go through --dipole)\n",
                    o.preset);
            return DM_EXIT_USAGE;
        }
        src.kind = DM_SOURCE_GAUSSIANS;
        dm_profile_gems3_skin(&src.gaussians);
        snprintf(name, sizeof name, "%s", o.preset);
    } else if (o.skin || o.skin_preset) {
        dm_skin_params sp;
        dm_error err = {0};
        if ((o.skin ? dm_skin_spec_parse(o.skin, "--skin", &sp, &err)
                    : dm_skin_preset(o.skin_preset, &sp, &err)) != DM_OK) {
            fprintf(stderr, "error: %s%s\n", o.skin ? "" : "--skin-preset: ", err.detail);
            return DM_EXIT_USAGE;
        }
        if (dm_profile_source_skin(&sp, &src, &err) != DM_OK) {
            fprintf(stderr, "error: %s\n", err.detail);
            return DM_EXIT_PROCESS;
        }
        snprintf(name, sizeof name, "%s", o.skin_preset ? o.skin_preset : "skin");
    } else if (o.burley) {
        src.kind = DM_SOURCE_BURLEY;
        dm_error err = {0};
        if (dm_burley_parse(o.albedo, o.mfp, "--burley", &src.burley, &err) != DM_OK) {
            fprintf(stderr, "error: %s\n", err.detail);
            return DM_EXIT_USAGE;
        }
        snprintf(name, sizeof name, "burley");
    } else {
        src.kind = DM_SOURCE_MEDIUM;
        if ((rc = parse_medium(&o, &src.medium))) return rc;
        snprintf(name, sizeof name, "%.40s-%s", src.medium.name[0] ? src.medium.name : "medium",
                 o.multipole ? "multipole" : "dipole");
    }
    if (o.name) snprintf(name, sizeof name, "%s", o.name);

    /* Process. */
    if (o.table && !o.quiet) print_table(&src, &o, name);
    if ((rc = write_tsv(&o, &src, name))) return rc;
    if (!o.output) return DM_EXIT_OK;
    dm_fit_options fo = {.gaussian_count = o.gaussians, .node_count = o.nodes};
    dm_fit_result fr;
    dm_error err = {0};
    double t0 = dm_now_ms();
    if (dm_profile_fit(&src, &fo, name, &fr, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return DM_EXIT_PROCESS;
    }
    double fit_ms = dm_now_ms() - t0;
    dm_profile out = fr.profile;
    double total[3];
    dm_profile_channel_sums(&out, total);
    if (o.normalize && dm_profile_normalize_white(&out, NULL, &err) != DM_OK) {
        fprintf(stderr, "error: %s (use --no-normalize to keep it)\n", err.detail);
        return DM_EXIT_PROCESS;
    }

    /* Write. */
    dm_provenance prov;
    provenance(&o, &src, &prov);
    dm_profile_doc doc = {.profile = &out,
                          .normalized = o.normalize,
                          .has_error = 1,
                          .error_relative_max = fr.error_relative_max,
                          .source = &src,
                          .source_preset = o.preset ? o.preset : o.skin_preset ? o.skin_preset
                                                               : o.burley || o.skin ? ""
                                                                                    : src.medium.name,
                          .provenance = &prov};
    memcpy(doc.total_reflectance, total, sizeof total);
    memcpy(doc.error_relative, fr.error_relative, sizeof fr.error_relative);
    if (dm_profile_write(o.output, &doc, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return DM_EXIT_SAVE;
    }
    if (!o.quiet) {
        printf("%s: %d Gaussians, %d blur passes, relative error R %.3e G %.3e B %.3e (max %.3e), fit %.1f ms\n",
               o.output, out.count, dm_profile_blur_passes(out.count), fr.error_relative[0], fr.error_relative[1],
               fr.error_relative[2], fr.error_relative_max, fit_ms);
        printf("total reflectance R %.4f G %.4f B %.4f%s\n", total[0], total[1], total[2],
               o.normalize ? " (normalised to white in the file)" : "");
        if (src.kind == DM_SOURCE_SKIN) {
            double phys[3];
            dm_profile_source_total(&src, phys);
            printf("skin total diffuse reflectance R %.4f G %.4f B %.4f (the physical profile's, linear sRGB)\n",
                   phys[0], phys[1], phys[2]);
        }
    }
    if (o.verbose) {
        double inc[DM_PROFILE_MAX_GAUSSIANS];
        dm_profile_incremental_variances(&out, inc);
        printf("%-3s %-12s %-12s %-9s %-9s %s\n", "k", "var_mm2", "blur_mm2", "w_R", "w_G", "w_B");
        for (int k = 0; k < out.count; ++k)
            printf("%-3d %-12.5g %-12.5g %-9.4f %-9.4f %.4f\n", k, out.variance_mm2[k], inc[k], out.weight[k][0],
                   out.weight[k][1], out.weight[k][2]);
    }
    return DM_EXIT_OK;
}
