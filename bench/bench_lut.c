/* bench_lut — what LUT accuracy costs in time: bake time and runtime-sampled error for
 * Beckmann sizes 64…2048, rho_dt sizes and node counts, and the whole dermis-bake-lut
 * process at its defaults. Medians of several runs. Writes bench/results/lut.md. */
#include <math.h>
#include <stdio.h>

#include "bake/dm_lut.h"
#include "common/bench_util.h"
#include "core/dm_cli.h"

enum { RUNS = 5 };

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "bench/results";
    FILE *f = bench_open(dir, "lut.md", "dermis-bake-lut: accuracy against time");
    if (!f) return 1;

    fprintf(f, "## Beckmann table (8-bit, 0.5·D^0.1)\n\n"
               "Relative error of `(2·bilinear(v))^10` against the exact D over the lobe (D > 1 %% of the\n"
               "row's peak, D < 1024), 4×4 samples per texel, by roughness band; bake time is the median\n"
               "of %d runs on all cores.\n\n"
               "| size | bake ms | max rel, all m | max rel, m ≥ 0.05 | max rel, m ≥ 0.1 | max rel, m ≥ 0.2 | rms rel, m ≥ 0.1 |\n"
               "|---|---|---|---|---|---|---|\n",
            RUNS);
    const double bands[4] = {0.0, 0.05, 0.1, 0.2};
    for (int size = 64; size <= 2048; size *= 2) {
        double t[RUNS];
        dm_beckmann_lut lut = {0};
        for (int r = 0; r < RUNS; ++r) {
            dm_beckmann_lut_free(&lut);
            dm_lut_bake_beckmann(size, size, 0, 0, &lut, NULL);
            t[r] = lut.bake_ms;
        }
        dm_lut_error e[4];
        dm_lut_beckmann_error(&lut, size >= 1024 ? 2 : 4, bands, 4, 0, e);
        fprintf(f, "| %d² | %.2f | %.2f %% | %.2f %% | %.2f %% | %.2f %% | %.2f %% |\n", size, bench_median(t, RUNS),
                100 * e[0].max_rel, 100 * e[1].max_rel, 100 * e[2].max_rel, 100 * e[3].max_rel, 100 * e[2].rms_rel);
        printf("  beckmann %4d²: %.2f ms, max rel (m>=0.1) %.2f %%\n", size, bench_median(t, RUNS), 100 * e[2].max_rel);
        dm_beckmann_lut_free(&lut);
    }

    fprintf(f, "\n## rho_dt and env-BRDF tables (float)\n\n"
               "Absolute error against a %d-node reference at texel centres, midpoints and borders, for\n"
               "m ≥ 0.05; 'centres' is the integral's own error; 'N·L-weighted' is max N·L·|Δ|, what\n"
               "reaches lit irradiance. Bake = rho_dt + scale + bias together, median of %d runs.\n\n"
               "| size | nodes | bake ms | rho_dt max | rho_dt centres | rho_dt N·L-weighted | scale max | bias max |\n"
               "|---|---|---|---|---|---|---|---|\n",
            DM_LUT_REFERENCE_NODES, RUNS);
    const int sizes[] = {16, 32, 64, 128};
    const int nodes[] = {16, 24, 32, 48};
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
            if (sizes[a] != 64 && nodes[b] != DM_LUT_NODES_DEFAULT) continue; /* sweep nodes at 64² only */
            double t[RUNS];
            dm_directional_lut lut = {0};
            for (int r = 0; r < RUNS; ++r) {
                dm_directional_lut_free(&lut);
                dm_lut_bake_directional(sizes[a], sizes[a], 0.028, nodes[b], 0, &lut, NULL);
                t[r] = lut.bake_ms;
            }
            double m_min = 0.05;
            dm_lut_error e[3];
            dm_lut_directional_error(&lut, &m_min, 1, 0, e);
            fprintf(f, "| %d² | %d | %.1f | %.2e | %.2e | %.2e | %.2e | %.2e |\n", sizes[a], nodes[b],
                    bench_median(t, RUNS), e[0].max_abs, e[0].max_abs_centres, e[0].max_abs_weighted, e[1].max_abs,
                    e[2].max_abs);
            printf("  rho_dt %3d² nodes %2d: %.1f ms, centres %.1e, weighted %.1e\n", sizes[a], nodes[b],
                   bench_median(t, RUNS), e[0].max_abs_centres, e[0].max_abs_weighted);
            dm_directional_lut_free(&lut);
        }

    /* the whole process, as a user runs it */
    char cmd[1024], tmp[] = "/tmp/dermis-bench-XXXXXX";
    if (!mkdtemp(tmp)) return 1;
    const char *bin = getenv("BUILD") ? getenv("BUILD") : "build/release";
    snprintf(cmd, sizeof cmd, "%s/bin/dermis-bake-lut -o %s --quiet", bin, tmp);
    double t[RUNS];
    for (int r = 0; r < RUNS; ++r) {
        double t0 = dm_now_ms();
        if (system(cmd) != 0) {
            fprintf(stderr, "error: '%s' failed\n", cmd);
            return 1;
        }
        t[r] = dm_now_ms() - t0;
    }
    double whole = bench_median(t, RUNS);
    fprintf(f, "\n## Whole process\n\n`dermis-bake-lut` at its defaults (512² Beckmann PNG, 64² rho_dt and env-BRDF\n"
               "EXR, 32 nodes), process start to exit, median of %d runs: **%.0f ms** (aim: < 300 ms).\n",
            RUNS, whole);
    printf("  whole process: %.0f ms\n", whole);
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmp);
    if (system(cmd) != 0) fprintf(stderr, "warning: could not remove %s\n", tmp);
    fclose(f);
    return 0;
}
