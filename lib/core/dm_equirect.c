#include "core/dm_equirect.h"

#include <math.h>

#include "core/dm_math.h"

void dm_equirect_dir(double u, double v, double d[3])
{
    double phi = DM_2PI * (u - 0.5);
    double theta = DM_PI * (1.0 - dm_clamp(v, 0.0, 1.0));
    double s = sin(theta);
    d[0] = s * sin(phi);
    d[1] = cos(theta);
    d[2] = -s * cos(phi);
}

void dm_equirect_uv(const double d[3], double *u, double *v)
{
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double y = len > 0.0 ? dm_clamp(d[1] / len, -1.0, 1.0) : 1.0;
    double uu = atan2(d[0], -d[2]) / DM_2PI + 0.5;
    *u = uu >= 1.0 ? 0.0 : uu; /* atan2 gives [−π, π]: u = 1 is the same seam as u = 0 */
    *v = 1.0 - acos(y) / DM_PI;
}

double dm_equirect_texel_solid_angle(int j, int width, int height)
{
    double theta_top = DM_PI * (1.0 - (double)(j + 1) / height);
    double theta_bottom = DM_PI * (1.0 - (double)j / height);
    return DM_2PI / width * (cos(theta_top) - cos(theta_bottom));
}
