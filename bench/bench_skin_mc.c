/* bench_skin_mc — the layered-slab Monte Carlo (bake/dm_skin_mc.h): photons per second by
 * case and thread count, and its agreement at large photon counts with MCML's published
 * cases and with the dipole. Usage: bench_skin_mc [OUTDIR]   (writes OUTDIR/skin_mc.md) */
#include <math.h>
#include <stdio.h>

#include "common/bench_util.h"

#include "bake/dm_skin_mc.h"
#include "core/dm_cli.h"
#include "core/dm_diffusion.h"
#include "core/dm_math.h"
#include "core/dm_parallel.h"

enum { BINS = 100 };
#define DR_MM 0.05

typedef struct timed {
    dm_skin_mc_result r;
    double ms;
} timed;

static double rd_r[BINS], rd_r_se[BINS];

static int run(const dm_skin_mc_layer *layers, int count, uint64_t photons, int threads, timed *t)
{
    dm_skin_mc_desc d = {.layers = layers, .layer_count = count, .photon_count = photons, .seed = 20250101,
                         .thread_count = threads, .dr_mm = DR_MM, .radial_bin_count = BINS};
    t->r = (dm_skin_mc_result){.rd_r_per_mm2 = rd_r, .rd_r_se_per_mm2 = rd_r_se};
    dm_error err = {0};
    double t0 = dm_now_ms();
    if (dm_skin_mc_run(&d, &t->r, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return 0;
    }
    t->ms = dm_now_ms() - t0;
    return 1;
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "bench/results";
    FILE *f = bench_open(dir, "skin_mc.md", "dm_skin_mc: Monte Carlo of a layered slab, throughput and agreement");
    if (!f) return DM_EXIT_SAVE;

    /* MCML's cases in mm (the paper's cm⁻¹ ÷ 10, cm × 10) */
    static const dm_skin_mc_layer vdh = {1.0, 1.0, 9.0, 0.75, 0.2};
    static const dm_skin_mc_layer gio = {1.5, 1.0, 9.0, 0.0, INFINITY};
    static const dm_skin_mc_layer semi = {1.0, 0.01, 10.0, 0.9, INFINITY};
    static const dm_skin_mc_layer skin[3] = {
        {1.5, 0.5, 20.0, 0.8, 0.01}, {1.4, 2.0, 30.0, 0.8, 0.1}, {1.36, 0.05, 20.0, 0.85, 1.5}};
    struct {
        const char *label;
        const dm_skin_mc_layer *layers;
        int count;
        uint64_t photons;
    } cases[] = {{"van de Hulst slab (a = 0.9, τ = 2, g = 0.75)", &vdh, 1, 1000000},
                 {"Giovanelli half-space (n = 1.5, a = 0.9, g = 0)", &gio, 1, 1000000},
                 {"MCML half-space (μa 0.01, μs 10 mm⁻¹, g 0.9)", &semi, 1, 100000},
                 {"three-layer skin-like stack", skin, 3, 200000}};
    enum { CASES = sizeof cases / sizeof *cases };
    timed res[CASES];

    int cores = dm_cpu_count();
    fprintf(f, "## Throughput\n\nSeed 20250101, batches of %d photons, %d radial bins; wall-clock time of one run.\n\n"
               "| case | photons | 1 thread, photons/s | %d threads, photons/s |\n|---|---|---|---|\n",
            DM_SKIN_MC_BATCH_DEFAULT, BINS, cores);
    for (int c = 0; c < CASES; ++c) {
        timed one, all;
        uint64_t n1 = cases[c].photons / 4;
        if (!run(cases[c].layers, cases[c].count, n1, 1, &one)) return 1;
        if (!run(cases[c].layers, cases[c].count, cases[c].photons, 0, &all)) return 1;
        res[c] = all;
        double p1 = n1 / (one.ms / 1000.0), pn = cases[c].photons / (all.ms / 1000.0);
        fprintf(f, "| %s | %llu | %.3g | %.3g |\n", cases[c].label, (unsigned long long)cases[c].photons, p1, pn);
        printf("  %-50s %9.3g photons/s (1 thread) %9.3g (%d threads)\n", cases[c].label, p1, pn, cores);
    }

    const timed *v = &res[0], *g = &res[1], *s = &res[2];
    fprintf(f, "\n## Agreement with the published values (Wang, Jacques & Zheng 1995, MCML)\n\n"
               "| case | quantity | published | this MC ± 1 SE | (MC − published)/SE |\n|---|---|---|---|---|\n");
    fprintf(f, "| van de Hulst slab | Rd | 0.09739 | %.5f ± %.5f | %+.1f |\n", v->r.diffuse_reflectance,
            v->r.diffuse_reflectance_se, (v->r.diffuse_reflectance - 0.09739) / v->r.diffuse_reflectance_se);
    fprintf(f, "| van de Hulst slab | Tt | 0.66096 | %.5f ± %.5f | %+.1f |\n", v->r.transmittance,
            v->r.transmittance_se, (v->r.transmittance - 0.66096) / v->r.transmittance_se);
    double gt = g->r.specular + g->r.diffuse_reflectance;
    fprintf(f, "| Giovanelli half-space | Rsp + Rd | 0.2600 | %.5f ± %.5f | %+.1f |\n", gt,
            g->r.diffuse_reflectance_se, (gt - 0.26) / g->r.diffuse_reflectance_se);
    printf("  vdH Rd %.5f +- %.5f (0.09739), Tt %.5f +- %.5f (0.66096); Giovanelli Rsp+Rd %.5f +- %.5f (0.2600)\n",
           v->r.diffuse_reflectance, v->r.diffuse_reflectance_se, v->r.transmittance, v->r.transmittance_se, gt,
           g->r.diffuse_reflectance_se);

    /* the dipole on MCML's half-space (n = 1, α′ = 0.990, l′ = 1 mm) */
    double sp = 10.0 * (1 - 0.9), dip = dm_dipole_total(0.01, sp, 1.0);
    fprintf(f, "\n## Against the dipole (MCML's half-space: μa 0.01, μs′ 1 mm⁻¹, n = 1)\n\n"
               "Rd: MC %.5f ± %.5f, dipole %.5f (dipole/MC − 1 = %+.2f %%).\n\n"
               "| r, mm | MC Rd(r), mm⁻² | ± SE | dipole | dipole/MC |\n|---|---|---|---|---|\n",
            s->r.diffuse_reflectance, s->r.diffuse_reflectance_se, dip,
            100 * (dip / s->r.diffuse_reflectance - 1));
    printf("  half-space Rd %.5f +- %.5f, dipole %.5f\n", s->r.diffuse_reflectance, s->r.diffuse_reflectance_se, dip);
    /* res[2]'s profile was overwritten by the later run: run it again for its bins */
    timed again;
    if (!run(&semi, 1, cases[2].photons, 0, &again)) return 1;
    static const int show[] = {0, 1, 2, 4, 6, 8, 10, 15, 20, 30, 40, 50, 60, 70, 80, 90, 99};
    for (size_t k = 0; k < sizeof show / sizeof *show; ++k) {
        int i = show[k];
        double r = (i + 0.5) * DR_MM, model = dm_dipole(0.01, sp, 1.0, r);
        fprintf(f, "| %.3f | %.4e | %.1e | %.4e | %.3f |\n", r, rd_r[i], rd_r_se[i], model, model / rd_r[i]);
    }
    fprintf(f, "\nEnergy (Rsp + Rd + Tt + ΣA + unfinished − 1) of the skin-like stack: %.1e.\n",
            res[3].r.specular + res[3].r.diffuse_reflectance + res[3].r.transmittance + res[3].r.absorbed[0] +
                res[3].r.absorbed[1] + res[3].r.absorbed[2] + res[3].r.unfinished - 1.0);
    fclose(f);
    return 0;
}
