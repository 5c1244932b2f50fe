/* internal.h — declarations shared by the host/ files; not installed, not part of the public API. */
#ifndef FRT_INTERNAL_H
#define FRT_INTERNAL_H

#include "fracterra.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* ---- philox.c: the noise contract (docs/ALGORITHM.md §2) ---- */
typedef struct frt_u32x4 {
    uint32_t v[4];
} frt_u32x4;

/* Philox4x32-10 of Salmon et al. (2011), bit-identical to Random123's philox4x32(10). */
frt_u32x4 frt_philox4x32_10(frt_u32x4 ctr, uint32_t key0, uint32_t key1);
/* Box–Muller on words w0, w1 (spec v2, docs/ALGORITHM.md §2.2): sqrt(-2 ln u) * cos(2 pi v) with every step
 * built from float32 +, -, x only, so that every IEEE backend gives the same bits. */
float frt_gauss_from_words(uint32_t w0, uint32_t w1);
/* The three stages, exposed for the accuracy tests: -2 ln u for u in (0, 1], sqrt by Newton from an integer seed,
 * cos(2 pi v) with exact quadrant reduction. */
float frt_neg2_ln(float u);
float frt_sqrt_nr(float x);
float frt_cos_2pi(float v);
/* g(level, i, j) for the key derived from `seed`: the Gaussian of §2.2 (the default distribution). */
float frt_noise(uint64_t seed, uint32_t level, uint32_t i, uint32_t j);
/* The distribution of the displacements (§2.8), prepared once from a resolved descriptor. The same fields go to the
 * shaders as push constants (shaders/philox.glsl frt_noise_draw). */
typedef struct frt_noise_params {
    uint32_t key[2];     /* (seed & 0xffffffff, seed >> 32) */
    frt_noise_kind kind; /* GAUSS, TRUNCATED, CLT or UNIFORM (never DEFAULT) */
    uint32_t n;          /* clt: N (uniform: 1); else 0 */
    float k;             /* truncated: K rounded to float; else 0 */
    float scale;         /* truncated: S_K; clt, uniform: sqrt(12 / N); gauss: 1 (unused) */
} frt_noise_params;
/* Fills `p` from a desc that frt_terrain_desc_resolved accepted (S_K and sqrt(12/N) in double, rounded once). */
void frt_noise_params_init(frt_noise_params *p, const frt_terrain_desc *resolved);
/* The displacement noise g(level, i, j) of the distribution `p` (§2.8); gauss gives frt_noise's bits. */
float frt_noise_draw(const frt_noise_params *p, uint32_t level, uint32_t i, uint32_t j);
/* S_K = 1 / sqrt(Var_K) of the Gaussian truncated to |g| <= K, in double (§2.8). */
double frt_truncated_scale(double k);
/* The shaders' code path for a distribution: 0 gauss, 1 truncated, 2 clt and uniform. The generator's pipelines are
 * specialised on it (specialization constant 0 = slot + 1, FRT_NOISE_KIND in shaders/philox.glsl), so that the gauss
 * pipeline carries no code of the others (shaders/philox.glsl says why). */
#define FRT_NOISE_SLOTS 3
/* Pipeline slots: a noise slot, plus FRT_NOISE_SLOTS for the variants that sample maps (§3.5, FRT_MAPS = 1). */
#define FRT_PIPELINE_SLOTS (2 * FRT_NOISE_SLOTS)
static inline uint32_t frt_noise_slot(frt_noise_kind kind)
{
    return kind == FRT_NOISE_TRUNCATED ? 1u : kind == FRT_NOISE_CLT || kind == FRT_NOISE_UNIFORM ? 2u : 0u;
}
/* Exact reinterpretation between a float and its bit pattern (GLSL floatBitsToUint / uintBitsToFloat). */
static inline uint32_t frt_float_bits(float x)
{
    uint32_t b;
    memcpy(&b, &x, sizeof b);
    return b;
}
static inline float frt_bits_float(uint32_t b)
{
    float x;
    memcpy(&x, &b, sizeof x);
    return x;
}

/* ---- desc.c ---- */
bool frt_region_is_set(const frt_region *region);
/* The names of docs/ALGORITHM.md §2.8, as the CLI takes them and the metadata records them: "gauss" (also for
 * FRT_NOISE_DEFAULT), "truncated", "clt", "uniform"; "unknown" for a value outside the enum. */
const char *frt_noise_name(frt_noise_kind kind);
/* Whether the kind takes a parameter (truncated: K, clt: N). */
bool frt_noise_has_param(frt_noise_kind kind);
/* Largest side of a periodic region (so that lattice coordinates stay below 2^31). */
#define FRT_REGION_MAX_SIDE (1u << 30)
/* A box of lattice points at one level: columns x .. x+width-1, rows y .. y+height-1 of that level's lattice
 * (coordinate = grid coordinate / 2^(n-l)). Periodic boxes may start at -1 and run past the lattice: they wrap. */
typedef struct frt_box {
    int64_t x, y;
    uint32_t width, height;
} frt_box;
/* The boxes a region needs at levels 0..n (boxes[n] is the region itself); `boxes` holds levels + 1 entries.
 * Returns the largest area of the boxes of levels 0..n-1: the scratch a generator needs for each of its two. */
uint64_t frt_region_boxes(const frt_terrain_desc *resolved, frt_box *boxes);
/* Per-level amplitudes sD(l), sS(l) computed in double and rounded once to float (§3). */
float frt_sigma_diamond(const frt_terrain_desc *resolved, uint32_t level);
float frt_sigma_square(const frt_terrain_desc *resolved, uint32_t level);
double frt_now_seconds(void);
/* Bit pattern of the float nearest 1/3: the 3-neighbour border mean multiplies by it. */
#define FRT_ONE_THIRD_BITS 0x3EAAAAABu
float frt_one_third(void);

/* ---- maps.c: roughness and amplitude by area (§3.5); the same float32 steps as shaders/maps.glsl ---- */
/* 2^-x for x in [0, 126), within 2 ulp, from +, -, x only. */
float frt_exp2_neg(float x);
/* Bilinear sample of a map (at least 2 x 2) at the level-l lattice point (i, j), i.e. at (i, j) / 2^l. */
float frt_map_sample(const frt_map *map, uint32_t level, uint32_t i, uint32_t j);
/* The displacement amplitude of a point created at `level` (a diamond point or a square point) at lattice (i, j):
 * `level_amp` (sD or sS of §3) without maps; sigma 2^-(e H(p)) with a roughness map; times A(p) with an amplitude
 * map. At level 0 pass diamond = false and level_amp = sigma. */
float frt_point_amplitude(const frt_terrain_desc *resolved, uint32_t level, bool diamond, uint32_t i, uint32_t j,
                          float level_amp);

/* ---- reference.c: densify (§3.4), shared with the Vulkan path ---- */
/* The coarse grid with its no-data points filled by levels 0..k of the contract (known heights kept): a malloc'd
 * (2^k+1)^2 grid (2^k x 2^k periodic), k = coarse_levels. */
frt_result frt_coarse_complete(const frt_terrain_desc *resolved, float **completed);
/* Copies level k's lattice box (coordinates of the level-k lattice, wrapping in periodic mode) out of it. */
void frt_coarse_box(const frt_terrain_desc *resolved, const float *completed, const frt_box *box, float *out);

/* ---- noise_vk.c: diagnostics used by the tests (same philox.glsl as the generator) ---- */
/* For each of `count` (counter, key) pairs — counters[4k..4k+3], keys[2k..2k+1] — writes the Philox words to
 * words_out[4k..4k+3] and the Gaussian of words 0,1 to gauss_out[k]. Either output may be NULL. */
frt_result frt_noise_vulkan(frt_context *ctx, const uint32_t *counters, const uint32_t *keys, size_t count,
                            uint32_t *words_out, float *gauss_out);
/* g(level, i, j) of the distribution `p` on the device, for `count` points: points[3k..3k+2] = (i, j, level). */
frt_result frt_noise_draw_vulkan(frt_context *ctx, const frt_noise_params *p, const uint32_t *points, size_t count,
                                 float *out);

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
/* The same with specialization constants (`spec` may be NULL). */
frt_result frt_pipeline_create_spec(frt_context *ctx, const uint32_t *spirv, size_t spirv_bytes, uint32_t push_size,
                                    const VkSpecializationInfo *spec, VkPipeline *pipeline, VkPipelineLayout *layout);
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
    /* Pipelines per noise slot (frt_noise_slot: one per distribution path, its kind a specialization constant) */
    VkPipeline gen_pipeline[FRT_PIPELINE_SLOTS]
                           [2]; /* [slot][0]: one cell per invocation, [slot][1]: a block of cells */
    VkPipelineLayout region_layout;
    VkPipeline region_pipeline[FRT_PIPELINE_SLOTS]; /* regions: one lattice point per invocation */
    struct frt_vk_buffer grid;
    struct frt_vk_buffer staging;
    struct frt_vk_buffer maps; /* §3.5: struct maps_info then the maps' samples, host-visible */
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

/* ---- files.c, formats.c, format_*.c: readers and writers behind frt_read/write_heightfield ---- */

/* Files larger than this many points are refused before anything is allocated (16 GiB of floats). */
#define FRT_FILE_MAX_POINTS (UINT64_C(1) << 32)

/* A field to write, with every default of frt_write_desc resolved and checked (frt_field_out_init). */
typedef struct frt_field_out {
    const char *name; /* the target path, for messages */
    const float *h;
    uint32_t width, height;
    frt_file_format format;
    uint32_t bits;                /* 8 or 16 */
    uint32_t mesh_stride;         /* >= 1 */
    double spacing_x, spacing_y;  /* finite, > 0 */
    double z_scale;               /* finite, != 0 */
    bool has_terrain;             /* `terrain` is valid (resolved) */
    frt_terrain_desc terrain;     /* resolved */
    const char *backend, *device; /* NULL: not recorded */
    const char *history;          /* NULL: not recorded */
    float min, max;               /* of the finite heights; 0, 0 when there are none */
    const double *geotransform;   /* GeoTIFF, as given (NULL: the default); checked by the writer */
    const char *projection;       /* GeoTIFF, as given (NULL or "": none) */
    bool has_nodata;              /* GeoTIFF, as given */
    double nodata;
} frt_field_out;

/* Checks `desc` (NULL = defaults) and fills `f`; `format` FRT_FILE_DEFAULT takes it from `name`. */
frt_result frt_field_out_init(frt_field_out *f, const char *name, const float *h, uint32_t width, uint32_t height,
                              const frt_write_desc *desc, char *err, size_t err_size);
/* Writes the field (not the .f32 sidecar) in f->format to `fp`, then flushes it; a failed write (a full disk) is
 * FRT_ERROR_IO with strerror in the message. Formats numbers in the C locale whatever the caller's. */
frt_result frt_write_stream(FILE *fp, const frt_field_out *f, char *err, size_t err_size);
/* The reader behind frt_read_heightfield[_info], on a stream positioned anywhere (it seeks to measure and to
 * rewind, so fmemopen streams work: tests/fuzz_read.c). `name` is used in messages. `sidecar_json` is the
 * sidecar's text, required for FRT_FILE_F32 and ignored otherwise. `out` NULL: header only (meshes are scanned
 * whole, since their size is the vertex grid's). Otherwise writes at most out_count floats and fills min/max. */
frt_result frt_read_stream(FILE *fp, frt_file_format format, const char *sidecar_json, const char *name,
                           frt_field_info *info, float *out, size_t out_count, char *err, size_t err_size);

/* formats.c: shared by the format files. */
/* Writes "'name'" followed by the formatted text to err (may be NULL); returns r. */
frt_result frt_fail(char *err, size_t err_size, frt_result r, const char *name, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;
/* Shortest decimal text that reads back as the same float / double ("0.8", "-2", "1e-05"); buf >= 32. */
const char *frt_float_text(char buf[static 32], float v);
const char *frt_double_text(char buf[static 32], double v);
/* Sample q (0..maxq) of height v: round((v - min) / (max - min) * maxq); a flat field, NaN -> 0. */
uint32_t frt_quantise(float v, float min, float max, uint32_t maxq);
/* Inverse: min + q / maxq * (max - min) when has_range, else q. */
float frt_dequantise(uint32_t q, uint32_t maxq, bool has_range, double min, double max);
/* Metadata JSON (json-c), malloc'd. FRT_JSON_SIDECAR: pretty, with the raw data layout keys (.f32 sidecar);
 * FRT_JSON_LINE: one line, for a PNG chunk or a comment line. NULL when out of memory. */
enum { FRT_JSON_SIDECAR = 1, FRT_JSON_LINE = 2 };
char *frt_meta_json(const frt_field_out *f, int style);
/* What frt_meta_parse found besides the metadata it stores into `info`. */
typedef struct frt_meta_extra {
    bool has_size;
    uint32_t width, height;
    uint32_t mesh_stride; /* 0 when absent */
    char dtype[16], byte_order[16];
} frt_meta_extra;
/* Parses fracterra metadata JSON into info (has_terrain, terrain, spacing, z_scale, backend, device); parameters
 * that are missing or out of range are left out rather than failing. FRT_ERROR_INVALID_ARGUMENT when `text` is
 * not a JSON object or width/height are present but not whole numbers in 1..2^32-1. */
frt_result frt_meta_parse(const char *text, size_t len, frt_field_info *info, frt_meta_extra *extra, const char *name,
                          const char *what, char *err, size_t err_size);

/* A buffered reader over a FILE*, for the parsers: cheap byte-at-a-time access and the size of the stream, so that
 * headers claiming more data than the file holds are refused before anything is allocated. */
typedef struct frt_rd {
    FILE *fp;
    const char *name;
    char *err;
    size_t err_size;
    uint64_t size;   /* bytes in the stream */
    uint64_t offset; /* bytes consumed */
    uint8_t *buf;
    size_t pos, len;
    int read_errno;   /* nonzero after a failed read */
    bool line_at_end; /* the last frt_rd_line ended at the end of the stream, without "\n" */
} frt_rd;
/* Measures the stream and rewinds it. FRT_ERROR_IO when it cannot be measured or buffered. */
frt_result frt_rd_open(frt_rd *rd, FILE *fp, const char *name, char *err, size_t err_size);
void frt_rd_close(frt_rd *rd);
/* Next byte, or -1 at the end of the stream (or on a read error: see read_errno). */
int frt_rd_getc(frt_rd *rd);
/* Reads exactly n bytes; false when the stream ends first. */
bool frt_rd_read(frt_rd *rd, void *dst, size_t n);
static inline uint64_t frt_rd_left(const frt_rd *rd)
{
    return rd->size > rd->offset ? rd->size - rd->offset : 0;
}
/* One line without its "\n" (and "\r"), NUL-terminated. Returns its length, -1 at the end of the stream, -2 when
 * the line does not fit in cap - 1 bytes (the rest of the line is skipped). */
long frt_rd_line(frt_rd *rd, char *line, size_t cap);
/* FRT_ERROR_IO: "'name' is truncated (what)", or the read error when there was one. */
frt_result frt_rd_truncated(frt_rd *rd, const char *what);
/* Reads n bytes that must equal `magic`: FRT_ERROR_INVALID_ARGUMENT "'name' is not WHAT" when they differ,
 * truncated when the stream ends first. */
frt_result frt_rd_magic(frt_rd *rd, const void *magic, size_t n, const char *what);
/* Checks the size a header claims (info->width, height): both >= 1, at most FRT_FILE_MAX_POINTS points, and with
 * `out`, room for them (FRT_ERROR_BUFFER_TOO_SMALL). */
frt_result frt_rd_check_grid(frt_rd *rd, const frt_field_info *info, const float *out, size_t out_count);

/* Mesh geometry shared by format_obj.c and format_ply.c (docs: frt_write_desc). Thinned grid: rows and columns
 * 0, K, 2K, ... and always the last one. */
uint32_t frt_mesh_side(uint32_t n, uint32_t stride);
/* Position and unit normal of thinned vertex (col i, row j): x = col * spacing_x, y = (height - 1 - row) *
 * spacing_y, z = h * z_scale; normal from central differences on the thinned grid (one-sided at the edges). */
void frt_mesh_vertex(const frt_field_out *f, uint32_t i, uint32_t j, float pos[3], float normal[3]);
/* The header comment lines of a mesh (without the comment marker), one per element of lines[]. */
int frt_mesh_comments(const frt_field_out *f, char lines[2][256]);

/* Recognises the regular grid of a mesh's vertices as they stream in (x increasing along a row, rows from north
 * to south), storing z into out (NULL: none) and checking the rows. */
typedef struct frt_grid_rd {
    float *out;
    size_t out_count;
    uint64_t n;     /* vertices seen */
    uint32_t width; /* 0 until the first row has ended */
    double *xs;     /* x of each column of the first row */
    size_t xs_cap;
    double y_row, y0, y1, tol;
    bool buffer_small;
} frt_grid_rd;
/* Takes one vertex; FRT_ERROR_INVALID_ARGUMENT ("not a regular grid mesh") when it breaks the grid. */
frt_result frt_grid_add(frt_grid_rd *g, frt_rd *rd, double x, double y, double z);
/* Ends the scan: sets info->width/height/spacing, divides the stored z by info->z_scale. Frees the scan. */
frt_result frt_grid_finish(frt_grid_rd *g, frt_rd *rd, frt_field_info *info);
void frt_grid_free(frt_grid_rd *g);

/* The format files: writers take the resolved field; readers fill info (out NULL: header only). */
frt_result frt_png_write(FILE *fp, const frt_field_out *f, char *err, size_t err_size);
frt_result frt_png_write_picture(FILE *fp, const char *name, const uint8_t *pixels, uint32_t width, uint32_t height,
                                 uint32_t channels, char *err, size_t err_size);
frt_result frt_png_read(frt_rd *rd, frt_field_info *info, float *out, size_t out_count);
frt_result frt_pgm_write(FILE *fp, const frt_field_out *f, char *err, size_t err_size);
frt_result frt_pgm_read(frt_rd *rd, frt_field_info *info, float *out, size_t out_count);
frt_result frt_f32_write(FILE *fp, const frt_field_out *f, char *err, size_t err_size);
frt_result frt_f32_read(frt_rd *rd, const char *sidecar_json, frt_field_info *info, float *out, size_t out_count);
frt_result frt_npy_write(FILE *fp, const frt_field_out *f, char *err, size_t err_size);
frt_result frt_npy_read(frt_rd *rd, frt_field_info *info, float *out, size_t out_count);
frt_result frt_obj_write(FILE *fp, const frt_field_out *f, char *err, size_t err_size);
frt_result frt_obj_read(frt_rd *rd, frt_field_info *info, float *out, size_t out_count);
frt_result frt_ply_write(FILE *fp, const frt_field_out *f, char *err, size_t err_size);
frt_result frt_ply_read(frt_rd *rd, frt_field_info *info, float *out, size_t out_count);
/* format_tiff.c: GDAL opens files by name, so GeoTIFF is written and read by path, not through a FILE*. The writer
 * makes its own temporary file beside f->name and renames it (atomic_file.c); `json` (FRT_JSON_LINE, may be NULL)
 * is recorded as the metadata item FRACTERRA. The reader expects `info` zeroed with format and the spacing/z_scale
 * defaults set (frt_read_stream's start). Both run in the caller's C locale (files.c). Without GDAL both return
 * FRT_ERROR_UNSUPPORTED. */
frt_result frt_tiff_write(const frt_field_out *f, const char *json, char *err, size_t err_size);
frt_result frt_tiff_read(const char *path, frt_field_info *info, float *out, size_t out_count, char *err,
                         size_t err_size);

/* A writer over a FILE* that remembers the first failure's errno and skips the rest. */
typedef struct frt_wr {
    FILE *fp;
    int errnum;
} frt_wr;
void frt_wr_bytes(frt_wr *w, const void *p, size_t n);
void frt_wr_printf(frt_wr *w, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* Flushes; FRT_ERROR_IO naming the file and strerror of the first failure. */
frt_result frt_wr_finish(frt_wr *w, const char *name, char *err, size_t err_size);
/* Little-endian stores whatever the host's order. */
void frt_put_le32(uint8_t *p, uint32_t v);
uint32_t frt_get_le32(const uint8_t *p);

/* ---- hillshade.c, profiles.c: pictures ---- */
/* The resolved settings and page geometry of a profile plot, shared by frt_profiles_size, frt_profiles and
 * frt_write_profiles (so the three agree), and by the tests and the CLI (the automatic dilation it used). */
typedef struct frt_profiles_layout {
    frt_profiles_desc desc; /* every default made explicit; dilation: the automatic value if 0 */
    uint32_t rows;          /* profiles drawn: y = 0, every, 2 every, ... <= height - 1 */
    uint32_t back_y;        /* y of the back (last drawn) profile */
    double zmin, zmax;      /* of z = dilation * h over the finite heights; 0, 0 when none */
    double zbase;           /* floor of the base: zmin - base */
    double margin;          /* device units (pixels or points) around the projected extent */
    double scale;           /* device units per u or v unit */
    double vmax;            /* top of the extent, in v */
    uint32_t picture_width, picture_height;
    uint32_t field_width, field_height;
} frt_profiles_layout;
/* Checks `desc` (NULL = defaults) against the field and fills `l`; FRT_ERROR_INVALID_ARGUMENT with a message in
 * err (may be NULL) when a setting is out of range or the picture would exceed 16384 a side. */
frt_result frt_profiles_layout_compute(const float *h, uint32_t width, uint32_t height, const frt_profiles_desc *desc,
                                       frt_profiles_layout *l, char *err, size_t err_size);
/* Device position (pixels or points, y down) of the point at column x, y rows from the front, height hv:
 * X = margin + scale * u, Y = margin + scale * (vmax - v). */
void frt_profiles_point(const frt_profiles_layout *l, double x, double y, double hv, double *px, double *py);

/* ---- format_gif.c: animated GIF of growth frames ---- */
/* Streams frames (8-bit palette indices, width x height) into an animated GIF that loops forever, through giflib,
 * to a temporary file renamed by frt_gif_commit; frt_gif_abort (or a failed commit) leaves no file. */
typedef struct frt_gif_writer frt_gif_writer;
frt_result frt_gif_open(frt_gif_writer **out, const char *path, uint32_t width, uint32_t height,
                        const uint8_t palette_rgb[768], char *err, size_t err_size);
frt_result frt_gif_add_frame(frt_gif_writer *g, const uint8_t *indices, uint32_t delay_centiseconds, char *err,
                             size_t err_size);
frt_result frt_gif_commit(frt_gif_writer *g, char *err, size_t err_size); /* frees `g` in every case */
void frt_gif_abort(frt_gif_writer *g);                                    /* frees `g`; NULL is fine */

#endif
