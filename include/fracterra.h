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

/* The distribution of the displacements (docs/ALGORITHM.md §2.8), each scaled to unit variance so that sigma keeps
 * its meaning. */
typedef enum frt_noise_kind {
    FRT_NOISE_DEFAULT = 0,
    FRT_NOISE_GAUSS = 1,     /* Box-Muller Gaussian (§2.2) */
    FRT_NOISE_TRUNCATED = 2, /* Gaussian conditioned on |g| <= K (noise_param, 0 -> 3), by rejection: the chopped
                                Gaussian of the 1988 report */
    FRT_NOISE_CLT = 3,       /* sum of N uniforms (noise_param, 0 -> 4): the thesis's and Peitgen & Saupe's Gauss() */
    FRT_NOISE_UNIFORM = 4    /* uniform on [-sqrt 3, sqrt 3] */
} frt_noise_kind;

/* A map over the unit square: width x height samples, row-major, sample (0, 0) at the corner (0, 0) and
 * (width-1, height-1) at (1, 1); sampled bilinearly (§3.5). */
typedef struct frt_map {
    const float *data; /* NULL: no map */
    uint32_t width, height;
} frt_map;

typedef struct frt_terrain_desc {
    uint32_t levels;       /* n: grid side is 2^n + 1; 0 -> 9; valid 1..FRT_MAX_LEVELS, or ..FRT_MAX_REGION_LEVELS
                              with a region */
    double hurst;          /* H in (0,1); 0 -> 0.8. Fractal dimension D = 3 - H */
    double sigma;          /* amplitude, any non-zero real (negative inverts peaks/valleys); 0 -> 1 */
    uint64_t seed;         /* Philox key; 0 -> 1 unless seed_is_explicit */
    bool seed_is_explicit; /* true: use `seed` as given, even 0 */
    frt_edge edge;         /* 0 -> FRT_EDGE_FFC */
    frt_region region;     /* all zero -> the whole grid */
    frt_noise_kind noise;  /* 0 -> FRT_NOISE_GAUSS */
    double noise_param;    /* truncated: K in [1, 6], 0 -> 3; clt: N, an integer 1..16, 0 -> 4; others: 0 */
    /* Densify (§3.4): known heights on the (2^k+1)^2 grid, k = coarse_levels (1..levels), row-major; they are placed
     * at spacing 2^(levels-k) and kept bit-exactly; NaN marks no data, filled at the level that creates the point. */
    const float *coarse;
    uint32_t coarse_levels;
    frt_map hurst_map;     /* optional: H per location, values in (0, 1) (§3.5) */
    frt_map amplitude_map; /* optional: a finite factor on sigma per location (§3.5) */
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

/* ---- Roughness of known heights (estimate.c) ---- */

#define FRT_ROUGHNESS_MIN_HURST 0.05
#define FRT_ROUGHNESS_MAX_HURST 0.95

typedef struct frt_roughness {
    double hurst;           /* H, within [FRT_ROUGHNESS_MIN_HURST, FRT_ROUGHNESS_MAX_HURST] */
    double sigma;           /* amplitude in the contract's units (§3: the grid spans the unit square) */
    bool clamped;           /* the fitted H lay outside that range and was clamped */
    uint32_t coarse_levels; /* k of the (2^k+1)^2 grid */
    uint32_t steps;         /* diamond and square steps in the fit */
    uint64_t residuals;     /* midpoint residuals in the fit */
    /* The fit's weighted centre: log2 RMS residual = log2_rms_centre at t = t_centre. For a given H the best sigma is
     * 2^(log2_rms_centre + H t_centre) (what --sigma auto uses with an explicit H). */
    double t_centre, log2_rms_centre;
} frt_roughness;

/* Estimates H and sigma of a (2^k+1)^2 grid `h` (row-major, NaN = no data) so that densifying it continues its
 * statistics: the variogram of its midpoint residuals per level, Var = sigma^2 2^(-2tH), fitted by weighted least
 * squares (docs/ALGORITHM.md §3.6). FRT_ERROR_INVALID_ARGUMENT when side is not 2^k+1 or fewer than three steps
 * have 16 known residuals (at least a 9 x 9 grid), or the grid is flat. */
frt_result frt_estimate_roughness(const float *h, uint32_t side, frt_roughness *out);

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
    FRT_FILE_PLY = 6,     /* binary little-endian PLY triangle mesh with vertex normals */
    FRT_FILE_TIFF = 7     /* GeoTIFF (.tif, .tiff) through GDAL: float32, georeferenced; reads any sample type.
                             FRT_ERROR_UNSUPPORTED when built without GDAL (FRT_WITH_GDAL=OFF) */
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
    const char *history;             /* optional: how the field was made, in words (recorded as "history") */
    /* GeoTIFF only. Affine map from (column, row) of the pixel corner to the map (GDAL's order): X = g[0] + col g[1]
     * + row g[2], Y = g[3] + col g[4] + row g[5]. NULL -> north up, pixel centres where the OBJ/PLY vertices lie:
     * {-spacing_x/2, spacing_x, 0, (height - 1/2) spacing_y, 0, -spacing_y}; a region of `terrain` is placed where
     * it lies in its whole grid (column region.x at x = region.x spacing_x), so that tiles line up */
    const double *geotransform;
    const char *projection; /* GeoTIFF: the CRS, WKT or what OSRSetFromUserInput takes ("EPSG:32633"); NULL: none */
    bool has_nodata;        /* GeoTIFF: NaN heights are stored as `nodata` (a float32 value, or NaN; no finite height
                               may equal it). false: NaN itself is the nodata value when the field has NaNs */
    double nodata;
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
    uint32_t bits;               /* bits per stored sample: 8 or 16 (PNG, PGM), 32 or 64 (float); GeoTIFF: its type's */
    bool has_terrain;            /* the file records the parameters that made it (fracterra wrote it) */
    frt_terrain_desc terrain;    /* valid when has_terrain */
    bool has_range;              /* quantised samples were mapped back to the recorded [min, max] */
    double spacing_x, spacing_y; /* as recorded, else 1 */
    double z_scale;              /* as recorded, else 1 */
    float min, max;              /* of the heights as read (set by frt_read_heightfield only) */
    char backend[16];            /* as recorded, else "" */
    char device[256];            /* as recorded, else "" */
    /* GeoTIFF: the georeferencing as GDAL reads it. spacing_x/y above come from the parameters fracterra recorded,
     * else from a north-up geotransform (|g[1]|, |g[5]|) unless the CRS is geographic (degrees are no height unit). */
    bool has_geotransform;
    double geotransform[6]; /* GDAL's order (frt_write_desc); {0, 1, 0, 0, 0, 1} when none */
    char projection[8192];  /* the CRS as WKT, "" if none; a longer one fails the read (FRT_ERROR_UNSUPPORTED) */
    bool has_nodata;        /* samples equal to `nodata` (and NaN samples) were read as NaN */
    double nodata;          /* in stored units, before any scale/offset */
} frt_field_info;

/* Reads only the header of `path` (and its sidecar): format, size and metadata; min/max are left 0. */
frt_result frt_read_heightfield_info(const char *path, frt_field_info *info, char *err, size_t err_size);

/* Reads the heights into `out` (at least width*height floats, from frt_read_heightfield_info); never writes
 * outside it. Quantised samples map back to the recorded [min, max] (within one quantum) when the file has
 * them, else to the raw sample values. GeoTIFF: the one band of a single-band file (several bands are
 * FRT_ERROR_UNSUPPORTED), any real sample type, times the band's scale plus its offset when it has them; samples
 * equal to its nodata value, and NaN, read as NaN. Meshes read back when their vertices form the regular grid that
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
