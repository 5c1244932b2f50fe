/* test_generate_vk.c — host/generate_vk.c: the Vulkan generator against the CPU reference, its per-level
 * statistics, exact properties, grids beyond one storage-buffer binding, limits, and a caller-owned device. */
#include "stats.h"

typedef struct vk_case {
    uint32_t levels;
    double hurst, sigma;
    uint64_t seed;
} vk_case;

static frt_terrain_desc make(vk_case c)
{
    frt_terrain_desc d = {0};
    d.levels = c.levels, d.hurst = c.hurst, d.sigma = c.sigma, d.seed = c.seed, d.seed_is_explicit = true;
    frt_terrain_desc_resolved(&d, &d);
    return d;
}

/* Vulkan vs CPU: bit-identical (spec v2, ALGORITHM.md §5): every step of the noise and of the refinement is a float32
 * +, -, * without contraction on both sides. Returns the number of points that differ. */
static size_t compare(frt_context *ctx, vk_case c, bool stats)
{
    frt_terrain_desc d = make(c);
    size_t count = frt_heightfield_size(&d);
    float *gpu = check_alloc(count * sizeof(float)), *cpu = check_alloc(count * sizeof(float));
    frt_run_info info;
    frt_result r = frt_generate(ctx, &d, gpu, count, &info);
    CHECK(r == FRT_SUCCESS, "levels %u: %s", c.levels, frt_context_error(ctx));
    CHECK(info.dispatches == c.levels + 1, "one dispatch per level: %u", info.dispatches);
    CHECK(frt_generate_cpu(&d, cpu, count, NULL) == FRT_SUCCESS, "cpu");
    size_t differ = 0;
    for (size_t i = 0; i < count; ++i)
        differ += memcmp(&gpu[i], &cpu[i], 4) != 0;
    double rel = max_abs_diff(gpu, cpu, count) / fabs(c.sigma);
    CHECK(differ == 0 && memcmp(gpu, cpu, count * sizeof(float)) == 0,
          "levels %u H %.2f sigma %g seed %llu: %zu of %zu points differ, max |vk - cpu| = %.3g |sigma|", c.levels,
          c.hurst, c.sigma, (unsigned long long)c.seed, differ, count, rel);
    printf("levels %2u H %.2f sigma %-8g seed %-20llu vk vs cpu: %zu of %zu points differ\n", c.levels, c.hurst,
           c.sigma, (unsigned long long)c.seed, differ, count);
    if (stats)
        check_level_statistics("vulkan", gpu, &d);
    free(gpu), free(cpu);
    return differ;
}

static void test_exact(frt_context *ctx)
{
    vk_case small = {7, 0.6, 1.5, 2024}, big = {10, 0.6, 1.5, 2024};
    frt_terrain_desc ds = make(small), db = make(big);
    float *a = check_alloc(129 * 129 * 4), *b = check_alloc(1025 * 1025 * 4), *c = check_alloc(1025 * 1025 * 4);
    CHECK(frt_generate(ctx, &ds, a, 129 * 129, NULL) == FRT_SUCCESS, "%s", frt_context_error(ctx));
    CHECK(frt_generate(ctx, &db, b, 1025 * 1025, NULL) == FRT_SUCCESS, "%s", frt_context_error(ctx));
    size_t wrong = 0;
    for (uint32_t y = 0; y <= 128; ++y)
        for (uint32_t x = 0; x <= 128; ++x)
            wrong += memcmp(&a[y * 129 + x], &b[(size_t)(8 * y) * 1025 + 8 * x], 4) != 0;
    CHECK(wrong == 0, "vulkan resolution independence: %zu points differ", wrong);
    CHECK(frt_generate(ctx, &db, c, 1025 * 1025, NULL) == FRT_SUCCESS, "%s", frt_context_error(ctx));
    CHECK(memcmp(b, c, 1025 * 1025 * 4) == 0, "vulkan determinism: same inputs, same bytes");
    db.seed = 2025;
    CHECK(frt_generate(ctx, &db, c, 1025 * 1025, NULL) == FRT_SUCCESS, "%s", frt_context_error(ctx));
    size_t same = 0;
    for (size_t i = 0; i < 1025 * 1025; ++i)
        same += b[i] == c[i];
    CHECK(same < 1025 * 1025 / 1000, "another seed gives another field (%zu equal)", same);
    /* (Border points: test_reference checks the 3-point formula exactly; compare() holds the device to it.) */
    CHECK(frt_generate(ctx, &ds, a, 129 * 128, NULL) == FRT_ERROR_BUFFER_TOO_SMALL, "short output rejected");
    free(a), free(b), free(c);
}

/* 8193^2 floats (256 MiB) exceed lavapipe's 128 MiB storage-buffer range: the device address path must hold. */
static void test_large(frt_context *ctx)
{
    const frt_device_info *dev = frt_context_device(ctx);
    vk_case c = {13, 0.75, 1.0, 5};
    frt_terrain_desc d = make(c);
    size_t count = frt_heightfield_size(&d);
    if ((uint64_t)count * 4 > dev->max_allocation_bytes) {
        printf("skipping 8193^2: %s allows %llu bytes per allocation\n", dev->name,
               (unsigned long long)dev->max_allocation_bytes);
        return;
    }
    printf("8193^2 = %.0f MiB vs maxStorageBufferRange %.0f MiB\n", count * 4.0 / 1048576.0,
           dev->max_storage_buffer_range / 1048576.0);
    compare(ctx, c, false);
    /* 16385^2 (1 GiB) where the device can hold it: every 2nd point must equal the 8193^2 field bit for bit
     * (resolution independence on one backend is exact), which was just compared with the CPU. */
    frt_terrain_desc d14 = make((vk_case){14, 0.75, 1.0, 5});
    size_t c14 = frt_heightfield_size(&d14);
    if ((uint64_t)c14 * 4 <= dev->max_allocation_bytes && (uint64_t)c14 * 4 <= dev->device_local_heap_bytes) {
        float *f13 = check_alloc(count * 4), *f14 = check_alloc(c14 * 4);
        CHECK(frt_generate(ctx, &d, f13, count, NULL) == FRT_SUCCESS, "%s", frt_context_error(ctx));
        frt_result r14 = frt_generate(ctx, &d14, f14, c14, NULL);
        CHECK(r14 == FRT_SUCCESS, "16385^2: %s", frt_context_error(ctx));
        size_t wrong = 0;
        for (uint32_t y = 0; y < 8193 && r14 == FRT_SUCCESS; ++y)
            for (uint32_t x = 0; x < 8193; ++x)
                wrong += memcmp(&f13[(size_t)y * 8193 + x], &f14[(size_t)(2 * y) * 16385 + 2 * x], 4) != 0;
        CHECK(wrong == 0, "16385^2 subsampled differs from 8193^2 at %zu points", wrong);
        printf("16385^2 on %s: %s\n", dev->name, r14 == FRT_SUCCESS && wrong == 0 ? "ok" : "FAILED");
        free(f13), free(f14);
    }
    /* Beyond what the device can allocate: a clear error, nothing written. */
    frt_terrain_desc huge = make((vk_case){15, 0.75, 1.0, 5});
    size_t hc = frt_heightfield_size(&huge);
    if ((uint64_t)hc * 4 > dev->max_allocation_bytes) {
        float probe = 1.0f; /* not written: the size check comes first, and the buffer is too small anyway */
        frt_result r = frt_generate(ctx, &huge, &probe, hc, NULL);
        CHECK(r == FRT_ERROR_TOO_LARGE, "32769^2 on %s: %s", dev->name, frt_result_string(r));
        CHECK(strstr(frt_context_error(ctx), "MiB") != NULL, "message names the sizes: %s", frt_context_error(ctx));
        printf("32769^2: %s\n", frt_context_error(ctx));
    }
}

/* The library on a VkDevice that the caller created (with the two features it needs). */
static void test_external_device(void)
{
    VkApplicationInfo app = {VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_2;
    VkInstanceCreateInfo ici = {VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pApplicationInfo = &app;
    VkInstance inst;
    if (vkCreateInstance(&ici, NULL, &inst) != VK_SUCCESS) {
        CHECK(0, "test instance");
        return;
    }
    uint32_t n = 1;
    VkPhysicalDevice pd;
    vkEnumeratePhysicalDevices(inst, &n, &pd);
    float prio = 1.0f;
    VkDeviceQueueCreateInfo q = {VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    q.queueFamilyIndex = 0; /* family 0 has compute on lavapipe and on every desktop GPU */
    q.queueCount = 1;
    q.pQueuePriorities = &prio;
    VkPhysicalDeviceVulkan12Features f12 = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    f12.bufferDeviceAddress = VK_TRUE;
    VkPhysicalDeviceFeatures2 f2 = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
    f2.features.shaderInt64 = VK_TRUE;
    VkDeviceCreateInfo dci = {VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &f2};
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &q;
    VkDevice dev;
    if (n == 0 || vkCreateDevice(pd, &dci, NULL, &dev) != VK_SUCCESS) {
        CHECK(0, "test device");
        vkDestroyInstance(inst, NULL);
        return;
    }
    frt_context_desc cd = {0};
    cd.instance = inst, cd.physical_device = pd, cd.vk_device = dev, cd.queue_family = 0;
    vkGetDeviceQueue(dev, 0, 0, &cd.queue);
    frt_context *ctx = NULL;
    char err[512];
    CHECK(frt_context_create(&cd, &ctx, err, sizeof err) == FRT_SUCCESS, "external context: %s", err);
    if (ctx) {
        frt_terrain_desc d = make((vk_case){6, 0.5, 1.0, 3});
        float a[65 * 65], b[65 * 65];
        CHECK(frt_generate(ctx, &d, a, 65 * 65, NULL) == FRT_SUCCESS, "%s", frt_context_error(ctx));
        frt_generate_cpu(&d, b, 65 * 65, NULL);
        CHECK(memcmp(a, b, sizeof a) == 0, "external device result is the CPU's, bit for bit");
        frt_context_destroy(ctx); /* must leave the caller's device alive */
    }
    CHECK(vkDeviceWaitIdle(dev) == VK_SUCCESS, "caller's device still usable");
    vkDestroyDevice(dev, NULL);
    vkDestroyInstance(inst, NULL);
}

/* Periodic mode (ALGORITHM.md §3.1) on the device: bit-identical to the CPU, for both shader variants (B = 4 runs
 * from level 6), and the wrap is really there (row 0's neighbour above is the last row). */
static void test_periodic(frt_context *ctx)
{
    const uint32_t levels[] = {1, 2, 3, 6, 9, 10};
    for (size_t k = 0; k < sizeof levels / sizeof levels[0]; ++k) {
        frt_terrain_desc d = {0};
        d.levels = levels[k], d.hurst = 0.6, d.sigma = -1.5, d.seed = 40 + k, d.edge = FRT_EDGE_PERIODIC;
        size_t count = frt_heightfield_size(&d);
        uint32_t side = frt_terrain_side(&d);
        CHECK(side == 1u << levels[k] && count == (size_t)side * side, "periodic side %u", side);
        float *gpu = check_alloc(count * sizeof(float)), *cpu = check_alloc(count * sizeof(float));
        CHECK(frt_generate(ctx, &d, gpu, count, NULL) == FRT_SUCCESS, "periodic %u: %s", levels[k],
              frt_context_error(ctx));
        CHECK(frt_generate_cpu(&d, cpu, count, NULL) == FRT_SUCCESS, "periodic cpu");
        size_t differ = 0;
        for (size_t i = 0; i < count; ++i)
            differ += memcmp(&gpu[i], &cpu[i], 4) != 0;
        CHECK(differ == 0, "periodic levels %u: %zu of %zu points differ between vulkan and cpu", levels[k], differ,
              count);
        printf("periodic levels %2u vk vs cpu: %zu of %zu points differ\n", levels[k], differ, count);
        free(gpu), free(cpu);
    }
}

/* A region on the device and on the CPU; both NULL-free on success. */
static bool region_both(frt_context *ctx, frt_terrain_desc d, float **gpu, float **cpu, frt_run_info *info)
{
    size_t count = frt_heightfield_size(&d);
    *gpu = check_alloc((count ? count : 1) * sizeof(float));
    *cpu = check_alloc((count ? count : 1) * sizeof(float));
    frt_result r = frt_generate(ctx, &d, *gpu, count, info);
    CHECK(r == FRT_SUCCESS, "region %u,%u %ux%u at n=%u: %s", d.region.x, d.region.y, d.region.width, d.region.height,
          d.levels, frt_context_error(ctx));
    return r == FRT_SUCCESS && count && frt_generate_cpu(&d, *cpu, count, NULL) == FRT_SUCCESS;
}

/* §3.2 on the device: a region equals the crop of the whole device grid and the CPU region, bit for bit. */
static void test_regions(frt_context *ctx)
{
    uint64_t st = 7;
    for (int periodic = 0; periodic <= 1; ++periodic) {
        const uint32_t levels[] = {1, 3, 7, 12};
        for (size_t k = 0; k < sizeof levels / sizeof levels[0]; ++k) {
            frt_terrain_desc d = {0};
            d.levels = levels[k], d.hurst = 0.55, d.sigma = 2.0, d.seed = 300 + k;
            d.edge = periodic ? FRT_EDGE_PERIODIC : FRT_EDGE_FFC;
            const uint32_t M = frt_terrain_side(&d);
            size_t count = frt_heightfield_size(&d);
            float *full = check_alloc(count * sizeof(float));
            CHECK(frt_generate(ctx, &d, full, count, NULL) == FRT_SUCCESS, "%s", frt_context_error(ctx));
            int bad = 0, windows = periodic || levels[k] < 12 ? 30 : 20;
            for (int t = 0; t < windows; ++t) {
                uint32_t w, h, x0, y0;
                if (t < 4) { /* a corner square, then the whole grid */
                    w = h = t == 3 ? M : (M < 5 ? M : 5);
                    x0 = (t & 1) ? M - w : 0, y0 = (t & 2) ? M - h : 0;
                    if (t == 3)
                        x0 = y0 = 0;
                } else {
                    st = st * 6364136223846793005ull + 1442695040888963407ull;
                    w = 1 + (uint32_t)(st >> 33) % (M < 300 ? M : 300);
                    st = st * 6364136223846793005ull + 1442695040888963407ull;
                    h = 1 + (uint32_t)(st >> 33) % (M < 300 ? M : 300);
                    st = st * 6364136223846793005ull + 1442695040888963407ull;
                    x0 = (uint32_t)(st >> 33) % (periodic ? M : M - w + 1);
                    st = st * 6364136223846793005ull + 1442695040888963407ull;
                    y0 = (uint32_t)(st >> 33) % (periodic ? M : M - h + 1);
                }
                d.region = (frt_region){x0, y0, w, h};
                float *gpu, *cpu;
                frt_run_info info = {0};
                bool ok = region_both(ctx, d, &gpu, &cpu, &info) && info.dispatches == levels[k] + 1 &&
                          memcmp(gpu, cpu, (size_t)w * h * sizeof(float)) == 0;
                for (uint32_t y = 0; ok && y < h; ++y)
                    for (uint32_t x = 0; x < w; ++x)
                        ok = ok &&
                             memcmp(&gpu[(size_t)y * w + x], &full[(size_t)((y0 + y) % M) * M + (x0 + x) % M], 4) == 0;
                if (!ok && bad++ < 3)
                    fprintf(stderr, "  %s n=%u window %u,%u %ux%u differs\n", periodic ? "periodic" : "ffc", levels[k],
                            x0, y0, w, h);
                free(gpu), free(cpu);
                d.region = (frt_region){0};
            }
            CHECK(bad == 0, "vulkan %s n=%u: %d of %d regions equal the CPU region and the crop of the whole grid",
                  periodic ? "periodic" : "ffc", levels[k], windows - bad, windows);
            free(full);
        }
    }
    /* Deep: n = 24 (a 1024^2 window) and n = 30 (FFC far corner, periodic across the wrap). */
    const struct {
        uint32_t n;
        frt_edge edge;
        frt_region g;
    } deep[] = {{24, FRT_EDGE_FFC, {5000000, 7000000, 1024, 1024}},
                {30, FRT_EDGE_FFC, {(1u << 30) - 99, (1u << 30) - 63, 100, 64}},
                {30, FRT_EDGE_PERIODIC, {(1u << 30) - 50, 3, 101, 77}}};
    for (size_t k = 0; k < sizeof deep / sizeof deep[0]; ++k) {
        frt_terrain_desc d = {0};
        d.levels = deep[k].n, d.edge = deep[k].edge, d.region = deep[k].g, d.seed = 11;
        float *gpu, *cpu;
        frt_run_info info = {0};
        bool ok = region_both(ctx, d, &gpu, &cpu, &info);
        size_t count = (size_t)d.region.width * d.region.height;
        CHECK(ok && memcmp(gpu, cpu, count * sizeof(float)) == 0 && info.dispatches == d.levels + 1,
              "n=%u %s region %ux%u: vulkan equals cpu bit for bit (%u dispatches)", d.levels,
              d.edge == FRT_EDGE_PERIODIC ? "periodic" : "ffc", d.region.width, d.region.height, info.dispatches);
        printf("region n=%u %ux%u: %.3f s on the device, %.3f s in all\n", d.levels, d.region.width, d.region.height,
               info.device_seconds, info.total_seconds);
        free(gpu), free(cpu);
    }
}

/* §3.4 on the device: densified grids and regions equal the CPU's bit for bit; levels k+1..n are dispatched. */
static void test_densify(frt_context *ctx)
{
    for (int periodic = 0; periodic <= 1; ++periodic)
        for (uint32_t k = 1; k <= 9; k += 4) {
            const uint32_t cs = (1u << k) + (periodic ? 0u : 1u);
            float *coarse = check_alloc((size_t)cs * cs * sizeof *coarse);
            for (uint32_t i = 0; i < cs * cs; ++i)
                coarse[i] = (i % 5 == 2) ? NAN : (float)((i * 2654435761u) % 977) * 0.5f;
            for (int region = 0; region <= 1; ++region) {
                frt_terrain_desc d = {0};
                d.levels = 10, d.hurst = 0.45, d.sigma = 20.0, d.seed = 8 + k;
                d.edge = periodic ? FRT_EDGE_PERIODIC : FRT_EDGE_FFC;
                d.coarse = coarse, d.coarse_levels = k;
                if (region)
                    d.region = (frt_region){periodic ? 1000 : 3, 500, 200, 130};
                float *gpu, *cpu;
                frt_run_info info = {0};
                bool ok = region_both(ctx, d, &gpu, &cpu, &info);
                size_t count = frt_heightfield_size(&d);
                CHECK(ok && memcmp(gpu, cpu, count * sizeof(float)) == 0 && info.dispatches == 10 - k,
                      "densify %s k=%u %s: vulkan equals cpu (%u dispatches)", periodic ? "periodic" : "ffc", k,
                      region ? "region" : "whole grid", info.dispatches);
                free(gpu), free(cpu);
            }
            free(coarse);
        }
}

int main(void)
{
    frt_context *ctx = check_context();
    if (!ctx)
        return CHECK_SKIP;
    const vk_case cases[] = {
        {1, 0.8, 1.0, 1},   {2, 0.5, 1.0, 9},       {5, 0.8, 1.0, 1},
        {6, 0.3, -2.0, 77}, {8, 0.9, 1e-3, 123456}, {9, 0.8, 1.0, 1},
        {10, 0.3, 1.0, 11}, {10, 0.5, 250.0, 0},    {10, 0.8, -1.0, 0xdeadbeefcafef00dull},
    };
    size_t differ = 0, ncases = sizeof cases / sizeof cases[0];
    for (size_t i = 0; i < ncases; ++i)
        differ += compare(ctx, cases[i], cases[i].levels == 10);
    printf("vk vs cpu over %zu grids: %zu points differ (bit-identical required)\n", ncases, differ);
    test_exact(ctx);
    test_periodic(ctx);
    test_regions(ctx);
    test_densify(ctx);
    test_large(ctx);

    check_context_done(ctx);
    test_external_device();
    return check_summary("test_generate_vk");
}
