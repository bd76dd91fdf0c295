/* dm_skin_data.h — the measured tables the physical skin model needs, vendored as data.
 *
 * One wavelength grid for all of them: λ = 400, 410, …, 700 nm (DM_SKIN_LAMBDA_COUNT rows,
 * every 10 nm, the step CIE 15 allows for colorimetry of smooth spectra). The values are
 * the sources' own rows at those wavelengths, not interpolated.
 *
 *   Hemoglobin molar extinction ε (HbO2, Hb), cm⁻¹/M: Scott Prahl, "Tabulated molar
 *   extinction coefficient for hemoglobin in water" (Oregon Medical Laser Center, from
 *   W. B. Gratzer and N. Kollias), as published in the repository droumis/spectra,
 *   data_hb.csv (2 nm rows). Prahl's data are free to use with attribution: this is it.
 *   CIE 1931 2° standard observer x̄, ȳ, z̄ (1 nm table ciexyz31_1.csv, repository
 *   sergeyvladi88/colorimetry) and CIE standard illuminant D65 (relative, 100 at 560 nm;
 *   CIE_std_illum_D65.csv, repository
 *   JakeCambium/532nm-and-695nm-dualband-Cary-spectrophotometer-plotting): public CIE
 *   standards (CIE 15, ISO/CIE 11664-1 and -2).
 *
 * tests/unit/test_skin_data.c checks three rows of each against SKIN-MODEL.md's values.
 */
#ifndef DM_SKIN_DATA_H
#define DM_SKIN_DATA_H

#ifdef __cplusplus
extern "C" {
#endif

enum {
    DM_SKIN_LAMBDA_MIN_NM = 400,
    DM_SKIN_LAMBDA_STEP_NM = 10,
    DM_SKIN_LAMBDA_COUNT = 31 /* 400..700 nm */
};

typedef struct dm_skin_data_row {
    double lambda_nm;
    double hbo2_molar_ext, hb_molar_ext; /* ε, cm⁻¹/M (Prahl) */
    double cie_x, cie_y, cie_z;         /* CIE 1931 2° colour matching functions */
    double d65;                         /* CIE D65 relative spectral power, 100 at 560 nm */
} dm_skin_data_row;

/* The table, DM_SKIN_LAMBDA_COUNT rows, ascending λ. */
extern const dm_skin_data_row dm_skin_data[DM_SKIN_LAMBDA_COUNT];

/* The row index of λ (a grid wavelength to within 1e-9 nm), or −1. */
int dm_skin_data_index(double lambda_nm);

#ifdef __cplusplus
}
#endif
#endif
