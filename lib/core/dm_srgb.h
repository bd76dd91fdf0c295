/* dm_srgb.h — the sRGB transfer curve (IEC 61966-2-1), both ways, in double precision: one
 * copy for the bakers, the reference and the renderer's comparison pictures. */
#ifndef DM_SRGB_H
#define DM_SRGB_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The exact decoding curve: encoded c in [0, 1] to linear, c/12.92 up to 0.04045, then
 * ((c + 0.055)/1.055)^2.4. */
double dm_srgb_to_linear(double c);
/* Linear c to an 8-bit code: clamped to [0, 1] (NaN to 0), encoded, round(255 e). */
uint8_t dm_srgb8_from_linear(double c);

#ifdef __cplusplus
}
#endif
#endif
