/* fracterra.h — public API: fractal terrain by random midpoint displacement (FFC / diamond-square)
 * on Vulkan compute, with a CPU reference. The algorithm and noise contract: docs/ALGORITHM.md. */
#ifndef FRACTERRA_H
#define FRACTERRA_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#ifdef __cplusplus
extern "C" {
#endif

#define FRT_VERSION_MAJOR 0
#define FRT_VERSION_MINOR 1
#define FRT_VERSION_PATCH 0
#define FRT_VERSION_STRING "0.1.0"
/* Version of the noise-stream contract (docs/ALGORITHM.md) that this build implements. */
#define FRT_SPEC_VERSION 1

#define FRT_DEFAULT_LEVELS 9u /* 513 x 513, as in the 1988 report */
#define FRT_DEFAULT_HURST 0.8
#define FRT_DEFAULT_SIGMA 1.0
#define FRT_DEFAULT_SEED 1u
#define FRT_MAX_LEVELS 15u /* 32769^2 floats = 4 GiB; devices may allow less */

/* Results. 0 is success; the others are grouped by kind (tens digit). */
typedef enum frt_result {
    FRT_SUCCESS = 0,
    FRT_ERROR_INVALID_ARGUMENT = 10, /* a parameter is out of range or inconsistent */
    FRT_ERROR_BUFFER_TOO_SMALL = 11, /* caller's output is smaller than frt_heightfield_size() */
    FRT_ERROR_UNSUPPORTED = 20,      /* the device lacks a required feature */
    FRT_ERROR_TOO_LARGE = 21,        /* the grid exceeds what the device or host can hold */
    FRT_ERROR_OUT_OF_MEMORY = 30,
    FRT_ERROR_NO_DEVICE = 40, /* no Vulkan driver or no matching device */
    FRT_ERROR_VULKAN = 41,    /* a Vulkan call failed */
    FRT_ERROR_DEVICE_LOST = 42,
    FRT_ERROR_IO = 50 /* reading or writing a file failed */
} frt_result;

/* A short static English description of `r`; never NULL. */
const char *frt_result_string(frt_result r);

/* How border points are treated. FFC: a border square point averages its 3 existing neighbours. */
typedef enum frt_edge { FRT_EDGE_DEFAULT = 0, FRT_EDGE_FFC = 1 } frt_edge;

typedef enum frt_backend {
    FRT_BACKEND_DEFAULT = 0, /* auto: Vulkan if a device exists, else CPU */
    FRT_BACKEND_VULKAN = 1,
    FRT_BACKEND_CPU = 2
} frt_backend;

/* What to generate. Zero-initialise, then set what you need: every zero field means its default. */
typedef struct frt_terrain_desc {
    uint32_t levels;       /* n: grid side is 2^n + 1; 0 -> 9; valid 1..FRT_MAX_LEVELS */
    double hurst;          /* H in (0,1); 0 -> 0.8. Fractal dimension D = 3 - H */
    double sigma;          /* amplitude, any non-zero real (negative inverts peaks/valleys); 0 -> 1 */
    uint64_t seed;         /* Philox key; 0 -> 1 unless seed_is_explicit */
    bool seed_is_explicit; /* true: use `seed` as given, even 0 */
    frt_edge edge;         /* 0 -> FRT_EDGE_FFC */
} frt_terrain_desc;

/* Fills `out` with `in` (NULL = all defaults) with every default made explicit, and checks ranges.
 * Returns FRT_ERROR_INVALID_ARGUMENT (leaving `out` filled as far as possible) if a value is out of range. */
frt_result frt_terrain_desc_resolved(const frt_terrain_desc *in, frt_terrain_desc *out);

/* Grid side 2^levels + 1, or 0 if levels is 0 or > FRT_MAX_LEVELS (no defaults applied). */
uint32_t frt_grid_side(uint32_t levels);

/* Number of floats a heightfield for `desc` needs (defaults applied), or 0 if `desc` is invalid.
 * The product is checked against SIZE_MAX; allocates nothing. */
size_t frt_heightfield_size(const frt_terrain_desc *desc);

/* Optional figures from a generation run. */
typedef struct frt_run_info {
    double device_seconds; /* time of the dispatches measured on the device (timestamps); CPU: compute time */
    double total_seconds;  /* wall time of the whole call, read-back included */
    uint32_t dispatches;   /* compute dispatches recorded (levels + 1) */
} frt_run_info;

/* CPU reference: single-threaded, plain C, the yardstick for every backend. Writes exactly
 * frt_heightfield_size(desc) floats, row-major h[y*M + x], into `out`; never writes outside it.
 * `info` may be NULL. */
frt_result frt_generate_cpu(const frt_terrain_desc *desc, float *out, size_t out_count, frt_run_info *info);

/* ---- Vulkan ---- */

typedef struct frt_context frt_context;

typedef enum frt_validation {
    FRT_VALIDATION_DEFAULT = 0, /* off, unless the environment sets FRT_VALIDATION=1 */
    FRT_VALIDATION_OFF = 1,
    FRT_VALIDATION_IF_AVAILABLE = 2, /* enable VK_LAYER_KHRONOS_validation when installed */
    FRT_VALIDATION_REQUIRED = 3      /* fail with FRT_ERROR_UNSUPPORTED when it is not installed */
} frt_validation;

typedef struct frt_context_desc {
    /* Device choice when the library creates its own: NULL or "" -> prefer discrete GPU, then
     * integrated, then virtual, then CPU (lavapipe); "3" -> index 3 in frt_enumerate_devices order;
     * other text -> first device whose name contains it (case-insensitive). */
    const char *device;
    frt_validation validation;
    /* To run on the caller's device, set all of these (the library then creates no instance or device and
     * destroys none). The device must have been created with the Vulkan 1.2 features bufferDeviceAddress
     * and shaderInt64 enabled, and `queue` must belong to `queue_family`, which must support compute. */
    VkInstance instance;
    VkPhysicalDevice physical_device;
    VkDevice vk_device;
    VkQueue queue;
    uint32_t queue_family;
} frt_context_desc;

typedef struct frt_device_info {
    uint32_t index;
    char name[256];
    VkPhysicalDeviceType type;
    uint32_t api_version;
    uint64_t device_local_heap_bytes; /* size of the largest device-local heap */
    uint64_t max_allocation_bytes;    /* maxMemoryAllocationSize */
    uint64_t max_storage_buffer_range;
    bool usable; /* has bufferDeviceAddress, shaderInt64 and a compute queue */
} frt_device_info;

/* Lists the Vulkan devices visible to a fresh instance. With `out` NULL, sets *count to the number of
 * devices; otherwise writes at most *count entries and sets *count to the number written.
 * FRT_ERROR_NO_DEVICE when no Vulkan driver is installed. */
frt_result frt_enumerate_devices(frt_device_info *out, uint32_t *count);

/* Creates a context (`desc` may be NULL). On failure *out is NULL; when `error` is non-NULL, a detailed
 * message of at most `error_size` bytes is written there. */
frt_result frt_context_create(const frt_context_desc *desc, frt_context **out, char *error, size_t error_size);
void frt_context_destroy(frt_context *ctx);

/* The device the context runs on. */
const frt_device_info *frt_context_device(const frt_context *ctx);

/* The detailed message of the last failure on this context ("" if none). Valid until the next call. */
const char *frt_context_error(const frt_context *ctx);

/* Validation messages (warnings and errors) received since the context was created; 0 without layers. */
uint32_t frt_context_validation_messages(const frt_context *ctx);

/* Generates on the context's device: one compute dispatch per refinement level, recorded in one command
 * buffer, then reads the field back into `out` (frt_heightfield_size(desc) floats, row-major). Never
 * writes outside `out`. FRT_ERROR_TOO_LARGE when the grid exceeds the device's allocation or heap size.
 * `info` may be NULL. */
frt_result frt_generate(frt_context *ctx, const frt_terrain_desc *desc, float *out, size_t out_count,
                        frt_run_info *info);

#ifdef __cplusplus
}
#endif
#endif
