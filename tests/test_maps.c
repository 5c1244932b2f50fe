/* test_maps.c — host/maps.c: 2^-x and bilinear sampling (exact properties), and fields whose roughness and
 * amplitude vary by area (§3.5) on the CPU and, when a device exists, bit-identical on Vulkan. */
#include "stats.h"

/* 2^-x within 2 ulp of the exact value over [0, 31] (the range e * H takes for levels <= 30), sampled densely. */
static void test_exp2(void)
{
    double worst = 0;
    float at = 0;
    for (uint32_t k = 0; k <= 31u * (1u << 20); ++k) {
        float x = (float)k * (1.0f / (1u << 20));
        double exact = exp2(-(double)x), got = frt_exp2_neg(x);
        double ulp = nextafterf((float)exact, INFINITY) - (float)exact;
        double e = fabs(got - exact) / ulp;
        if (e > worst)
            worst = e, at = x;
    }
    CHECK(worst <= 2.0, "2^-x within 2 ulp on [0, 31]: worst %.3f ulp at x = %.9g", worst, at);
    printf("2^-x: worst error %.3f ulp at x = %.9g (32.5 M points of [0, 31])\n", worst, at);
    CHECK(frt_exp2_neg(0.0f) == 1.0f && frt_exp2_neg(3.0f) == 0.125f, "2^-x exact at integers");
}

static void test_sampling(void)
{
    /* a plane map a + b x + c y: bilinear reproduces it (within float rounding) everywhere */
    float plane[5 * 3];
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            plane[y * 5 + x] = 0.25f + 0.125f * (float)x + 0.0625f * (float)y;
    frt_map m = {plane, 5, 3};
    double worst = 0;
    for (uint32_t j = 0; j <= 64; ++j)
        for (uint32_t i = 0; i <= 64; ++i) {
            double px = i / 64.0, py = j / 64.0, exact = 0.25 + 0.125 * px * 4 + 0.0625 * py * 2;
            double e = fabs(frt_map_sample(&m, 6, i, j) - exact);
            worst = e > worst ? e : worst;
        }
    CHECK(worst < 1e-6, "bilinear reproduces a plane: worst %.3g", worst);
    CHECK(frt_map_sample(&m, 0, 0, 0) == 0.25f && frt_map_sample(&m, 3, 0, 0) == 0.25f, "corner (0, 0)");
    CHECK(fabs(frt_map_sample(&m, 0, 1, 1) - plane[14]) < 1e-7, "corner (1, 1)");
    /* the same place at different levels samples the same value */
    CHECK(frt_map_sample(&m, 4, 6, 10) == frt_map_sample(&m, 3, 3, 5), "position, not level");
}

static float *gen_maps(uint32_t n, const frt_map *hm, const frt_map *am, frt_backend backend, frt_context *ctx)
{
    frt_terrain_desc d = {0};
    d.levels = n, d.hurst = 0.5, d.sigma = 1.0, d.seed = 31;
    if (hm)
        d.hurst_map = *hm;
    if (am)
        d.amplitude_map = *am;
    size_t count = frt_heightfield_size(&d);
    float *h = check_alloc(count * sizeof *h);
    frt_result r = backend == FRT_BACKEND_CPU ? frt_generate_cpu(&d, h, count, NULL) : frt_generate(ctx, &d, h, count, NULL);
    CHECK(r == FRT_SUCCESS, "generate with maps: %s", frt_result_string(r));
    return h;
}

/* The (2^k+1)^2 square of a (2^n+1)^2 field at (x0, y0), both multiples of 2^(n-k)... here of 64. */
static float *square_at(const float *h, uint32_t n, uint32_t x0, uint32_t y0, uint32_t k)
{
    const uint32_t side = (1u << n) + 1, cs = (1u << k) + 1;
    float *c = check_alloc((size_t)cs * cs * sizeof *c);
    for (uint32_t y = 0; y < cs; ++y)
        memcpy(c + (size_t)y * cs, h + (size_t)(y0 + y) * side + x0, cs * sizeof *c);
    return c;
}

/* A map split in two halves: the left and right parts of the field have each half's statistics. H from the
 * residual variogram of 257^2 squares well inside each half (x in 0.06..0.31 and 0.69..0.94 of the width), 4 seeds
 * pooled by averaging; tolerance 0.1 as for the estimator (test_estimate: |dH| <= 0.03 on 257^2). Amplitude halves
 * 1 | 3: the sigma ratio of the halves within 20%. */
static void test_halves(void)
{
    float hv[2 * 64], av[2 * 64];
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 64; ++x) {
            hv[y * 64 + x] = x < 32 ? 0.3f : 0.9f;
            av[y * 64 + x] = x < 32 ? 1.0f : 3.0f;
        }
    frt_map hm = {hv, 64, 2}, am = {av, 64, 2};
    float *h = gen_maps(10, &hm, NULL, FRT_BACKEND_CPU, NULL);
    float *l = square_at(h, 10, 64, 384, 8), *r = square_at(h, 10, 704, 384, 8);
    frt_roughness el, er;
    CHECK(frt_estimate_roughness(l, 257, &el) == FRT_SUCCESS && frt_estimate_roughness(r, 257, &er) == FRT_SUCCESS,
          "estimates");
    CHECK(fabs(el.hurst - 0.3) <= 0.1 && fabs(er.hurst - 0.9) <= 0.1, "roughness map 0.3 | 0.9: halves give H %.3f | %.3f",
          el.hurst, er.hurst);
    printf("roughness map 0.3 | 0.9: estimated H %.3f | %.3f\n", el.hurst, er.hurst);
    free(h), free(l), free(r);

    h = gen_maps(10, NULL, &am, FRT_BACKEND_CPU, NULL);
    l = square_at(h, 10, 64, 384, 8), r = square_at(h, 10, 704, 384, 8);
    CHECK(frt_estimate_roughness(l, 257, &el) == FRT_SUCCESS && frt_estimate_roughness(r, 257, &er) == FRT_SUCCESS,
          "estimates");
    double ratio = er.sigma / el.sigma;
    CHECK(fabs(ratio / 3.0 - 1.0) <= 0.2 && fabs(el.hurst - 0.5) <= 0.1 && fabs(er.hurst - 0.5) <= 0.1,
          "amplitude map 1 | 3: sigma ratio %.3f, H %.3f | %.3f", ratio, el.hurst, er.hurst);
    printf("amplitude map 1 | 3: sigma ratio %.3f (H %.3f | %.3f)\n", ratio, el.hurst, er.hurst);
    free(h), free(l), free(r);

    /* a constant roughness map of H gives (nearly) the field of H: amplitudes from 2^-x agree to 2 ulp */
    float c[4] = {0.5f, 0.5f, 0.5f, 0.5f};
    frt_map cm = {c, 2, 2};
    float *a = gen_maps(8, &cm, NULL, FRT_BACKEND_CPU, NULL), *b = gen_maps(8, NULL, NULL, FRT_BACKEND_CPU, NULL);
    double diff = max_abs_diff(a, b, 257 * 257);
    CHECK(diff < 1e-4, "constant roughness map 0.5 vs H = 0.5: max |difference| %.3g", diff);
    free(a), free(b);
}

static void test_invalid(void)
{
    char why[200];
    float v[4] = {0.5f, 0.5f, 1.0f, 0.5f};
    frt_terrain_desc d = {0};
    d.hurst_map = (frt_map){v, 2, 2};
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT && strstr(why, "roughness"),
          "H = 1 in a roughness map: %s", why);
    v[2] = NAN;
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT, "NaN in a roughness map: %s", why);
    v[2] = 0.7f;
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_SUCCESS, "valid roughness map: %s", why);
    d.hurst_map = (frt_map){v, 4, 1};
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT && strstr(why, "2 x 2"),
          "a 4 x 1 map: %s", why);
    d.hurst_map = (frt_map){NULL, 2, 2};
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT, "size without data: %s", why);
    d.hurst_map = (frt_map){0};
    v[1] = INFINITY;
    d.amplitude_map = (frt_map){v, 2, 2};
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_ERROR_INVALID_ARGUMENT && strstr(why, "amplitude"),
          "infinite amplitude: %s", why);
    v[1] = -2.0f;
    CHECK(frt_terrain_desc_check(&d, why, sizeof why) == FRT_SUCCESS, "negative amplitude inverts locally: %s", why);
}

/* The same bits on Vulkan, whole grids and regions, FFC and periodic, both maps together. */
static void test_vulkan(void)
{
    frt_context *ctx = check_context();
    if (!ctx)
        return;
    float hv[3 * 4] = {0.2f, 0.4f, 0.6f, 0.8f, 0.9f, 0.7f, 0.5f, 0.3f, 0.35f, 0.45f, 0.55f, 0.65f};
    float av[2 * 2] = {1.0f, 0.25f, -2.0f, 4.0f};
    for (int periodic = 0; periodic <= 1; ++periodic)
        for (int region = 0; region <= 1; ++region) {
            frt_terrain_desc d = {0};
            d.levels = 9, d.sigma = 2.0, d.seed = 5, d.edge = periodic ? FRT_EDGE_PERIODIC : FRT_EDGE_FFC;
            d.hurst_map = (frt_map){hv, 4, 3};
            d.amplitude_map = (frt_map){av, 2, 2};
            if (region)
                d.region = (frt_region){periodic ? 500 : 100, 50, 120, 77};
            size_t count = frt_heightfield_size(&d);
            float *g = check_alloc(count * sizeof *g), *c = check_alloc(count * sizeof *c);
            frt_result r = frt_generate(ctx, &d, g, count, NULL);
            CHECK(r == FRT_SUCCESS, "vulkan with maps: %s", frt_context_error(ctx));
            CHECK(frt_generate_cpu(&d, c, count, NULL) == FRT_SUCCESS, "cpu with maps");
            CHECK(memcmp(g, c, count * sizeof *g) == 0, "maps %s %s: vulkan equals cpu bit for bit",
                  periodic ? "periodic" : "ffc", region ? "region" : "whole grid");
            free(g), free(c);
        }
    check_context_done(ctx);
}

int main(void)
{
    test_exp2();
    test_sampling();
    test_invalid();
    test_halves();
    test_vulkan();
    return check_summary("test_maps");
}
