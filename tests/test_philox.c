/* test_philox.c — host/philox.c: Random123 known answers, the spec v2 Gaussian transform's accuracy over every input
 * it can receive, its known answers, and its distribution against N(0,1). */
#include "stats.h"

/* |got - want| in units of the float32 ulp of want's binade (want computed in double). */
static double ulps(float got, double want)
{
    if (want == 0)
        return got == 0 ? 0 : INFINITY;
    int e;
    frexp(fabs(want), &e); /* |want| in [2^(e-1), 2^e): float ulp 2^(e-24) */
    return fabs((double)got - want) / ldexp(1.0, e - 24);
}

/* cos(2 pi v) in double by the same exact quadrant split as §2.5, so the reference keeps its relative accuracy
 * next to the zeros of cos (a double 2 pi v would not). */
static double cos_2pi_ref(float v)
{
    float w = v * 4.0f;
    uint32_t q = (uint32_t)w;
    double t = (double)w - q;
    if (t > 0.5)
        t -= 1.0, q += 1u;
    /* pi/2 in double (M_PI_2 is not C11) */
    double c = (q & 1u) ? sin(0x1.921fb54442d18p+0 * t) : cos(0x1.921fb54442d18p+0 * t);
    return ((q + 1u) & 2u) ? -c : c;
}

/* Every input the transform can get: float(w) for a 32-bit w is one of 2^24 + 2^26 + 1 values (every integer up to
 * 2^24, then every float up to 2^32), and u, v are functions of it alone. Each stage is checked on all of them
 * against double precision (ALGORITHM.md §2.6). The bounds: 2 ulp for -2 ln u and cos 2 pi v, as the spec promises
 * (the polynomials' own errors are 0.06 ulp for the log and 0.47 ulp for the sine, whose leading coefficient is the
 * float nearest pi/2; the rest is float rounding), 1 ulp for the square root of a float, 2 ulp for the radius
 * sqrt(-2 ln u) as a whole. Returns the relative error bound for g = r * c that the measured maxima imply: an ulp is
 * at most 2^-23 of a value, and the product adds one rounding of 2^-24. */
static double test_transform_accuracy(void)
{
    double e_ln = 0, e_sqrt = 0, e_r = 0, e_cos = 0;
    float at_ln = 0, at_r = 0, at_cos = 0;
    size_t n = 0, bad = 0;
    const uint32_t two24 = 1u << 24, two32_bits = 0x4F800000u; /* 2^32 as a float */
    for (uint64_t i = 0;; ++i) {
        float F = i <= two24 ? (float)i : frt_bits_float(frt_float_bits(0x1p24f) + (uint32_t)(i - two24));
        if (frt_float_bits(F) > two32_bits)
            break;
        ++n;
        float u = F * 0x1p-32f + 0x1p-33f, v = F * 0x1p-32f; /* §2.2 */
        float x = frt_neg2_ln(u), r = frt_sqrt_nr(x), c = frt_cos_2pi(v);
        double lu = log((double)u), e = ulps(x, -2.0 * lu);
        if (e > e_ln)
            e_ln = e, at_ln = u;
        e_sqrt = fmax(e_sqrt, ulps(r, sqrt((double)x)));
        e = ulps(r, sqrt(-2.0 * lu));
        if (e > e_r)
            e_r = e, at_r = u;
        e = ulps(c, cos_2pi_ref(v));
        if (e > e_cos)
            e_cos = e, at_cos = v;
        bad += !(x >= 0 && isfinite(x) && fabsf(c) <= 1.0f);
    }
    CHECK(n == (1u << 24) + (1u << 26) + 1, "%zu distinct inputs", n);
    CHECK(bad == 0, "%zu results out of range", bad);
    CHECK(e_ln <= 2.0, "-2 ln u: %.3f ulp at u = %a", e_ln, (double)at_ln);
    CHECK(e_sqrt <= 1.0, "sqrt: %.3f ulp", e_sqrt);
    CHECK(e_r <= 2.0, "sqrt(-2 ln u): %.3f ulp at u = %a", e_r, (double)at_r);
    CHECK(e_cos <= 2.0, "cos 2 pi v: %.3f ulp at v = %a", e_cos, (double)at_cos);
    printf("spec v2 transform over all %zu inputs, max error vs double: -2 ln u %.3f ulp (u = %a), sqrt %.3f ulp, "
           "sqrt(-2 ln u) %.3f ulp, cos 2 pi v %.3f ulp (v = %a); bound 2 ulp\n",
           n, e_ln, (double)at_ln, e_sqrt, e_r, e_cos, (double)at_cos);
    /* Edges: u = 1 and x = 0 give +0, and v on a quadrant boundary gives the exact value. */
    CHECK(frt_float_bits(frt_neg2_ln(1.0f)) == 0, "-2 ln 1 = +0");
    CHECK(frt_float_bits(frt_sqrt_nr(0.0f)) == 0, "sqrt 0 = +0");
    CHECK(frt_cos_2pi(0.0f) == 1.0f && frt_cos_2pi(0.5f) == -1.0f && frt_cos_2pi(1.0f) == 1.0f, "cos at 0, pi, 2 pi");
    CHECK(frt_cos_2pi(0.25f) == 0 && frt_cos_2pi(0.75f) == 0, "cos at pi/2, 3 pi/2");
    return (2.0 * e_r + 2.0 * e_cos + 1.0) * 0x1p-24;
}

/* Random123's kat_vectors for "philox4x32 10": counter, key, expected output. */
static const uint32_t KAT[3][10] = {
    {0, 0, 0, 0, 0, 0, 0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8},
    {0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff, 0x408f276d, 0x41c83b0e, 0xa20bc7c6,
     0x6d5451fd},
    {0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344, 0xa4093822, 0x299f31d0, 0xd16cfe09, 0x94fdcceb, 0x5001e420,
     0x24126ea1},
};

/* Spec v2 known answers of the transform (ALGORITHM.md §2.6): words w0, w1 and the bits of g. They cover the
 * largest radius (w0 = 0), u rounding to 1 (radius +0), the cos zeros at v = 1/4 and 3/4 (g = -0 and +0), and
 * the Philox known-answer outputs above. */
#define GAUSS_KAT_COUNT 10
static const uint32_t GAUSS_KAT[GAUSS_KAT_COUNT][3] = {
    {0x00000000, 0x00000000, 0x40d87047}, /* 6.76370573 */
    {0xffffffff, 0xffffffff, 0x00000000}, /* 0 */
    {0x00000000, 0x40000000, 0x80000000}, /* -0 */
    {0x6627e8d5, 0xe169c58d, 0x3f7dbb35}, /* 0.991137803 */
    {0x408f276d, 0x41c83b0e, 0xbd94a538}, /* -0.0725807548 */
    {0xd16cfe09, 0x94fdcceb, 0xbf0d2d00}, /* -0.551467896 */
    {0x80000000, 0x20000000, 0x3f55224c}, /* 0.832554579 */
    {0x12345678, 0x9abcdef0, 0xbfe92f37}, /* -1.82175338 */
    {0xfffffe00, 0x5f000000, 0xb9b085ba}, /* -0.0003366897 */
    {0x00000001, 0xbfffffff, 0x00000000}, /* 0 */
};

int main(void)
{
    for (int k = 0; k < 3; ++k) {
        frt_u32x4 c = {{KAT[k][0], KAT[k][1], KAT[k][2], KAT[k][3]}};
        frt_u32x4 w = frt_philox4x32_10(c, KAT[k][4], KAT[k][5]);
        for (int i = 0; i < 4; ++i)
            CHECK(w.v[i] == KAT[k][6 + i], "vector %d word %d: %08x, expected %08x", k, i, w.v[i], KAT[k][6 + i]);
    }

    const double g_bound = test_transform_accuracy();

    /* Known answers of the transform (ALGORITHM.md §2.6): the float bits every backend must give. w0 = 0 is the
     * smallest u = 2^-33 (the largest radius, sqrt(66 ln 2)); w0 = 2^32 - 1 rounds u to 1 (radius 0). */
    for (int k = 0; k < GAUSS_KAT_COUNT; ++k) {
        uint32_t got = frt_float_bits(frt_gauss_from_words(GAUSS_KAT[k][0], GAUSS_KAT[k][1]));
        CHECK(got == GAUSS_KAT[k][2], "g(%08x, %08x) = %08x (%.9g), expected %08x (%.9g)", GAUSS_KAT[k][0],
              GAUSS_KAT[k][1], got, (double)frt_bits_float(got), GAUSS_KAT[k][2],
              (double)frt_bits_float(GAUSS_KAT[k][2]));
    }
    /* g(0, i, j) for seed 1: the default terrain's corners divided by sigma. */
    const uint32_t corners[4] = {0x3ec2c3e5, 0x3f207fa8, 0x3f44c53d, 0xbd84d644};
    for (uint32_t k = 0; k < 4; ++k)
        CHECK(frt_float_bits(frt_noise(1, 0, k & 1u, k >> 1)) == corners[k], "g(0, %u, %u) for seed 1", k & 1u, k >> 1);
    float gmax = frt_gauss_from_words(0, 0);
    CHECK(fabs(gmax - sqrt(66.0 * log(2.0))) < 1e-6, "g(0,0) = %.9g", (double)gmax);

    /* 2^20 samples of g over a grid of counters against N(0,1). KS critical value at alpha = 0.001 is
     * 1.949/sqrt(n) (asymptotic Kolmogorov distribution). */
    const size_t n = 1u << 20;
    float *g = check_alloc(n * sizeof *g);
    double sum = 0, sum2 = 0, sum4 = 0, g_rel = 0;
    for (size_t k = 0; k < n; ++k) {
        g[k] = frt_noise(12345, 7, (uint32_t)(k & 1023), (uint32_t)(k >> 10));
        frt_u32x4 c = {{(uint32_t)(k & 1023), (uint32_t)(k >> 10), 7, 0}};
        frt_u32x4 w = frt_philox4x32_10(c, 12345, 0);
        float u = (float)w.v[0] * 0x1p-32f + 0x1p-33f, v = (float)w.v[1] * 0x1p-32f;
        double ref = sqrt(-2.0 * log((double)u)) * cos_2pi_ref(v);
        if (ref != 0)
            g_rel = fmax(g_rel, fabs(g[k] - ref) / fabs(ref));
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
    CHECK(g_rel <= g_bound, "g: relative error %.3g over the bound %.3g", g_rel, g_bound);
    printf("g vs sqrt(-2 ln u) cos(2 pi v) in double: max relative error %.3g (%.2f * 2^-24; bound %.2f * 2^-24)\n",
           g_rel, g_rel / 0x1p-24, g_bound / 0x1p-24);
    printf("CPU Gaussian: n=%zu mean=%.2e var=%.5f m4=%.4f KS D=%.6f (crit %.6f)\n", n, mean, var, kurt, d, crit);
    free(g);
    return check_summary("test_philox");
}
