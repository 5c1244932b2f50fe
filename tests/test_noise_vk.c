/* test_noise_vk.c — host/noise_vk.c: shaders/philox.glsl on the device equals host/philox.c bit for bit, words and
 * Gaussians (spec v2), and the device's Gaussian passes a goodness-of-fit test. */
#include "stats.h"

/* Simple reproducible 64-bit generator for test inputs (splitmix64). */
static uint64_t splitmix(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

int main(void)
{
    frt_context *ctx = check_context();
    if (!ctx)
        return CHECK_SKIP;

    /* Known answers (Random123 kat_vectors, philox4x32 10) through the shader. */
    const uint32_t ctr[12] = {0,          0,          0,          0,          0xffffffff, 0xffffffff,
                              0xffffffff, 0xffffffff, 0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344};
    const uint32_t key[6] = {0, 0, 0xffffffff, 0xffffffff, 0xa4093822, 0x299f31d0};
    const uint32_t want[12] = {0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8, 0x408f276d, 0x41c83b0e,
                               0xa20bc7c6, 0x6d5451fd, 0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1};
    uint32_t got[12];
    CHECK(frt_noise_vulkan(ctx, ctr, key, 3, got, NULL) == FRT_SUCCESS, "%s", frt_context_error(ctx));
    for (int i = 0; i < 12; ++i)
        CHECK(got[i] == want[i], "KAT word %d: %08x, expected %08x", i, got[i], want[i]);

    /* 2^17 random counters and keys: every word and every Gaussian (random words, so u and v range over their whole
     * domain) equal between device and CPU. */
    const size_t nr = 1u << 17;
    uint32_t *c = check_alloc(nr * 16), *k = check_alloc(nr * 8), *w = check_alloc(nr * 16);
    float *gr = check_alloc(nr * sizeof *gr);
    uint64_t state = 2026;
    for (size_t i = 0; i < nr; ++i) {
        uint64_t a = splitmix(&state), b = splitmix(&state), e = splitmix(&state);
        c[4 * i] = (uint32_t)a, c[4 * i + 1] = (uint32_t)(a >> 32), c[4 * i + 2] = (uint32_t)b,
              c[4 * i + 3] = (uint32_t)(b >> 32);
        k[2 * i] = (uint32_t)e, k[2 * i + 1] = (uint32_t)(e >> 32);
    }
    CHECK(frt_noise_vulkan(ctx, c, k, nr, w, gr) == FRT_SUCCESS, "%s", frt_context_error(ctx));
    size_t mismatched = 0, g_mismatched = 0;
    for (size_t i = 0; i < nr; ++i) {
        frt_u32x4 in = {{c[4 * i], c[4 * i + 1], c[4 * i + 2], c[4 * i + 3]}};
        frt_u32x4 out = frt_philox4x32_10(in, k[2 * i], k[2 * i + 1]);
        mismatched += memcmp(out.v, &w[4 * i], 16) != 0;
        float cpu = frt_gauss_from_words(out.v[0], out.v[1]);
        g_mismatched += memcmp(&cpu, &gr[i], 4) != 0;
    }
    CHECK(mismatched == 0, "%zu of %zu random counters differ between device and CPU", mismatched, nr);
    CHECK(g_mismatched == 0, "%zu of %zu Gaussians of random words differ between device and CPU", g_mismatched, nr);
    free(c), free(k), free(w), free(gr);

    /* 2^20 Gaussians from the shader: the contract's counters (i, j, level 5, 0) under one key. */
    const size_t n = 1u << 20;
    c = check_alloc(n * 16), k = check_alloc(n * 8);
    float *g = check_alloc(n * sizeof *g);
    for (size_t i = 0; i < n; ++i) {
        c[4 * i] = (uint32_t)(i & 1023), c[4 * i + 1] = (uint32_t)(i >> 10), c[4 * i + 2] = 5, c[4 * i + 3] = 0;
        k[2 * i] = 99, k[2 * i + 1] = 0;
    }
    CHECK(frt_noise_vulkan(ctx, c, k, n, NULL, g) == FRT_SUCCESS, "%s", frt_context_error(ctx));
    /* Device vs CPU transform, bit for bit: spec v2 is built from float32 +, -, * only, which Vulkan requires to be
     * correctly rounded, with `precise` forbidding fused multiply-adds (ALGORITHM.md §5). */
    size_t differ = 0, first = n;
    for (size_t i = 0; i < n; ++i) {
        float cpu = frt_noise(99, 5, (uint32_t)(i & 1023), (uint32_t)(i >> 10));
        if (memcmp(&cpu, &g[i], 4) != 0 && differ++ == 0)
            first = i;
    }
    CHECK(differ == 0, "%zu of %zu device Gaussians differ from the CPU's", differ, n);
    if (differ) {
        uint32_t ii = (uint32_t)(first & 1023), jj = (uint32_t)(first >> 10);
        frt_u32x4 in = {{ii, jj, 5, 0}};
        frt_u32x4 ww = frt_philox4x32_10(in, 99, 0);
        fprintf(stderr, "first difference: words %08x %08x, device %.9g, CPU %.9g\n", ww.v[0], ww.v[1],
                (double)g[first], (double)frt_noise(99, 5, ii, jj));
    }
    printf("device vs CPU Gaussian: %zu samples, %zu differ (bit-identical required)\n", n, differ);
    double d = ks_normal(g, n), crit = 1.949 / sqrt((double)n); /* KS at alpha = 0.001 */
    CHECK(d < crit, "device KS D = %.6f, critical %.6f", d, crit);
    printf("device Gaussian: n=%zu KS D=%.6f (critical %.6f at alpha=0.001)\n", n, d, crit);
    free(c), free(k), free(g);

    CHECK(frt_noise_vulkan(ctx, NULL, NULL, 0, NULL, NULL) == FRT_ERROR_INVALID_ARGUMENT, "empty input");
    check_context_done(ctx);
    return check_summary("test_noise_vk");
}
