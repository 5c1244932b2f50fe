/* context.c — the Vulkan context: instance, device choice, validation messages, buffers, pipelines, commands. */
#include "internal.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define VALIDATION_LAYER "VK_LAYER_KHRONOS_validation"

frt_result frt_set_error(frt_context *ctx, frt_result r, const char *fmt, ...)
{
    if (ctx) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(ctx->error, sizeof ctx->error, fmt, ap);
        va_end(ap);
    }
    return r;
}

static const char *vk_result_name(VkResult vr)
{
    switch (vr) {
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
    default: return "VkResult";
    }
}

frt_result frt_vk_check(frt_context *ctx, VkResult vr, const char *what)
{
    if (vr == VK_SUCCESS)
        return FRT_SUCCESS;
    frt_result r = FRT_ERROR_VULKAN;
    if (vr == VK_ERROR_OUT_OF_HOST_MEMORY || vr == VK_ERROR_OUT_OF_DEVICE_MEMORY)
        r = FRT_ERROR_OUT_OF_MEMORY;
    else if (vr == VK_ERROR_DEVICE_LOST)
        r = FRT_ERROR_DEVICE_LOST;
    return frt_set_error(ctx, r, "%s failed: %s (%d)", what, vk_result_name(vr), (int)vr);
}

static VKAPI_ATTR VkBool32 VKAPI_CALL on_validation(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                    VkDebugUtilsMessageTypeFlagsEXT types,
                                                    const VkDebugUtilsMessengerCallbackDataEXT *data, void *user)
{
    frt_context *ctx = user;
    /* Before the instance exists, general messages are the loader's own (e.g. "Found no drivers" when none is
     * installed); that case is reported once, as FRT_ERROR_NO_DEVICE with an install hint. */
    if (!ctx->instance && !(types & VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT))
        return VK_FALSE;
    if (severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)) {
        ctx->validation_messages++;
        fprintf(stderr, "fracterra: Vulkan validation: %s\n", data && data->pMessage ? data->pMessage : "(no text)");
    }
    return VK_FALSE;
}

static bool layer_available(const char *name)
{
    uint32_t n = 0;
    if (vkEnumerateInstanceLayerProperties(&n, NULL) != VK_SUCCESS || n == 0)
        return false;
    VkLayerProperties *layers = calloc(n, sizeof *layers);
    if (!layers)
        return false;
    bool found = false;
    if (vkEnumerateInstanceLayerProperties(&n, layers) == VK_SUCCESS)
        for (uint32_t i = 0; i < n && !found; ++i)
            found = strcmp(layers[i].layerName, name) == 0;
    free(layers);
    return found;
}

static const char NO_DRIVER_HINT[] =
    "no Vulkan driver found. For software Vulkan install Mesa lavapipe "
    "(Debian/Ubuntu: apt-get install mesa-vulkan-drivers libvulkan1), or use --backend cpu";

static frt_result create_instance(frt_context *ctx, bool validation)
{
    VkApplicationInfo app = {VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "fracterra";
    app.applicationVersion = VK_MAKE_VERSION(FRT_VERSION_MAJOR, FRT_VERSION_MINOR, FRT_VERSION_PATCH);
    app.pEngineName = "fracterra";
    app.apiVersion = VK_API_VERSION_1_2;
    const char *layers[] = {VALIDATION_LAYER};
    const char *exts[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    VkInstanceCreateInfo ci = {VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ci.pApplicationInfo = &app;
    VkDebugUtilsMessengerCreateInfoEXT mci = {VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mci.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    mci.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                      VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    mci.pfnUserCallback = on_validation;
    mci.pUserData = ctx;
    if (validation) {
        ci.enabledLayerCount = 1;
        ci.ppEnabledLayerNames = layers;
        ci.enabledExtensionCount = 1;
        ci.ppEnabledExtensionNames = exts;
        ci.pNext = &mci; /* also reports problems in vkCreateInstance/vkDestroyInstance */
    }
    VkResult vr = vkCreateInstance(&ci, NULL, &ctx->instance);
    if (vr == VK_ERROR_INCOMPATIBLE_DRIVER)
        return frt_set_error(ctx, FRT_ERROR_NO_DEVICE, "%s", NO_DRIVER_HINT);
    if (vr != VK_SUCCESS)
        return frt_vk_check(ctx, vr, "vkCreateInstance");
    if (validation) {
        PFN_vkCreateDebugUtilsMessengerEXT create =
            (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(ctx->instance, "vkCreateDebugUtilsMessengerEXT");
        if (!create)
            return frt_set_error(ctx, FRT_ERROR_UNSUPPORTED, "VK_EXT_debug_utils is not available");
        vr = create(ctx->instance, &mci, NULL, &ctx->messenger);
        if (vr != VK_SUCCESS)
            return frt_vk_check(ctx, vr, "vkCreateDebugUtilsMessengerEXT");
    }
    return FRT_SUCCESS;
}

/* Fills q with up to 32 queue families of pd and returns how many. */
static uint32_t queue_families(VkPhysicalDevice pd, VkQueueFamilyProperties q[32])
{
    uint32_t n = 32;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, q);
    return n;
}

static bool find_compute_queue(VkPhysicalDevice pd, uint32_t *family)
{
    VkQueueFamilyProperties q[32];
    uint32_t n = queue_families(pd, q);
    for (uint32_t i = 0; i < n; ++i)
        if (q[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
            *family = i;
            return true;
        }
    return false;
}

static void describe_device(VkPhysicalDevice pd, uint32_t index, frt_device_info *out)
{
    memset(out, 0, sizeof *out);
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(pd, &p);
    VkPhysicalDeviceMaintenance3Properties m3 = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    VkPhysicalDeviceProperties2 p2 = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &m3};
    vkGetPhysicalDeviceProperties2(pd, &p2);
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(pd, &mp);
    out->index = index;
    snprintf(out->name, sizeof out->name, "%s", p.deviceName);
    out->type = p.deviceType;
    out->api_version = p.apiVersion;
    for (uint32_t h = 0; h < mp.memoryHeapCount; ++h)
        if ((mp.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) &&
            mp.memoryHeaps[h].size > out->device_local_heap_bytes)
            out->device_local_heap_bytes = mp.memoryHeaps[h].size;
    out->max_allocation_bytes = m3.maxMemoryAllocationSize;
    out->max_storage_buffer_range = p.limits.maxStorageBufferRange;
    VkPhysicalDeviceVulkan12Features f12 = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 f2 = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
    uint32_t family;
    out->usable = false;
    if (VK_API_VERSION_MINOR(p.apiVersion) >= 2 || VK_API_VERSION_MAJOR(p.apiVersion) > 1) {
        vkGetPhysicalDeviceFeatures2(pd, &f2);
        out->usable = f12.bufferDeviceAddress && f2.features.shaderInt64 && find_compute_queue(pd, &family);
    }
}

static int type_rank(VkPhysicalDeviceType t)
{
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
    }
}

static bool contains_nocase(const char *hay, const char *needle)
{
    size_t n = strlen(needle);
    for (; *hay; ++hay) {
        size_t i = 0;
        while (i < n && hay[i] && tolower((unsigned char)hay[i]) == tolower((unsigned char)needle[i]))
            ++i;
        if (i == n)
            return true;
    }
    return n == 0;
}

static frt_result pick_device(frt_context *ctx, const char *want)
{
    uint32_t n = 0;
    VkResult vr = vkEnumeratePhysicalDevices(ctx->instance, &n, NULL);
    if (vr != VK_SUCCESS)
        return frt_vk_check(ctx, vr, "vkEnumeratePhysicalDevices");
    if (n == 0)
        return frt_set_error(ctx, FRT_ERROR_NO_DEVICE, "%s", NO_DRIVER_HINT);
    VkPhysicalDevice *pds = calloc(n, sizeof *pds);
    frt_device_info *infos = calloc(n, sizeof *infos);
    if (!pds || !infos) {
        free(pds);
        free(infos);
        return frt_set_error(ctx, FRT_ERROR_OUT_OF_MEMORY, "out of host memory listing devices");
    }
    vkEnumeratePhysicalDevices(ctx->instance, &n, pds);
    for (uint32_t i = 0; i < n; ++i)
        describe_device(pds[i], i, &infos[i]);

    int chosen = -1;
    frt_result r = FRT_SUCCESS;
    if (want && *want) {
        char *end = NULL;
        unsigned long idx = strtoul(want, &end, 10);
        bool numeric = isdigit((unsigned char)want[0]) && end && *end == '\0';
        for (uint32_t i = 0; i < n && chosen < 0; ++i)
            if (numeric ? idx == i : contains_nocase(infos[i].name, want))
                chosen = (int)i;
        if (chosen < 0)
            r = frt_set_error(ctx, FRT_ERROR_NO_DEVICE,
                              "no Vulkan device matches '%s' (%u device%s; 'fracterra devices' lists them)", want, n,
                              n == 1 ? "" : "s");
        else if (!infos[chosen].usable)
            r = frt_set_error(ctx, FRT_ERROR_UNSUPPORTED,
                              "device %d (%s) lacks Vulkan 1.2 bufferDeviceAddress, shaderInt64 or a compute queue",
                              chosen, infos[chosen].name);
    } else {
        for (uint32_t i = 0; i < n; ++i)
            if (infos[i].usable && (chosen < 0 || type_rank(infos[i].type) < type_rank(infos[chosen].type)))
                chosen = (int)i;
        if (chosen < 0)
            r = frt_set_error(ctx, FRT_ERROR_UNSUPPORTED,
                              "no Vulkan device has the Vulkan 1.2 bufferDeviceAddress and shaderInt64 features");
    }
    if (r == FRT_SUCCESS) {
        ctx->physical = pds[chosen];
        ctx->info = infos[chosen];
    }
    free(pds);
    free(infos);
    return r;
}

static frt_result create_device(frt_context *ctx)
{
    if (!find_compute_queue(ctx->physical, &ctx->queue_family))
        return frt_set_error(ctx, FRT_ERROR_UNSUPPORTED, "device has no compute queue");
    float prio = 1.0f;
    VkDeviceQueueCreateInfo qci = {VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = ctx->queue_family;
    qci.queueCount = 1;
    qci.pQueuePriorities = &prio;
    VkPhysicalDeviceVulkan12Features f12 = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    f12.bufferDeviceAddress = VK_TRUE;
    VkPhysicalDeviceFeatures2 f2 = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
    f2.features.shaderInt64 = VK_TRUE;
    VkDeviceCreateInfo dci = {VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &f2};
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    VkResult vr = vkCreateDevice(ctx->physical, &dci, NULL, &ctx->device);
    if (vr != VK_SUCCESS)
        return frt_vk_check(ctx, vr, "vkCreateDevice");
    vkGetDeviceQueue(ctx->device, ctx->queue_family, 0, &ctx->queue);
    return FRT_SUCCESS;
}

static frt_result finish_setup(frt_context *ctx)
{
    vkGetPhysicalDeviceProperties(ctx->physical, &ctx->props);
    vkGetPhysicalDeviceMemoryProperties(ctx->physical, &ctx->mem_props);
    VkCommandPoolCreateInfo pci = {VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = ctx->queue_family;
    frt_result r = frt_vk_check(ctx, vkCreateCommandPool(ctx->device, &pci, NULL, &ctx->pool), "vkCreateCommandPool");
    if (r != FRT_SUCCESS)
        return r;
    VkQueueFamilyProperties q[32];
    uint32_t n = queue_families(ctx->physical, q);
    if (ctx->queue_family < n && q[ctx->queue_family].timestampValidBits > 0) {
        VkQueryPoolCreateInfo qp = {VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        qp.queryType = VK_QUERY_TYPE_TIMESTAMP;
        qp.queryCount = 2;
        r = frt_vk_check(ctx, vkCreateQueryPool(ctx->device, &qp, NULL, &ctx->timestamps), "vkCreateQueryPool");
    }
    return r;
}

frt_result frt_context_create(const frt_context_desc *desc, frt_context **out, char *error, size_t error_size)
{
    frt_context_desc d;
    if (desc)
        d = *desc;
    else
        memset(&d, 0, sizeof d);
    if (!out)
        return FRT_ERROR_INVALID_ARGUMENT;
    *out = NULL;
    frt_context *ctx = calloc(1, sizeof *ctx);
    if (!ctx)
        return FRT_ERROR_OUT_OF_MEMORY;

    frt_validation v = d.validation;
    if (v == FRT_VALIDATION_DEFAULT) {
        const char *env = getenv("FRT_VALIDATION");
        v = (env && strcmp(env, "1") == 0) ? FRT_VALIDATION_IF_AVAILABLE : FRT_VALIDATION_OFF;
        if (env && strcmp(env, "required") == 0)
            v = FRT_VALIDATION_REQUIRED;
    }
    frt_result r = FRT_SUCCESS;
    if (d.vk_device) {
        if (!d.instance || !d.physical_device || !d.queue)
            r = frt_set_error(ctx, FRT_ERROR_INVALID_ARGUMENT,
                              "an external device needs instance, physical_device, vk_device and queue");
        ctx->owns_device = false;
        ctx->instance = d.instance;
        ctx->physical = d.physical_device;
        ctx->device = d.vk_device;
        ctx->queue = d.queue;
        ctx->queue_family = d.queue_family;
        describe_device(ctx->physical, 0, &ctx->info);
    } else {
        ctx->owns_device = true;
        bool have_layer = v != FRT_VALIDATION_OFF && layer_available(VALIDATION_LAYER);
        if (v == FRT_VALIDATION_REQUIRED && !have_layer)
            r = frt_set_error(ctx, FRT_ERROR_UNSUPPORTED,
                              "validation was required but " VALIDATION_LAYER
                              " is not installed (Debian: apt-get install vulkan-validationlayers)");
        if (r == FRT_SUCCESS)
            r = create_instance(ctx, have_layer);
        if (r == FRT_SUCCESS)
            r = pick_device(ctx, d.device);
        if (r == FRT_SUCCESS)
            r = create_device(ctx);
    }
    if (r == FRT_SUCCESS)
        r = finish_setup(ctx);
    if (r != FRT_SUCCESS) {
        if (error && error_size)
            snprintf(error, error_size, "%s", ctx->error[0] ? ctx->error : frt_result_string(r));
        frt_context_destroy(ctx);
        return r;
    }
    *out = ctx;
    return FRT_SUCCESS;
}

void frt_context_destroy(frt_context *ctx)
{
    if (!ctx)
        return;
    if (ctx->device) {
        vkDeviceWaitIdle(ctx->device);
        frt_generate_vk_release(ctx);
        frt_noise_vk_release(ctx);
        if (ctx->timestamps)
            vkDestroyQueryPool(ctx->device, ctx->timestamps, NULL);
        if (ctx->pool)
            vkDestroyCommandPool(ctx->device, ctx->pool, NULL);
        if (ctx->owns_device)
            vkDestroyDevice(ctx->device, NULL);
    }
    if (ctx->owns_device && ctx->instance) {
        if (ctx->messenger) {
            PFN_vkDestroyDebugUtilsMessengerEXT destroy = (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
                ctx->instance, "vkDestroyDebugUtilsMessengerEXT");
            if (destroy)
                destroy(ctx->instance, ctx->messenger, NULL);
        }
        vkDestroyInstance(ctx->instance, NULL);
    }
    free(ctx);
}

const frt_device_info *frt_context_device(const frt_context *ctx)
{
    return ctx ? &ctx->info : NULL;
}
const char *frt_context_error(const frt_context *ctx)
{
    return ctx ? ctx->error : "";
}
uint32_t frt_context_validation_messages(const frt_context *ctx)
{
    return ctx ? ctx->validation_messages : 0;
}

frt_result frt_enumerate_devices(frt_device_info *out, uint32_t *count)
{
    if (!count)
        return FRT_ERROR_INVALID_ARGUMENT;
    frt_context tmp;
    memset(&tmp, 0, sizeof tmp);
    frt_result r = create_instance(&tmp, false);
    if (r != FRT_SUCCESS) {
        *count = 0;
        return r;
    }
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(tmp.instance, &n, NULL);
    if (n == 0) {
        vkDestroyInstance(tmp.instance, NULL);
        *count = 0;
        return FRT_ERROR_NO_DEVICE;
    }
    if (out) {
        VkPhysicalDevice *pds = calloc(n, sizeof *pds);
        if (!pds) {
            vkDestroyInstance(tmp.instance, NULL);
            return FRT_ERROR_OUT_OF_MEMORY;
        }
        vkEnumeratePhysicalDevices(tmp.instance, &n, pds);
        if (n > *count)
            n = *count;
        for (uint32_t i = 0; i < n; ++i)
            describe_device(pds[i], i, &out[i]);
        free(pds);
    }
    *count = n;
    vkDestroyInstance(tmp.instance, NULL);
    return FRT_SUCCESS;
}

/* ---- helpers for the other Vulkan files ---- */

static int find_memory_type(const frt_context *ctx, uint32_t bits, VkMemoryPropertyFlags need,
                            VkMemoryPropertyFlags want)
{
    int fallback = -1;
    for (uint32_t i = 0; i < ctx->mem_props.memoryTypeCount; ++i) {
        VkMemoryPropertyFlags f = ctx->mem_props.memoryTypes[i].propertyFlags;
        if (!(bits & (1u << i)) || (f & need) != need)
            continue;
        if ((f & want) == want)
            return (int)i;
        if (fallback < 0)
            fallback = (int)i;
    }
    return fallback;
}

frt_result frt_buffer_create(frt_context *ctx, VkDeviceSize size, bool host_visible, struct frt_vk_buffer *out)
{
    memset(out, 0, sizeof *out);
    VkBufferCreateInfo bci = {VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = size;
    bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
                VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    frt_result r = frt_vk_check(ctx, vkCreateBuffer(ctx->device, &bci, NULL, &out->buffer), "vkCreateBuffer");
    if (r != FRT_SUCCESS)
        return r;
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx->device, out->buffer, &req);
    int type = host_visible
                   ? find_memory_type(ctx, req.memoryTypeBits,
                                      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                                      VK_MEMORY_PROPERTY_HOST_CACHED_BIT)
                   : find_memory_type(ctx, req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (type < 0) {
        frt_buffer_destroy(ctx, out);
        return frt_set_error(ctx, FRT_ERROR_UNSUPPORTED, "no suitable memory type for a %s buffer",
                             host_visible ? "host-visible" : "device");
    }
    VkMemoryAllocateFlagsInfo flags = {VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    VkMemoryAllocateInfo mai = {VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, &flags};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = (uint32_t)type;
    r = frt_vk_check(ctx, vkAllocateMemory(ctx->device, &mai, NULL, &out->memory), "vkAllocateMemory");
    if (r == FRT_SUCCESS)
        r = frt_vk_check(ctx, vkBindBufferMemory(ctx->device, out->buffer, out->memory, 0), "vkBindBufferMemory");
    if (r == FRT_SUCCESS && (ctx->mem_props.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) &&
        (ctx->mem_props.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT))
        r = frt_vk_check(ctx, vkMapMemory(ctx->device, out->memory, 0, VK_WHOLE_SIZE, 0, &out->mapped), "vkMapMemory");
    if (r != FRT_SUCCESS) {
        frt_buffer_destroy(ctx, out);
        return r;
    }
    VkBufferDeviceAddressInfo ai = {VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    ai.buffer = out->buffer;
    out->address = vkGetBufferDeviceAddress(ctx->device, &ai);
    out->size = size;
    return FRT_SUCCESS;
}

void frt_buffer_destroy(frt_context *ctx, struct frt_vk_buffer *b)
{
    if (b->buffer)
        vkDestroyBuffer(ctx->device, b->buffer, NULL);
    if (b->memory)
        vkFreeMemory(ctx->device, b->memory, NULL); /* unmaps implicitly */
    memset(b, 0, sizeof *b);
}

frt_result frt_pipeline_create(frt_context *ctx, const uint32_t *spirv, size_t spirv_bytes, uint32_t push_size,
                               VkPipeline *pipeline, VkPipelineLayout *layout)
{
    return frt_pipeline_create_spec(ctx, spirv, spirv_bytes, push_size, NULL, pipeline, layout);
}

frt_result frt_pipeline_create_spec(frt_context *ctx, const uint32_t *spirv, size_t spirv_bytes, uint32_t push_size,
                                    const VkSpecializationInfo *spec, VkPipeline *pipeline, VkPipelineLayout *layout)
{
    VkShaderModuleCreateInfo smci = {VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    smci.codeSize = spirv_bytes;
    smci.pCode = spirv;
    VkShaderModule module;
    frt_result r = frt_vk_check(ctx, vkCreateShaderModule(ctx->device, &smci, NULL, &module), "vkCreateShaderModule");
    if (r != FRT_SUCCESS)
        return r;
    if (!*layout) {
        VkPushConstantRange range = {VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size};
        VkPipelineLayoutCreateInfo lci = {VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        lci.pushConstantRangeCount = 1;
        lci.pPushConstantRanges = &range;
        r = frt_vk_check(ctx, vkCreatePipelineLayout(ctx->device, &lci, NULL, layout), "vkCreatePipelineLayout");
    }
    if (r == FRT_SUCCESS) {
        VkComputePipelineCreateInfo cci = {VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        cci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        cci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        cci.stage.module = module;
        cci.stage.pName = "main";
        cci.stage.pSpecializationInfo = spec;
        cci.layout = *layout;
        r = frt_vk_check(ctx, vkCreateComputePipelines(ctx->device, VK_NULL_HANDLE, 1, &cci, NULL, pipeline),
                         "vkCreateComputePipelines");
    }
    vkDestroyShaderModule(ctx->device, module, NULL);
    return r;
}

frt_result frt_cmd_begin(frt_context *ctx, VkCommandBuffer *cmd)
{
    VkCommandBufferAllocateInfo ai = {VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = ctx->pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    frt_result r = frt_vk_check(ctx, vkAllocateCommandBuffers(ctx->device, &ai, cmd), "vkAllocateCommandBuffers");
    if (r != FRT_SUCCESS)
        return r;
    VkCommandBufferBeginInfo bi = {VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    r = frt_vk_check(ctx, vkBeginCommandBuffer(*cmd, &bi), "vkBeginCommandBuffer");
    if (r != FRT_SUCCESS)
        vkFreeCommandBuffers(ctx->device, ctx->pool, 1, cmd);
    return r;
}

frt_result frt_cmd_submit_wait(frt_context *ctx, VkCommandBuffer cmd)
{
    frt_result r = frt_vk_check(ctx, vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    VkFence fence = VK_NULL_HANDLE;
    if (r == FRT_SUCCESS) {
        VkFenceCreateInfo fci = {VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        r = frt_vk_check(ctx, vkCreateFence(ctx->device, &fci, NULL, &fence), "vkCreateFence");
    }
    if (r == FRT_SUCCESS) {
        VkSubmitInfo si = {VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.commandBufferCount = 1;
        si.pCommandBuffers = &cmd;
        r = frt_vk_check(ctx, vkQueueSubmit(ctx->queue, 1, &si, fence), "vkQueueSubmit");
    }
    if (r == FRT_SUCCESS)
        r = frt_vk_check(ctx, vkWaitForFences(ctx->device, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
    if (fence)
        vkDestroyFence(ctx->device, fence, NULL);
    vkFreeCommandBuffers(ctx->device, ctx->pool, 1, &cmd);
    return r;
}
