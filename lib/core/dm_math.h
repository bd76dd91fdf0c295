/* dm_math.h — constants (strict C11 hides M_PI) and tiny inline helpers. */
#ifndef DM_MATH_H
#define DM_MATH_H

#include <math.h>
#include <stddef.h>

#define DM_PI 3.14159265358979323846
#define DM_PI_2 1.57079632679489661923
#define DM_2PI 6.28318530717958647693
#define DM_SQRT2 1.41421356237309504880

static inline double dm_clamp(double x, double lo, double hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}
static inline float dm_clampf(float x, float lo, float hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

/* How many of count floats are NaN or infinite; *first (may be NULL) receives the index of
 * the first of them (count when none). Writers of pictures call it before writing. */
static inline size_t dm_count_nonfinite(const float *values, size_t count, size_t *first)
{
    size_t bad = 0, at = count;
    for (size_t i = 0; i < count; ++i)
        if (!isfinite(values[i])) {
            if (!bad) at = i;
            ++bad;
        }
    if (first) *first = at;
    return bad;
}

#endif
