/* test_philox.c — host/philox.c: Random123 known answers, and the CPU Gaussian transform against N(0,1). */
#include "stats.h"

/* Random123's kat_vectors for "philox4x32 10": counter, key, expected output. */
static const uint32_t KAT[3][10] = {
    {0, 0, 0, 0, 0, 0, 0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8},
    {0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff, 0x408f276d, 0x41c83b0e, 0xa20bc7c6,
     0x6d5451fd},
    {0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344, 0xa4093822, 0x299f31d0, 0xd16cfe09, 0x94fdcceb, 0x5001e420,
     0x24126ea1},
};

int main(void)
{
    for (int k = 0; k < 3; ++k) {
        frt_u32x4 c = {{KAT[k][0], KAT[k][1], KAT[k][2], KAT[k][3]}};
        frt_u32x4 w = frt_philox4x32_10(c, KAT[k][4], KAT[k][5]);
        for (int i = 0; i < 4; ++i)
            CHECK(w.v[i] == KAT[k][6 + i], "vector %d word %d: %08x, expected %08x", k, i, w.v[i], KAT[k][6 + i]);
    }

    /* Transform edge cases: w0 = 0 gives the smallest u = 2^-33 (finite, the largest radius sqrt(66 ln 2));
     * w1 = 0 gives cos 0 = 1. */
    float gmax = frt_gauss_from_words(0, 0);
    CHECK(fabsf(gmax - sqrtf(66.0f * logf(2.0f))) < 1e-5f, "g(0,0) = %.7g", gmax);
    CHECK(isfinite(frt_gauss_from_words(0xffffffffu, 0xffffffffu)), "g(max,max) must be finite");

    /* 2^20 samples of g over a grid of counters against N(0,1). KS critical value at alpha = 0.001 is
     * 1.949/sqrt(n) (asymptotic Kolmogorov distribution). */
    const size_t n = 1u << 20;
    float *g = check_alloc(n * sizeof *g);
    double sum = 0, sum2 = 0, sum4 = 0;
    for (size_t k = 0; k < n; ++k) {
        g[k] = frt_noise(12345, 7, (uint32_t)(k & 1023), (uint32_t)(k >> 10));
        double x = g[k];
        sum += x, sum2 += x * x, sum4 += x * x * x * x;
    }
    double mean = sum / n, var = sum2 / n - mean * mean, kurt = sum4 / n;
    /* Standard errors for n samples of N(0,1): mean 1/sqrt(n), variance sqrt(2/n), 4th moment sqrt(96/n); 5 of
     * each. */
    CHECK(fabs(mean) < 5.0 / sqrt((double)n), "mean %.6f", mean);
    CHECK(fabs(var - 1.0) < 5.0 * sqrt(2.0 / n), "variance %.6f", var);
    CHECK(fabs(kurt - 3.0) < 5.0 * sqrt(96.0 / n), "4th moment %.5f (normal: 3)", kurt);
    double d = ks_normal(g, n), crit = 1.949 / sqrt((double)n);
    CHECK(d < crit, "KS D = %.6f, critical %.6f", d, crit);
    printf("CPU Gaussian: n=%zu mean=%.2e var=%.5f m4=%.4f KS D=%.6f (crit %.6f)\n", n, mean, var, kurt, d, crit);
    free(g);
    return check_summary("test_philox");
}
