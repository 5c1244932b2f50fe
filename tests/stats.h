/* stats.h — statistics the tests share: per-level residuals of a heightfield, KS against N(0,1), variogram H. */
#ifndef FRT_TEST_STATS_H
#define FRT_TEST_STATS_H

#include "check.h"

typedef struct residual_stats {
    size_t n;
    double mean, var; /* of residual / amplitude: expect 0 and 1 */
} residual_stats;

/* For level l of a field of n levels: residuals (height - parents' mean) / amplitude for diamond points and for
 * interior square points (4 neighbours), using the contract's float formulas for the mean. */
static inline void level_residuals(const float *h, uint32_t n, uint32_t level, float amp_d, float amp_s,
                                   residual_stats *diamond, residual_stats *square)
{
    const uint32_t side = (1u << n) + 1, full = side - 1, s = 1u << (n - level);
    double ds = 0, ds2 = 0, ss = 0, ss2 = 0;
    size_t dn = 0, sn = 0;
#define H(x, y) h[(size_t)(y)*side + (x)]
    for (uint32_t y = s; y < full; y += 2 * s)
        for (uint32_t x = s; x < full; x += 2 * s) {
            float mean = ((H(x - s, y - s) + H(x + s, y - s)) + (H(x - s, y + s) + H(x + s, y + s))) * 0.25f;
            double r = ((double)H(x, y) - mean) / amp_d;
            ds += r, ds2 += r * r, ++dn;
        }
    for (uint32_t y = 0; y <= full; y += s)
        for (uint32_t x = ((y / s) % 2 == 0) ? s : 0; x <= full; x += 2 * s) {
            if (x == 0 || y == 0 || x == full || y == full)
                continue;
            float mean = ((H(x - s, y) + H(x + s, y)) + (H(x, y - s) + H(x, y + s))) * 0.25f;
            double r = ((double)H(x, y) - mean) / amp_s;
            ss += r, ss2 += r * r, ++sn;
        }
#undef H
    diamond->n = dn;
    diamond->mean = dn ? ds / dn : 0;
    diamond->var = dn > 1 ? (ds2 - ds * ds / dn) / (dn - 1) : 0;
    square->n = sn;
    square->mean = sn ? ss / sn : 0;
    square->var = sn > 1 ? (ss2 - ss * ss / sn) / (sn - 1) : 0;
}

/* Checks every level with >= 1000 new points of each kind. The sample variance of n N(0,1) residuals has
 * (n-1) s^2 ~ chi^2(n-1), i.e. s^2 = 1 +- sqrt(2/(n-1)) for large n; we allow 5 of those standard deviations
 * (two-sided false alarm 6e-7 per check, about 1e-5 over a whole suite) and 5/sqrt(n) for the mean. */
static inline void check_level_statistics(const char *what, const float *h, const frt_terrain_desc *d)
{
    for (uint32_t level = 1; level <= d->levels; ++level) {
        residual_stats dia = {0}, sq = {0};
        level_residuals(h, d->levels, level, frt_sigma_diamond(d, level), frt_sigma_square(d, level), &dia, &sq);
        residual_stats *both[2] = {&dia, &sq};
        const char *names[2] = {"diamond", "square"};
        for (int k = 0; k < 2; ++k) {
            residual_stats *r = both[k];
            if (r->n < 1000)
                continue;
            double var_tol = 5.0 * sqrt(2.0 / (double)(r->n - 1)), mean_tol = 5.0 / sqrt((double)r->n);
            CHECK(fabs(r->var - 1.0) <= var_tol, "%s level %u %s: variance ratio %.5f, allowed 1 +- %.5f (n=%zu)", what,
                  level, names[k], r->var, var_tol, r->n);
            CHECK(fabs(r->mean) <= mean_tol, "%s level %u %s: mean %.5f, allowed +- %.5f", what, level, names[k],
                  r->mean, mean_tol);
        }
    }
}

static inline int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* Kolmogorov–Smirnov statistic of the samples (sorted in place) against N(0,1). */
static inline double ks_normal(float *v, size_t n)
{
    qsort(v, n, sizeof *v, cmp_float);
    double d = 0;
    for (size_t i = 0; i < n; ++i) {
        double cdf = 0.5 * erfc(-(double)v[i] / sqrt(2.0));
        double lo = cdf - (double)i / n, hi = (double)(i + 1) / n - cdf;
        if (lo > d)
            d = lo;
        if (hi > d)
            d = hi;
    }
    return d;
}

/* Mean squared increment at lag d, along rows and columns. */
static inline double variogram(const float *h, uint32_t side, uint32_t d)
{
    double sum = 0;
    size_t n = 0;
    for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x + d < side; ++x) {
            double a = (double)h[(size_t)y * side + x + d] - h[(size_t)y * side + x];
            double b = (double)h[(size_t)(x + d) * side + y] - h[(size_t)x * side + y];
            sum += a * a + b * b;
            n += 2;
        }
    return sum / (double)n;
}

/* Least-squares slope of y against x. */
static inline double slope(const double *x, const double *y, int n)
{
    double mx = 0, my = 0, sxy = 0, sxx = 0;
    for (int i = 0; i < n; ++i)
        mx += x[i] / n, my += y[i] / n;
    for (int i = 0; i < n; ++i)
        sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
    return sxy / sxx;
}

#endif
