/* dm_srgb.c — the sRGB transfer curve (core/dm_srgb.h). */
#include "core/dm_srgb.h"

#include <math.h>

double dm_srgb_to_linear(double c)
{
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

uint8_t dm_srgb8_from_linear(double c)
{
    c = c > 0 ? (c < 1 ? c : 1) : 0; /* NaN → 0 */
    double e = c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
    return (uint8_t)lrint(e * 255.0);
}
