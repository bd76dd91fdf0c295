/* dm_sort.h — ascending sorts of plain float and double arrays (qsort with one comparator
 * each), for the percentiles and medians across dermis. NaN must be left out first: it has
 * no place in the order. */
#ifndef DM_SORT_H
#define DM_SORT_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

void dm_sort_floats(float *v, size_t n);
void dm_sort_doubles(double *v, size_t n);
/* The median of v (sorted in place): the middle value, or the mean of the two middle ones;
 * 0 when n is 0. */
double dm_median_doubles(double *v, size_t n);

#ifdef __cplusplus
}
#endif
#endif
