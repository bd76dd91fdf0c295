/* dm_v4.h — an RGBA texel's four floats as one vector (the GCC and Clang vector extension),
 * for the CPU image passes that stand in for shaders (core/dm_level_sum.h,
 * core/dm_glow_blur.h): the same IEEE operations per float as scalar code, four at a time,
 * so the same results. */
#ifndef DM_V4_H
#define DM_V4_H

#include <string.h>

typedef float dm_v4 __attribute__((vector_size(16)));

static inline dm_v4 dm_v4_load(const float *p)
{
    dm_v4 v;
    memcpy(&v, p, sizeof v);
    return v;
}

static inline void dm_v4_store(float *p, dm_v4 v)
{
    memcpy(p, &v, sizeof v);
}

/* a + f (b − a): a texture unit's linear interpolation */
static inline dm_v4 dm_v4_lerp(dm_v4 a, dm_v4 b, float f)
{
    return a + f * (b - a);
}

#endif
