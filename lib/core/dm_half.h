/* dm_half.h — IEEE 754 binary16 ("half", the 16f texture formats and EXR HALF channels) to
 * float. One copy for the pack, EXR and renderer readers. */
#ifndef DM_HALF_H
#define DM_HALF_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Exact for every half: zeros, subnormals (m · 2^−24), normals, ±Inf and NaN (payload kept). */
float dm_half_to_float(uint16_t h);

#ifdef __cplusplus
}
#endif

#endif
