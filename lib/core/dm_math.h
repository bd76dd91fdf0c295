/* dm_math.h — constants (strict C11 hides M_PI) and tiny inline helpers. */
#ifndef DM_MATH_H
#define DM_MATH_H

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

#endif
