/* bench/common/frame_rankings.h — bench/accuracy's instrument check (issue #27): the frame
 * reference's error bars, a ranking's margin against its own bar (measured again against the
 * transport references of frame_truth.h's steps), and the rankings that must hold. Header-only
 * like bench_util.h; included by accuracy_report.h. */
#ifndef BENCH_FRAME_RANKINGS_H
#define BENCH_FRAME_RANKINGS_H

#include <math.h>
#include <stdio.h>

#include "common/accuracy_rows.h"

/* The frame reference's own error bar in the transport run's normalised unit at these
 * settings, all channels and red: the sum of its terms' bounds (docs/dermis-reference.md,
 * Convergence, from bench/results/ref_convergence.md's measured steps):
 *   rays, 3² with --refine 8: the 2² -> 3² step at 1280x720 (12.3 %, red 5.4) extrapolated
 *     as 1/k² to 8²: 1.4 % (red 0.6); --refine's own departure from 8² everywhere, 0.008 %;
 *   atlas 8192 (TRANSPORT_ATLAS): second order, so what is left at 4096 is 4/3 of the
 *     4096 -> 8192 step (1.1 %, red 0.56) and at 8192 a third of it: 0.4 % (red 0.19);
 *   quadrature: the cut and spacing step, 0.12 % (red 0.13).
 * At atlas 4096 it was 3 % (red 1.5: the atlas 1.5), at 3² without --refine the rays alone
 * 8 % (red 3.5 %). A ranking's margin below it is not resolved; the issue asks five times it. */
#define FRAME_ERROR_BAR_RGB 0.019
#define FRAME_ERROR_BAR_RED 0.0093
/* The dipole's transport frame (the Gaussian-count rows' truth) at atlas 4096 without --refine:
 * its twelve Gaussians reach far (a frame at 3² takes twelve times the scene profile's), so the
 * rays' term is 3²'s, about 8 % (red 3.5), the atlas's 4096's 1.5 % (red 0.75), plus the
 * quadrature's. */
#define FRAME_ERROR_BAR_DIPOLE_RGB 0.096
#define FRAME_ERROR_BAR_DIPOLE_RED 0.044
/* A ranking's margin has a bar of its own: two rows measured against the same reference share
 * most of its error (a reference that is too bright somewhere raises both rows' errors there),
 * so the margin moves far less than either score. Each term of the bar above, for the margin:
 * how far the margin moves over a step of that term (frame_truth.h, FT_*), times what is
 * left of the term at the bench's settings per unit of the step, as the scores' own bounds
 * give it —
 *   rays, the scene profile's: 3² without --refine was ~8 % and is 1.4 % with --refine 8, so
 *     what is left is 1.4 per 6.6 of the step;
 *   rays, the dipole's (never refined): the 2² -> 3² step, of which 3² leaves 0.8 as 1/k²;
 *   atlas, the scene profile's: the 4096 x 2² -> 8192 x 1 step, of which 8192 leaves a third
 *     (second order: the step is 3e where e is what is left);
 *   atlas, the dipole's: the 2048 x 4² -> 4096 x 2² step, of which 4096 leaves 0.3 (1.5 % of
 *     the scores' 5.0 % step);
 *   quadrature: the whole step (cut 4 -> 6 sigma, spacing 0.3 -> 0.15 sigma), as the scores'
 *     bar takes it, measured at QUAD_ATLAS x QUAD_AS² with one ray at the pixel centre (the
 *     convergence table's setting for it: the step is the convolution's, not the atlas's);
 * — plus --refine's own bound (0.01 %), unmeasured for margins, taken whole for each of the
 * two rows where the truth is refined. */
#define MARGIN_RAYS_LEFT (1.4 / 6.6)
#define MARGIN_RAYS_LEFT_DIPOLE ((1.0 / 9) / (1.0 / 4 - 1.0 / 9))
#define MARGIN_ATLAS_LEFT (1.0 / 3.0)
#define MARGIN_ATLAS_LEFT_DIPOLE (1.5 / 5.0)
#define MARGIN_FIXED (2 * 0.0001)
/* A margin against an error bar: "resolved" (at least the bar), "resolved five times over"
 * (the standard: the bar at most a fifth of it) or "*not resolved*". */
static const char *margin_word(double m, double bar)
{
    return m >= 5 * bar ? "resolved five times over" : m >= bar ? "resolved (under five times the bar)" : "*not resolved*";
}

/* Whether rows a and b were both measured against their truth's pair of step k. */
static bool both_step(const row *a, const row *b, int k)
{
    return a->fr.stepok[k] && b->fr.stepok[k];
}

/* The bar of the margin between rows a and b (normalised units): its own where both were
 * measured against the references of every step (MARGIN_*), else the scores' bar `bar`. */
static double margin_bar(const row *a, const row *b, double bar)
{
    for (int k = 0; k < FT_STEP_COUNT; ++k)
        if (!both_step(a, b, k)) return bar;
    if (a->ft != b->ft) return bar;
    const double *ca = a->fr.step, *cb = b->fr.step;
    double m = a->fr.tr[REG_ALL].normalised_rgb - b->fr.tr[REG_ALL].normalised_rgb;
    double rays = ca[FT_COARSE_RAYS] - cb[FT_COARSE_RAYS] - m, atlas = ca[FT_COARSE_ATLAS] - cb[FT_COARSE_ATLAS] - m;
    double quad = (ca[FT_QUAD_FINE] - cb[FT_QUAD_FINE]) - (ca[FT_QUAD_BASE] - cb[FT_QUAD_BASE]);
    return a->ft->rays_left * fabs(rays) + a->ft->atlas_left * fabs(atlas) + fabs(quad) + a->ft->fixed;
}

/* The margins checked, for the table of close ones (margins_table). */
typedef struct checked_margin {
    const row *a, *b;
    double bar; /* the scores' bar */
} checked_margin;
static checked_margin margins[MAX_ROWS * 2];
static int nmargins;

/* "by M points: VERDICT (its bar B)" for the margin between a and b: the verdict against the
 * margin's own bar where it has one. */
static void margin_text(FILE *md, const row *a, const row *b, double bar)
{
    double m = fabs(a->fr.tr[REG_ALL].normalised_rgb - b->fr.tr[REG_ALL].normalised_rgb), mb = margin_bar(a, b, bar);
    fprintf(md, "by %.2f points: %s (%s bar %.2f)\n", 100 * m, margin_word(m, mb), mb == bar ? "the scores'" : "the margin's own",
            100 * mb);
    if (nmargins < (int)(sizeof margins / sizeof margins[0])) margins[nmargins++] = (checked_margin){a, b, bar};
}

/* The close margins (under ten times the scores' bar) against each reference: how far each
 * moves over each step, which is what its own bar is made of. */
static void margins_table(FILE *md)
{
    static const char *const step[FT_STEP_COUNT] = {"rays a step back", "atlas a step back", "quadrature: default",
                                                    "quadrature: finer"};
    fprintf(md, "\nThe close margins (under ten times the scores' bar) against each transport reference: the second "
                "row's score minus the first's, points (the bench's reference; the rays a step back: the scene "
                "profile's without `--refine`, the dipole's at %d²; the atlas a step back: the scene profile's at %d × "
                "%d², the dipole's at %d × %d²; the quadrature's pair at atlas %d × %d², one ray at the pixel centre, "
                "cut 4 σ and spacing 0.3 σ, then %g σ and %g σ):\n\n"
                "| rows | the bench's |",
            FRAME_PS - 1, TRANSPORT_ATLAS / 2, 2 * TRANSPORT_AS, FRAME_ATLAS / 2, 2 * FRAME_AS, QUAD_ATLAS, QUAD_AS,
            QUAD_CUT, QUAD_SPACING);
    for (int k = 0; k < FT_STEP_COUNT; ++k) fprintf(md, " %s |", step[k]);
    fprintf(md, " its own bar |\n|---|---:|---:|---:|---:|---:|---:|\n");
    for (int i = 0; i < nmargins; ++i) {
        const row *a = margins[i].a, *b = margins[i].b;
        double m = b->fr.tr[REG_ALL].normalised_rgb - a->fr.tr[REG_ALL].normalised_rgb;
        if (fabs(m) >= 10 * margins[i].bar || margin_bar(a, b, margins[i].bar) == margins[i].bar) continue;
        fprintf(md, "| %s, %s | %.3f |", a->s.name, b->s.name, 100 * m);
        for (int k = 0; k < FT_STEP_COUNT; ++k)
            if (both_step(a, b, k)) fprintf(md, " %.3f |", 100 * (b->fr.step[k] - a->fr.step[k]));
            else fprintf(md, " – |");
        fprintf(md, " %.3f |\n", 100 * margin_bar(a, b, margins[i].bar));
    }
}

/* The instrument's own test (issue #27), in the transport run (normalised over all channels):
 * no subsurface scores worse than every technique at the scene's settings (the rows marked
 * technique, against the same truth; the other settings are listed, as what the metric says
 * of them), more Gaussians never worse than fewer, and TSD 2048 <= 1024 <= 512. One line per
 * check, with its margin against the reference's error bar. */
static void frame_rankings(FILE *md, const row *rows)
{
    const row *flat = row_named(rows, "no subsurface");
    int bad = 0, checked = 0;
    fprintf(md, "\n**Rankings** (transport run, normalised over all channels). The reference's own error bar in this "
                "unit at these settings is %.1f %% of the signal (red %.2f %%): the sum of its terms' bounds "
                "(`docs/dermis-reference.md`, Convergence: %dx%d rays with `--refine %d`, atlas %d × %d², quadrature). "
                "A margin between two rows has a bar of its own, since both are measured against the same "
                "reference and share most of its error: the margin is measured again against transport references "
                "a step back in rays (no `--refine`) and in atlas (%d, %d² samples: the same irradiance points), each "
                "term being what is left of that step at the bench's settings (%.2f of the rays' step, %.2f of the "
                "atlas's: second order), plus the whole quadrature step (cut 4 → %g σ, spacing 0.3 → %g σ, at atlas "
                "%d × %d² and the pixel centre, as the convergence table measures it) and `--refine`'s bound for each "
                "row (%.2f points in all). Each margin is given in points and against its own bar (else the "
                "scores'): *not resolved* below it, *resolved* above it, *resolved five times over* where the bar is "
                "at most a fifth of it (the issue's standard).\n\n",
            100 * FRAME_ERROR_BAR_RGB, 100 * FRAME_ERROR_BAR_RED, FRAME_PS, FRAME_PS, FRAME_REFINE, TRANSPORT_ATLAS,
            TRANSPORT_AS, TRANSPORT_ATLAS / 2, 2 * TRANSPORT_AS, MARGIN_RAYS_LEFT, MARGIN_ATLAS_LEFT, QUAD_CUT,
            QUAD_SPACING, QUAD_ATLAS, QUAD_AS, 100 * MARGIN_FIXED);
    double f = flat ? frame_norm3(&flat->fr.tr[REG_ALL]) : 0;
    for (int pass = 0; flat && pass < 2; ++pass) {
        fprintf(md, pass ? "\nThe other settings against the floor (what the metric says of them; not a check):\n\n"
                         : "The techniques at the scene's settings or finer against the floor, no subsurface at %.2f %%:\n\n",
                100 * f);
        for (int c = 0; c < nrows; ++c) {
            if (&rows[c] == flat || !rows[c].fok || rows[c].ft != flat->ft || rows[c].s.technique_row != !pass) continue;
            double e = frame_norm3(&rows[c].fr.tr[REG_ALL]);
            if (!pass) ++checked, bad += !(e < f);
            fprintf(md, "- %s%s: %.2f %%, %s ", !pass && !(e < f) ? "**violated**: " : "", rows[c].s.name, 100 * e,
                    e < f ? "better" : "worse");
            margin_text(md, &rows[c], flat, FRAME_ERROR_BAR_RGB);
        }
        if (!pass) fprintf(md, "- no subsurface scores worse than each of these %d technique rows%s\n", checked,
                           bad ? ": NOT ALL (above)" : "");
    }
    char a[40], b[40];
    double prev = INFINITY;
    const row *best = NULL; /* the best of fewer Gaussians; the size before */
    int g_bad = 0, g_n = 0;
    bool fits = false; /* the Gaussian-count rows (DERMIS_BENCH_ROWS may leave them out) */
    for (int c = 0; c < nrows; ++c) fits |= fit_row(&rows[c].s);
    if (fits && dipole)
        fprintf(md, "\nMore Gaussians, against their own truth (the skin1 dipole's transport frame, %dx%d rays without "
                    "`--refine`, atlas %d × %d²: its scores' error bar %.1f %%, red %.1f %%; a margin's own bar as above, "
                    "the rays' step %d² → %d² with %.2f of it left, the atlas's %d × %d² → %d × %d² with %.2f):\n\n",
                FRAME_PS, FRAME_PS, FRAME_ATLAS, FRAME_AS, 100 * FRAME_ERROR_BAR_DIPOLE_RGB, 100 * FRAME_ERROR_BAR_DIPOLE_RED,
                FRAME_PS - 1, FRAME_PS, MARGIN_RAYS_LEFT_DIPOLE, FRAME_ATLAS / 2, 2 * FRAME_AS, FRAME_ATLAS, FRAME_AS,
                MARGIN_ATLAS_LEFT_DIPOLE);
    else if (fits) fprintf(md, "\nMore Gaussians, against gems3-skin:\n\n");
    for (int g = 1; g <= MAX_G; ++g) {
        const row *r = NULL;
        for (int B = 1024; B >= 256 && !r; B /= 2) snprintf(a, sizeof a, "%d G%d", B, g), r = row_named(rows, a);
        if (!r) continue;
        double e = frame_norm3(&r->fr.tr[REG_ALL]);
        if (prev == INFINITY) fprintf(md, "- %s: %.2f %%\n", a, 100 * e);
        else {
            fprintf(md, "- %s%s: %.2f %%, %s than the best of fewer ", e > prev * (1 + 1e-9) ? "**violated**: " : "", a, 100 * e,
                    e > prev ? "worse" : "better");
            margin_text(md, r, best, dipole ? FRAME_ERROR_BAR_DIPOLE_RGB : FRAME_ERROR_BAR_RGB);
        }
        g_bad += e > prev * (1 + 1e-9);
        if (e < prev) prev = e, best = r;
        ++g_n;
    }
    if (g_n) fprintf(md, "- more Gaussians never score worse than fewer (%d rows)%s\n", g_n, g_bad ? ": NOT SO (above)" : "");
    /* the fits also rendered at half the scene's size: listed, not checked */
    for (int g = 1; g <= MAX_G; ++g) {
        snprintf(a, sizeof a, "512 G%d", g), snprintf(b, sizeof b, "1024 G%d", g);
        const row *r = row_named(rows, a);
        if (r && row_named(rows, b))
            fprintf(md, "- at 512² (the pack's half-size maps, no seam map at that size; not a check): %s %.2f %%\n", a,
                    100 * frame_norm3(&r->fr.tr[REG_ALL]));
    }
    prev = INFINITY;
    int t_bad = 0, t_n = 0;
    fprintf(md, "\nTexture space by irradiance size:\n\n");
    for (int N = 256; N <= 2048; N *= 2) {
        snprintf(a, sizeof a, "%d", N), snprintf(b, sizeof b, "%d frame", N);
        const row *r = row_named(rows, a) ? row_named(rows, a) : row_named(rows, b);
        if (!r) continue;
        double e = frame_norm3(&r->fr.tr[REG_ALL]);
        if (prev == INFINITY) fprintf(md, "- TSD %d: %.2f %%\n", N, 100 * e);
        else {
            fprintf(md, "- %sTSD %d: %.2f %%, %s than %d ", e > prev * (1 + 1e-9) ? "**violated**: " : "", N, 100 * e,
                    e > prev ? "worse" : "better", N / 2);
            margin_text(md, r, best, FRAME_ERROR_BAR_RGB);
        }
        t_bad += e > prev * (1 + 1e-9);
        prev = e, best = r, ++t_n;
    }
    if (t_n > 1) fprintf(md, "- texture space: a larger irradiance never scores worse%s\n", t_bad ? ": NOT SO (above)" : "");
    margins_table(md);
}

#endif
