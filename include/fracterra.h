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
#define FRT_SPEC_VERSION 2

#define FRT_DEFAULT_LEVELS 9u /* 513 x 513, as in the 1988 report */
#define FRT_DEFAULT_HURST 0.8
#define FRT_DEFAULT_SIGMA 1.0
#define FRT_DEFAULT_SEED 1u
#define FRT_MAX_LEVELS 15u /* whole grids: 32769^2 floats = 4 GiB; devices may allow less */
#define FRT_MAX_REGION_LEVELS 30u /* a region (window) of a virtual grid of side 2^30 + 1 */

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

/* How border points are treated (docs/ALGORITHM.md §3, §3.1).
 * FFC: a (2^n+1)^2 grid; a border square point averages its 3 existing neighbours.
 * PERIODIC: a 2^n x 2^n grid on a torus; neighbours wrap, so copies of the field tile without seams. */
typedef enum frt_edge { FRT_EDGE_DEFAULT = 0, FRT_EDGE_FFC = 1, FRT_EDGE_PERIODIC = 2 } frt_edge;

typedef enum frt_backend {
    FRT_BACKEND_DEFAULT = 0, /* auto: Vulkan if a device exists, else CPU */
    FRT_BACKEND_VULKAN = 1,
    FRT_BACKEND_CPU = 2
} frt_backend;

/* What to generate. Zero-initialise, then set what you need: every zero field means its default. */
/* A window of the virtual grid: columns x .. x+width-1, rows y .. y+height-1 (docs/ALGORITHM.md §3.2).
 * All zero: the whole grid. Only the ancestors the window needs are computed, so a region may come from a grid
 * of up to FRT_MAX_REGION_LEVELS levels, and it equals, bit for bit, the same window of the whole grid.
 * FFC: the window lies inside the (2^n+1)^2 grid. Periodic: x, y < 2^n, and the window wraps around the torus
 * (width and height at most 2^30), so a tile may repeat the first column after the last. */
typedef struct frt_region {
    uint32_t x, y;
    uint32_t width, height;
} frt_region;

typedef struct frt_terrain_desc {
    uint32_t levels;       /* n: grid side is 2^n + 1; 0 -> 9; valid 1..FRT_MAX_LEVELS, or ..FRT_MAX_REGION_LEVELS
                              with a region */
    double hurst;          /* H in (0,1); 0 -> 0.8. Fractal dimension D = 3 - H */
    double sigma;          /* amplitude, any non-zero real (negative inverts peaks/valleys); 0 -> 1 */
    uint64_t seed;         /* Philox key; 0 -> 1 unless seed_is_explicit */
    bool seed_is_explicit; /* true: use `seed` as given, even 0 */
    frt_edge edge;         /* 0 -> FRT_EDGE_FFC */
    frt_region region;     /* all zero -> the whole grid */
} frt_terrain_desc;

/* Fills `out` with `in` (NULL = all defaults) with every default made explicit, and checks ranges.
 * Returns FRT_ERROR_INVALID_ARGUMENT (leaving `out` filled as far as possible) if a value is out of range. */
frt_result frt_terrain_desc_resolved(const frt_terrain_desc *in, frt_terrain_desc *out);

/* The same checks, with defaults applied; on failure a one-line reason ("region 0 x 5: width and height must
 * both be at least 1") is written to `why` (may be NULL). */
frt_result frt_terrain_desc_check(const frt_terrain_desc *desc, char *why, size_t why_size);

/* Grid side 2^levels + 1 (the FFC grid), or 0 if levels is 0 or > FRT_MAX_REGION_LEVELS (no defaults applied). */
uint32_t frt_grid_side(uint32_t levels);

/* Side of the whole (virtual) grid `desc` describes, defaults applied: 2^n + 1 (FFC) or 2^n (periodic); 0 if
 * `desc` is invalid. With a region this is the side of the grid the window is cut from, not of the output. */
uint32_t frt_terrain_side(const frt_terrain_desc *desc);

/* Width and height of the heightfield a generator writes for `desc`: the region's, or the whole grid's.
 * FRT_ERROR_INVALID_ARGUMENT (and 0 x 0) if `desc` is invalid. Either pointer may be NULL. */
frt_result frt_terrain_extent(const frt_terrain_desc *desc, uint32_t *width, uint32_t *height);

/* Number of floats a heightfield for `desc` needs (defaults applied): width * height of frt_terrain_extent,
 * or 0 if `desc` is invalid. The product is checked against SIZE_MAX; allocates nothing. */
size_t frt_heightfield_size(const frt_terrain_desc *desc);

/* Optional figures from a generation run. */
typedef struct frt_run_info {
    double device_seconds; /* time of the dispatches measured on the device (timestamps); CPU: compute time */
    double total_seconds;  /* wall time of the whole call, read-back included */
    uint32_t dispatches;   /* compute dispatches recorded (levels + 1) */
} frt_run_info;

/* CPU reference: single-threaded, plain C, the yardstick for every backend. Writes exactly
 * frt_heightfield_size(desc) floats, row-major h[y*width + x] (frt_terrain_extent), into `out`; never writes
 * outside it.
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
 * buffer, then reads the field (or the region) back into `out` (frt_heightfield_size(desc) floats, row-major). Never
 * writes outside `out`. FRT_ERROR_TOO_LARGE when the grid exceeds the device's allocation or heap size.
 * `info` may be NULL. */
frt_result frt_generate(frt_context *ctx, const frt_terrain_desc *desc, float *out, size_t out_count,
                        frt_run_info *info);

/* ---- Heightfield files (files.c, format_*.c) ---- */

typedef enum frt_file_format {
    FRT_FILE_DEFAULT = 0, /* chosen by the path's extension */
    FRT_FILE_PNG = 1,     /* greyscale PNG, 16-bit (or 8); min/max and parameters in text chunks */
    FRT_FILE_PGM = 2,     /* Netpbm P5, 16-bit (or 8), big-endian; min/max and parameters in comments */
    FRT_FILE_F32 = 3,     /* raw little-endian float32, row-major, with a FILE.json sidecar */
    FRT_FILE_NPY = 4,     /* NumPy .npy, '<f4', C order */
    FRT_FILE_OBJ = 5,     /* Wavefront OBJ triangle mesh with vertex normals */
    FRT_FILE_PLY = 6      /* binary little-endian PLY triangle mesh with vertex normals */
} frt_file_format;

/* The format named by `path`'s extension (case-insensitive), or FRT_FILE_DEFAULT when it names none. */
frt_file_format frt_file_format_from_path(const char *path);
/* Lower-case extension without the dot ("png", ...); "" for FRT_FILE_DEFAULT or an unknown value. */
const char *frt_file_format_name(frt_file_format format);

/* How to write a heightfield. Zero-initialise: every zero field means its default. */
typedef struct frt_write_desc {
    frt_file_format format;          /* 0 -> from the extension */
    uint32_t bits;                   /* PNG and PGM sample depth: 0 -> 16, or 8 */
    uint32_t mesh_stride;            /* OBJ/PLY: keep every K-th row and column (and always the last); 0 -> 1 */
    double spacing_x, spacing_y;     /* ground distance between columns / rows, in height units; 0 -> 1 */
    double z_scale;                  /* OBJ/PLY: vertex z = h * z_scale; 0 -> 1 */
    double range_min, range_max;     /* PNG/PGM: heights mapped to 0..2^bits-1 (clamped); equal -> the field's
                                        own min and max. For a series of pictures on one scale */
    const frt_terrain_desc *terrain; /* optional: the parameters that made the field, recorded as metadata */
    const char *backend;             /* optional: "vulkan" or "cpu", recorded */
    const char *device;              /* optional: device name, recorded */
} frt_write_desc;

/* Writes a width x height heightfield h[y*width + x] to `path`. The file (and the .f32 sidecar) is written to a
 * temporary file beside it and renamed on success, so a failure never leaves a partial file and never replaces
 * an existing one. Quantised formats map [min, max] of the field to the full sample range. On failure a
 * one-line message naming the file and the problem is written to `err` (may be NULL). */
frt_result frt_write_heightfield(const char *path, const float *h, uint32_t width, uint32_t height,
                                 const frt_write_desc *desc, char *err, size_t err_size);

/* What a heightfield file holds. */
typedef struct frt_field_info {
    frt_file_format format;
    uint32_t width, height;
    uint32_t bits;               /* bits per stored sample: 8 or 16 (PNG, PGM), 32 or 64 (float) */
    bool has_terrain;            /* the file records the parameters that made it (fracterra wrote it) */
    frt_terrain_desc terrain;    /* valid when has_terrain */
    bool has_range;              /* quantised samples were mapped back to the recorded [min, max] */
    double spacing_x, spacing_y; /* as recorded, else 1 */
    double z_scale;              /* as recorded, else 1 */
    float min, max;              /* of the heights as read (set by frt_read_heightfield only) */
    char backend[16];            /* as recorded, else "" */
    char device[256];            /* as recorded, else "" */
} frt_field_info;

/* Reads only the header of `path` (and its sidecar): format, size and metadata; min/max are left 0. */
frt_result frt_read_heightfield_info(const char *path, frt_field_info *info, char *err, size_t err_size);

/* Reads the heights into `out` (at least width*height floats, from frt_read_heightfield_info); never writes
 * outside it. Quantised samples map back to the recorded [min, max] (within one quantum) when the file has
 * them, else to the raw sample values. Meshes read back when their vertices form the regular grid that
 * fracterra writes (z / z_scale). `info` may be NULL. Truncated, malformed or inconsistent files give
 * FRT_ERROR_IO or FRT_ERROR_INVALID_ARGUMENT with a message naming the problem. */
frt_result frt_read_heightfield(const char *path, float *out, size_t out_count, frt_field_info *info, char *err,
                                size_t err_size);

/* Writes an 8-bit picture (channels 1 = grey, 3 = RGB, row-major) as PNG, atomically like the above. */
frt_result frt_write_picture(const char *path, const uint8_t *pixels, uint32_t width, uint32_t height,
                             uint32_t channels, char *err, size_t err_size);

/* ---- Pictures (hillshade.c, profiles.c) ---- */

typedef struct frt_hillshade_desc {
    double azimuth;              /* light from, degrees clockwise from north (up); 0 -> 315; 360 for north */
    double altitude;             /* degrees above the horizon; 0 -> 45 */
    double z_factor;             /* vertical exaggeration; 0 -> automatic (RMS slope of 25 degrees) */
    double spacing_x, spacing_y; /* distance between columns / rows in height units; 0 -> 1 */
    bool color;                  /* blend with a hypsometric colour ramp: RGB output */
} frt_hillshade_desc;

/* Bytes frt_hillshade writes: width * height * (color ? 3 : 1); 0 when that overflows or a side is 0. */
size_t frt_hillshade_size(uint32_t width, uint32_t height, const frt_hillshade_desc *desc);

/* Shaded relief by Horn's method, as gdaldem hillshade -compute_edges: 1 + 254 * max(0, cos(incidence)), edges
 * from linearly extrapolated border samples (2a - b, as gdaldem does); 0 where a height is not finite. `desc` may be
 * NULL. */
frt_result frt_hillshade(const float *h, uint32_t width, uint32_t height, const frt_hillshade_desc *desc, uint8_t *out,
                         size_t out_size);

/* The 1988 report's orthographic profile plot. Point (x, y, z) with x the column, y counted from the front
 * (last) row and z = dilation * h projects to u = 1.5x + 0.25y, v = tilt * (0.25y + 1.5z) (v up). */
typedef struct frt_profiles_desc {
    uint32_t every;    /* draw every K-th row, front to back, with hidden-line removal; 0 -> 8 */
    double dilation;   /* vertical dilation (grid-spacing units per height unit; negative inverts); 0 -> automatic:
                          relief spans 1/10 of the plot's width */
    double tilt;       /* 0 -> 1 */
    double base;       /* thickness of a solid base ("stratum") below the lowest point, in z units; 0 -> none */
    uint32_t width;    /* picture width in pixels (PNG) or points (SVG, PDF); 0 -> 1200 */
    double line_width; /* in pixels or points; 0 -> 1 */
} frt_profiles_desc;

/* Picture size for the plot of a width x height field; the height follows the projected extent. */
frt_result frt_profiles_size(const float *h, uint32_t width, uint32_t height, const frt_profiles_desc *desc,
                             uint32_t *picture_width, uint32_t *picture_height);

/* Draws the plot into a caller-allocated 8-bit grey picture (white paper, black lines) of the size above. */
frt_result frt_profiles(const float *h, uint32_t width, uint32_t height, const frt_profiles_desc *desc, uint8_t *out,
                        uint32_t picture_width, uint32_t picture_height);

/* Writes the plot to `path`: .png (anti-aliased), .svg or .pdf (vectors) by extension, through cairo;
 * atomically like frt_write_heightfield. */
frt_result frt_write_profiles(const char *path, const float *h, uint32_t width, uint32_t height,
                              const frt_profiles_desc *desc, char *err, size_t err_size);

#ifdef __cplusplus
}
#endif
#endif
