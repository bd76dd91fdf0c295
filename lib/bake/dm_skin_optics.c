/* dm_skin_optics.c — skin parameters and their optics per wavelength (dm_skin_optics.h). */
#include "bake/dm_skin_optics.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bake/dm_skin_data.h"

dm_skin_params dm_skin_params_default(void)
{
    return (dm_skin_params){.melanin_fraction = 0.005,
                            .eumelanin_blend = 0.7,
                            .blood_fraction = 0.005,
                            .oxygenation = 0.75,
                            .epidermis_mm = 0.25,
                            .dermis_mm = 0.0,
                            .eta = 1.4};
}

typedef struct preset {
    const char *name;
    double cm, beta, ch, epidermis_mm;
} preset;
/* DJ2006's exemplars (their 0.25 mm epidermis), then a Fitzpatrick gallery that is our own
 * mapping (no paper tabulates Fitzpatrick I–VI parameters): spread over the NIST forearm
 * cohort (100 subjects), I near its top and VI near its bottom at 450, 550 and 650 nm, in the
 * forearm's measured epidermis (Sandby-Møller, Poulsen & Wulf 2003: 18 µm stratum corneum +
 * 57 µm cellular epidermis = 0.075 mm); melanosome fractions geometric from 0.6 % to 4.2 %
 * (×1.48 a type), inside Jacques' (1998) light-adult band 1.3–6.3 % from III on, and by
 * Jacques' law at 694 nm 0.11–0.79 mm⁻¹ of epidermal absorption, Norvang et al.'s (1997)
 * measured Caucasian and Asian range 0.3–1.2 mm⁻¹ from IV on. Eumelanin share and blood as
 * the default. docs/skin-model.md: the totals beside the cohort, and why not DJ2006's
 * 0.25 mm (the cohort's band is then spanned by Cm 0.006–0.016 at 450 nm and red leaves it
 * first). */
static const preset presets[] = {
    {"caucasian", 0.005, 0.7, 0.005, 0.25},       {"asian", 0.15, 0.0, 0.01, 0.25},
    {"african", 0.5, 0.7, 0.05, 0.25},            {"fitzpatrick-1", 0.006, 0.7, 0.005, 0.075},
    {"fitzpatrick-2", 0.009, 0.7, 0.005, 0.075},  {"fitzpatrick-3", 0.013, 0.7, 0.005, 0.075},
    {"fitzpatrick-4", 0.019, 0.7, 0.005, 0.075},  {"fitzpatrick-5", 0.028, 0.7, 0.005, 0.075},
    {"fitzpatrick-6", 0.042, 0.7, 0.005, 0.075},
};
enum { PRESET_COUNT = sizeof presets / sizeof presets[0] };

dm_result dm_skin_preset(const char *name, dm_skin_params *p, dm_error *err)
{
    for (int i = 0; i < PRESET_COUNT; ++i) {
        if (strcmp(name, presets[i].name) != 0) continue;
        *p = dm_skin_params_default();
        p->melanin_fraction = presets[i].cm;
        p->eumelanin_blend = presets[i].beta;
        p->blood_fraction = presets[i].ch;
        p->epidermis_mm = presets[i].epidermis_mm;
        return DM_OK;
    }
    return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                   "skin preset '%s': unknown, expected caucasian, asian, african or fitzpatrick-1 … fitzpatrick-6",
                   name);
}

const char *dm_skin_preset_name(int index)
{
    return index >= 0 && index < PRESET_COUNT ? presets[index].name : NULL;
}

static dm_result in_range(double v, double lo, double hi, const char *what, const char *field, const char *extra,
                          dm_error *err)
{
    if (isfinite(v) && v >= lo && v <= hi) return DM_OK;
    return dm_fail(err, isfinite(v) ? DM_ERR_RANGE : DM_ERR_NON_FINITE, "%s: %s = %g, expected a value in [%g, %g]%s",
                   what, field, v, lo, hi, extra);
}

dm_result dm_skin_params_validate(const dm_skin_params *p, const char *what, dm_error *err)
{
    dm_result r;
    if ((r = in_range(p->melanin_fraction, 0.0, DM_SKIN_MELANIN_MAX, what, "melanin_fraction (melanin, Cm)", "", err)) ||
        (r = in_range(p->eumelanin_blend, 0.0, 1.0, what, "eumelanin_blend (eumelanin, betam)", "", err)) ||
        (r = in_range(p->blood_fraction, 0.0, DM_SKIN_BLOOD_MAX, what, "blood_fraction (blood, Ch)", "", err)) ||
        (r = in_range(p->oxygenation, 0.0, 1.0, what, "oxygenation (gamma)", "", err)) ||
        (r = in_range(p->epidermis_mm, DM_SKIN_EPIDERMIS_MIN_MM, DM_SKIN_EPIDERMIS_MAX_MM, what, "epidermis_mm (epidermis-mm)", "",
                      err)) ||
        (r = in_range(p->eta, DM_SKIN_ETA_MIN, DM_SKIN_ETA_MAX, what, "eta", "", err)))
        return r;
    if (p->dermis_mm != 0.0)
        return in_range(p->dermis_mm, DM_SKIN_DERMIS_MIN_MM, DM_SKIN_DERMIS_MAX_MM, what, "dermis_mm (dermis-mm)",
                        " or 0 (semi-infinite)", err);
    return DM_OK;
}

double dm_skin_eumelanin_sigma_a(double lambda_nm)
{
    return 6.6e10 * pow(lambda_nm, -3.33);
}

double dm_skin_pheomelanin_sigma_a(double lambda_nm)
{
    return 2.9e14 * pow(lambda_nm, -4.75);
}

double dm_skin_baseline_sigma_a(double lambda_nm)
{
    return 0.0244 + 8.53 * exp(-(lambda_nm - 154.0) / 66.2);
}

/* Whole blood: 150 g/L of hemoglobin, 64 500 g/mol; ε in cm⁻¹/M gives cm⁻¹, ÷10 mm⁻¹. */
double dm_skin_blood_sigma_a(double molar_ext_per_cm_per_molar)
{
    return log(10.0) * molar_ext_per_cm_per_molar * 150.0 / 64500.0 / 10.0;
}

double dm_skin_scattering(double lambda_nm)
{
    return 14.74 * pow(lambda_nm, -0.22) + 2.2e11 * pow(lambda_nm, -4.0);
}

void dm_skin_optics_at(const dm_skin_params *p, int lambda_index, dm_skin_optics *out)
{
    assert(lambda_index >= 0 && lambda_index < DM_SKIN_LAMBDA_COUNT);
    const dm_skin_data_row *row = &dm_skin_data[lambda_index];
    double l = row->lambda_nm, base = dm_skin_baseline_sigma_a(l), s = dm_skin_scattering(l);
    double mel = p->eumelanin_blend * dm_skin_eumelanin_sigma_a(l) +
                 (1.0 - p->eumelanin_blend) * dm_skin_pheomelanin_sigma_a(l);
    double blood = p->oxygenation * dm_skin_blood_sigma_a(row->hbo2_molar_ext) +
                   (1.0 - p->oxygenation) * dm_skin_blood_sigma_a(row->hb_molar_ext);
    out->lambda_nm = l;
    out->epidermis_sigma_a = p->melanin_fraction * mel + (1.0 - p->melanin_fraction) * base;
    out->epidermis_sigma_s_prime = s;
    out->dermis_sigma_a = p->blood_fraction * blood + (1.0 - p->blood_fraction) * base;
    out->dermis_sigma_s_prime = 0.5 * s;
}
