#include "core/dm_sh.h"

void dm_sh9_basis(const double d[3], double y[DM_SH9_COUNT])
{
    const double x = d[0], yy = d[1], z = d[2];
    y[0] = 0.28209479177387814;
    y[1] = 0.48860251190291992 * yy;
    y[2] = 0.48860251190291992 * z;
    y[3] = 0.48860251190291992 * x;
    y[4] = 1.0925484305920792 * x * yy;
    y[5] = 1.0925484305920792 * yy * z;
    y[6] = 0.31539156525252005 * (3.0 * z * z - 1.0);
    y[7] = 1.0925484305920792 * x * z;
    y[8] = 0.54627421529603959 * (x * x - yy * yy);
}

void dm_sh9_irradiance(const double sh[DM_SH9_COUNT][3], const double n[3], double e[3])
{
    static const double a[DM_SH9_COUNT] = {DM_SH_A0, DM_SH_A1, DM_SH_A1, DM_SH_A1, DM_SH_A2,
                                           DM_SH_A2, DM_SH_A2, DM_SH_A2, DM_SH_A2};
    double y[DM_SH9_COUNT];
    dm_sh9_basis(n, y);
    for (int c = 0; c < 3; ++c) {
        double s = 0.0;
        for (int k = 0; k < DM_SH9_COUNT; ++k) s += a[k] * sh[k][c] * y[k];
        e[c] = s;
    }
}
