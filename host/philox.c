/* philox.c — the counter-based noise of the contract: Philox4x32-10 and the Gaussian transform (ALGORITHM.md §2). */
#include "internal.h"

#include <math.h>

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

float frt_gauss_from_words(uint32_t w0, uint32_t w1)
{
    /* Each line is one float32 operation; the build uses -ffp-contract=off so that no multiply-add is fused,
     * matching `precise` in shaders/philox.glsl. logf/cosf/sqrtf are glibc's (log and cos within 1 ulp);
     * device versions may differ by a few ulp: ALGORITHM.md §5. */
    float u = (float)w0 * 0x1p-32f + 0x1p-33f; /* (0, 1]: never 0, so the log is finite */
    float v = (float)w1 * 0x1p-32f;            /* [0, 1] */
    float r = sqrtf(-2.0f * logf(u));
    float a = 6.2831855f * v; /* float nearest 2*pi */
    return r * cosf(a);
}

float frt_noise(uint64_t seed, uint32_t level, uint32_t i, uint32_t j)
{
    frt_u32x4 c = {{i, j, level, 0u}};
    frt_u32x4 w = frt_philox4x32_10(c, (uint32_t)seed, (uint32_t)(seed >> 32));
    return frt_gauss_from_words(w.v[0], w.v[1]);
}
