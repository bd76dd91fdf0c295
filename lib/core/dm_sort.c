/* dm_sort.c — dm_sort.h. */
#include "core/dm_sort.h"

#include <stdlib.h>

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void dm_sort_floats(float *v, size_t n)
{
    if (n > 1) qsort(v, n, sizeof *v, cmp_float);
}

void dm_sort_doubles(double *v, size_t n)
{
    if (n > 1) qsort(v, n, sizeof *v, cmp_double);
}

double dm_median_doubles(double *v, size_t n)
{
    if (n == 0) return 0.0;
    dm_sort_doubles(v, n);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
