/* test_reference.c — host/reference.c and host/desc.c: the contract's exact properties on the CPU, per-level
 * statistics, and the Hurst exponent recovered from the variogram. */
#include "stats.h"

static float *gen_edge(uint32_t levels, double hurst, double sigma, uint64_t seed, frt_edge edge)
{
    frt_terrain_desc d = {0};
    d.levels = levels, d.hurst = hurst, d.sigma = sigma, d.seed = seed, d.seed_is_explicit = true, d.edge = edge;
    size_t count = frt_heightfield_size(&d);
    float *h = check_alloc(count * sizeof *h);
    frt_result r = frt_generate_cpu(&d, h, count, NULL);
    CHECK(r == FRT_SUCCESS, "generate_cpu: %s", frt_result_string(r));
    return h;
}

static float *gen(uint32_t levels, double hurst, double sigma, uint64_t seed)
{
    return gen_edge(levels, hurst, sigma, seed, FRT_EDGE_FFC);
}

static float *gen_periodic(uint32_t levels, double hurst, double sigma, uint64_t seed)
{
    return gen_edge(levels, hurst, sigma, seed, FRT_EDGE_PERIODIC);
}

static void test_desc(void)
{
    frt_terrain_desc d = {0}, r;
    CHECK(frt_terrain_desc_resolved(&d, &r) == FRT_SUCCESS, "zero desc is valid");
    CHECK(r.levels == 9 && r.hurst == 0.8 && r.sigma == 1.0 && r.seed == 1 && r.edge == FRT_EDGE_FFC,
          "defaults: levels %u H %g sigma %g seed %llu", r.levels, r.hurst, r.sigma, (unsigned long long)r.seed);
    CHECK(frt_terrain_desc_resolved(NULL, &r) == FRT_SUCCESS && r.levels == 9, "NULL desc means defaults");
    CHECK(frt_heightfield_size(&d) == 513u * 513u, "default size %zu", frt_heightfield_size(&d));
    d.seed_is_explicit = true;
    CHECK(frt_terrain_desc_resolved(&d, &r) == FRT_SUCCESS && r.seed == 0, "explicit seed 0 is kept");
    frt_terrain_desc bad = {0};
    bad.hurst = 1.0;
    CHECK(frt_terrain_desc_resolved(&bad, &r) == FRT_ERROR_INVALID_ARGUMENT, "H = 1 rejected");
    bad.hurst = -0.1;
    CHECK(frt_heightfield_size(&bad) == 0, "H < 0 has no size");
    bad.hurst = NAN;
    CHECK(frt_terrain_desc_resolved(&bad, &r) == FRT_ERROR_INVALID_ARGUMENT, "H NaN rejected");
    bad.hurst = 0.5;
    bad.levels = FRT_MAX_LEVELS + 1;
    CHECK(frt_terrain_desc_resolved(&bad, &r) == FRT_ERROR_INVALID_ARGUMENT, "too many levels rejected");
    bad.levels = 4;
    bad.sigma = INFINITY;
    CHECK(frt_terrain_desc_resolved(&bad, &r) == FRT_ERROR_INVALID_ARGUMENT, "infinite sigma rejected");
    CHECK(frt_grid_side(0) == 0 && frt_grid_side(1) == 3 && frt_grid_side(15) == 32769, "grid sides");
    float small[8];
    frt_terrain_desc d2 = {0};
    d2.levels = 2;
    CHECK(frt_generate_cpu(&d2, small, 8, NULL) == FRT_ERROR_BUFFER_TOO_SMALL, "5x5 needs 25 floats");
    CHECK(strcmp(frt_result_string(FRT_ERROR_TOO_LARGE), "grid too large for the device or host") == 0, "strings");
    /* sD, sS: sigma 2^-(l-1/2)H and sigma 2^-lH, rounded once to float. */
    frt_terrain_desc rr = {0};
    frt_terrain_desc_resolved(&rr, &rr);
    CHECK(frt_sigma_diamond(&rr, 1) == (float)exp2(-0.4) && frt_sigma_square(&rr, 3) == (float)exp2(-2.4),
          "per-level amplitudes");
}

/* The contract written out for single points, checked against the whole-field generator. */
static void test_contract_points(void)
{
    const uint32_t n = 5, side = 33, full = 32;
    const double hurst = 0.65, sigma = 2.5;
    const uint64_t seed = 0x123456789abcdefull;
    float *h = gen(n, hurst, sigma, seed);
    frt_terrain_desc d = {0};
    d.levels = n, d.hurst = hurst, d.sigma = sigma, d.seed = seed, d.seed_is_explicit = true;
    frt_terrain_desc_resolved(&d, &d);
    /* corners: sigma * g(0, i, j) */
    CHECK(h[0] == (float)sigma * frt_noise(seed, 0, 0, 0), "corner (0,0)");
    CHECK(h[full] == (float)sigma * frt_noise(seed, 0, 1, 0), "corner (M-1,0) uses i = 1");
    CHECK(h[(size_t)full * side] == (float)sigma * frt_noise(seed, 0, 0, 1), "corner (0,M-1) uses j = 1");
    /* level 1 diamond: the centre */
    float mean = ((h[0] + h[full]) + (h[(size_t)full * side] + h[(size_t)full * side + full])) * 0.25f;
    CHECK(h[16 * side + 16] == mean + frt_sigma_diamond(&d, 1) * frt_noise(seed, 1, 1, 1), "centre");
    /* every border square point is the 3-point mean, in the order W, E, N, S, times the float nearest 1/3 */
    size_t checked = 0, wrong = 0;
    for (uint32_t level = 1; level <= n; ++level) {
        uint32_t s = 1u << (n - level);
        float amp = frt_sigma_square(&d, level);
        for (uint32_t t = s; t < full; t += 2 * s) {
            /* top (y = 0): W, E, S */
            float top = ((h[t - s] + h[t + s]) + h[(size_t)s * side + t]) * frt_one_third();
            wrong += h[t] != top + amp * frt_noise(seed, level, t / s, 0);
            /* left (x = 0): E, N, S */
            float left =
                ((h[(size_t)t * side + s] + h[(size_t)(t - s) * side]) + h[(size_t)(t + s) * side]) * frt_one_third();
            wrong += h[(size_t)t * side] != left + amp * frt_noise(seed, level, 0, t / s);
            /* bottom (y = M-1): W, E, N */
            size_t b = (size_t)full * side;
            float bottom = ((h[b + t - s] + h[b + t + s]) + h[b - (size_t)s * side + t]) * frt_one_third();
            wrong += h[b + t] != bottom + amp * frt_noise(seed, level, t / s, full / s);
            /* right (x = M-1): W, N, S */
            float right = ((h[(size_t)t * side + full - s] + h[(size_t)(t - s) * side + full]) +
                           h[(size_t)(t + s) * side + full]) *
                          frt_one_third();
            wrong += h[(size_t)t * side + full] != right + amp * frt_noise(seed, level, full / s, t / s);
            checked += 4;
        }
    }
    CHECK(wrong == 0 && checked == 4 * 31, "%zu of %zu border points are not the 3-point mean + noise", wrong, checked);
    free(h);
}

static void test_exact_properties(void)
{
    /* Resolution independence: the grid at n is every 2^k-th point of the grid at n + k. */
    float *a = gen(6, 0.7, 1.0, 42), *b = gen(9, 0.7, 1.0, 42);
    size_t wrong = 0;
    for (uint32_t y = 0; y <= 64; ++y)
        for (uint32_t x = 0; x <= 64; ++x)
            wrong += a[y * 65 + x] != b[(size_t)(8 * y) * 513 + 8 * x];
    CHECK(wrong == 0, "resolution independence: %zu of 4225 points differ", wrong);
    /* Determinism and seed sensitivity. */
    float *c = gen(9, 0.7, 1.0, 42), *e = gen(9, 0.7, 1.0, 43);
    CHECK(memcmp(b, c, 513 * 513 * sizeof(float)) == 0, "same inputs, same bytes");
    size_t same = 0;
    for (size_t i = 0; i < 513 * 513; ++i)
        same += b[i] == e[i];
    CHECK(same < 513 * 513 / 1000, "another seed gives another field (%zu equal points)", same);
    /* Negative sigma inverts exactly: every step is odd in sigma and rounding is symmetric. */
    float *f = gen(9, 0.7, -1.0, 42);
    wrong = 0;
    for (size_t i = 0; i < 513 * 513; ++i)
        wrong += f[i] != -b[i];
    CHECK(wrong == 0, "sigma -1 is the exact negation of sigma 1 (%zu differ)", wrong);
    /* The 64-bit seed uses both key words. */
    float *g1 = gen(4, 0.7, 1.0, 1ull << 32), *g0 = gen(4, 0.7, 1.0, 0);
    CHECK(memcmp(g1, g0, 17 * 17 * sizeof(float)) != 0, "seed high word matters");
    free(a), free(b), free(c), free(e), free(f), free(g1), free(g0);
}

static void test_statistics(void)
{
    const double hs[3] = {0.3, 0.5, 0.8};
    for (int k = 0; k < 3; ++k) {
        frt_terrain_desc d = {0};
        d.levels = 10, d.hurst = hs[k], d.sigma = 3.0, d.seed = 7, d.seed_is_explicit = true;
        frt_terrain_desc_resolved(&d, &d);
        float *h = gen(10, hs[k], 3.0, 7);
        check_level_statistics("cpu", h, &d);
        free(h);
    }
}

/* H from the variogram gamma(d) ~ d^(2H) at 1025^2: lags 4..128, gamma averaged over 8 seeds. */
static void test_hurst_estimate(void)
{
    const double hs[3] = {0.3, 0.5, 0.8};
    double est[3];
    for (int k = 0; k < 3; ++k) {
        double lx[6], ly[6] = {0};
        for (int seed = 1; seed <= 8; ++seed) {
            float *h = gen(10, hs[k], 1.0, (uint64_t)seed);
            for (int i = 0; i < 6; ++i)
                ly[i] += variogram(h, 1025, 4u << i) / 8.0;
            free(h);
        }
        for (int i = 0; i < 6; ++i)
            lx[i] = log(4.0 * (1 << i)), ly[i] = log(ly[i]);
        est[k] = slope(lx, ly, 6) / 2.0;
        /* 0.1 as the issue asks. Midpoint displacement is not stationary fBm, and this estimator reads it about
         * 0.05 low at H = 0.8 (Peitgen & Saupe 1988, §2.3.2, on its "creases"); seeds vary it by ~0.02. */
        CHECK(fabs(est[k] - hs[k]) <= 0.1, "H %.1f estimated as %.3f", hs[k], est[k]);
        printf("variogram H: true %.1f, estimated %.3f\n", hs[k], est[k]);
    }
    CHECK(est[0] < est[1] && est[1] < est[2], "estimates monotone in H: %.3f %.3f %.3f", est[0], est[1], est[2]);
}

/* Periodic mode (ALGORITHM.md §3.1): sizes, the contract at single points, resolution independence, and the seam. */
static void test_periodic(void)
{
    frt_terrain_desc d = {0};
    d.levels = 4, d.edge = FRT_EDGE_PERIODIC;
    CHECK(frt_terrain_side(&d) == 16 && frt_heightfield_size(&d) == 256, "periodic 16 x 16");
    d.edge = 3;
    CHECK(frt_terrain_side(&d) == 0 && frt_heightfield_size(&d) == 0, "unknown edge mode rejected");

    /* Level 0 is the single point (0, 0); at level 1 (n = 1, side 2) the diamond point (1, 1) averages four copies
     * of it and each square point averages h(0,0) twice and the diamond point twice (W, E, N, S wrap). */
    float *h1 = gen_periodic(1, 0.7, 2.0, 5);
    frt_terrain_desc r1 = {0};
    r1.levels = 1, r1.hurst = 0.7, r1.sigma = 2.0, r1.seed = 5, r1.seed_is_explicit = true, r1.edge = FRT_EDGE_PERIODIC;
    frt_terrain_desc_resolved(&r1, &r1);
    float h00 = 2.0f * frt_noise(5, 0, 0, 0);
    float dia = ((h00 + h00) + (h00 + h00)) * 0.25f + frt_sigma_diamond(&r1, 1) * frt_noise(5, 1, 1, 1);
    float sq10 = ((h00 + h00) + (dia + dia)) * 0.25f + frt_sigma_square(&r1, 1) * frt_noise(5, 1, 1, 0);
    CHECK(h1[0] == h00 && h1[3] == dia && h1[1] == sq10, "periodic contract at level 0 and 1");
    free(h1);

    /* Resolution independence, as for FFC: the grid at n is every 2^k-th point of the grid at n + k. */
    float *a = gen_periodic(6, 0.5, 1.0, 21), *b = gen_periodic(9, 0.5, 1.0, 21);
    size_t wrong = 0;
    for (uint32_t y = 0; y < 64; ++y)
        for (uint32_t x = 0; x < 64; ++x)
            wrong += memcmp(&a[y * 64 + x], &b[(size_t)(8 * y) * 512 + 8 * x], 4) != 0;
    CHECK(wrong == 0, "periodic n = 6 is every 8th point of n = 9: %zu differ", wrong);
    free(a), free(b);

    /* The seam. By the torus's reflection symmetry the difference across the wrap, h(M-1) - h(0), has the law of
     * h(1) - h(0); FFC has no such symmetry and its opposite edges are unrelated. Over 16 seeds at 256 x 256 each
     * statistic pools 16 * 256 * 2 = 8192 differences; neighbouring rows are correlated, so take ~1000 effective
     * samples: the variance ratio then has a standard deviation of about sqrt(2 * 2 / 1000) = 0.063, and the bound
     * [0.75, 1.33] is more than 4 standard deviations wide. */
    double wrap = 0.0, inner = 0.0, ffc_wrap = 0.0, ffc_inner = 0.0;
    const uint32_t M = 256;
    for (uint64_t seed = 1; seed <= 16; ++seed) {
        float *p = gen_periodic(8, 0.8, 1.0, seed), *f = gen(8, 0.8, 1.0, seed);
        for (uint32_t k = 0; k < M; ++k) {
            double dw = (double)p[k * M + M - 1] - p[k * M], dn = (double)p[(M - 1) * M + k] - p[k];
            double iw = (double)p[k * M + 1] - p[k * M], in = (double)p[M + k] - p[k];
            wrap += dw * dw + dn * dn;
            inner += iw * iw + in * in;
            double fw = (double)f[k * 257 + 256] - f[k * 257], fi = (double)f[k * 257 + 1] - f[k * 257];
            ffc_wrap += fw * fw;
            ffc_inner += fi * fi;
        }
        free(p), free(f);
    }
    double ratio = wrap / inner, ffc_ratio = ffc_wrap / ffc_inner;
    printf("periodic seam: var(wrap) / var(inside) = %.3f (FFC's opposite edges: %.1f)\n", ratio, ffc_ratio);
    CHECK(ratio > 0.75 && ratio < 1.33, "periodic seam has the statistics of the inside: ratio %.3f", ratio);
    CHECK(ffc_ratio > 10.0, "control: FFC's opposite edges do not match (ratio %.1f)", ffc_ratio);
}

/* A region of the CPU generator (levels up to 30); NULL when the call fails. */
static float *gen_region(uint32_t levels, uint64_t seed, frt_edge edge, uint32_t x, uint32_t y, uint32_t w, uint32_t h)
{
    frt_terrain_desc d = {0};
    d.levels = levels, d.hurst = 0.7, d.sigma = 1.0, d.seed = seed, d.seed_is_explicit = true, d.edge = edge;
    d.region = (frt_region){x, y, w, h};
    size_t count = frt_heightfield_size(&d);
    if (count != (size_t)w * h)
        return NULL;
    float *out = check_alloc(count * sizeof *out);
    if (frt_generate_cpu(&d, out, count, NULL) != FRT_SUCCESS) {
        free(out);
        return NULL;
    }
    return out;
}

/* The window of the whole field `full` (side M), wrapping in periodic mode, compared bit for bit. */
static bool region_matches(const float *full, uint32_t M, const float *reg, uint32_t x0, uint32_t y0, uint32_t w,
                           uint32_t h)
{
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            if (frt_float_bits(reg[(size_t)y * w + x]) !=
                frt_float_bits(full[(size_t)((y0 + y) % M) * M + (x0 + x) % M]))
                return false;
    return true;
}

static uint32_t lcg_below(uint64_t *state, uint32_t bound)
{
    *state = *state * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)((*state >> 33) % bound);
}

/* §3.2: a region equals, bit for bit, the same window cut from the whole grid, for every window shape. */
static void test_regions_exact(void)
{
    static const uint32_t levels[] = {1, 2, 3, 4, 6, 9, 12};
    for (int periodic = 0; periodic <= 1; ++periodic) {
        const frt_edge edge = periodic ? FRT_EDGE_PERIODIC : FRT_EDGE_FFC;
        for (size_t k = 0; k < sizeof levels / sizeof levels[0]; ++k) {
            const uint32_t n = levels[k], M = periodic ? 1u << n : (1u << n) + 1u;
            float *full = gen_edge(n, 0.7, 1.0, 1234 + n, edge);
            uint64_t st = n * 77 + (uint64_t)periodic;
            int windows = 0, bad = 0;
            const int trials = n >= 12 ? 40 : 120;
            for (int t = 0; t < trials; ++t) {
                uint32_t x0, y0, w, h;
                if (t == 0) /* the whole grid */
                    x0 = y0 = 0, w = h = M;
                else if (t <= 4) { /* 1 x 1 at each corner */
                    x0 = (t & 1) ? 0 : M - 1, y0 = (t & 2) ? 0 : M - 1, w = h = 1;
                } else if (t <= 8) { /* strips along each border */
                    w = (t <= 6) ? M : 1 + lcg_below(&st, 3);
                    h = (t <= 6) ? 1 + lcg_below(&st, 3) : M;
                    x0 = (t == 8) ? M - w : 0;
                    y0 = (t == 6) ? M - h : 0;
                } else {
                    w = 1 + lcg_below(&st, M < 70 ? M : 70);
                    h = 1 + lcg_below(&st, M < 70 ? M : 70);
                    x0 = lcg_below(&st, periodic ? M : M - w + 1);
                    y0 = lcg_below(&st, periodic ? M : M - h + 1);
                }
                float *reg = gen_region(n, 1234 + n, edge, x0, y0, w, h);
                ++windows;
                if (!reg || !region_matches(full, M, reg, x0, y0, w, h)) {
                    if (bad++ < 3)
                        fprintf(stderr, "  n=%u %s window %u,%u %ux%u differs\n", n, periodic ? "periodic" : "ffc", x0,
                                y0, w, h);
                }
                free(reg);
            }
            CHECK(bad == 0, "%s n=%u: %d of %d windows equal the crop of the whole grid bit for bit",
                  periodic ? "periodic" : "ffc", n, windows - bad, windows);
            free(full);
        }
    }
    /* Periodic windows wrap: a 2M x 2M window shows the field four times, seams included. */
    float *full = gen_periodic(5, 0.7, 1.0, 1239);
    float *reg = gen_region(5, 1239, FRT_EDGE_PERIODIC, 17, 9, 64, 64);
    CHECK(reg && region_matches(full, 32, reg, 17, 9, 64, 64), "periodic window wrapping twice equals the torus");
    free(reg);
    free(full);
}

/* Resolution independence across depths: the region at n + k, every 2^k-th point, is the region at n. */
static void test_regions_deep(void)
{
    const uint32_t n = 22, k = 3, s = 1u << k, x0 = 1234567, y0 = 3456789, w = 48, h = 40;
    float *coarse = gen_region(n, 99, FRT_EDGE_FFC, x0, y0, w, h);
    float *fine = gen_region(n + k, 99, FRT_EDGE_FFC, x0 * s, y0 * s, (w - 1) * s + 1, (h - 1) * s + 1);
    bool same = coarse && fine;
    for (uint32_t y = 0; same && y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            same = same && frt_float_bits(coarse[(size_t)y * w + x]) ==
                               frt_float_bits(fine[(size_t)(y * s) * ((w - 1) * s + 1) + x * s]);
    CHECK(same, "region at n=%u equals every %u-th point of the region at n=%u", n, s, n + k);
    free(coarse);
    free(fine);

    /* The deepest grid: corners, the far corner and the middle of 2^30 + 1, FFC and periodic. */
    const uint32_t last = 1u << 30;
    float *corner = gen_region(30, 5, FRT_EDGE_FFC, last - 3, last - 3, 4, 4);
    float *top = gen_region(1, 5, FRT_EDGE_FFC, 2, 2, 1, 1);
    CHECK(corner && top && frt_float_bits(corner[15]) == frt_float_bits(top[0]),
          "n=30: the far corner is the level-0 corner");
    bool finite = corner != NULL;
    for (int i = 0; finite && i < 16; ++i)
        finite = isfinite(corner[i]);
    CHECK(finite, "n=30 corner region is finite");
    free(corner);
    free(top);
    float *wrap = gen_region(30, 5, FRT_EDGE_PERIODIC, last - 2, last - 2, 5, 5);
    float *origin = gen_region(30, 5, FRT_EDGE_PERIODIC, 0, 0, 3, 3);
    bool wraps = wrap && origin;
    for (uint32_t y = 0; wraps && y < 3; ++y)
        for (uint32_t x = 0; x < 3; ++x)
            wraps = wraps && frt_float_bits(wrap[(y + 2) * 5 + x + 2]) == frt_float_bits(origin[y * 3 + x]);
    CHECK(wraps, "n=30 periodic window across the wrap continues at (0, 0)");
    free(wrap);
    free(origin);
}

static void test_regions_invalid(void)
{
    char why[200];
    frt_terrain_desc d = {0};
    d.levels = 10;
    d.region = (frt_region){0, 0, 1025, 1025};
    uint32_t w = 0, h = 0;
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_SUCCESS && why[0] == '\0', "whole-grid region is valid");
    CHECK(frt_terrain_extent(&d, &w, &h) == FRT_SUCCESS && w == 1025 && h == 1025, "extent of a region");
    d.region = (frt_region){0, 0, 1026, 1};
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT && strstr(why, "outside"),
          "window past the right edge: %s", why);
    CHECK(frt_heightfield_size(&d) == 0 && frt_terrain_extent(&d, &w, &h) != FRT_SUCCESS && w == 0,
          "invalid region has no size");
    d.region = (frt_region){1000, 1020, 10, 6};
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT, "window past the bottom: %s", why);
    d.region = (frt_region){3, 3, 0, 5};
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT && strstr(why, "at least 1"),
          "zero width: %s", why);
    d.region = (frt_region){3, 3, 0, 0};
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT, "origin without size: %s", why);
    d.region = (frt_region){0, 0, 4, 4};
    d.levels = 31;
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT && strstr(why, "at most 30"),
          "31 levels: %s", why);
    d.levels = 16;
    d.region = (frt_region){0};
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT && strstr(why, "region"),
          "16 levels without a region: %s", why);
    d.edge = FRT_EDGE_PERIODIC;
    d.region = (frt_region){65536, 0, 4, 4};
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT && strstr(why, "periodic"),
          "periodic origin outside: %s", why);
    d.region = (frt_region){65535, 65535, 4, 4};
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_SUCCESS, "periodic window may wrap");
    float one;
    d.region = (frt_region){0, 0, 1, 1};
    CHECK(frt_generate_cpu(&d, &one, 1, NULL) == FRT_SUCCESS, "1 x 1 region needs one float");
    d.region = (frt_region){0, 0, 2, 1};
    CHECK(frt_generate_cpu(&d, &one, 1, NULL) == FRT_ERROR_BUFFER_TOO_SMALL, "region larger than the buffer");
}

/* §3.4 densify: the coarse grid of a generated field, with holes, gives back exactly the field, whole or a region. */
static void test_densify(void)
{
    for (int periodic = 0; periodic <= 1; ++periodic) {
        const frt_edge edge = periodic ? FRT_EDGE_PERIODIC : FRT_EDGE_FFC;
        const uint32_t n = 9, k = 5, M = periodic ? 1u << n : (1u << n) + 1, cs = periodic ? 1u << k : (1u << k) + 1;
        const uint32_t step = 1u << (n - k);
        float *full = gen_edge(n, 0.65, 3.0, 4242, edge);
        float *coarse = check_alloc((size_t)cs * cs * sizeof *coarse);
        for (uint32_t y = 0; y < cs; ++y)
            for (uint32_t x = 0; x < cs; ++x)
                coarse[y * cs + x] = full[(size_t)(y * step) * M + x * step];
        /* holes: a corner, a border cell, an interior block (created at several different levels) */
        coarse[0] = NAN;
        coarse[cs / 2] = NAN;
        for (uint32_t y = 9; y < 14; ++y)
            for (uint32_t x = 3; x < 11; ++x)
                coarse[y * cs + x] = NAN;
        frt_terrain_desc d = {0};
        d.levels = n, d.hurst = 0.65, d.sigma = 3.0, d.seed = 4242, d.edge = edge;
        d.coarse = coarse, d.coarse_levels = k;
        float *out = check_alloc((size_t)M * M * sizeof *out);
        CHECK(frt_generate_cpu(&d, out, (size_t)M * M, NULL) == FRT_SUCCESS, "densify");
        CHECK(memcmp(out, full, (size_t)M * M * sizeof *out) == 0,
              "%s: densifying every %u-th point (with holes) of a field gives back that field bit for bit",
              periodic ? "periodic" : "ffc", step);
        const uint32_t rx = periodic ? M - 40 : 100, ry = 37, rw = 90, rh = 61;
        d.region = (frt_region){rx, ry, rw, rh};
        float *reg = check_alloc((size_t)rw * rh * sizeof *reg);
        CHECK(frt_generate_cpu(&d, reg, (size_t)rw * rh, NULL) == FRT_SUCCESS && region_matches(full, M, reg, rx, ry, rw, rh),
              "%s: a densified region is the crop of the densified grid", periodic ? "periodic" : "ffc");
        free(reg);

        /* Foreign data: kept bit for bit (including values no generator would make), holes finite. */
        for (uint32_t i = 0; i < cs * cs; ++i)
            coarse[i] = (i % 7 == 3) ? NAN : (float)((i * 2654435761u) % 1000) * 0.37f - 100.0f;
        d.region = (frt_region){0};
        d.levels = 8, d.coarse_levels = k;
        const uint32_t M8 = periodic ? 256 : 257, s8 = 1u << (8 - k);
        CHECK(frt_generate_cpu(&d, out, (size_t)M8 * M8, NULL) == FRT_SUCCESS, "densify foreign data");
        size_t kept = 0, filled = 0, known = 0, holes = 0;
        for (uint32_t y = 0; y < cs; ++y)
            for (uint32_t x = 0; x < cs; ++x) {
                float c = coarse[y * cs + x], o = out[(size_t)(y * s8) * M8 + x * s8];
                if (isnan(c))
                    ++holes, filled += isfinite(o);
                else
                    ++known, kept += memcmp(&c, &o, 4) == 0;
            }
        bool finite = true;
        for (size_t i = 0; i < (size_t)M8 * M8; ++i)
            finite = finite && isfinite(out[i]);
        CHECK(kept == known && filled == holes && finite, "%s: %zu of %zu known samples kept, %zu of %zu holes filled",
              periodic ? "periodic" : "ffc", kept, known, filled, holes);
        /* coarse_levels == levels: the completed coarse grid itself */
        d.levels = k;
        CHECK(frt_generate_cpu(&d, out, (size_t)cs * cs, NULL) == FRT_SUCCESS && out[1] == coarse[1],
              "densify to the coarse grid's own levels");
        free(full), free(coarse), free(out);
    }
    char why[200];
    float c3[9] = {0, 1, 2, 3, INFINITY, 5, 6, 7, 8};
    frt_terrain_desc d = {0};
    d.levels = 4, d.coarse = c3, d.coarse_levels = 1;
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT && strstr(why, "infinite"),
          "infinite coarse height: %s", why);
    c3[4] = NAN;
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_SUCCESS, "NaN is no data: %s", why);
    d.coarse_levels = 5;
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT, "coarse deeper than levels: %s",
          why);
    d.coarse_levels = 0;
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT, "coarse without levels: %s", why);
}

/* §2.8: the noise distribution's defaults and validation, with a reason for each rejection. */
static void test_noise_desc(void)
{
    frt_terrain_desc d = {0}, r;
    char why[200];
    CHECK(frt_terrain_desc_resolved(&d, &r) == FRT_SUCCESS && r.noise == FRT_NOISE_GAUSS && r.noise_param == 0,
          "default noise is gauss without a parameter");
    d.noise = FRT_NOISE_TRUNCATED;
    CHECK(frt_terrain_desc_resolved(&d, &r) == FRT_SUCCESS && r.noise_param == 3, "truncated: K 0 -> 3");
    d.noise = FRT_NOISE_CLT;
    CHECK(frt_terrain_desc_resolved(&d, &r) == FRT_SUCCESS && r.noise_param == 4, "clt: N 0 -> 4");
    d.noise = FRT_NOISE_UNIFORM;
    CHECK(frt_terrain_desc_resolved(&d, &r) == FRT_SUCCESS && r.noise_param == 0, "uniform takes no parameter");
    static const struct {
        frt_noise_kind kind;
        double param;
        bool ok;
        const char *reason; /* in the message when rejected */
    } cases[] = {
        {FRT_NOISE_TRUNCATED, 1, true, ""},
        {FRT_NOISE_TRUNCATED, 6, true, ""},
        {FRT_NOISE_TRUNCATED, 2.5, true, ""},
        {FRT_NOISE_TRUNCATED, 0.5, false, "[1, 6]"},
        {FRT_NOISE_TRUNCATED, 7, false, "[1, 6]"},
        {FRT_NOISE_TRUNCATED, -3, false, "[1, 6]"},
        {FRT_NOISE_TRUNCATED, NAN, false, "[1, 6]"},
        {FRT_NOISE_TRUNCATED, INFINITY, false, "[1, 6]"},
        {FRT_NOISE_CLT, 1, true, ""},
        {FRT_NOISE_CLT, 16, true, ""},
        {FRT_NOISE_CLT, 2.5, false, "1..16"},
        {FRT_NOISE_CLT, 17, false, "1..16"},
        {FRT_NOISE_CLT, -4, false, "1..16"},
        {FRT_NOISE_CLT, NAN, false, "1..16"},
        {FRT_NOISE_GAUSS, 2, false, "takes none"},
        {FRT_NOISE_UNIFORM, 1, false, "takes none"},
        {(frt_noise_kind)5, 0, false, "unknown noise"},
        {(frt_noise_kind)-1, 0, false, "unknown noise"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        frt_terrain_desc e = {0};
        e.noise = cases[k].kind, e.noise_param = cases[k].param;
        frt_result res = frt_terrain_desc_check(&e, why, sizeof why);
        if (cases[k].ok)
            CHECK(res == FRT_SUCCESS && why[0] == '\0', "noise %d param %g is valid: %s", (int)cases[k].kind,
                  cases[k].param, why);
        else
            CHECK(res == FRT_ERROR_INVALID_ARGUMENT && strstr(why, cases[k].reason) && frt_heightfield_size(&e) == 0,
                  "noise %d param %g: '%s' should say '%s'", (int)cases[k].kind, cases[k].param, why, cases[k].reason);
    }
}

/* §2.8 through the CPU generator: every path (whole FFC grid, periodic grid, regions of both) draws the chosen
 * distribution: single points follow the contract, regions equal the whole grid's crop, the grid at n is every
 * 2^k-th point of the grid at n + k, and the per-level residuals have variance 1. */
static void test_noise_fields(void)
{
    static const struct {
        frt_noise_kind kind;
        double param;
    } kinds[] = {{FRT_NOISE_TRUNCATED, 1},
                 {FRT_NOISE_TRUNCATED, 3},
                 {FRT_NOISE_CLT, 4},
                 {FRT_NOISE_CLT, 13},
                 {FRT_NOISE_UNIFORM, 0}};
    float *gauss = gen(6, 0.7, 1.0, 42);
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; ++k) {
        for (int periodic = 0; periodic <= 1; ++periodic) {
            frt_terrain_desc d = {0};
            d.levels = 6, d.hurst = 0.7, d.sigma = 2.0, d.seed = 42, d.seed_is_explicit = true;
            d.edge = periodic ? FRT_EDGE_PERIODIC : FRT_EDGE_FFC;
            d.noise = kinds[k].kind, d.noise_param = kinds[k].param;
            CHECK(frt_terrain_desc_resolved(&d, &d) == FRT_SUCCESS, "valid");
            frt_noise_params np;
            frt_noise_params_init(&np, &d);
            const uint32_t M = frt_terrain_side(&d);
            float *h = check_alloc((size_t)M * M * sizeof *h);
            CHECK(frt_generate_cpu(&d, h, (size_t)M * M, NULL) == FRT_SUCCESS, "generate");
            /* the first corner and the centre, written out */
            const float corner = (float)d.sigma * frt_noise_draw(&np, 0, 0, 0);
            const uint32_t c = M / 2, last = periodic ? 0 : M - 1;
            const float mean = ((h[0] + h[last]) + (h[(size_t)last * M] + h[(size_t)last * M + last])) * 0.25f;
            const float centre = mean + frt_sigma_diamond(&d, 1) * frt_noise_draw(&np, 1, 1, 1);
            CHECK(h[0] == corner && h[(size_t)c * M + c] == centre,
                  "noise %d %s: corner and centre follow the contract", (int)d.noise, periodic ? "periodic" : "ffc");
            size_t same = 0;
            for (size_t i = 0; i < 65u * 65u && !periodic; ++i)
                same += h[i] == gauss[i] * 2.0f;
            CHECK(periodic || same < 65u * 65u / 10, "noise %d: %zu points equal the gauss field's", (int)d.noise,
                  same);
            /* a region is the crop of the whole grid, bit for bit (reference.c region_noise) */
            frt_terrain_desc rd = d;
            rd.region = (frt_region){periodic ? 50u : 17u, periodic ? 60u : 5u, 23, 31};
            float *reg = check_alloc(23 * 31 * sizeof *reg);
            CHECK(frt_generate_cpu(&rd, reg, 23 * 31, NULL) == FRT_SUCCESS, "region");
            CHECK(region_matches(h, M, reg, rd.region.x, rd.region.y, 23, 31),
                  "noise %d %s: the region is the whole grid's crop", (int)d.noise, periodic ? "periodic" : "ffc");
            /* resolution independence at n = 9 */
            frt_terrain_desc big = d;
            big.levels = 9;
            const uint32_t B = frt_terrain_side(&big);
            float *hb = check_alloc((size_t)B * B * sizeof *hb);
            CHECK(frt_generate_cpu(&big, hb, (size_t)B * B, NULL) == FRT_SUCCESS, "generate n = 9");
            size_t wrong = 0;
            for (uint32_t y = 0; y < M; ++y)
                for (uint32_t x = 0; x < M; ++x)
                    wrong += h[(size_t)y * M + x] != hb[(size_t)(8 * y) * B + 8 * x];
            CHECK(wrong == 0, "noise %d %s: resolution independence, %zu points differ", (int)d.noise,
                  periodic ? "periodic" : "ffc", wrong);
            if (!periodic)
                check_level_statistics("cpu noise", hb, &big);
            free(h), free(reg), free(hb);
        }
    }
    free(gauss);
}

int main(void)
{
    test_desc();
    test_noise_desc();
    test_noise_fields();
    test_regions_invalid();
    test_regions_exact();
    test_regions_deep();
    test_densify();
    test_periodic();
    test_contract_points();
    test_exact_properties();
    test_statistics();
    test_hurst_estimate();
    return check_summary("test_reference");
}
