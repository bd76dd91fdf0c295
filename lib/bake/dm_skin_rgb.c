/* dm_skin_rgb.c — spectrum to linear sRGB under D65 (dm_skin_rgb.h). */
#include "bake/dm_skin_rgb.h"

/* IEC 61966-2-1: XYZ (D65) to linear sRGB. */
static const double srgb_from_xyz[3][3] = {
    {3.2406, -1.5372, -0.4986},
    {-0.9689, 1.8758, 0.0415},
    {0.0557, -0.2040, 1.0570},
};

/* x̄ S, ȳ S, z̄ S per wavelength over Σ ȳ S (Δλ cancels). */
static void xyz_weights(double wx[DM_SKIN_LAMBDA_COUNT][3])
{
    double norm = 0.0;
    for (int i = 0; i < DM_SKIN_LAMBDA_COUNT; ++i) norm += dm_skin_data[i].d65 * dm_skin_data[i].cie_y;
    for (int i = 0; i < DM_SKIN_LAMBDA_COUNT; ++i) {
        const dm_skin_data_row *row = &dm_skin_data[i];
        wx[i][0] = row->d65 * row->cie_x / norm;
        wx[i][1] = row->d65 * row->cie_y / norm;
        wx[i][2] = row->d65 * row->cie_z / norm;
    }
}

static void unscaled_weights(double w[DM_SKIN_LAMBDA_COUNT][3])
{
    double wx[DM_SKIN_LAMBDA_COUNT][3];
    xyz_weights(wx);
    for (int i = 0; i < DM_SKIN_LAMBDA_COUNT; ++i)
        for (int c = 0; c < 3; ++c)
            w[i][c] = srgb_from_xyz[c][0] * wx[i][0] + srgb_from_xyz[c][1] * wx[i][1] + srgb_from_xyz[c][2] * wx[i][2];
}

void dm_skin_rgb_white_scale(double scale[3])
{
    double w[DM_SKIN_LAMBDA_COUNT][3], white[3] = {0, 0, 0};
    unscaled_weights(w);
    for (int i = 0; i < DM_SKIN_LAMBDA_COUNT; ++i)
        for (int c = 0; c < 3; ++c) white[c] += w[i][c];
    for (int c = 0; c < 3; ++c) scale[c] = 1.0 / white[c];
}

void dm_skin_rgb_weights(double w[DM_SKIN_LAMBDA_COUNT][3])
{
    double scale[3];
    dm_skin_rgb_white_scale(scale);
    unscaled_weights(w);
    for (int i = 0; i < DM_SKIN_LAMBDA_COUNT; ++i)
        for (int c = 0; c < 3; ++c) w[i][c] *= scale[c];
}

/* out = Σ_λ w[λ] · reflectance[λ], three channels. */
static void weigh(const double w[DM_SKIN_LAMBDA_COUNT][3], const double *reflectance, double out[3])
{
    out[0] = out[1] = out[2] = 0.0;
    for (int i = 0; i < DM_SKIN_LAMBDA_COUNT; ++i)
        for (int c = 0; c < 3; ++c) out[c] += w[i][c] * reflectance[i];
}

void dm_skin_spectrum_to_xyz(const double *reflectance, double xyz[3])
{
    double wx[DM_SKIN_LAMBDA_COUNT][3];
    xyz_weights(wx);
    weigh((const double(*)[3])wx, reflectance, xyz);
}

void dm_skin_spectrum_to_rgb(const double *reflectance, double rgb[3])
{
    double w[DM_SKIN_LAMBDA_COUNT][3];
    dm_skin_rgb_weights(w);
    weigh((const double(*)[3])w, reflectance, rgb);
}
