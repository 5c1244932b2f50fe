/* internal.h — declarations shared by the host/ files; not installed, not part of the public API. */
#ifndef FRT_INTERNAL_H
#define FRT_INTERNAL_H

#include "fracterra.h"

#include <stdarg.h>
#include <stdio.h>

/* ---- philox.c: the noise contract (docs/ALGORITHM.md §2) ---- */
typedef struct frt_u32x4 {
    uint32_t v[4];
} frt_u32x4;

/* Philox4x32-10 of Salmon et al. (2011), bit-identical to Random123's philox4x32(10). */
frt_u32x4 frt_philox4x32_10(frt_u32x4 ctr, uint32_t key0, uint32_t key1);
/* Box–Muller on words w0, w1 (spec v1): sqrt(-2 ln u) * cos(2 pi v), float32 throughout. */
float frt_gauss_from_words(uint32_t w0, uint32_t w1);
/* g(level, i, j) for the key derived from `seed`. */
float frt_noise(uint64_t seed, uint32_t level, uint32_t i, uint32_t j);

/* ---- desc.c ---- */
/* Per-level amplitudes sD(l), sS(l) computed in double and rounded once to float (§3). */
float frt_sigma_diamond(const frt_terrain_desc *resolved, uint32_t level);
float frt_sigma_square(const frt_terrain_desc *resolved, uint32_t level);
double frt_now_seconds(void);
/* Bit pattern of the float nearest 1/3: the 3-neighbour border mean multiplies by it. */
#define FRT_ONE_THIRD_BITS 0x3EAAAAABu
float frt_one_third(void);

/* ---- noise_vk.c: diagnostics used by the tests (same philox.glsl as the generator) ---- */
/* For each of `count` (counter, key) pairs — counters[4k..4k+3], keys[2k..2k+1] — writes the Philox words to
 * words_out[4k..4k+3] and the Gaussian of words 0,1 to gauss_out[k]. Either output may be NULL. */
frt_result frt_noise_vulkan(frt_context *ctx, const uint32_t *counters, const uint32_t *keys, size_t count,
                            uint32_t *words_out, float *gauss_out);

/* ---- context.c helpers for the other Vulkan files ---- */
struct frt_vk_buffer {
    VkBuffer buffer;
    VkDeviceMemory memory;
    VkDeviceSize size;
    void *mapped; /* non-NULL when host-visible */
    VkDeviceAddress address;
};
frt_result frt_set_error(frt_context *ctx, frt_result r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
frt_result frt_vk_check(frt_context *ctx, VkResult vr, const char *what);
/* Creates a storage buffer with a device address. `host_visible`: require mappable memory (it is mapped);
 * otherwise prefer device-local. */
frt_result frt_buffer_create(frt_context *ctx, VkDeviceSize size, bool host_visible, struct frt_vk_buffer *out);
void frt_buffer_destroy(frt_context *ctx, struct frt_vk_buffer *b);
/* Creates a compute pipeline from SPIR-V with a push-constant block of `push_size` bytes. */
frt_result frt_pipeline_create(frt_context *ctx, const uint32_t *spirv, size_t spirv_bytes, uint32_t push_size,
                               VkPipeline *pipeline, VkPipelineLayout *layout);
/* Begins a one-time command buffer, and submits + waits for it. */
frt_result frt_cmd_begin(frt_context *ctx, VkCommandBuffer *cmd);
frt_result frt_cmd_submit_wait(frt_context *ctx, VkCommandBuffer cmd);

/* The context, shared by the Vulkan files (context.c owns its life cycle). */
struct frt_context {
    bool owns_device; /* false when running on the caller's VkDevice */
    VkInstance instance;
    VkDebugUtilsMessengerEXT messenger;
    VkPhysicalDevice physical;
    VkDevice device;
    VkQueue queue;
    uint32_t queue_family;
    VkPhysicalDeviceProperties props;
    VkPhysicalDeviceMemoryProperties mem_props;
    frt_device_info info;
    VkCommandPool pool;
    VkQueryPool timestamps; /* 2 queries; VK_NULL_HANDLE when the queue has no timestamps */
    uint32_t validation_messages;
    char error[1024];
    /* generate_vk.c: pipelines (made on first use) and the grid buffer, kept for reuse */
    VkPipelineLayout gen_layout;
    VkPipeline gen_pipeline[2]; /* [0]: one cell per invocation, [1]: a block of cells */
    struct frt_vk_buffer grid;
    struct frt_vk_buffer staging;
    /* noise_vk.c */
    VkPipelineLayout noise_layout;
    VkPipeline noise_pipeline;
};
void frt_generate_vk_release(frt_context *ctx);
void frt_noise_vk_release(frt_context *ctx);

/* ---- atomic_file.c: write to a temporary file beside the target, rename on success ---- */
typedef struct frt_atomic_file {
    FILE *fp;
    char *path;     /* the target */
    char *tmp_path; /* the temporary beside it */
} frt_atomic_file;
/* Creates the temporary file now, so that an unwritable target fails before any work is done. */
frt_result frt_atomic_open(frt_atomic_file *af, const char *path, char *err, size_t err_size);
/* Flushes, syncs and renames over the target; on any failure removes the temporary and leaves the target. */
frt_result frt_atomic_commit(frt_atomic_file *af, char *err, size_t err_size);
void frt_atomic_abort(frt_atomic_file *af);

/* ---- formats.c and format_*.c: heightfield files chosen by extension ---- */
typedef enum frt_format { FRT_FORMAT_NONE = 0, FRT_FORMAT_F32, FRT_FORMAT_NPY, FRT_FORMAT_PNG } frt_format;
/* What a file records besides the heights. */
typedef struct frt_field_meta {
    frt_terrain_desc desc; /* resolved */
    const char *backend;   /* "vulkan" or "cpu" */
    const char *device;    /* device name */
    float min, max;
} frt_field_meta;
frt_format frt_format_from_path(const char *path);
/* The sidecar path for .f32 output: FILE.json (malloc'd). */
char *frt_sidecar_path(const char *path);
/* The parameters as one JSON object (malloc'd): the sidecar's content and the PNG text chunk. */
char *frt_meta_json(const frt_field_meta *m, uint32_t width, uint32_t height);
void frt_field_minmax(const float *h, size_t count, float *min, float *max);
frt_result frt_write_f32(FILE *fp, const float *h, size_t count);
frt_result frt_write_npy(FILE *fp, const float *h, uint32_t width, uint32_t height);
frt_result frt_write_png16(FILE *fp, const float *h, uint32_t width, uint32_t height, const frt_field_meta *m,
                           char *err, size_t err_size);

#endif
