/* onoff_diff.h — how far a picture with an effect on is from the same with it off, over
 * the lit values (the terminator tests of the ground truth and of the renderer). */
#ifndef TEST_ONOFF_DIFF_H
#define TEST_ONOFF_DIFF_H

#include <math.h>
#include <stddef.h>

typedef struct onoff_diff {
    int lit;          /* values > 1e-3 of the brightest with the effect off */
    double mean;      /* mean of |on − off| / off over them */
    double over5;     /* the fraction of them off by more than 5 % */
    double sum_ratio; /* Σ |on − off| / Σ off */
} onoff_diff;

/* on and off: n RGBA values; red channel, where off's alpha (coverage) is set. */
static inline onoff_diff onoff_compare(const float *on, const float *off, size_t n)
{
    double top = 0, num = 0, den = 0, rel = 0;
    for (size_t i = 0; i < n; ++i) top = fmax(top, off[i * 4]);
    onoff_diff d = {0};
    int over = 0;
    for (size_t i = 0; i < n; ++i) {
        if (off[i * 4 + 3] == 0 || !(off[i * 4] > 1e-3 * top)) continue;
        double e = fabs((double)on[i * 4] - off[i * 4]);
        ++d.lit;
        rel += e / off[i * 4];
        over += e > 0.05 * off[i * 4];
        num += e;
        den += off[i * 4];
    }
    d.mean = d.lit ? rel / d.lit : 0;
    d.over5 = d.lit ? (double)over / d.lit : 0;
    d.sum_ratio = den > 0 ? num / den : 0;
    return d;
}

#endif
