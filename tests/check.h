/* check.h — the tests' small harness: CHECK macros that count, a summary line, and a shared Vulkan context. */
#ifndef FRT_CHECK_H
#define FRT_CHECK_H

#include "internal.h"

#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int check_passed, check_failed;

#define CHECK(cond, ...)                                                                                               \
    do {                                                                                                               \
        if (cond) {                                                                                                    \
            ++check_passed;                                                                                            \
        } else {                                                                                                       \
            ++check_failed;                                                                                            \
            fprintf(stderr, "FAIL %s:%d: %s: ", __FILE__, __LINE__, #cond);                                            \
            fprintf(stderr, __VA_ARGS__);                                                                              \
            fputc('\n', stderr);                                                                                       \
        }                                                                                                              \
    } while (0)

/* ctest treats exit code 77 as "skipped" (SKIP_RETURN_CODE in tests/CMakeLists.txt). */
#define CHECK_SKIP 77

static inline int check_summary(const char *name)
{
    printf("%s: %d passed, %d failed\n", name, check_passed, check_failed);
    return check_failed ? 1 : 0;
}

static inline void *check_alloc(size_t bytes)
{
    void *p = malloc(bytes);
    if (!p) {
        fprintf(stderr, "out of memory (%zu bytes)\n", bytes);
        exit(2);
    }
    return p;
}

/* Under LeakSanitizer: the Vulkan loader unloads the driver and layer libraries when the instance goes, and their
 * process-lifetime allocations then show as "<unknown module>", which no suppression can name. Loading them
 * once more with RTLD_NODELETE keeps them mapped so tests/lsan.supp can match them by library name. */
static inline void check_pin_vulkan_modules(void)
{
#if defined(__SANITIZE_ADDRESS__)
    const char *libs[] = {"libvulkan_lvp.so", "libVkLayer_khronos_validation.so"};
    for (int i = 0; i < 2; ++i)
        (void)dlopen(libs[i], RTLD_NOW | RTLD_NODELETE);
#endif
}

/* A context with validation on where installed (required when FRT_TEST_REQUIRE_VALIDATION=1). Returns NULL when
 * there is no Vulkan device and FRT_TEST_REQUIRE_VULKAN is not 1 (the caller then skips); with it set, a missing
 * device is a failure. */
static inline frt_context *check_context(void)
{
    const char *req_val = getenv("FRT_TEST_REQUIRE_VALIDATION");
    const char *req_vk = getenv("FRT_TEST_REQUIRE_VULKAN");
    check_pin_vulkan_modules();
    frt_context_desc cd;
    memset(&cd, 0, sizeof cd);
    cd.device = getenv("FRT_TEST_DEVICE");
    cd.validation = req_val && strcmp(req_val, "1") == 0 ? FRT_VALIDATION_REQUIRED : FRT_VALIDATION_IF_AVAILABLE;
    frt_context *ctx = NULL;
    char err[1024];
    frt_result r = frt_context_create(&cd, &ctx, err, sizeof err);
    if (r != FRT_SUCCESS) {
        bool required = req_vk && strcmp(req_vk, "1") == 0;
        fprintf(stderr, "%s: no Vulkan context: %s\n", required ? "FAIL" : "SKIP", err);
        if (required)
            exit(1);
        return NULL;
    }
    printf("device: %s\n", frt_context_device(ctx)->name);
    return ctx;
}

/* Destroys the context and checks that the validation layer said nothing. */
static inline void check_context_done(frt_context *ctx)
{
    if (!ctx)
        return;
    uint32_t messages = frt_context_validation_messages(ctx);
    frt_context_destroy(ctx);
    CHECK(messages == 0, "%u Vulkan validation messages (printed above)", messages);
}

static inline float max_abs_diff(const float *a, const float *b, size_t n)
{
    float m = 0.0f;
    for (size_t i = 0; i < n; ++i) {
        float d = fabsf(a[i] - b[i]);
        if (!(d <= m)) /* also catches NaN */
            m = isnan(d) ? INFINITY : d;
    }
    return m;
}

#endif
