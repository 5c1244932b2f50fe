/* test_philox.c — host/philox.c: Random123 known answers, the spec v2 Gaussian transform's accuracy over every input
 * it can receive, its known answers, its distribution against N(0,1), and the distributions of §2.8 (gauss,
 * truncated, clt, uniform): definitions rebuilt from Philox words, moments, tails, rejection rate, KS. */
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
/* §2.8 known answers: g(0, i, j), seed 1, at (0,0), (1,0), (0,1), (1,1). */
#define KAT_TRUNC3 0x3ec56a32, 0x3f22ae9f, 0x3f477286, 0xbd86a4e4
#define KAT_TRUNC1 0x3f347c36, 0x3f94bb25, 0x3fb657ea, 0xbdf631e9
#define KAT_CLT4 0x3fefde4a, 0x3f96457c, 0xc001e95f, 0xbe206fb0
#define KAT_CLT16 0xbf2e67d5, 0xbf558d6c, 0xbe2dfa10, 0x3f62077c
#define KAT_UNIFORM 0x3fad0af9, 0x3f1887a0, 0x3d34209b, 0x3fd03657
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

/* ---- The distributions of ALGORITHM.md §2.8 ---- */

#define PI_D 3.14159265358979323846

static frt_noise_params noise_params(frt_noise_kind kind, double param, uint64_t seed)
{
    frt_terrain_desc d = {0};
    d.noise = kind, d.noise_param = param, d.seed = seed, d.seed_is_explicit = true;
    CHECK(frt_terrain_desc_resolved(&d, &d) == FRT_SUCCESS, "noise %d param %g is valid", (int)kind, param);
    frt_noise_params p;
    frt_noise_params_init(&p, &d);
    return p;
}

/* The exact even moments mu[2], mu[4], mu[6], mu[8] of the unit-variance distribution (odd ones are 0). */
static void exact_moments(frt_noise_kind kind, double param, double mu[9])
{
    memset(mu, 0, 9 * sizeof *mu);
    if (kind == FRT_NOISE_GAUSS) {
        mu[2] = 1, mu[4] = 3, mu[6] = 15, mu[8] = 105;
    } else if (kind == FRT_NOISE_TRUNCATED) {
        /* Standard normal truncated to [-K, K], Z = 2 Phi(K) - 1: integrating x^(k-1) * x phi(x) by parts gives
         * E[X^k] = (k - 1) E[X^(k-2)] - 2 K^(k-1) phi(K) / Z; then scaled to unit variance. */
        const double K = param, phi = exp(-0.5 * K * K) / sqrt(2 * PI_D), Z = erf(K / sqrt(2.0));
        double m[9] = {1};
        for (int k = 2; k <= 8; k += 2)
            m[k] = (k - 1) * m[k - 2] - 2 * pow(K, k - 1) * phi / Z;
        for (int k = 2; k <= 8; k += 2)
            mu[k] = m[k] / pow(m[2], k / 2);
    } else {
        /* clt: the sum of N uniforms on (-1/2, 1/2) has cumulants N k_r with k_2 = 1/12, k_4 = -1/120, k_6 = 1/252,
         * k_8 = -1/240; standardised, c_r = N k_r / (N / 12)^(r/2); moments from cumulants (odd ones 0). */
        const double N = kind == FRT_NOISE_UNIFORM ? 1 : param, v = N / 12;
        const double c2 = 1, c4 = N * (-1.0 / 120) / (v * v), c6 = N * (1.0 / 252) / (v * v * v),
                     c8 = N * (-1.0 / 240) / (v * v * v * v);
        mu[2] = c2;
        mu[4] = c4 + 3 * c2 * c2;
        mu[6] = c6 + 15 * c4 * c2 + 15 * c2 * c2 * c2;
        mu[8] = c8 + 28 * c6 * c2 + 35 * c4 * c4 + 210 * c4 * c2 * c2 + 105 * c2 * c2 * c2 * c2;
    }
}

/* CDF of the unit-variance distribution, for the KS test. */
static double noise_cdf(frt_noise_kind kind, double param, double x)
{
    if (kind == FRT_NOISE_GAUSS)
        return 0.5 * erfc(-x / sqrt(2.0));
    if (kind == FRT_NOISE_TRUNCATED) {
        const double K = param, y = x / frt_truncated_scale(K); /* back to the unit normal's scale */
        if (y <= -K)
            return 0;
        if (y >= K)
            return 1;
        return (erf(y / sqrt(2.0)) + erf(K / sqrt(2.0))) / (2 * erf(K / sqrt(2.0)));
    }
    /* Irwin-Hall: the sum S of N uniforms on [0, 1] has P(S <= s) = sum_k (-1)^k C(N, k) (s - k)^N / N! over
     * k <= s. For N <= 16 the alternating sum loses at most ~6 of double's 16 digits. */
    const int N = kind == FRT_NOISE_UNIFORM ? 1 : (int)param;
    const double s = x / sqrt(12.0 / N) + N / 2.0;
    if (s <= 0)
        return 0;
    if (s >= N)
        return 1;
    double sum = 0, binom = 1, fact = 1;
    for (int k = 1; k <= N; ++k)
        fact *= k;
    for (int k = 0; k <= N && k < s; ++k) {
        sum += (k % 2 ? -1 : 1) * binom * pow(s - k, N);
        binom = binom * (N - k) / (k + 1);
    }
    return sum / fact;
}

static double ks_cdf(float *v, size_t n, frt_noise_kind kind, double param)
{
    qsort(v, n, sizeof *v, cmp_float);
    double d = 0;
    for (size_t i = 0; i < n; ++i) {
        double cdf = noise_cdf(kind, param, v[i]);
        d = fmax(d, fmax(cdf - (double)i / n, (double)(i + 1) / n - cdf));
    }
    return d;
}

/* §2.8 rebuilt from the Philox words and the Gaussian of §2.2, independently of frt_noise_draw; *attempts gets the
 * truncated draw's number of Philox calls. */
static float spec_draw(const frt_noise_params *p, uint32_t level, uint32_t i, uint32_t j, uint32_t *attempts)
{
    *attempts = 1;
    if (p->kind == FRT_NOISE_TRUNCATED) {
        for (uint32_t t = 0; t < 64; ++t) {
            frt_u32x4 c = {{i, j, level, t}};
            frt_u32x4 w = frt_philox4x32_10(c, p->key[0], p->key[1]);
            float g = frt_gauss_from_words(w.v[0], w.v[1]);
            *attempts = t + 1;
            if (fabsf(g) <= p->k)
                return g * p->scale;
        }
        return 0.0f * p->scale;
    }
    if (p->kind == FRT_NOISE_CLT || p->kind == FRT_NOISE_UNIFORM) {
        float s = 0;
        for (uint32_t m = 0; m < p->n; ++m) {
            frt_u32x4 c = {{i, j, level, m / 4}};
            frt_u32x4 w = frt_philox4x32_10(c, p->key[0], p->key[1]);
            float u = (float)w.v[m % 4] * 0x1p-32f;
            s = m == 0 ? u : s + u;
        }
        return (s - (float)p->n / 2) * p->scale;
    }
    frt_u32x4 c = {{i, j, level, 0}};
    frt_u32x4 w = frt_philox4x32_10(c, p->key[0], p->key[1]);
    return frt_gauss_from_words(w.v[0], w.v[1]);
}

/* 2^20 draws of each distribution over the counters (i, j) = (k mod 1024, k / 1024) at level 7. Moments are taken
 * about 0 (the exact mean) and checked at 5 standard errors of their estimators (two-sided false alarm 6e-7 each):
 * the mean m1 has variance 1/n, m2 (mu4 - 1)/n, and the kurtosis m4 / m2^2, linearised at (1, kappa) as
 * m4 - 2 kappa m2, has variance (mu8 - 4 kappa mu6 + 4 kappa^3 - kappa^2) / n (24 / n for the Gaussian). */
static void test_distributions(void)
{
    static const struct {
        frt_noise_kind kind;
        double param;
        const char *name;
    } cases[] = {{FRT_NOISE_GAUSS, 0, "gauss"},
                 {FRT_NOISE_TRUNCATED, 3, "truncated:3"},
                 {FRT_NOISE_TRUNCATED, 1.5, "truncated:1.5"},
                 {FRT_NOISE_CLT, 4, "clt:4"},
                 {FRT_NOISE_CLT, 12, "clt:12"},
                 {FRT_NOISE_UNIFORM, 0, "uniform"}};
    const size_t n = 1u << 20;
    const uint32_t level = 7;
    const uint64_t seed = 12345;
    float *g = check_alloc(n * sizeof *g);
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        const frt_noise_kind kind = cases[c].kind;
        const double param = cases[c].param;
        const frt_noise_params p = noise_params(kind, param, seed);
        double mu[9];
        exact_moments(kind, param, mu);
        const double kappa = mu[4];
        double s1 = 0, s2 = 0, s4 = 0, gmax = 0;
        size_t spec_differ = 0, gauss_differ = 0, first_rejected = 0, calls = 0;
        uint32_t most_attempts = 0;
        for (size_t k = 0; k < n; ++k) {
            const uint32_t i = (uint32_t)(k & 1023), j = (uint32_t)(k >> 10);
            g[k] = frt_noise_draw(&p, level, i, j);
            uint32_t attempts;
            float ref = spec_draw(&p, level, i, j, &attempts);
            spec_differ += memcmp(&ref, &g[k], 4) != 0;
            calls += attempts;
            first_rejected += attempts > 1;
            most_attempts = attempts > most_attempts ? attempts : most_attempts;
            const float gauss = frt_noise(seed, level, i, j);
            if (kind == FRT_NOISE_GAUSS) {
                gauss_differ += memcmp(&gauss, &g[k], 4) != 0;
            } else if (kind == FRT_NOISE_TRUNCATED && fabsf(gauss) <= p.k) { /* attempt 0 is the gauss value */
                const float scaled = gauss * p.scale;
                gauss_differ += memcmp(&scaled, &g[k], 4) != 0;
            }
            const double x = g[k];
            s1 += x, s2 += x * x, s4 += x * x * x * x;
            gmax = fmax(gmax, fabs(x));
        }
        const double m1 = s1 / n, m2 = s2 / n, m4 = s4 / n, kurt = m4 / (m2 * m2);
        const double se1 = 1 / sqrt((double)n), se2 = sqrt((mu[4] - 1) / n),
                     sek = sqrt((mu[8] - 4 * kappa * mu[6] + 4 * kappa * kappa * kappa - kappa * kappa) / n);
        const char *name = cases[c].name;
        CHECK(spec_differ == 0, "%s: %zu of %zu draws differ from the definition rebuilt from Philox words", name,
              spec_differ, n);
        CHECK(gauss_differ == 0, "%s: %zu draws differ from the Gaussian of §2.2 where they must equal it", name,
              gauss_differ);
        CHECK(fabs(m1) <= 5 * se1, "%s: mean %.6f, allowed +- %.6f", name, m1, 5 * se1);
        CHECK(fabs(m2 - 1) <= 5 * se2, "%s: variance %.6f, allowed 1 +- %.6f", name, m2, 5 * se2);
        CHECK(fabs(kurt - kappa) <= 5 * sek, "%s: kurtosis %.5f, exact %.5f +- %.5f", name, kurt, kappa, 5 * sek);
        double bound = INFINITY;
        if (kind == FRT_NOISE_TRUNCATED) {
            /* |g_t| <= K (float) and rounding is monotone, so |g_t * S| <= float(K * S) */
            bound = p.k * p.scale;
            CHECK(gmax <= bound, "%s: max |g| %.7f above K S_K = %.7f", name, gmax, bound);
            /* the density at K is not small: 2^20 draws come within 1% of the bound */
            CHECK(gmax >= 0.99 * bound, "%s: max |g| %.7f, far below K S_K = %.7f", name, gmax, bound);
            /* attempt 0 is rejected with p = 2 (1 - Phi(K)) = erfc(K / sqrt 2): binomial, 5 standard errors */
            const double pr = erfc(param / sqrt(2.0)), rate = (double)first_rejected / n, se = sqrt(pr * (1 - pr) / n);
            CHECK(fabs(rate - pr) <= 5 * se, "%s: attempt 0 rejected at %.6f, expected %.6f +- %.6f", name, rate, pr,
                  5 * se);
            printf("%s: rejected %.5f of first attempts (expected %.5f), %.5f Philox calls per draw, at most %u\n",
                   name, rate, pr, (double)calls / n, most_attempts);
        } else if (kind != FRT_NOISE_GAUSS) {
            /* |s - N/2| <= N/2 exactly, so |g| <= float(N/2 * scale), which is sqrt(3N) to within an ulp */
            const double N = p.n;
            bound = (float)(N / 2) * p.scale;
            CHECK(gmax <= bound && bound <= sqrt(3 * N) * (1 + 0x1p-22), "%s: max |g| %.7f, bound %.7f, sqrt(3N) %.7f",
                  name, gmax, bound, sqrt(3 * N));
            if (kind == FRT_NOISE_UNIFORM) /* 2^20 uniforms: P(none within 1e-4 of an end) = e^-105 */
                CHECK(gmax >= sqrt(3.0) * (1 - 1e-4), "uniform: max |g| %.7f, far from sqrt 3", gmax);
        }
        const double d = ks_cdf(g, n, kind, param), crit = 1.949 / sqrt((double)n); /* KS at alpha = 0.001 */
        CHECK(d < crit, "%s: KS D = %.6f against the exact CDF, critical %.6f", name, d, crit);
        printf("%-13s n=%zu mean %+.5f (+-%.5f) var %.5f (+-%.5f) kurtosis %.4f exact %.4f (+-%.4f) max|g| %.4f "
               "(bound %.4f) KS D %.5f (crit %.5f)\n",
               name, n, m1, 5 * se1, m2, 5 * se2, kurt, kappa, 5 * sek, gmax, bound, d, crit);
    }
    free(g);

    /* uniform is exactly clt:1; the default distribution is gauss, bit for bit frt_noise */
    const frt_noise_params u = noise_params(FRT_NOISE_UNIFORM, 0, 7), c1 = noise_params(FRT_NOISE_CLT, 1, 7),
                           dflt = noise_params(FRT_NOISE_DEFAULT, 0, 7);
    size_t differ = 0;
    for (uint32_t k = 0; k < 4096; ++k) {
        float a = frt_noise_draw(&u, 3, k, 5), b = frt_noise_draw(&c1, 3, k, 5), e = frt_noise_draw(&dflt, 3, k, 5),
              f = frt_noise(7, 3, k, 5);
        differ += memcmp(&a, &b, 4) != 0 || memcmp(&e, &f, 4) != 0;
    }
    CHECK(differ == 0, "uniform != clt:1 or default != gauss at %zu of 4096 points", differ);
    CHECK(dflt.kind == FRT_NOISE_GAUSS && c1.scale == (float)sqrt(12.0) && u.n == 1, "resolved parameters");
    /* S_K and sqrt(12/N) are computed in double and rounded once (§2.8) */
    const frt_noise_params t3 = noise_params(FRT_NOISE_TRUNCATED, 0, 7), c4 = noise_params(FRT_NOISE_CLT, 0, 7);
    CHECK(t3.k == 3.0f && t3.scale == (float)frt_truncated_scale(3.0) && c4.n == 4 && c4.scale == (float)sqrt(3.0),
          "defaults truncated:3 (S = %.9g) and clt:4", (double)t3.scale);
    CHECK(fabs(frt_truncated_scale(1.0) - 1.0 / sqrt(0.29112509)) < 1e-6, "S_1 = %.9f", frt_truncated_scale(1.0));

    /* Known answers (ALGORITHM.md §2.8): g(0, i, j) for seed 1 at (0,0), (1,0), (0,1), (1,1), per distribution. */
    static const struct {
        frt_noise_kind kind;
        double param;
        uint32_t bits[4];
    } kat[] = {
        {FRT_NOISE_TRUNCATED, 0, {KAT_TRUNC3}}, {FRT_NOISE_TRUNCATED, 1, {KAT_TRUNC1}}, {FRT_NOISE_CLT, 0, {KAT_CLT4}},
        {FRT_NOISE_CLT, 16, {KAT_CLT16}},       {FRT_NOISE_UNIFORM, 0, {KAT_UNIFORM}},
    };
    const frt_noise_params t1 = noise_params(FRT_NOISE_TRUNCATED, 1, 1);
    /* with rejections: g(5, 11, 0) takes 4 attempts, g(5, 83, 0) 6 */
    CHECK(frt_float_bits(frt_noise_draw(&t1, 5, 11, 0)) == 0xbf073460u, "truncated:1 g(5, 11, 0), 4 attempts");
    CHECK(frt_float_bits(frt_noise_draw(&t1, 5, 83, 0)) == 0x3f535e9au, "truncated:1 g(5, 83, 0), 6 attempts");
    /* all 64 attempts rejected gives 0: unreachable for K >= 1 (p < 1e-31), so forced with a K below the range */
    frt_noise_params tiny = t1;
    tiny.k = 0x1p-100f;
    CHECK(frt_float_bits(frt_noise_draw(&tiny, 5, 11, 0)) == 0, "64 rejections give +0");
    for (size_t c = 0; c < sizeof kat / sizeof kat[0]; ++c) {
        const frt_noise_params p = noise_params(kat[c].kind, kat[c].param, 1);
        for (uint32_t k = 0; k < 4; ++k) {
            uint32_t got = frt_float_bits(frt_noise_draw(&p, 0, k & 1u, k >> 1));
            CHECK(got == kat[c].bits[k], "known answer kind %d param %g at (%u, %u): %08x (%.9g), expected %08x",
                  (int)kat[c].kind, kat[c].param, k & 1u, k >> 1, got, (double)frt_bits_float(got), kat[c].bits[k]);
        }
    }
}

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
    test_distributions();
    return check_summary("test_philox");
}
