/* bench_skin_weights — what fixed variances cost (issue #30, point 3): across the physical
 * skin's parameter range, the error of a free fit (its own six variances per skin) beside
 * the live weights on fixed variances (GPU Gems 3's six; the Caucasian exemplar's free-fit
 * six, what a pack of that skin holds; the one set among the rows' own that is best for
 * the whole range), all measured alike (dm_profile_fit_error: r-weighted relative L2, the
 * worst channel); and the time of one live refit against the offline fit.
 * Usage: bench_skin_weights OUTDIR   (writes OUTDIR/skin_weights.md) */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "common/bench_util.h"

#include "bake/dm_profile_fit.h"
#include "bake/dm_skin_profile.h"
#include "bake/dm_skin_ad.h"
#include "bake/dm_skin_weights.h"
#include "core/dm_cli.h"

enum { ROWS = 15, TIMED = 201, OFFLINE_RUNS = 5 };

typedef struct row {
    const char *label, *preset;
    double melanin, blood, epidermis_mm; /* < 0: the preset's */
    dm_skin_params p;
    dm_profile_source src;
    dm_fit_result free_fit;
} row;

#define ROW(l, pr, m, b, e) {.label = l, .preset = pr, .melanin = m, .blood = b, .epidermis_mm = e}
static row rows[ROWS] = {ROW("caucasian", "caucasian", -1, -1, -1),
                         ROW("asian", "asian", -1, -1, -1),
                         ROW("african", "african", -1, -1, -1),
                         ROW("fitzpatrick-1", "fitzpatrick-1", -1, -1, -1),
                         ROW("fitzpatrick-2", "fitzpatrick-2", -1, -1, -1),
                         ROW("fitzpatrick-3", "fitzpatrick-3", -1, -1, -1),
                         ROW("fitzpatrick-4", "fitzpatrick-4", -1, -1, -1),
                         ROW("fitzpatrick-5", "fitzpatrick-5", -1, -1, -1),
                         ROW("fitzpatrick-6", "fitzpatrick-6", -1, -1, -1),
                         ROW("caucasian, no melanin", "caucasian", 0.0, -1, -1),
                         ROW("caucasian, blood 0.001", "caucasian", -1, 0.001, -1),
                         ROW("caucasian, blood 0.05", "caucasian", -1, 0.05, -1),
                         ROW("caucasian, blood 0.1", "caucasian", -1, 0.1, -1),
                         ROW("caucasian, epidermis 0.05 mm", "caucasian", -1, -1, 0.05),
                         ROW("caucasian, epidermis 1 mm", "caucasian", -1, -1, 1.0)};

static dm_skin_weights_plan plan;

/* The worst channel's error of the live weights for variances v at row r. */
static double fixed_error(const double *v, int count, row *r)
{
    dm_profile w;
    double e[3];
    if (dm_skin_weights_plan_init(&plan, v, count, NULL, NULL) != DM_OK ||
        dm_skin_weights_fit(&plan, &r->p, NULL, &w, NULL) != DM_OK ||
        dm_profile_fit_error(&r->src, &w, NULL, e, NULL) != DM_OK)
        return -1.0;
    return fmax(e[0], fmax(e[1], e[2]));
}

static double cpu_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "Usage: bench_skin_weights OUTDIR\n");
        return DM_EXIT_USAGE;
    }
    FILE *f = bench_open(argv[1], "skin_weights.md", "Live skin weights: fixed variances against a free fit");
    if (!f) return DM_EXIT_SAVE;
    double load[3] = {0};
    FILE *la = fopen("/proc/loadavg", "r");
    if (la) {
        if (fscanf(la, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) load[0] = -1;
        fclose(la);
    }
    fprintf(f, "Load average at the start: %.2f (on %ld cores).\n\n", load[0], sysconf(_SC_NPROCESSORS_ONLN));
    for (int i = 0; i < ROWS; ++i) {
        row *r = &rows[i];
        dm_error err = {0};
        if (dm_skin_preset(r->preset, &r->p, &err) != DM_OK) goto fail;
        if (r->melanin >= 0) r->p.melanin_fraction = r->melanin;
        if (r->blood >= 0) r->p.blood_fraction = r->blood;
        if (r->epidermis_mm >= 0) r->p.epidermis_mm = r->epidermis_mm;
        if (dm_profile_source_skin(&r->p, &r->src, &err) != DM_OK || dm_profile_fit(&r->src, NULL, NULL, &r->free_fit, &err) != DM_OK) {
        fail:
            fprintf(stderr, "error: %s: %s\n", r->label, err.detail);
            fclose(f);
            return DM_EXIT_PROCESS;
        }
        fprintf(stderr, "%s: free fit %.4f\n", r->label, r->free_fit.error_relative_max);
    }
    /* the set chosen once: among the rows' own free-fit variances, the one whose worst excess
     * over the free fit (fixed − free, over the rows) is the lowest */
    int best = 0;
    double best_worst = 1e30;
    for (int c = 0; c < ROWS; ++c) {
        double worst = 0;
        for (int i = 0; i < ROWS; ++i) {
            double e = fixed_error(rows[c].free_fit.profile.variance_mm2, rows[c].free_fit.profile.count, &rows[i]);
            worst = e < 0 ? 1e30 : fmax(worst, e - rows[i].free_fit.error_relative_max);
        }
        if (worst < best_worst) best_worst = worst, best = c;
    }
    const dm_profile *cau = &rows[0].free_fit.profile, *once = &rows[best].free_fit.profile;
    fprintf(f, "Error: sqrt(∫ r (R − ΣG)² dr / ∫ r R² dr), the worst channel, on the free fit's quadrature "
               "(dm_profile_fit_error against the dense physical profile). Six Gaussians throughout. "
               "Fixed variances, weights by the live fit (bake/dm_skin_weights.h):\n\n"
               "- GPU Gems 3: 0.0064, 0.0484, 0.187, 0.567, 1.99, 7.41 mm²;\n"
               "- Caucasian: the Caucasian exemplar's free fit, what a pack of that skin holds:");
    for (int k = 0; k < cau->count; ++k) fprintf(f, " %.4g", cau->variance_mm2[k]);
    fprintf(f, " mm²;\n- chosen once: among the rows' own free-fit sets, the one whose worst excess over the free "
               "fit, over all rows, is the lowest (%s's; worst excess %.4f):", rows[best].label, best_worst);
    for (int k = 0; k < once->count; ++k) fprintf(f, " %.4g", once->variance_mm2[k]);
    fprintf(f, " mm².\n\n| skin | Cm | Ch | epidermis mm | free | GPU Gems 3 | Caucasian | chosen once |\n"
               "|---|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < ROWS; ++i) {
        row *r = &rows[i];
        double g = fixed_error(DM_SKIN_GEMS3_VARIANCES_MM2, 6, r), c = fixed_error(cau->variance_mm2, cau->count, r),
               o = fixed_error(once->variance_mm2, once->count, r);
        fprintf(f, "| %s | %g | %g | %g | %.4f | %.4f | %.4f | %.4f |\n", r->label, r->p.melanin_fraction,
                r->p.blood_fraction, r->p.epidermis_mm, r->free_fit.error_relative_max, g, c, o);
        fprintf(stderr, "%s: free %.4f gems3 %.4f caucasian %.4f once %.4f\n", r->label,
                r->free_fit.error_relative_max, g, c, o);
    }
    /* time: a melanin sweep (the slider), the live refit against the offline fit */
    double wall[TIMED], cpu[TIMED], off[OFFLINE_RUNS];
    dm_skin_weights_plan_init(&plan, cau->variance_mm2, cau->count, NULL, NULL);
    for (int i = 0; i < TIMED; ++i) {
        dm_skin_params p = rows[0].p;
        p.melanin_fraction = 0.5 * i / (TIMED - 1);
        dm_profile w;
        double t0 = dm_now_ms(), c0 = cpu_ms();
        dm_skin_weights_fit(&plan, &p, NULL, &w, NULL);
        wall[i] = dm_now_ms() - t0, cpu[i] = cpu_ms() - c0;
    }
    for (int i = 0; i < OFFLINE_RUNS; ++i) {
        dm_profile w;
        dm_skin_profile_options o = {.gaussian_count = cau->count};
        memcpy(o.variance_mm2, cau->variance_mm2, sizeof o.variance_mm2);
        double t0 = dm_now_ms();
        dm_skin_profile_fit(&rows[0].p, &o, NULL, &w, NULL, NULL);
        off[i] = dm_now_ms() - t0;
    }
    double mw = bench_median(wall, TIMED), mc = bench_median(cpu, TIMED), mo = bench_median(off, OFFLINE_RUNS);
    fprintf(f, "\nTime of one refit (the Caucasian variances; a melanin sweep 0–0.5, %d refits, median): live "
               "(%d nodes, %d pairs, %d adding-doubling streams) **%.2f ms wall, %.2f ms CPU**; the offline fit "
               "of the same variances (dm_skin_profile_fit: 401 nodes, 20 pairs, %d streams) %.1f ms wall (median "
               "of %d).\n",
            TIMED, DM_SKIN_WEIGHTS_NODES_DEFAULT, DM_SKIN_WEIGHTS_PAIRS_DEFAULT, DM_SKIN_WEIGHTS_STREAMS_DEFAULT, mw, mc,
            DM_SKIN_AD_STREAMS_DEFAULT, mo, OFFLINE_RUNS);
    printf("live refit median %.2f ms wall, %.2f ms CPU; offline %.1f ms\n", mw, mc, mo);
    if (fclose(f) != 0) {
        fprintf(stderr, "error: %s/skin_weights.md: write failed\n", argv[1]);
        return DM_EXIT_SAVE;
    }
    printf("wrote %s/skin_weights.md\n", argv[1]);
    return DM_EXIT_OK;
}
