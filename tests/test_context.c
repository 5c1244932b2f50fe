/* test_context.c — host/context.c: device choice by index and name, validation messages are counted, and a
 * missing Vulkan driver gives the install hint. */
#include "check.h"

#include <stdlib.h>

int main(int argc, char **argv)
{
    /* Run again with no driver: the loader reads VK_DRIVER_FILES (and the older VK_ICD_FILENAMES) at its first use
     * in a process, so this case gets its own process: `test_context --no-driver`. */
    if (argc > 1 && strcmp(argv[1], "--no-driver") == 0) {
        setenv("VK_DRIVER_FILES", "/nonexistent/icd.json", 1);
        setenv("VK_ICD_FILENAMES", "/nonexistent/icd.json", 1);
        frt_context *ctx = NULL;
        char err[512] = "";
        frt_result r = frt_context_create(NULL, &ctx, err, sizeof err);
        CHECK(r == FRT_ERROR_NO_DEVICE && ctx == NULL, "no driver: %s", frt_result_string(r));
        CHECK(strstr(err, "mesa-vulkan-drivers") != NULL, "the message says how to install lavapipe: %s", err);
        uint32_t n = 5;
        CHECK(frt_enumerate_devices(NULL, &n) == FRT_ERROR_NO_DEVICE && n == 0, "no devices listed");
        return check_summary("test_context --no-driver");
    }

    frt_context *ctx = check_context();
    if (!ctx)
        return CHECK_SKIP;
    const frt_device_info *dev = frt_context_device(ctx);
    CHECK(dev->usable && dev->name[0], "device info");
    CHECK(frt_context_error(ctx)[0] == '\0', "no error yet");

    uint32_t n = 0;
    CHECK(frt_enumerate_devices(NULL, &n) == FRT_SUCCESS && n >= 1, "devices: %u", n);
    frt_device_info *all = check_alloc(n * sizeof *all);
    CHECK(frt_enumerate_devices(all, &n) == FRT_SUCCESS, "list");
    bool listed = false;
    for (uint32_t i = 0; i < n; ++i)
        listed |= strcmp(all[i].name, dev->name) == 0;
    CHECK(listed, "the chosen device is listed");

    char err[512];
    frt_context *other = NULL;
    frt_context_desc cd = {0};
    cd.device = "no-such-device-xyz";
    CHECK(frt_context_create(&cd, &other, err, sizeof err) == FRT_ERROR_NO_DEVICE && !other, "unknown name");
    CHECK(strstr(err, "no-such-device-xyz") != NULL, "message names it: %s", err);
    char idx[16];
    snprintf(idx, sizeof idx, "%u", n); /* one past the last */
    cd.device = idx;
    CHECK(frt_context_create(&cd, &other, err, sizeof err) == FRT_ERROR_NO_DEVICE, "index out of range");
    cd.device = "0";
    CHECK(frt_context_create(&cd, &other, err, sizeof err) == FRT_SUCCESS, "device by index: %s", err);
    CHECK(other && strcmp(frt_context_device(other)->name, all[0].name) == 0, "index 0 is the first listed");
    frt_context_destroy(other);
    /* a case-insensitive substring of the name */
    char part[8] = {0};
    for (int i = 0; i < 4 && all[0].name[i]; ++i)
        part[i] = (char)(all[0].name[i] >= 'a' && all[0].name[i] <= 'z' ? all[0].name[i] - 32 : all[0].name[i]);
    cd.device = part;
    CHECK(frt_context_create(&cd, &other, err, sizeof err) == FRT_SUCCESS, "device by name '%s': %s", part, err);
    frt_context_destroy(other);
    free(all);

    /* The validation counter really counts: a buffer of size 0 breaks a valid-usage rule. Only meaningful when the
     * layer is loaded; CI requires it (FRT_TEST_REQUIRE_VALIDATION=1). */
    frt_context_desc vd = {0};
    vd.validation = FRT_VALIDATION_IF_AVAILABLE;
    frt_context *v = NULL;
    if (frt_context_create(&vd, &v, err, sizeof err) == FRT_SUCCESS && v->messenger) {
        VkBufferCreateInfo bci = {VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        bci.size = 0; /* VUID-VkBufferCreateInfo-size-00912 */
        bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
        VkBuffer b = VK_NULL_HANDLE;
        fprintf(stderr, "(the next validation message is expected)\n");
        if (vkCreateBuffer(v->device, &bci, NULL, &b) == VK_SUCCESS && b)
            vkDestroyBuffer(v->device, b, NULL);
        CHECK(frt_context_validation_messages(v) >= 1, "the deliberate error was counted");
        printf("validation layer active: deliberate error counted\n");
    } else {
        printf("validation layer not installed: counter not exercised\n");
    }
    frt_context_destroy(v);
    check_context_done(ctx);
    return check_summary("test_context");
}
