/* edge_table.h — the screen-space technique's albedo edge against the profile's (issue #29;
 * tests/common/edge_plate.h renders and measures it): a Markdown section for bench/accuracy.c's
 * report and bench/ss_edge.c. Needs a current GL context. Header-only. */
#ifndef BENCH_EDGE_TABLE_H
#define BENCH_EDGE_TABLE_H

#include <stdio.h>

#include "../../tests/common/edge_plate.h"

/* Writes the section into md; returns 0, or −1 after saying on stderr what failed. */
static inline int edge_table(FILE *md)
{
    static const int taps[] = {11, 17, 25};
    static const struct {
        double mm_per_px;
        const char *what;
    } scales[] = {{0.075, "the issue's close-up"}, {0.1, "close up"}, {0.34, "`make demo` (lps.json) on the face"},
                  {0.75, "lps-screen-space.json on the face"}};
    fprintf(md, "\n## Screen-space edge response\n\nA flat plate with an albedo step (sRGB %d,%d,%d to %d,%d,%d: a dark "
                "mole on skin) under one directional light, screen-space technique, gems3-skin, mix 0.5, at a given "
                "size of pixel (`tests/common/edge_plate.h`), against the profile's own edge computed in double "
                "precision: E·A^(1−mix)·(a₀^mix + (a₁^mix − a₀^mix)·ESF(x)), ESF the integral of the profile's "
                "line-spread function (its marginal). Largest error over a row, in %% of the step, R / G / B. "
                "The kernels are one per size of pixel, near taps on whole pixels weighing the line-spread "
                "function's mass over each (`lib/core/dm_ssss_kernel.h`, since issue #29 point 4); before, one "
                "kernel of the line-spread function's bin masses at Jimenez's taps gave at 17 taps 3.49 / 5.22 / "
                "6.73 %% at 0.075 mm/px, 2.69 / 2.71 / 3.36 %% at 0.1, 1.20 / 0.93 / 2.49 %% at 0.34 and 0.54 / "
                "2.96 / 3.52 %% at 0.75, and the rank-1 factor of the 2-D profile before issue #29 8.18 / 4.40 / "
                "4.50 %% at 0.1 (the red edge half as wide as the profile's). `tests/render/test_render_ss_edge.c` "
                "holds 17 taps to 2 %% at 0.075 and 0.1 mm/px and 1 %% at 0.34 and 0.75. Bench: `bench/ss_edge.c` "
                "writes this section ""alone (`ss_edge.md`), in a second.\n\n"
                "| taps | mm per pixel | where | largest error %% R / G / B |\n|---:|---:|---|---:|\n",
            edge_plate_lo[0], edge_plate_lo[1], edge_plate_lo[2], edge_plate_hi[0], edge_plate_hi[1], edge_plate_hi[2]);
    for (size_t t = 0; t < sizeof taps / sizeof taps[0]; ++t)
        for (size_t s = 0; s < sizeof scales / sizeof scales[0]; ++s) {
            double err[3];
            char msg[256];
            if (edge_plate_error(scales[s].mm_per_px, taps[t], err, msg, sizeof msg) != 0) {
                fprintf(stderr, "error: edge: %s\n", msg);
                return -1;
            }
            fprintf(md, "| %d | %.3g | %s | %.2f / %.2f / %.2f |\n", taps[t], scales[s].mm_per_px, scales[s].what,
                    100 * err[0], 100 * err[1], 100 * err[2]);
        }
    return 0;
}

#endif
