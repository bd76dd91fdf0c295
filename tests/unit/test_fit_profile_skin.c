/* dermis-fit-profile --skin / --skin-preset as a user runs it (the physical skin of
 * bake/dm_skin_profile.h as a profile source), and the library source behind it
 * (dm_profile_source_skin): every preset fits and reads back, the table's error does not
 * rise with N, bad parameters are usage errors naming the parameter and its range, the hard
 * cases, and a sweep over the whole range. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/expect_tool.h"
#include "../common/tmpdir.h"
#include "bake/dm_profile_fit.h"
#include "bake/dm_profile_tsv.h"
#include "bake/dm_skin_spec.h"
#include "core/dm_profile.h"

#define BIN DERMIS_BIN "/dermis-fit-profile"

/* Reads back what the tool wrote and checks what every skin profile must hold. */
static void check_written(const char *path, const char *what)
{
    dm_profile p;
    dm_error err = {0};
    cr_assert_eq(dm_profile_read(path, &p, &err), DM_OK, "%s: %s", what, err.detail);
    for (int k = 0; k < p.count; ++k)
        for (int c = 0; c < 3; ++c)
            cr_assert(isfinite(p.weight[k][c]) && p.weight[k][c] >= 0.0, "%s: weight[%d][%d] = %g", what, k, c,
                      p.weight[k][c]);
    char *json = test_slurp(path);
    cr_assert(json && strstr(json, "\"model\": \"skin\"") && strstr(json, "\"melanin_fraction\"") &&
                  strstr(json, "\"skin_total_reflectance_r\"") && strstr(json, "\"provenance\""),
              "%s: %s", what, json);
    free(json);
}

Test(fit_profile_skin, every_preset_fits, .timeout = 60)
{
    char dir[64], cmd[1024], path[256];
    cr_assert(test_tmpdir(dir, sizeof dir));
    int count = 0;
    for (int i = 0; dm_skin_preset_name(i); ++i, ++count) {
        const char *name = dm_skin_preset_name(i);
        snprintf(path, sizeof path, "%s/%s.json", dir, name);
        snprintf(cmd, sizeof cmd, BIN " --skin-preset %s -o %s --quiet", name, path);
        cr_assert_eq(test_run(cmd, NULL), 0, "%s", cmd);
        check_written(path, name);
    }
    cr_assert_eq(count, 9, "three DJ2006 exemplars and six Fitzpatrick types");
    /* the list names them all, with their parameters as --skin takes them */
    char log[256];
    snprintf(log, sizeof log, "%s/list", dir);
    cr_assert_eq(test_run(BIN " --list-presets", log), 0);
    char *out = test_slurp(log);
    cr_assert(out && strstr(out, "fitzpatrick-6") && strstr(out, "african") && strstr(out, "melanin=0.042,"), "%s", out);
    free(out);
}

/* --skin with a preset's parameters is the preset: same bytes but for the names. */
Test(fit_profile_skin, skin_spec_equals_the_preset)
{
    dm_skin_params p;
    cr_assert_eq(dm_skin_preset("fitzpatrick-3", &p, NULL), DM_OK);
    char spec[512], back[512];
    dm_skin_spec_format(&p, 17, spec, sizeof spec);
    dm_skin_params q;
    dm_error err = {0};
    cr_assert_eq(dm_skin_spec_parse(spec, "test", &q, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(memcmp(&p, &q, sizeof p), 0, "the spec does not read back exactly: %s", spec);
    dm_skin_spec_format(&q, 17, back, sizeof back);
    cr_assert_str_eq(spec, back);
}

/* The fit minimises Σ_c e_c² (dm_profile_fit.h); N + 1 Gaussians can hold N's solution
 * (one weight zero), so the optimum cannot rise with N: the table's Σ err_c² is held
 * non-increasing, to 1e-3 relative (the Levenberg–Marquardt search stops short of the
 * exact optimum; per channel, and err_max, may rise slightly: Asian green 0.4345 → 0.4346). */
Test(fit_profile_skin, table_error_does_not_rise_with_n, .timeout = 60)
{
    const char *presets[3] = {"caucasian", "asian", "fitzpatrick-4"};
    char dir[64], log[256], cmd[512];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(log, sizeof log, "%s/log", dir);
    for (int j = 0; j < 3; ++j) {
        snprintf(cmd, sizeof cmd, BIN " --skin-preset %s --table", presets[j]);
        cr_assert_eq(test_run(cmd, log), 0);
        char *out = test_slurp(log), *line = strchr(out, '\n');
        double prev = INFINITY;
        int rows = 0;
        while (line && line[1]) {
            int n, passes;
            double e[4];
            if (sscanf(line + 1, "%d %d %lf %lf %lf %lf", &n, &passes, &e[0], &e[1], &e[2], &e[3]) != 6) break;
            double sum = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
            cr_assert(isfinite(sum) && sum <= prev * (1.0 + 1e-3), "%s N %d: Σ err² %.6g after %.6g", presets[j], n,
                      sum, prev);
            prev = fmin(prev, sum);
            ++rows;
            line = strchr(line + 1, '\n');
        }
        cr_assert_eq(rows, DM_PROFILE_MAX_GAUSSIANS, "%s: %s", presets[j], out);
        free(out);
    }
}

Test(fit_profile_skin, bad_parameters_are_usage_errors_naming_the_parameter)
{
    char dir[64], log[256];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(log, sizeof log, "%s/log", dir);
    const test_usage_case bad[] = {
        {"--skin melanin=0.6,eumelanin=0.7,blood=0.01", "melanin_fraction (melanin, Cm) = 0.6, expected a value in [0, 0.5]"},
        {"--skin melanin=0.1,eumelanin=1.5,blood=0.01", "eumelanin_blend (eumelanin, betam) = 1.5, expected a value in [0, 1]"},
        {"--skin melanin=0.1,eumelanin=0.5,blood=-0.01", "blood_fraction (blood, Ch) = -0.01, expected a value in [0, 0.1]"},
        {"--skin melanin=0.1,eumelanin=0.5,blood=0.01,oxygenation=2", "oxygenation (gamma) = 2"},
        {"--skin melanin=0.1,eumelanin=0.5,blood=0.01,epidermis-mm=0", "epidermis_mm (epidermis-mm) = 0, expected a value in [0.001, 2]"},
        {"--skin melanin=0.1,eumelanin=0.5,blood=0.01,dermis-mm=0.05", "dermis_mm (dermis-mm) = 0.05"},
        {"--skin melanin=0.1,eumelanin=0.5,blood=0.01,eta=3", "eta = 3"},
        {"--skin melanin=nan,eumelanin=0.5,blood=0.01", "melanin_fraction (melanin, Cm) = nan"},
        {"--skin melanin=0.1,blood=0.01", "'eumelanin' is required"},
        {"--skin melanin=0.1,eumelanin=x,blood=0.01", "eumelanin = 'x', expected a number"},
        {"--skin melanin=0.1,eumelanin=0.5,blood=0.01,hair=1", "unknown key 'hair'"},
        {"--skin melanin=0.1,melanin=0.2,eumelanin=0.5,blood=0.01", "'melanin' given twice"},
        {"--skin melanin", "not key=value"},
        {"--skin-preset martian", "fitzpatrick-1"},
        {"--skin-preset caucasian --dipole skin1", "exclude"},
        {"--list-presets --skin-preset caucasian", "--list-presets"},
    };
    test_expect_usage_errors(BIN, dir, bad, sizeof bad / sizeof bad[0]);
    cr_expect_eq(test_count_files(dir, "x.json"), 0, "an output was written despite the error");
}

/* ---- the library source: hard cases and a sweep ---- */

static void fits(const dm_skin_params *p, int n, const char *what)
{
    dm_profile_source src;
    dm_error err = {0};
    cr_assert_eq(dm_profile_source_skin(p, &src, &err), DM_OK, "%s: %s", what, err.detail);
    double total[3];
    dm_profile_source_total(&src, total);
    dm_fit_options fo = {.gaussian_count = n};
    dm_fit_result fr;
    cr_assert_eq(dm_profile_fit(&src, &fo, what, &fr, &err), DM_OK, "%s: %s", what, err.detail);
    cr_assert_eq(dm_profile_validate(&fr.profile, what, &err), DM_OK, "%s: %s", what, err.detail);
    for (int c = 0; c < 3; ++c) {
        cr_assert(isfinite(total[c]) && total[c] > -0.05 && total[c] < 1.0, "%s: total[%d] = %g", what, c, total[c]);
        cr_assert(isfinite(fr.error_relative[c]) && fr.error_relative[c] >= 0.0, "%s: error[%d] %g", what, c,
                  fr.error_relative[c]);
        for (int k = 0; k < fr.profile.count; ++k)
            cr_assert(isfinite(fr.profile.weight[k][c]) && fr.profile.weight[k][c] >= 0.0, "%s: weight[%d][%d] = %g",
                      what, k, c, fr.profile.weight[k][c]);
    }
}

Test(fit_profile_skin, hard_cases, .timeout = 60)
{
    dm_skin_params p = dm_skin_params_default();
    p.melanin_fraction = 0.0, fits(&p, 6, "melanin 0");
    p.melanin_fraction = 0.5, fits(&p, 6, "melanin 0.5");
    p = dm_skin_params_default(), p.blood_fraction = 0.0, fits(&p, 6, "blood 0");
    p.blood_fraction = 1e-6, fits(&p, 6, "blood 1e-6");
    /* thinner than a transport mean free path (≥ 0.1 mm at every λ): the closed form */
    p = dm_skin_params_default(), p.epidermis_mm = 0.01, fits(&p, 6, "epidermis 0.01 mm");
    p.epidermis_mm = 0.001, fits(&p, 6, "epidermis 0.001 mm");
}

Test(fit_profile_skin, sweep_whole_range, .timeout = 240)
{
    const double cm[3] = {0.0, 0.1, 0.5}, ch[3] = {0.0, 0.02, 0.1}, epi[3] = {0.001, 0.25, 2.0};
    int count = 0;
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c)
            for (int e = 0; e < 3; ++e) {
                int alt = (a + c + e) % 2; /* the other two-level parameters alternate */
                dm_skin_params p = {cm[a], alt ? 1.0 : 0.0, ch[c], alt ? 0.0 : 1.0, epi[e], alt ? 0.1 : 0.0, 1.4};
                char what[128];
                snprintf(what, sizeof what, "Cm %g βm %g Ch %g γ %g epi %g dermis %g", p.melanin_fraction,
                         p.eumelanin_blend, p.blood_fraction, p.oxygenation, p.epidermis_mm, p.dermis_mm);
                fits(&p, 4, what);
                ++count;
            }
    cr_assert_eq(count, 27);
}

/* The source's total is the exact colorimetric one, R̃_c(0) summed over the wavelengths, for
 * every preset: what dm_skin_profile_fit reports, to the bit. The dense representation's weight
 * sums are not, where the epidermis takes the closed form (its unspread light, a flat
 * transform, makes them overshoot): the African exemplar's are about twice the total. The colour
 * from the skin (material.albedo_from) and every printed total take the exact one. */
Test(fit_profile_skin, source_total_is_the_exact_colorimetric_total, .timeout = 60)
{
    for (int i = 0; dm_skin_preset_name(i); ++i) {
        const char *name = dm_skin_preset_name(i);
        dm_skin_params p;
        dm_error err = {0};
        cr_assert_eq(dm_skin_preset(name, &p, &err), DM_OK);
        dm_profile_source src;
        cr_assert_eq(dm_profile_source_skin(&p, &src, &err), DM_OK, "%s", err.detail);
        dm_skin_report rep, phys;
        dm_profile fitted;
        cr_assert_eq(dm_skin_profile_fit(&p, NULL, name, &fitted, &rep, &err), DM_OK, "%s", err.detail);
        cr_assert_eq(dm_skin_physics_report(&p, 0, &phys, &err), DM_OK, "%s", err.detail);
        double total[3], dense[3];
        dm_profile_source_total(&src, total);
        dm_skin_dense_total(&src.skin_dense, dense);
        for (int c = 0; c < 3; ++c) {
            cr_assert_eq(total[c], rep.total_rgb[c], "%s channel %d: %.17g vs %.17g", name, c, total[c], rep.total_rgb[c]);
            cr_assert_eq(phys.total_rgb[c], rep.total_rgb[c], "%s channel %d", name, c);
            if (!strcmp(name, "african"))
                cr_expect(dense[c] > 1.5 * total[c], "%s channel %d: dense sums %.4f, total %.4f", name, c, dense[c], total[c]);
            if (!strcmp(name, "caucasian"))
                cr_expect(fabs(dense[c] - total[c]) < 1e-5, "%s channel %d: %.7f vs %.7f", name, c, dense[c], total[c]);
        }
    }
}

/* --radial and --spectrum: tables for plots, with their provenance, whose numbers are the
 * source's (the radial total over 0.01-20 mm by the trapezoid in ln r is within 2 % of the
 * exact total for the Caucasian exemplar, whose light leaves between 0.05 and 5 mm — not for
 * the gallery's thin epidermis, whose unspread light, 10–25 % of it, returns within 0.01 mm;
 * the spectrum's colorimetric line is the JSON's total). */
Test(fit_profile_skin, radial_and_spectrum_tables, .timeout = 60)
{
    char dir[64], cmd[600], rad[128], spec[128], json[128];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(rad, sizeof rad, "%s/r.tsv", dir);
    snprintf(spec, sizeof spec, "%s/s.tsv", dir);
    snprintf(json, sizeof json, "%s/p.json", dir);
    snprintf(cmd, sizeof cmd, BIN " --skin-preset caucasian --radial %s --spectrum %s -o %s --quiet", rad, spec, json);
    cr_assert_eq(test_run(cmd, NULL), 0, "%s", cmd);
    char *r = test_slurp(rad), *s = test_slurp(spec), *j = test_slurp(json);
    cr_assert(r && s && j);
    cr_assert(!strncmp(r, "# provenance {\"tool\":\"dermis-fit-profile\"", 41) && strstr(r, "caucasian"), "%.200s", r);
    cr_assert(strstr(r, "\nr_mm\tsrc_r\tsrc_g\tsrc_b\tfit_r\tfit_g\tfit_b\n"));
    double total[3] = {0, 0, 0}, prev_r = 0, prev[3] = {0, 0, 0};
    int rows = 0;
    for (char *line = strtok(r, "\n"); line; line = strtok(NULL, "\n")) {
        double v[7];
        if (line[0] == '#' || sscanf(line, "%lf %lf %lf %lf %lf %lf %lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6]) != 7)
            continue;
        for (int c = 0; c < 3; ++c) {
            double m = 2 * 3.14159265358979323846 * v[0] * v[0] * v[1 + c]; /* per ln r */
            if (rows) total[c] += 0.5 * (m + prev[c]) * log(v[0] / prev_r);
            prev[c] = m;
        }
        prev_r = v[0];
        ++rows;
    }
    cr_assert_eq(rows, DM_PROFILE_TSV_RADIAL_ROWS);
    double want[3];
    const char *t = strstr(strstr(j, "\"source\""), "\"total_reflectance_rgb\": [");
    cr_assert(t && sscanf(t + 26, "%lf, %lf, %lf", &want[0], &want[1], &want[2]) == 3, "%s", j);
    for (int c = 0; c < 3; ++c)
        cr_expect(fabs(total[c] / want[c] - 1) < 0.02, "channel %d: %.4f over 0.01-20 mm, total %.4f", c, total[c], want[c]);
    int lines = 0;
    for (const char *p = strstr(s, "lambda_nm\ttotal\tflags\n"); p && *p; ++p) lines += *p == '\n';
    cr_expect_eq(lines, 1 + DM_SKIN_LAMBDA_COUNT + 1, "header, 31 rows, the colorimetric line: %s", s);
    double col[3];
    const char *c = strstr(s, "# colorimetric total, linear sRGB (D65): ");
    cr_assert(c && sscanf(c + 41, "%lf %lf %lf", &col[0], &col[1], &col[2]) == 3, "%s", s);
    for (int k = 0; k < 3; ++k) cr_expect(fabs(col[k] - want[k]) < 1e-8, "%.9g vs %.9g", col[k], want[k]);
    free(r), free(s), free(j);
    const test_usage_case bad[] = {
        {"--dipole skin1 --spectrum x.tsv", "--spectrum applies to --skin and --skin-preset only"},
        {"--skin-preset asian --radial x.txt", "--radial"},
    };
    test_expect_usage_errors(BIN, dir, bad, sizeof bad / sizeof bad[0]);
}
