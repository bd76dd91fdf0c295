/* bench_profile_fit — what accuracy costs: fit error and fit time for N = 1..8 Gaussians
 * on the skin presets, beside the blur passes each N costs the runtime.
 * Usage: bench_profile_fit OUTDIR   (writes OUTDIR/profile_fit.md) */
#include <stdio.h>
#include <string.h>

#include "common/bench_util.h"

#include "bake/dm_profile_fit.h"
#include "core/dm_cli.h"

enum { RUNS = 3 };

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "Usage: bench_profile_fit OUTDIR\n");
        return DM_EXIT_USAGE;
    }
    FILE *f = bench_open(argv[1], "profile_fit.md", "dermis-fit-profile: fit error and time against N");
    if (!f) return DM_EXIT_SAVE;
    fprintf(f, "Single-threaded fit, %d quadrature nodes, median of %d runs.\n\n", DM_FIT_NODES_DEFAULT, RUNS);
    fprintf(f, "Error: sqrt(∫ r (R − ΣG)² dr / ∫ r R² dr) per channel (before normalisation to white). "
               "Passes: separable blur passes the runtime spends, 2(N − 1).\n\n");

    struct {
        const char *label, *preset;
        int multipole;
        double thickness;
        const char *skin; /* a physical skin preset (bake/dm_skin_optics.h) */
    } cases[] = {{"gems3-skin (6 Gaussians)", NULL, 0, 0, NULL},
                 {"skin1 dipole (Jensen 2001)", "skin1", 0, 0, NULL},
                 {"skin2 dipole (Jensen 2001)", "skin2", 0, 0, NULL},
                 {"skin1 multipole, 1 mm slab", "skin1", 1, 1.0, NULL},
                 {"physical skin, Caucasian exemplar (--skin-preset caucasian)", NULL, 0, 0, "caucasian"}};
    for (size_t ci = 0; ci < sizeof cases / sizeof cases[0]; ++ci) {
        dm_profile_source s;
        memset(&s, 0, sizeof s);
        if (cases[ci].skin) {
            dm_skin_params p;
            dm_error err = {0};
            if (dm_skin_preset(cases[ci].skin, &p, &err) != DM_OK || dm_profile_source_skin(&p, &s, &err) != DM_OK) {
                fprintf(stderr, "error: %s: %s\n", cases[ci].label, err.detail);
                fclose(f);
                return DM_EXIT_PROCESS;
            }
        } else if (!cases[ci].preset) {
            s.kind = DM_SOURCE_GAUSSIANS;
            dm_profile_gems3_skin(&s.gaussians);
        } else {
            s.kind = DM_SOURCE_MEDIUM;
            dm_medium_preset(cases[ci].preset, &s.medium, NULL);
            if (cases[ci].multipole) {
                s.medium.model = DM_MODEL_MULTIPOLE;
                s.medium.thickness_mm = cases[ci].thickness;
            }
        }
        fprintf(f, "## %s\n\n| N | passes | err R | err G | err B | err max | fit ms (median) | LM steps |\n"
                   "|---|---|---|---|---|---|---|---|\n",
                cases[ci].label);
        for (int n = 1; n <= DM_PROFILE_MAX_GAUSSIANS; ++n) {
            dm_fit_options o = {.gaussian_count = n};
            dm_fit_result r;
            double ms[RUNS];
            dm_error err = {0};
            int refused = 0;
            for (int run = 0; run < RUNS && !refused; ++run) {
                double t0 = dm_now_ms();
                refused = dm_profile_fit(&s, &o, NULL, &r, &err) != DM_OK;
                ms[run] = dm_now_ms() - t0;
            }
            if (refused) { /* reported in its row, as dermis-fit-profile --table does */
                fprintf(f, "| %d | %d | refused: %s | | | | | |\n", n, dm_profile_blur_passes(n), err.detail);
                fprintf(stderr, "%s N %d: refused: %s\n", cases[ci].label, n, err.detail);
                continue;
            }
            double median = bench_median(ms, RUNS);
            fprintf(f, "| %d | %d | %.2e | %.2e | %.2e | %.2e | %.1f | %d |\n", n, dm_profile_blur_passes(n),
                    r.error_relative[0], r.error_relative[1], r.error_relative[2], r.error_relative_max, median,
                    r.iterations);
            fprintf(stderr, "%s N %d: error %.2e, %.1f ms\n", cases[ci].label, n, r.error_relative_max, median);
        }
        fprintf(f, "\n");
    }
    if (fclose(f) != 0) {
        fprintf(stderr, "error: %s/profile_fit.md: write failed\n", argv[1]);
        return DM_EXIT_SAVE;
    }
    printf("wrote %s/profile_fit.md\n", argv[1]);
    return DM_EXIT_OK;
}
