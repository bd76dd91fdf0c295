/* bench_env — dermis-bake-env's accuracy against time on the five bundled environments.
 * Usage: bench_env OUT_DIR   (writes OUT_DIR/bench_env.md)
 *
 * For every map: the full default bake (load, SH, background, prefilter, error check,
 * write) as the tool runs it, median of 3; then the prefilter alone at 64..4096 samples,
 * with its error against exact quadrature (dm_env_prefilter_error) on 64 texels per level. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>

#include "bake/dm_env_bake.h"
#include "core/dm_cli.h"
#include "core/dm_parallel.h"
#include "core/dm_sort.h"

static const char *MAPS[] = {"courtyard.exr", "night.exr", "royal_esplanade_1k.hdr", "studio.exr",
                             "venice_sunset_1k.hdr"};
enum { MAP_COUNT = 5, REPEATS = 3, CHECK_TEXELS = 64 };

static void cpu_model(char *out, size_t size)
{
    snprintf(out, size, "unknown");
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (!f) return;
    char line[512];
    while (fgets(line, sizeof line, f))
        if (!strncmp(line, "model name", 10)) {
            char *c = strchr(line, ':');
            if (c) snprintf(out, size, "%s", c + 2);
            out[strcspn(out, "\n")] = 0;
            break;
        }
    fclose(f);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "Usage: bench_env OUT_DIR\n");
        return DM_EXIT_USAGE;
    }
    char path[4096], out_path[4096], tmp_out[4096];
    snprintf(out_path, sizeof out_path, "%s/bench_env.md", argv[1]);
    snprintf(tmp_out, sizeof tmp_out, "%s/bench_env.tmp.exr", argv[1]);
    FILE *md = fopen(out_path, "w");
    if (!md) {
        fprintf(stderr, "error: %s: cannot write\n", out_path);
        return DM_EXIT_SAVE;
    }
    struct utsname u;
    uname(&u);
    char cpu[256];
    cpu_model(cpu, sizeof cpu);
    fprintf(md, "# dermis-bake-env: bake time and prefilter error\n\n");
    fprintf(md, "Machine: `%s %s %s %s %s`, %s, %d cores (all used).\n\n", u.sysname, u.nodename, u.release,
            u.version, u.machine, cpu, dm_cpu_count());
    fprintf(md, "Error: per texel, max over R, G, B of |P - P_ref| divided by the reference's largest channel; "
                "P_ref by exact quadrature over the source texels; %d texels per level (2-D Hammersley spread), "
                "rms and max over all levels (m = 0.1, 0.28, 0.46, 0.64, 0.82, 1).\n\n",
            CHECK_TEXELS);
    fprintf(md, "## Full bake, defaults (%d samples, 6 levels, background at source size, %d check texels)\n\n",
            DM_ENV_SAMPLES_DEFAULT, DM_ENV_CHECK_TEXELS_DEFAULT);
    fprintf(md, "| map | size | load ms | SH ms | background ms | prefilter ms | check ms | write ms | total ms (median of %d) |\n",
            REPEATS);
    fprintf(md, "|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for (int mi = 0; mi < MAP_COUNT; ++mi) {
        snprintf(path, sizeof path, "%s/env/%s", DERMIS_ASSETS, MAPS[mi]);
        double total[REPEATS], load = 0, sh = 0, bg = 0, pf = 0, ck = 0, wr = 0;
        int w = 0, h = 0;
        for (int rep = 0; rep < REPEATS; ++rep) {
            dm_error err = {0};
            double t0 = dm_now_ms();
            dm_envmap map;
            if (dm_envmap_load(path, DM_ENVMAP_NEGATIVE_TOLERANCE_DEFAULT, &map, &err) != DM_OK) {
                fprintf(stderr, "error: %s\n", err.detail);
                return DM_EXIT_LOAD;
            }
            double t1 = dm_now_ms();
            dm_env_options opt = {0};
            dm_env_bake bake;
            if (dm_env_bake_run(&map, &opt, &bake, &err) != DM_OK) {
                fprintf(stderr, "error: %s\n", err.detail);
                return DM_EXIT_PROCESS;
            }
            double t2 = dm_now_ms();
            dm_provenance prov;
            dm_prov_init(&prov, "bench_env");
            if (dm_env_write(tmp_out, &bake, &prov, &err) != DM_OK) {
                fprintf(stderr, "error: %s\n", err.detail);
                return DM_EXIT_SAVE;
            }
            double t3 = dm_now_ms();
            total[rep] = t3 - t0;
            if (rep == REPEATS - 1) {
                load = t1 - t0;
                sh = bake.sh_ms;
                bg = bake.background_ms;
                pf = bake.prefilter_ms;
                ck = bake.check_ms;
                wr = t3 - t2;
                w = map.width;
                h = map.height;
            }
            dm_env_bake_free(&bake);
            dm_envmap_free(&map);
        }
        remove(tmp_out);
        dm_sort_doubles(total, REPEATS);
        fprintf(md, "| %s | %dx%d | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | **%.0f** |\n", MAPS[mi], w, h, load, sh, bg,
                pf, ck, wr, total[REPEATS / 2]);
        fprintf(stderr, "%s: full bake %.0f ms\n", MAPS[mi], total[REPEATS / 2]);
        fflush(md);
    }

    fprintf(md, "\n## Prefilter (all 6 levels) against sample count\n\n");
    fprintf(md, "| map | samples | prefilter ms | error rms | error max | worst level (m) |\n");
    fprintf(md, "|---|---:|---:|---:|---:|---:|\n");
    for (int mi = 0; mi < MAP_COUNT; ++mi) {
        snprintf(path, sizeof path, "%s/env/%s", DERMIS_ASSETS, MAPS[mi]);
        dm_envmap map;
        dm_error err = {0};
        if (dm_envmap_load(path, DM_ENVMAP_NEGATIVE_TOLERANCE_DEFAULT, &map, &err) != DM_OK) {
            fprintf(stderr, "error: %s\n", err.detail);
            return DM_EXIT_LOAD;
        }
        for (int n = 64; n <= 4096; n *= 4) {
            double ms = 0, sq = 0, mx = 0, worst_m = 0;
            int texels = 0;
            for (int k = 0; k < DM_ENV_LEVELS_DEFAULT; ++k) {
                double m = dm_env_default_m(k, DM_ENV_LEVELS_DEFAULT);
                int lw = dm_env_level_width(m, DM_ENV_SPEC_SIZE_DEFAULT, map.width);
                float *lv = malloc((size_t)lw * (lw / 2) * 3 * sizeof(float));
                double t0 = dm_now_ms();
                if (!lv || dm_env_prefilter(&map, m, n, 0.0, lw, 0, lv, &err) != DM_OK) {
                    fprintf(stderr, "error: prefilter: %s\n", err.detail);
                    return DM_EXIT_PROCESS;
                }
                ms += dm_now_ms() - t0;
                dm_env_error e;
                dm_env_prefilter_error(&map, m, 0.0, lv, lw, CHECK_TEXELS, 0, &e);
                sq += e.rms_rel * e.rms_rel * e.texels;
                texels += e.texels;
                if (e.max_rel > mx) {
                    mx = e.max_rel;
                    worst_m = m;
                }
                free(lv);
            }
            fprintf(md, "| %s | %d | %.0f | %.3f | %.3f | %.2f |\n", MAPS[mi], n, ms, sqrt(sq / texels), mx, worst_m);
            fprintf(stderr, "%s: %d samples %.0f ms, rms %.3f\n", MAPS[mi], n, ms, sqrt(sq / texels));
            fflush(md);
        }
        dm_envmap_free(&map);
    }
    fclose(md);
    printf("%s\n", out_path);
    return DM_EXIT_OK;
}
