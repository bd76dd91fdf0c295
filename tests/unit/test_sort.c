/* test_sort.c — core/dm_sort.h: the ascending sorts and the median the benches and
 * dermis-render's timings take. */
#include <criterion/criterion.h>

#include "core/dm_sort.h"

Test(sort, doubles_ascend_and_the_median_takes_the_middle)
{
    double odd[5] = {3.0, -1.0, 7.5, 2.0, 2.0};
    cr_expect_eq(dm_median_doubles(odd, 5), 2.0);
    for (int i = 1; i < 5; ++i) cr_expect_leq(odd[i - 1], odd[i], "not sorted at %d", i);
    double even[4] = {4.0, 1.0, 3.0, 10.0}; /* the mean of the two middle values */
    cr_expect_eq(dm_median_doubles(even, 4), 3.5);
    double one = 42.0;
    cr_expect_eq(dm_median_doubles(&one, 1), 42.0);
    cr_expect_eq(dm_median_doubles(NULL, 0), 0.0, "empty: 0, nothing read");
}

Test(sort, floats_ascend)
{
    float v[6] = {0.5f, -2.0f, 1e30f, 0.0f, -0.0f, 3.0f};
    dm_sort_floats(v, 6);
    for (int i = 1; i < 6; ++i) cr_expect_leq(v[i - 1], v[i], "not sorted at %d", i);
}
