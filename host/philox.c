/* philox.c — the counter-based noise of the contract: Philox4x32-10, the Gaussian transform and the distributions
 * built on them (ALGORITHM.md §2). */
#include "internal.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* The transform needs every float expression evaluated in float32 (ALGORITHM.md §5): not x87's extended precision.
 * (Contraction is switched off by the build: -ffp-contract=off.) */
#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "the noise contract needs FLT_EVAL_METHOD == 0 (docs/ALGORITHM.md section 5)"
#endif

/* Random123's constants for philox4x32: multipliers and Weyl key increments. */
#define PHILOX_M0 0xD2511F53u
#define PHILOX_M1 0xCD9E8D57u
#define PHILOX_W0 0x9E3779B9u
#define PHILOX_W1 0xBB67AE85u

frt_u32x4 frt_philox4x32_10(frt_u32x4 c, uint32_t k0, uint32_t k1)
{
    for (int round = 0; round < 10; ++round) {
        if (round > 0) {
            k0 += PHILOX_W0;
            k1 += PHILOX_W1;
        }
        uint64_t p0 = (uint64_t)PHILOX_M0 * c.v[0];
        uint64_t p1 = (uint64_t)PHILOX_M1 * c.v[2];
        frt_u32x4 n;
        n.v[0] = (uint32_t)(p1 >> 32) ^ c.v[1] ^ k0;
        n.v[1] = (uint32_t)p1;
        n.v[2] = (uint32_t)(p0 >> 32) ^ c.v[3] ^ k1;
        n.v[3] = (uint32_t)p0;
        c = n;
    }
    return c;
}

/* ---- The Gaussian transform of spec v2 (ALGORITHM.md §2.2–2.5) ----
 * Built only from float32 +, -, * (each rounded to nearest, none fused: the build uses -ffp-contract=off, the
 * shader `precise`) and exact bit operations, so shaders/philox.glsl gives the same bits on any IEEE-754 device.
 * Every line below is one step of the spec, in the spec's order; do not "simplify" them. The three stages are
 * external so that tests/test_philox.c can measure each on every input (it declares them itself). */

/* §2.3: -2 ln m = -2f - f^2 Q(f), Q = 2P the degree-8 polynomial of the table; 2 ln 2 = L2_HI + L2_LO. */
#define Q0 (-0x1.00001ep+0f)
#define Q1 0x1.5542f6p-1f
#define Q2 (-0x1.01e9dap-1f)
#define Q3 0x1.6830e8p-2f
#define Q4 (-0x1.5c3ae6p-1f)
#define Q5 (-0x1.2f3e04p+0f)
#define Q6 (-0x1.f88f2ep+1f)
#define Q7 (-0x1.3cfc78p+2f)
#define Q8 (-0x1.be5254p+1f)
#define L2_HI 0x1.62e300p+0f
#define L2_LO 0x1.2fefa4p-16f
/* §2.5: cos(pi t / 2) = 1 + s (C1 + ... + s C4), sin(pi t / 2) = t (S0 + ... + s S3), s = t^2. */
#define C1 (-0x1.3bd3ccp+0f)
#define C2 0x1.03c1b0p-2f
#define C3 (-0x1.55b2b6p-6f)
#define C4 0x1.d4f7eep-11f
#define S0 0x1.921fb6p+0f
#define S1 (-0x1.4abc24p-1f)
#define S2 0x1.4680a4p-4f
#define S3 (-0x1.33198ep-8f)

/* §2.3: -2 ln u for u in [2^-33, 1]. u = 2^e * m with m in (0.5, 1] from the bits (exact), f = m - 1 (exact),
 * Q(f) by Estrin's scheme (short dependency chains: the noise is latency-bound on lavapipe), and -e * 2 ln 2 from
 * a 17-bit head (exact product) and a tail. The terms do not cancel: -2f >= 0 and f^2 Q(f) <= 0 is smaller. */
float frt_neg2_ln(float u)
{
    const uint32_t b = frt_float_bits(u);
    const uint32_t eb = (b - 1u) & 0xFF800000u; /* exponent field of the binade (0.5, 1] * 2^e holding u */
    const float m = frt_bits_float(b - eb + 0x3F000000u);
    const float k = (float)(126 - (int32_t)(eb >> 23)); /* -e, 0..33 */
    const float f = m - 1.0f;
    const float f2 = f * f;
    const float f4 = f2 * f2;
    const float a0 = Q0 + f * Q1;
    const float a1 = Q2 + f * Q3;
    const float a2 = Q4 + f * Q5;
    const float a3 = Q6 + f * Q7;
    const float b0 = a0 + f2 * a1;
    const float b1 = a2 + f2 * a3;
    const float q = b0 + f4 * (b1 + f4 * Q8);
    return (k * L2_HI + (k * L2_LO - 2.0f * f)) - f2 * q;
}

/* §2.4: sqrt x for x in [0, 46]: the classic integer seed for 1/sqrt x (from max(x, 2^-40), so that x = 0 cannot
 * overflow y * y), two Newton steps written as 1.5 y - (h y)(y y) (two products in parallel), then x * y and one
 * residual correction. x = 0 gives +0. */
float frt_sqrt_nr(float x)
{
    const uint32_t bx = frt_float_bits(x);
    float y = frt_bits_float(0x5F3759DFu - ((bx > 0x2B800000u ? bx : 0x2B800000u) >> 1));
    const float h = 0.5f * x;
    y = 1.5f * y - (h * y) * (y * y);
    y = 1.5f * y - (h * y) * (y * y);
    const float r = x * y;
    return r + (0.5f * y) * (x - r * r);
}

/* §2.5: cos(2 pi v) for v = float(w1) * 2^-32 in [0, 1]. 4v splits exactly into a quadrant q and t in
 * [-1/2, 1/2], so the angle is never rounded; then polynomials in s = t^2 (degrees 8 and 7 in t). */
float frt_cos_2pi(float v)
{
    const float w = v * 4.0f;
    int32_t q = (int32_t)w; /* 0..4, exact truncation */
    float t = w - (float)q; /* [0, 1), exact */
    if (t > 0.5f) {
        t = t - 1.0f; /* exact (Sterbenz) */
        q += 1;
    }
    const float s = t * t;
    const float c = 1.0f + s * (C1 + s * (C2 + s * (C3 + s * C4)));
    const float sn = t * (S0 + s * (S1 + s * (S2 + s * S3)));
    const float r = (q & 1) ? sn : c; /* quadrants 0..3: c, -sn, -c, sn */
    return ((q + 1) & 2) ? -r : r;
}

float frt_gauss_from_words(uint32_t w0, uint32_t w1)
{
    const float u = (float)w0 * 0x1p-32f + 0x1p-33f; /* (0, 1]: never 0, so the log is finite */
    const float v = (float)w1 * 0x1p-32f;            /* [0, 1] */
    return frt_sqrt_nr(frt_neg2_ln(u)) * frt_cos_2pi(v);
}

float frt_noise(uint64_t seed, uint32_t level, uint32_t i, uint32_t j)
{
    frt_u32x4 c = {{i, j, level, 0u}};
    frt_u32x4 w = frt_philox4x32_10(c, (uint32_t)seed, (uint32_t)(seed >> 32));
    return frt_gauss_from_words(w.v[0], w.v[1]);
}

/* ---- The distributions (ALGORITHM.md §2.8) ----
 * Each step is one float32 operation of the spec, in its order; shaders/philox.glsl frt_noise_draw is the same code.
 * The first Philox call (the fourth counter word 0) is the gauss value, truncated's attempt 0 and clt's uniforms
 * 0..3. */

#define TRUNCATED_ATTEMPTS 64u

double frt_truncated_scale(double k)
{
    /* Var_K = 1 - 2 K phi(K) / (2 Phi(K) - 1); 2 Phi(K) - 1 = erf(K / sqrt 2), phi(K) = exp(-K^2/2) / sqrt(2 pi). */
    const double phi = exp(-0.5 * k * k) / sqrt(2.0 * 3.14159265358979323846);
    const double var = 1.0 - 2.0 * k * phi / erf(k / sqrt(2.0));
    return 1.0 / sqrt(var);
}

void frt_noise_params_init(frt_noise_params *p, const frt_terrain_desc *d)
{
    memset(p, 0, sizeof *p);
    p->key[0] = (uint32_t)d->seed;
    p->key[1] = (uint32_t)(d->seed >> 32);
    p->kind = d->noise == FRT_NOISE_DEFAULT ? FRT_NOISE_GAUSS : d->noise;
    p->scale = 1.0f;
    switch (p->kind) {
    case FRT_NOISE_TRUNCATED:
        p->k = (float)d->noise_param;
        p->scale = (float)frt_truncated_scale(d->noise_param);
        break;
    case FRT_NOISE_CLT:
    case FRT_NOISE_UNIFORM:
        p->n = p->kind == FRT_NOISE_UNIFORM ? 1u : (uint32_t)d->noise_param;
        p->scale = (float)sqrt(12.0 / (double)p->n);
        break;
    default: break;
    }
}

/* Truncated: rejection with the attempt t in the counter's 4th word; all 64 rejected (p < 1e-31 for K >= 1): 0. */
static float draw_truncated(const frt_noise_params *p, frt_u32x4 c)
{
    float g = 0.0f;
    uint32_t t = 0;
    do {
        c.v[3] = t;
        frt_u32x4 w = frt_philox4x32_10(c, p->key[0], p->key[1]);
        g = frt_gauss_from_words(w.v[0], w.v[1]);
    } while (fabsf(g) > p->k && ++t < TRUNCATED_ATTEMPTS);
    if (fabsf(g) > p->k)
        g = 0.0f;
    return g * p->scale;
}

/* Clt and uniform: u_m = float(word m mod 4 of the call with 4th counter word m / 4) * 2^-32, summed left to right
 * from u_0, then (s - N/2) * C_N (N/2 is exact). */
static float draw_clt(const frt_noise_params *p, frt_u32x4 c)
{
    frt_u32x4 w = {{0}};
    float s = 0.0f; /* 0 + u_0 = u_0 exactly */
    for (uint32_t m = 0; m < p->n; ++m) {
        if ((m & 3u) == 0) {
            c.v[3] = m >> 2;
            w = frt_philox4x32_10(c, p->key[0], p->key[1]);
        }
        s = s + (float)w.v[m & 3u] * 0x1p-32f;
    }
    return (s - (float)p->n * 0.5f) * p->scale;
}

/* The gauss path is frt_noise itself, tested first and kept free of the others' code: the CPU reference calls this
 * for every point, and the other paths inlined beside it made it 5-10% slower. */
float frt_noise_draw(const frt_noise_params *p, uint32_t level, uint32_t i, uint32_t j)
{
    const frt_u32x4 c = {{i, j, level, 0u}};
    if (p->kind != FRT_NOISE_GAUSS) { /* one test on the gauss path */
        if (p->kind == FRT_NOISE_TRUNCATED)
            return draw_truncated(p, c);
        if (p->kind == FRT_NOISE_CLT || p->kind == FRT_NOISE_UNIFORM)
            return draw_clt(p, c);
    }
    const frt_u32x4 w = frt_philox4x32_10(c, p->key[0], p->key[1]);
    return frt_gauss_from_words(w.v[0], w.v[1]);
}
