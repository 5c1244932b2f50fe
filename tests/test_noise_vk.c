/* test_noise_vk.c — host/noise_vk.c: shaders/philox.glsl on the device equals host/philox.c bit for bit, words and
 * Gaussians (spec v2), and the device's Gaussian passes a goodness-of-fit test; every distribution of §2.8 gives the
 * same bits on the device and the CPU, as single draws and through the generator (whole grids and regions, FFC and
 * periodic). */
#include "stats.h"

/* Simple reproducible 64-bit generator for test inputs (splitmix64). */
static uint64_t splitmix(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static const struct {
    frt_noise_kind kind;
    double param;
    const char *name;
} DISTRIBUTIONS[] = {{FRT_NOISE_GAUSS, 0, "gauss"},
                     {FRT_NOISE_TRUNCATED, 1, "truncated:1"},
                     {FRT_NOISE_TRUNCATED, 3, "truncated:3"},
                     {FRT_NOISE_TRUNCATED, 6, "truncated:6"},
                     {FRT_NOISE_CLT, 1, "clt:1"},
                     {FRT_NOISE_CLT, 4, "clt:4"},
                     {FRT_NOISE_CLT, 7, "clt:7"},
                     {FRT_NOISE_CLT, 16, "clt:16"},
                     {FRT_NOISE_UNIFORM, 0, "uniform"}};
#define DISTRIBUTION_COUNT (sizeof DISTRIBUTIONS / sizeof DISTRIBUTIONS[0])

/* frt_noise_draw on the device (noise.comp, the kind at run time) against the CPU: 2^18 random (level, i, j) per
 * distribution and seed, plus the all-rejected fallback forced with a K below the range. */
static void test_draws(frt_context *ctx)
{
    const size_t n = 1u << 18;
    uint32_t *pts = check_alloc(n * 12);
    float *dev = check_alloc(n * sizeof *dev);
    uint64_t state = 77;
    for (size_t i = 0; i < n; ++i) {
        uint64_t a = splitmix(&state), b = splitmix(&state);
        pts[3 * i] = (uint32_t)a, pts[3 * i + 1] = (uint32_t)(a >> 32), pts[3 * i + 2] = (uint32_t)(b % 31);
    }
    for (size_t c = 0; c < DISTRIBUTION_COUNT; ++c) {
        const uint64_t seeds[2] = {1, 0xfedcba9876543210ull};
        for (int s = 0; s < 2; ++s) {
            frt_terrain_desc d = {0};
            d.noise = DISTRIBUTIONS[c].kind, d.noise_param = DISTRIBUTIONS[c].param, d.seed = seeds[s];
            d.seed_is_explicit = true;
            CHECK(frt_terrain_desc_resolved(&d, &d) == FRT_SUCCESS, "%s valid", DISTRIBUTIONS[c].name);
            frt_noise_params p;
            frt_noise_params_init(&p, &d);
            CHECK(frt_noise_draw_vulkan(ctx, &p, pts, n, dev) == FRT_SUCCESS, "%s", frt_context_error(ctx));
            size_t differ = 0;
            for (size_t i = 0; i < n; ++i) {
                float cpu = frt_noise_draw(&p, pts[3 * i + 2], pts[3 * i], pts[3 * i + 1]);
                differ += memcmp(&cpu, &dev[i], 4) != 0;
            }
            CHECK(differ == 0, "%s seed %llx: %zu of %zu device draws differ from the CPU's", DISTRIBUTIONS[c].name,
                  (unsigned long long)seeds[s], differ, n);
            if (s == 0)
                printf("device vs CPU %-12s %zu draws, %zu differ\n", DISTRIBUTIONS[c].name, n, differ);
        }
    }
    frt_terrain_desc d = {0};
    d.noise = FRT_NOISE_TRUNCATED;
    frt_terrain_desc_resolved(&d, &d);
    frt_noise_params p;
    frt_noise_params_init(&p, &d);
    p.k = 0x1p-100f; /* every attempt rejected */
    CHECK(frt_noise_draw_vulkan(ctx, &p, pts, 1024, dev) == FRT_SUCCESS, "%s", frt_context_error(ctx));
    size_t nonzero = 0;
    for (size_t i = 0; i < 1024; ++i)
        nonzero += frt_float_bits(dev[i]) != 0 ||
                   frt_float_bits(frt_noise_draw(&p, pts[3 * i + 2], pts[3 * i], pts[3 * i + 1])) != 0;
    CHECK(nonzero == 0, "64 rejections give +0 on both: %zu of 1024 are not", nonzero);
    CHECK(frt_noise_draw_vulkan(ctx, &p, NULL, 1, dev) == FRT_ERROR_INVALID_ARGUMENT, "no points");
    free(pts), free(dev);
}

/* One field on both backends: FRT_SUCCESS on each and the same bytes. Returns the device's field. */
static float *both(frt_context *ctx, const frt_terrain_desc *d, const char *what)
{
    const size_t count = frt_heightfield_size(d);
    float *dev = check_alloc(count * sizeof *dev), *cpu = check_alloc(count * sizeof *cpu);
    CHECK(frt_generate(ctx, d, dev, count, NULL) == FRT_SUCCESS, "%s: %s", what, frt_context_error(ctx));
    CHECK(frt_generate_cpu(d, cpu, count, NULL) == FRT_SUCCESS, "%s: cpu", what);
    size_t differ = 0;
    for (size_t i = 0; i < count; ++i)
        differ += memcmp(&dev[i], &cpu[i], 4) != 0;
    CHECK(differ == 0, "%s: %zu of %zu points differ between device and CPU", what, differ, count);
    free(cpu);
    return dev;
}

/* The generator's specialised pipelines (generate.comp both block variants, region.comp) against the CPU, per
 * distribution: whole grids FFC (n = 10: levels with 1x1 and 4x4 blocks) and periodic, and regions of both that must
 * also equal the crop of the device's whole grid. */
static void test_fields(frt_context *ctx)
{
    for (size_t c = 0; c < DISTRIBUTION_COUNT; ++c) {
        for (int periodic = 0; periodic <= 1; ++periodic) {
            char what[96];
            frt_terrain_desc d = {0};
            d.levels = 10, d.hurst = 0.75, d.sigma = -1.5, d.seed = 0x5eed0000 + c, d.seed_is_explicit = true;
            d.edge = periodic ? FRT_EDGE_PERIODIC : FRT_EDGE_FFC;
            d.noise = DISTRIBUTIONS[c].kind, d.noise_param = DISTRIBUTIONS[c].param;
            snprintf(what, sizeof what, "%s %s n = 10", DISTRIBUTIONS[c].name, periodic ? "periodic" : "ffc");
            float *whole = both(ctx, &d, what);
            const uint32_t M = frt_terrain_side(&d);
            /* FFC: a window touching the right border; periodic: one that wraps around the torus */
            frt_terrain_desc r = d;
            r.region = periodic ? (frt_region){1000, 990, 77, 61} : (frt_region){950, 300, 75, 64};
            snprintf(what, sizeof what, "%s %s region", DISTRIBUTIONS[c].name, periodic ? "periodic" : "ffc");
            float *reg = both(ctx, &r, what);
            size_t wrong = 0;
            for (uint32_t y = 0; y < r.region.height; ++y)
                for (uint32_t x = 0; x < r.region.width; ++x)
                    wrong += memcmp(&reg[(size_t)y * r.region.width + x],
                                    &whole[(size_t)((r.region.y + y) % M) * M + (r.region.x + x) % M], 4) != 0;
            CHECK(wrong == 0, "%s: %zu points differ from the whole grid's crop", what, wrong);
            free(whole), free(reg);
        }
        printf("device vs CPU %-12s whole grids and regions, FFC and periodic: compared\n", DISTRIBUTIONS[c].name);
    }
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
    test_draws(ctx);
    test_fields(ctx);
    check_context_done(ctx);
    return check_summary("test_noise_vk");
}
