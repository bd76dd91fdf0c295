/* The vendored skin tables (bake/dm_skin_data.h) against the rows SKIN-MODEL.md quotes, the
 * laws of bake/dm_skin_optics.h against its worked numbers, and the sRGB weights
 * (bake/dm_skin_rgb.h) against the D65 white point. */
#include <criterion/criterion.h>
#include <math.h>

#include "bake/dm_skin_data.h"
#include "bake/dm_skin_optics.h"
#include "bake/dm_skin_rgb.h"

static const dm_skin_data_row *row(double nm)
{
    int i = dm_skin_data_index(nm);
    cr_assert(i >= 0, "no row at %g nm", nm);
    return &dm_skin_data[i];
}

/* Exact: the table holds the sources' printed digits. */
Test(skin_data, hemoglobin_rows)
{
    const double want[3][3] = {{450, 62816, 103292}, {550, 43016, 53412}, {650, 368, 3750.12}};
    for (int k = 0; k < 3; ++k) {
        const dm_skin_data_row *r = row(want[k][0]);
        cr_assert(r->hbo2_molar_ext == want[k][1] && r->hb_molar_ext == want[k][2], "%g nm: %g %g", want[k][0],
                  r->hbo2_molar_ext, r->hb_molar_ext);
    }
}

Test(skin_data, cie_rows)
{
    const double want[3][4] = {{450, 0.3362, 0.038, 1.77211}, {550, 0.43345, 0.99495, 0.00875}, {650, 0.2835, 0.107, 0}};
    for (int k = 0; k < 3; ++k) {
        const dm_skin_data_row *r = row(want[k][0]);
        /* SKIN-MODEL.md prints 5 significant digits of the 10-digit table: half a unit of the 5th */
        cr_assert(fabs(r->cie_x - want[k][1]) <= 5e-6 && fabs(r->cie_y - want[k][2]) <= 5e-6 &&
                      fabs(r->cie_z - want[k][3]) <= 5e-6,
                  "%g nm: %.9f %.9f %.9f", want[k][0], r->cie_x, r->cie_y, r->cie_z);
    }
}

Test(skin_data, d65_rows)
{
    cr_assert_eq(row(560)->d65, 100.0);
    cr_assert_eq(row(450)->d65, 117.008);
    cr_assert_eq(row(650)->d65, 80.0268);
}

Test(skin_data, grid_and_index)
{
    for (int i = 0; i < DM_SKIN_LAMBDA_COUNT; ++i) {
        cr_assert_eq(dm_skin_data[i].lambda_nm, 400.0 + 10.0 * i);
        cr_assert_eq(dm_skin_data_index(dm_skin_data[i].lambda_nm), i);
    }
    cr_assert_eq(dm_skin_data_index(395), -1);
    cr_assert_eq(dm_skin_data_index(455), -1);
    cr_assert_eq(dm_skin_data_index(710), -1);
    cr_assert_eq(dm_skin_data_index(NAN), -1);
}

/* SKIN-MODEL.md: whole blood at 450/550/650 nm, HbO2 ≈ 33.6/23.0/0.20, Hb ≈ 55.3/28.6/2.0
 * mm⁻¹ (three digits: 0.5 % of each, or half the last digit for the small ones). */
Test(skin_data, blood_absorption)
{
    const double nm[3] = {450, 550, 650}, o2[3] = {33.6, 23.0, 0.20}, de[3] = {55.3, 28.6, 2.0};
    for (int k = 0; k < 3; ++k) {
        double a = dm_skin_blood_sigma_a(row(nm[k])->hbo2_molar_ext), b = dm_skin_blood_sigma_a(row(nm[k])->hb_molar_ext);
        cr_assert(fabs(a - o2[k]) <= fmax(0.005 * o2[k], 0.005), "HbO2 %g nm: %g", nm[k], a);
        cr_assert(fabs(b - de[k]) <= fmax(0.005 * de[k], 0.05), "Hb %g nm: %g", nm[k], b);
    }
}

/* DJ2006's σs′ ≈ 9.2/6.1/4.8 mm⁻¹ at 450/550/650 (two digits: ±0.05). */
Test(skin_data, scattering_law)
{
    const double nm[3] = {450, 550, 650}, want[3] = {9.2, 6.1, 4.8};
    for (int k = 0; k < 3; ++k) {
        double s = dm_skin_scattering(nm[k]);
        cr_assert(fabs(s - want[k]) <= 0.05, "%g nm: %g", nm[k], s);
    }
    /* Jacques' cm⁻¹ laws, ÷10: eumelanin 6.6e11 λ^−3.33, pheomelanin 2.9e15 λ^−4.75 cm⁻¹ */
    cr_assert(fabs(dm_skin_eumelanin_sigma_a(500) - 6.6e11 * pow(500, -3.33) / 10) < 1e-12 * dm_skin_eumelanin_sigma_a(500));
    cr_assert(fabs(dm_skin_pheomelanin_sigma_a(500) - 2.9e15 * pow(500, -4.75) / 10) <
              1e-12 * dm_skin_pheomelanin_sigma_a(500));
    cr_assert(fabs(dm_skin_baseline_sigma_a(154) - (0.0244 + 8.53)) < 1e-12);
}

/* A perfect white under D65 is the D65 white point XYZ = (0.95047, 1, 1.08883) (CIE 15):
 * the 10 nm sums land within 0.5 % of it, an independent check of the CIE and D65 tables
 * together; sRGB then maps it to (1, 1, 1) by construction, within 1 % before scaling. */
Test(skin_data, white_point)
{
    double white[DM_SKIN_LAMBDA_COUNT], xyz[3], rgb[3], scale[3];
    for (int i = 0; i < DM_SKIN_LAMBDA_COUNT; ++i) white[i] = 1.0;
    dm_skin_spectrum_to_xyz(white, xyz);
    cr_assert(fabs(xyz[0] - 0.95047) < 0.005 * 0.95047 && fabs(xyz[1] - 1.0) < 1e-12 &&
                  fabs(xyz[2] - 1.08883) < 0.005 * 1.08883,
              "XYZ %.5f %.5f %.5f", xyz[0], xyz[1], xyz[2]);
    dm_skin_spectrum_to_rgb(white, rgb);
    dm_skin_rgb_white_scale(scale);
    for (int c = 0; c < 3; ++c) {
        cr_assert(fabs(rgb[c] - 1.0) < 1e-12, "rgb[%d] = %.15f", c, rgb[c]);
        cr_assert(fabs(scale[c] - 1.0) < 0.01, "scale[%d] = %g", c, scale[c]);
    }
    /* the negative lobes the docs speak of: R below 550 nm, G at the blue end */
    double w[DM_SKIN_LAMBDA_COUNT][3];
    dm_skin_rgb_weights(w);
    cr_assert(w[dm_skin_data_index(500)][0] < 0.0 && w[dm_skin_data_index(450)][1] < 0.0);
}
