/* dermis-pack — scene + sources → one .dpk pack holding only what the scene's effects need.
 * parse → load the scene (once) → run the bake steps that apply (packer/dm_pack_build.h) →
 * write → report. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_lut.h"
#include "packer/dm_pack_build.h"
#include "core/dm_cli.h"
#include "core/dm_output.h"
#include "pack/dm_pack.h"

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
            "A scene whose memory estimate (by its irradiance size) exceeds what is available is\n"
            "refused before any work, naming both; DERMIS_MEM_AVAILABLE_MB (MiB) overrides what is\n"
            "counted as available (default: MemAvailable, or a cgroup's limit when lower).\n"
            "Exit codes: 0 ok, 1 usage, 2 cannot load an input, 3 processing failed or refused\n"
            "(memory), 4 cannot save.\n",
            DM_LUT_BECKMANN_SIZE_DEFAULT, DM_LUT_SIZE_MAX, DM_LUT_DIRECTIONAL_SIZE_DEFAULT, DM_LUT_NODES_DEFAULT);
}

typedef struct options {
    const char *scene, *output;
    const char *assets[8];
    int asset_count;
    bool explain;
    dm_pack_build_options build;
} options;

/* The integer after option argv[*i], in [min, max], into *out; false (said on stderr) when
 * missing or out of range. */
static bool int_option(int argc, char **argv, int *i, int64_t min, int64_t max, int *out)
{
    const char *a = argv[*i];
    int64_t v;
    const char *t = dm_cli_value(argc, argv, i);
    if (!t || !dm_cli_int(a, t, min, max, &v)) return false;
    *out = (int)v;
    return true;
}

static int parse_args(int argc, char **argv, options *o)
{
    *o = (options){.build = {.beckmann_size = DM_LUT_BECKMANN_SIZE_DEFAULT,
                             .lut_size = DM_LUT_DIRECTIONAL_SIZE_DEFAULT,
                             .lut_nodes = DM_LUT_NODES_DEFAULT}};
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (dm_cli_version(a, "dermis-pack")) exit(0);
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            exit(DM_EXIT_OK);
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            if (!(o->output = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--explain")) {
            o->explain = true;
        } else if (!strcmp(a, "--beckmann")) {
            if (!(o->build.beckmann = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--rho-dt")) {
            if (!(o->build.rho_dt = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--env-brdf")) {
            if (!(o->build.env_brdf = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--stretch")) {
            if (!(o->build.stretch_file = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--env")) {
            if (o->build.env_file_count == 8) {
                fprintf(stderr, "error: --env: at most 8 files (one per environment map)\n");
                return DM_EXIT_USAGE;
            }
            if (!(o->build.env_files[o->build.env_file_count++] = dm_cli_value(argc, argv, &i))) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--beckmann-size")) {
            if (!int_option(argc, argv, &i, 16, DM_LUT_SIZE_MAX, &o->build.beckmann_size)) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--lut-size")) {
            if (!int_option(argc, argv, &i, 8, 1024, &o->build.lut_size)) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--lut-nodes")) {
            if (!int_option(argc, argv, &i, 8, 128, &o->build.lut_nodes)) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--threads")) {
            if (!int_option(argc, argv, &i, 0, 256, &o->build.threads)) return DM_EXIT_USAGE;
        } else if (!strcmp(a, "--assets")) {
            const char *v = dm_cli_value(argc, argv, &i);
            if (!v) return DM_EXIT_USAGE;
            if (o->asset_count == 8) {
                fprintf(stderr, "error: --assets: at most 8 folders\n");
                return DM_EXIT_USAGE;
            }
            o->assets[o->asset_count++] = v;
        } else if (!strcmp(a, "-v") || !strcmp(a, "--verbose")) {
            o->build.verbose = true;
        } else if (!strcmp(a, "--quiet")) {
            o->build.quiet = true;
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
    if (o->build.verbose && o->build.quiet) {
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

int main(int argc, char **argv)
{
    options opt;
    int rc = parse_args(argc, argv, &opt);
    if (rc != DM_EXIT_OK) return rc;
    const char *in[5 + DM_PACK_BUILD_ENV_FILES] = {opt.scene, opt.build.beckmann, opt.build.rho_dt, opt.build.env_brdf,
                                                   opt.build.stretch_file};
    memcpy(in + 5, opt.build.env_files, sizeof opt.build.env_files);
    if (opt.output && (rc = dm_output_check_cli("-o", opt.output, (const char *const[]){".dpk", NULL}, in, 13, NULL)))
        return rc; /* before any work (core/dm_output.h) */
    const dm_pack_build_options *bo = &opt.build;

    dm_pack_build *j = malloc(sizeof *j);
    if (!j) return DM_EXIT_PROCESS;
    dm_error err = {0};
    double t0 = dm_now_ms();
    if (dm_pack_build_begin(j, opt.scene, opt.assets, opt.asset_count, bo, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_pack_build_free(j);
        free(j);
        return DM_EXIT_LOAD;
    }
    if (j->scene.light_count == 0 && !j->scene.effects[DM_EFFECT_ENVIRONMENT_LIGHTING])
        fprintf(stderr,
                "warning: %s: no light and no environment lighting: every picture of this pack will be black; add a "
                "light to $.lights or turn on $.effects.environment_lighting with an $.environment.path\n",
                opt.scene);
    if (opt.explain) {
        dm_pack_build_explain(&j->scene);
        dm_pack_build_free(j);
        free(j);
        return DM_EXIT_OK;
    }
    if (dm_pack_build_memory_check(j, &err) != DM_OK) { /* before any work: packer/dm_pack_build.h */
        fprintf(stderr, "error: %s\n", err.detail);
        dm_pack_build_free(j);
        free(j);
        return DM_EXIT_PROCESS;
    }
    /* Files given for entries the scene does not need are a mistake worth saying. */
    const struct { const char *file, *entry, *opt; } given[] = {
        {bo->beckmann, "lut.beckmann", "--beckmann"}, {bo->rho_dt, "lut.rho_dt", "--rho-dt"},
        {bo->env_brdf, "lut.env_brdf", "--env-brdf"}, {bo->stretch_file, "stretch", "--stretch"}};
    for (size_t k = 0; k < sizeof given / sizeof given[0]; ++k)
        if (given[k].file && !dm_pack_build_wants(j, given[k].entry) && !bo->quiet)
            fprintf(stderr, "warning: %s %s: the scene's effects do not need %s; ignored\n", given[k].opt,
                    given[k].file, given[k].entry);

    const char *failed = "";
    if (dm_pack_build_run(j, &failed, &err) != DM_OK) {
        fprintf(stderr, "error: %s: %s\n", failed, err.detail);
        bool input = j->input_failed || err.code == DM_ERR_FILE_OPEN || err.code == DM_ERR_FILE_READ ||
                     err.code == DM_ERR_MISMATCH || err.code == DM_ERR_FORMAT || err.code == DM_ERR_UNSUPPORTED;
        dm_pack_build_free(j);
        free(j);
        return input ? DM_EXIT_LOAD : DM_EXIT_PROCESS;
    }
    for (int f = 0; f < bo->env_file_count; ++f)
        if (!j->env_file_used[f] && !bo->quiet)
            fprintf(stderr, "warning: --env %s: baked from none of the scene's environment maps (or none is "
                            "needed); ignored\n", bo->env_files[f]);

    size_t total = 0;
    double tw = dm_now_ms();
    dm_result r = dm_pack_build_write(j, opt.output, &total, &err);
    tw = dm_now_ms() - tw;
    if (r != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_pack_build_free(j);
        free(j);
        return r == DM_ERR_FILE_WRITE ? DM_EXIT_SAVE : DM_EXIT_PROCESS;
    }
    if (!bo->quiet) {
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
            if (bo->verbose) printf("      provenance %s\n", b->provenance_json);
        }
        char sz[32];
        print_size(sz, sizeof sz, total);
        printf("  %d entries, %s, written and verified in %.1f ms, total %.1f ms\n", j->row_count, sz, tw,
               dm_now_ms() - t0);
    }
    dm_pack_build_free(j);
    free(j);
    return DM_EXIT_OK;
}
