/* cli_tiles.c — `fracterra tiles`: a virtual grid of up to 2^30+1 samples a side cut into tiles (or an XYZ pyramid
 * of PNG tiles for web maps), each generated alone as a library region, written atomically, shareable between
 * processes (--only I/K), described by an index.json that every process writes byte for byte the same. */
#include "cli.h"

#include <errno.h>
#include <float.h>
#include <getopt.h>
#include <json-c/json.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define TILES_FORMAT_VERSION 1 /* of index.json: bump when a key changes meaning */
#define DEFAULT_TILE 256u      /* the web-map tile size */
#define RANGE_LEVELS 10u       /* the derived range looks at the whole grid of at most this many levels */
#define PATH_CAP 4096

static void tiles_help(void)
{
    printf("Usage: fracterra tiles --levels N [--tile T] --out DIR [options]\n"
           "\n"
           "Cuts the virtual grid of N levels (side 2^N+1, or 2^N periodic; N up to %u) into square tiles and\n"
           "generates each tile alone: only the samples it depends on are computed, and it equals, bit for bit,\n"
           "the same window of the whole grid. Tile (row, col) holds columns col*T .. col*T+T and rows\n"
           "row*T .. row*T+T: T+1 x T+1 samples, the border ones shared with the neighbours, (2^N/T)^2 tiles.\n"
           "\n"
           "Terrain (as in generate):\n"
           "  --levels N          refinement levels of the virtual grid, 1..%u (required)\n"
           "  --hurst H           Hurst exponent, 0 < H < 1 (default %.1f)\n"
           "  --dimension D       fractal dimension, 2 < D < 3, H = 3 - D (not with --hurst)\n"
           "  --sigma S           amplitude, any non-zero real (default 1)\n"
           "  --seed U64          noise key, decimal or 0x hex (default 1)\n"
           "  --edge E            ffc (default) or periodic: the last tile's border wraps to column/row 0\n"
           "  --noise DIST        gauss (default) | truncated[:K] | clt[:N] | uniform (ALGORITHM.md §2.8)\n"
           "  --backend B         auto | vulkan | cpu (default auto)\n"
           "  --device D          Vulkan device by index or name substring\n"
           "\n"
           "Tiles:\n"
           "  --tile T            cells per tile side, a power of two from 1 to 2^N (default %u)\n"
           "  -o, --out DIR       output directory, created if missing (its parent must exist):\n"
           "                      DIR/ROW/COL.EXT and DIR/index.json\n"
           "  --format F          f32 (default): raw float32 with a .json sidecar; npy; or png, pgm:\n"
           "                      quantised on one height range shared by every tile\n"
           "  --bits 8|16         sample depth of png and pgm tiles (default 16)\n"
           "  --range MIN,MAX     the shared range of png and pgm tiles (default: derived from the seed and\n"
           "                      parameters, the same in every process; recorded in index.json)\n"
           "  --pyramid           an XYZ pyramid of T x T PNG tiles for web maps instead: DIR/Z/X/Y.png for\n"
           "                      zoom Z = 0 .. N - log2(T), zoom Z being the grid of log2(T) + Z levels\n"
           "  --only I/K          make only share I of K, 0 <= I < K: the tiles whose index (row-major; for a\n"
           "                      pyramid, zoom by zoom) modulo K is I. K processes make what one makes\n"
           "  -q, --quiet         no progress and no summary line on stderr\n"
           "  -h, --help          this text\n"
           "\n"
           "Every file appears only when complete (temporary file, then rename). Tiles record no backend or device,\n"
           "so any process on any device writes the same bytes; index.json is written last.\n",
           FRT_MAX_REGION_LEVELS, FRT_MAX_REGION_LEVELS, FRT_DEFAULT_HURST, DEFAULT_TILE);
}

/* One resolution of the job: the plain tiles have one, a pyramid one per zoom. */
typedef struct layer {
    uint32_t levels;       /* of the grid the tiles are cut from */
    uint32_t per_side;     /* tiles per side */
    uint64_t first, count; /* global tile indices first .. first + count - 1 */
} layer;

typedef struct job {
    frt_terrain_desc terrain; /* resolved, no region */
    uint32_t tile, log2_tile; /* T */
    uint32_t samples;         /* per tile side: T + 1, or T in a pyramid */
    bool pyramid;
    uint32_t n_layers;
    layer layers[FRT_MAX_REGION_LEVELS + 1];
    uint64_t total;
    frt_file_format format;
    bool quantised;
    uint32_t bits;
    bool range_given;
    double range_min, range_max;
    uint32_t range_levels; /* derived range: the levels of the grid it was read from */
    double range_margin;   /* derived range: the widening for the levels beyond those */
    uint64_t share, shares;
    const char *dir;
} job;

/* Side of the whole virtual grid of `levels` levels; frt_terrain_side() answers only for descriptors that are valid
 * without a region (at most FRT_MAX_LEVELS levels). */
static uint32_t grid_side(const frt_terrain_desc *t, uint32_t levels)
{
    return (1u << levels) + (t->edge == FRT_EDGE_PERIODIC ? 0u : 1u);
}

static bool parse_share(const char *s, uint64_t *i, uint64_t *k)
{
    const char *slash = strchr(s, '/');
    char buf[64];
    if (!slash || (size_t)(slash - s) >= sizeof buf)
        return false;
    memcpy(buf, s, (size_t)(slash - s));
    buf[slash - s] = '\0';
    return frt_parse_u64(buf, i) && frt_parse_u64(slash + 1, k) && *k >= 1 && *i < *k;
}

static bool parse_range(const char *s, double *lo, double *hi)
{
    char buf[128];
    if (strlen(s) >= sizeof buf)
        return false;
    strcpy(buf, s);
    char *comma = strchr(buf, ',');
    if (!comma)
        return false;
    *comma = '\0';
    /* the writers quantise in float: both ends must be floats, and stay apart when rounded to float */
    return frt_parse_double(buf, lo) && frt_parse_double(comma + 1, hi) && fabs(*lo) <= FLT_MAX &&
           fabs(*hi) <= FLT_MAX && (float)*lo < (float)*hi;
}

/* The writers quantise on a float range (frt_quantise): keep the range float-exact, rounded outward, so that
 * index.json states exactly the range every tile records. */
static double float_below(double v)
{
    float f = (float)v;
    return (double)f > v ? (double)nextafterf(f, -INFINITY) : (double)f;
}

static double float_above(double v)
{
    float f = (float)v;
    return (double)f < v ? (double)nextafterf(f, INFINITY) : (double)f;
}

/* The shared height range of quantised tiles when --range is not given. It must come out the same in every
 * process, so it is computed on the CPU (not on whichever device a process has): the min and max of the whole grid
 * at L = min(N, RANGE_LEVELS) levels, which is exactly every 2^(N-L)-th sample of the N-level grid
 * (docs/ALGORITHM.md §3). When N > L, the finer levels move a sample away from the convex combination of coarse
 * samples that it would otherwise be by a sum of independent Gaussians of standard deviation at most
 * sd = |sigma| sqrt(sum_{l=L+1..N} 2^(-2(l-1/2)H)) (each level adds a convex combination of its displacements,
 * the largest being sD(l)); the range is widened by (sqrt(2 ln P) + 2) sd, P the grid's sample count: the expected
 * maximum of P such Gaussians plus two standard deviations of slack. Heights outside are clamped. Last, the ends are
 * rounded outward to multiples of 2^-20 of the span's power of two, so that a last-bit difference between two
 * machines' exp2/log hardly ever shows (for N <= L no libm call is involved and the result is exact everywhere). */
static int derive_range(job *jb)
{
    frt_terrain_desc d = jb->terrain;
    d.levels = d.levels < RANGE_LEVELS ? d.levels : RANGE_LEVELS;
    memset(&d.region, 0, sizeof d.region);
    const size_t count = frt_heightfield_size(&d);
    float *h = count ? malloc(count * sizeof *h) : NULL;
    if (!h)
        return frt_cli_fail(FRT_EXIT_DEVICE,
                            "cannot allocate the %u-level grid that sets the height range on this host", d.levels);
    frt_result r = frt_generate_cpu(&d, h, count, NULL);
    if (r != FRT_SUCCESS) {
        free(h);
        return frt_cli_fail(FRT_EXIT_USAGE, "the height range: %s", frt_result_string(r));
    }
    float lo = h[0], hi = h[0];
    for (size_t i = 1; i < count; ++i) {
        lo = h[i] < lo ? h[i] : lo;
        hi = h[i] > hi ? h[i] : hi;
    }
    free(h);
    double var = 0.0;
    for (uint32_t l = d.levels + 1; l <= jb->terrain.levels; ++l)
        var += exp2(-2.0 * ((double)l - 0.5) * jb->terrain.hurst);
    double margin = 0.0;
    if (var > 0.0) {
        const double side = (double)grid_side(&jb->terrain, jb->terrain.levels);
        margin = (sqrt(2.0 * log(side * side)) + 2.0) * fabs(jb->terrain.sigma) * sqrt(var);
    }
    double a = (double)lo - margin, b = (double)hi + margin;
    if (!(b > a)) { /* a flat field (it never is, but a range must be a range) */
        a -= 0.5;
        b += 0.5;
    }
    int e;
    frexp(b - a, &e);
    const double q = ldexp(1.0, e - 20);
    jb->range_min = float_below(floor(a / q) * q);
    jb->range_max = float_above(ceil(b / q) * q);
    jb->range_levels = d.levels;
    jb->range_margin = margin;
    return FRT_EXIT_OK;
}

/* ---- index.json ---- */

static json_object *json_double(double v)
{
    char buf[32];
    return json_object_new_double_s(v, frt_double_text(buf, v)); /* shortest text that reads back exactly */
}

static const char *edge_name(const frt_terrain_desc *t)
{
    return t->edge == FRT_EDGE_PERIODIC ? "periodic" : "ffc";
}

/* The index: everything needed to find and place every tile, and nothing that depends on the process (share,
 * backend, device, time), so that every process writes the same bytes. */
static char *index_json(const job *jb)
{
    const frt_terrain_desc *t = &jb->terrain;
    const bool periodic = t->edge == FRT_EDGE_PERIODIC;
    const char *ext = frt_file_format_name(jb->format);
    char templ[64];
    json_object *o = json_object_new_object();
    if (!o)
        return NULL;
    json_object_object_add(o, "format", json_object_new_string("fracterra tiles"));
    json_object_object_add(o, "format_version", json_object_new_int(TILES_FORMAT_VERSION));
    json_object_object_add(o, "layout", json_object_new_string(jb->pyramid ? "xyz" : "grid"));
    json_object_object_add(o, "spec_version", json_object_new_int(FRT_SPEC_VERSION));
    json_object_object_add(o, "fracterra_version", json_object_new_string(FRT_VERSION_STRING));
    json_object_object_add(o, "levels", json_object_new_int64(t->levels));
    json_object_object_add(o, "edge", json_object_new_string(edge_name(t)));
    json_object_object_add(o, "grid_side", json_object_new_int64(grid_side(t, t->levels)));
    json_object_object_add(o, "tile", json_object_new_int64(jb->tile));
    json_object_object_add(o, "tile_samples", json_object_new_int64(jb->samples));
    if (jb->pyramid) {
        snprintf(templ, sizeof templ, "{z}/{x}/{y}.%s", ext);
        json_object_object_add(o, "min_zoom", json_object_new_int(0));
        json_object_object_add(o, "max_zoom", json_object_new_int64(jb->n_layers - 1));
        json_object_object_add(o, "tile_count", json_object_new_uint64(jb->total));
        json_object_object_add(o, "url_template", json_object_new_string(templ));
        json_object_object_add(o, "path_template", json_object_new_string(templ));
        json_object_object_add(
            o, "placement",
            json_object_new_string("tile (x, y) of zoom z holds columns x*tile .. x*tile+tile-1 and rows "
                                   "y*tile .. y*tile+tile-1 (y from the top) of the grid of log2(tile)+z levels; "
                                   "zoom z is every other sample of zoom z+1"));
        json_object *zooms = json_object_new_array();
        for (uint32_t z = 0; z < jb->n_layers; ++z) {
            const layer *ly = &jb->layers[z];
            json_object *zo = json_object_new_object();
            json_object_object_add(zo, "z", json_object_new_int64(z));
            json_object_object_add(zo, "levels", json_object_new_int64(ly->levels));
            json_object_object_add(zo, "grid_side", json_object_new_int64(grid_side(t, ly->levels)));
            json_object_object_add(zo, "tiles_per_side", json_object_new_int64(ly->per_side));
            json_object_array_add(zooms, zo);
        }
        json_object_object_add(o, "zooms", zooms);
    } else {
        snprintf(templ, sizeof templ, "{row}/{col}.%s", ext);
        json_object_object_add(o, "tiles_per_side", json_object_new_int64(jb->layers[0].per_side));
        json_object_object_add(o, "tile_count", json_object_new_uint64(jb->total));
        json_object_object_add(o, "path_template", json_object_new_string(templ));
        json_object_object_add(
            o, "placement",
            json_object_new_string(periodic ? "tile (row, col) holds columns col*tile .. col*tile+tile and rows "
                                              "row*tile .. row*tile+tile, modulo grid_side; neighbours share their "
                                              "border samples"
                                            : "tile (row, col) holds columns col*tile .. col*tile+tile and rows "
                                              "row*tile .. row*tile+tile; neighbours share their border samples"));
    }
    json_object_object_add(o, "file_format", json_object_new_string(ext));
    if (jb->quantised) {
        json_object_object_add(o, "bits", json_object_new_int64(jb->bits));
        json_object *rg = json_object_new_object();
        json_object_object_add(rg, "min", json_double(jb->range_min));
        json_object_object_add(rg, "max", json_double(jb->range_max));
        json_object_object_add(rg, "source", json_object_new_string(jb->range_given ? "given" : "derived"));
        if (!jb->range_given) {
            json_object_object_add(rg, "from_levels", json_object_new_int64(jb->range_levels));
            json_object_object_add(rg, "margin", json_double(jb->range_margin));
        }
        json_object_object_add(rg, "mapping",
                               json_object_new_string(jb->bits == 8 ? "height = min + sample / 255 * (max - min)"
                                                                    : "height = min + sample / 65535 * (max - min)"));
        json_object_object_add(o, "range", rg);
    }
    json_object *p = json_object_new_object();
    json_object_object_add(p, "hurst", json_double(t->hurst));
    json_object_object_add(p, "dimension", json_double(3.0 - t->hurst));
    json_object_object_add(p, "sigma", json_double(t->sigma));
    json_object_object_add(p, "seed", json_object_new_uint64(t->seed));
    json_object_object_add(p, "edge", json_object_new_string(edge_name(t)));
    json_object_object_add(p, "noise", json_object_new_string(frt_noise_name(t->noise)));
    if (frt_noise_has_param(t->noise))
        json_object_object_add(p, "noise_param", json_double(t->noise_param));
    json_object_object_add(o, "parameters", p);
    const char *text = json_object_to_json_string_ext(o, JSON_C_TO_STRING_PRETTY | JSON_C_TO_STRING_SPACED |
                                                             JSON_C_TO_STRING_NOSLASHESCAPE);
    char *out = NULL;
    if (text) {
        size_t n = strlen(text);
        out = malloc(n + 2);
        if (out) {
            memcpy(out, text, n);
            out[n] = '\n';
            out[n + 1] = '\0';
        }
    }
    json_object_put(o);
    return out;
}

static int write_index(const job *jb)
{
    char path[PATH_CAP], err[1200];
    snprintf(path, sizeof path, "%s/index.json", jb->dir);
    char *text = index_json(jb);
    if (!text)
        return frt_cli_fail(FRT_EXIT_IO, "out of memory for '%s'", path);
    frt_atomic_file af;
    frt_result r = frt_atomic_open(&af, path, err, sizeof err);
    if (r == FRT_SUCCESS) {
        fputs(text, af.fp);
        r = frt_atomic_commit(&af, err, sizeof err);
    }
    free(text);
    return r == FRT_SUCCESS ? FRT_EXIT_OK : frt_cli_fail(FRT_EXIT_IO, "%s", err);
}

/* ---- directories: made as needed, and removed again (when empty) if the run fails ---- */

typedef struct dirs {
    char **made; /* made by this process, in order */
    size_t n, cap;
    char last[PATH_CAP]; /* the last directory known to exist */
} dirs;

static bool dirs_note(dirs *d, const char *path)
{
    if (d->n == d->cap) {
        size_t cap = d->cap ? 2 * d->cap : 64;
        char **m = realloc(d->made, cap * sizeof *m);
        if (!m)
            return false;
        d->made = m;
        d->cap = cap;
    }
    if (!(d->made[d->n] = strdup(path)))
        return false;
    ++d->n;
    return true;
}

/* Makes the directories of `file` below `root` (which exists). Other processes may make the same ones at the same
 * time: EEXIST is success. */
static int dirs_ensure(dirs *d, const char *root, const char *file)
{
    char dir[PATH_CAP];
    snprintf(dir, sizeof dir, "%s", file);
    char *slash = strrchr(dir, '/');
    *slash = '\0';
    if (strcmp(dir, d->last) == 0)
        return FRT_EXIT_OK;
    for (char *p = dir + strlen(root) + 1;; ++p) {
        if (*p != '/' && *p != '\0')
            continue;
        const char c = *p;
        *p = '\0';
        if (mkdir(dir, 0755) == 0) {
            if (!dirs_note(d, dir))
                return frt_cli_fail(FRT_EXIT_IO, "out of memory");
        } else if (errno != EEXIST) {
            return frt_cli_fail(FRT_EXIT_IO, "cannot create the directory '%s': %s", dir, strerror(errno));
        }
        *p = c;
        if (c == '\0')
            break;
    }
    snprintf(d->last, sizeof d->last, "%s", dir);
    return FRT_EXIT_OK;
}

static void dirs_free(dirs *d, bool remove_empty)
{
    for (size_t i = d->n; i-- > 0;) {
        if (remove_empty)
            rmdir(d->made[i]); /* only succeeds when empty: finished tiles are complete files and stay */
        free(d->made[i]);
    }
    free(d->made);
    memset(d, 0, sizeof *d);
}

/* ---- generation ---- */

typedef struct engine {
    frt_backend backend;
    const char *device;
    frt_context *ctx; /* NULL: the CPU */
    const char *backend_name, *device_name;
} engine;

static int engine_open(engine *e)
{
    e->backend_name = "cpu";
    e->device_name = "CPU reference";
    if (e->backend == FRT_BACKEND_CPU)
        return FRT_EXIT_OK;
    frt_context_desc cd;
    memset(&cd, 0, sizeof cd);
    cd.device = e->device;
    char err[1024];
    if (frt_context_create(&cd, &e->ctx, err, sizeof err) == FRT_SUCCESS) {
        e->backend_name = "vulkan";
        e->device_name = frt_context_device(e->ctx)->name;
        return FRT_EXIT_OK;
    }
    if (e->backend == FRT_BACKEND_DEFAULT && !e->device) {
        fprintf(stderr, "%s: warning: no usable Vulkan device (%s); using the CPU path\n", frt_cli_command, err);
        return FRT_EXIT_OK;
    }
    return frt_cli_fail(FRT_EXIT_DEVICE, "%s", err);
}

/* Generates one region into `out`. In auto mode a device that cannot make it (too large for its memory, or no
 * region support) hands this and every later tile to the CPU, with one warning: the bits are the same. */
static int engine_generate(engine *e, const frt_terrain_desc *d, float *out, size_t count)
{
    if (e->ctx) {
        frt_result r = frt_generate(e->ctx, d, out, count, NULL);
        if (r == FRT_SUCCESS)
            return FRT_EXIT_OK;
        const char *why = frt_context_error(e->ctx)[0] ? frt_context_error(e->ctx) : frt_result_string(r);
        if ((r == FRT_ERROR_TOO_LARGE || r == FRT_ERROR_UNSUPPORTED) && e->backend == FRT_BACKEND_DEFAULT &&
            !e->device) {
            fprintf(stderr, "%s: warning: %s; using the CPU path\n", frt_cli_command, why);
            frt_context_destroy(e->ctx);
            e->ctx = NULL;
            e->backend_name = "cpu";
            e->device_name = "CPU reference";
        } else {
            return frt_cli_fail(FRT_EXIT_DEVICE, "%s", why);
        }
    }
    frt_result r = frt_generate_cpu(d, out, count, NULL);
    return r == FRT_SUCCESS ? FRT_EXIT_OK : frt_cli_fail(FRT_EXIT_USAGE, "%s", frt_result_string(r));
}

/* The file of tile `k` (row-major) of layer `z`, and its region. */
static bool tile_of(const job *jb, uint32_t z, uint64_t k, char *path, frt_terrain_desc *d)
{
    const layer *ly = &jb->layers[z];
    const uint32_t row = (uint32_t)(k / ly->per_side), col = (uint32_t)(k % ly->per_side);
    *d = jb->terrain;
    d->levels = ly->levels;
    d->region.x = col * jb->tile;
    d->region.y = row * jb->tile;
    d->region.width = d->region.height = jb->samples;
    const char *ext = frt_file_format_name(jb->format);
    int n = jb->pyramid ? snprintf(path, PATH_CAP, "%s/%u/%u/%u.%s", jb->dir, z, col, row, ext)
                        : snprintf(path, PATH_CAP, "%s/%u/%u.%s", jb->dir, row, col, ext);
    return n > 0 && n < PATH_CAP;
}

/* k + step, or `end` when that reaches it: K may be as large as 2^64 - 1, and the sum must not wrap around. */
static uint64_t advance(uint64_t k, uint64_t step, uint64_t end)
{
    return end - k > step ? k + step : end;
}

/* Tiles of this share: the global indices i with i % shares == share. */
static uint64_t share_count(const job *jb)
{
    return jb->total > jb->share ? (jb->total - 1 - jb->share) / jb->shares + 1 : 0;
}

static int make_tiles(job *jb, engine *e, dirs *dr, float *field, size_t count, uint64_t *made)
{
    const uint64_t mine = share_count(jb);
    char label[400], path[PATH_CAP], err[1200];
    snprintf(label, sizeof label, "%llu tiles on %s", (unsigned long long)mine, e->device_name);
    frt_progress_begin(label, mine);
    frt_write_desc wd;
    memset(&wd, 0, sizeof wd);
    wd.format = jb->format;
    wd.bits = jb->bits;
    if (jb->quantised) {
        wd.range_min = jb->range_min;
        wd.range_max = jb->range_max;
    }
    /* No backend or device: tiles from any process on any device are the same bytes. */
    int code = FRT_EXIT_OK;
    for (uint32_t z = 0; z < jb->n_layers && code == FRT_EXIT_OK; ++z) {
        const layer *ly = &jb->layers[z];
        /* k: the index within the layer, starting at the first one whose global index is `share` mod `shares` */
        const uint64_t rem = ly->first % jb->shares;
        const uint64_t skip = jb->share >= rem ? jb->share - rem : jb->shares - (rem - jb->share);
        for (uint64_t k = skip; k < ly->count; k = advance(k, jb->shares, ly->count)) {
            frt_terrain_desc d;
            if (!tile_of(jb, z, k, path, &d)) {
                code = frt_cli_fail(FRT_EXIT_USAGE, "'%s': the tile paths are too long", jb->dir);
                break;
            }
            if ((code = engine_generate(e, &d, field, count)) != FRT_EXIT_OK)
                break;
            if ((code = dirs_ensure(dr, jb->dir, path)) != FRT_EXIT_OK)
                break;
            wd.terrain = &d;
            frt_result r = frt_write_heightfield(path, field, jb->samples, jb->samples, &wd, err, sizeof err);
            if (r != FRT_SUCCESS) {
                /* Another process whose run failed may have removed the (then empty) directory: make it again,
                 * once. */
                dr->last[0] = '\0';
                if (dirs_ensure(dr, jb->dir, path) == FRT_EXIT_OK)
                    r = frt_write_heightfield(path, field, jb->samples, jb->samples, &wd, err, sizeof err);
            }
            if (r != FRT_SUCCESS) {
                code = frt_cli_fail(r == FRT_ERROR_IO ? FRT_EXIT_IO : FRT_EXIT_USAGE, "%s", err);
                break;
            }
            frt_progress_set(++*made);
        }
    }
    frt_progress_end();
    return code;
}

/* ---- the command ---- */

static bool is_pow2(uint32_t v)
{
    return v && !(v & (v - 1));
}

static uint32_t log2_u32(uint32_t v)
{
    uint32_t l = 0;
    while (v >>= 1)
        ++l;
    return l;
}

int frt_cmd_tiles(int argc, char **argv)
{
    frt_cli_command = "fracterra tiles";
    enum {
        OPT_LEVELS = 256,
        OPT_BACKEND,
        OPT_DEVICE,
        OPT_TILE,
        OPT_FORMAT,
        OPT_BITS,
        OPT_RANGE,
        OPT_PYRAMID,
        OPT_ONLY,
        OPT_NOISE
    };
    static const struct option opts[] = {{"levels", required_argument, 0, OPT_LEVELS},
                                         {"hurst", required_argument, 0, FRT_OPT_HURST},
                                         {"dimension", required_argument, 0, FRT_OPT_DIMENSION},
                                         {"sigma", required_argument, 0, FRT_OPT_SIGMA},
                                         {"seed", required_argument, 0, FRT_OPT_SEED},
                                         {"edge", required_argument, 0, FRT_OPT_EDGE},
                                         {"noise", required_argument, 0, OPT_NOISE},
                                         {"backend", required_argument, 0, OPT_BACKEND},
                                         {"device", required_argument, 0, OPT_DEVICE},
                                         {"tile", required_argument, 0, OPT_TILE},
                                         {"out", required_argument, 0, 'o'},
                                         {"output", required_argument, 0, 'o'},
                                         {"format", required_argument, 0, OPT_FORMAT},
                                         {"bits", required_argument, 0, OPT_BITS},
                                         {"range", required_argument, 0, OPT_RANGE},
                                         {"pyramid", no_argument, 0, OPT_PYRAMID},
                                         {"only", required_argument, 0, OPT_ONLY},
                                         {"quiet", no_argument, 0, 'q'},
                                         {"help", no_argument, 0, 'h'},
                                         {0, 0, 0, 0}};
    frt_terrain_desc desc;
    memset(&desc, 0, sizeof desc);
    job jb;
    memset(&jb, 0, sizeof jb);
    jb.shares = 1;
    engine eng;
    memset(&eng, 0, sizeof eng);
    bool have_levels = false, have_hurst = false, have_dim = false, have_bits = false, quiet = false;
    double dimension = 0.0;
    uint32_t tile = DEFAULT_TILE;
    const char *format_text = NULL;
    bool have_tile = false;
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":o:qh", opts, NULL)) != -1) {
        switch (c) {
        case OPT_LEVELS:
            if (!frt_parse_u32(optarg, &desc.levels) || desc.levels < 1 || desc.levels > FRT_MAX_REGION_LEVELS)
                return frt_cli_fail(FRT_EXIT_USAGE, "--levels must be an integer from 1 to %u, got '%s'",
                                    FRT_MAX_REGION_LEVELS, optarg);
            have_levels = true;
            break;
        case FRT_OPT_HURST:
        case FRT_OPT_DIMENSION:
        case FRT_OPT_SIGMA:
        case FRT_OPT_SEED:
        case FRT_OPT_EDGE: {
            int code = frt_cli_terrain_option(c, optarg, &desc, &dimension);
            if (code != FRT_EXIT_OK)
                return code;
            have_hurst |= c == FRT_OPT_HURST;
            have_dim |= c == FRT_OPT_DIMENSION;
            break;
        }
        case OPT_NOISE:
            if (!frt_parse_noise(optarg, &desc.noise, &desc.noise_param))
                return frt_cli_fail(FRT_EXIT_USAGE,
                                    "--noise must be gauss, truncated[:K], clt[:N] or uniform, got '%s'", optarg);
            break;
        case OPT_BACKEND:
            if (!frt_parse_backend(optarg, &eng.backend))
                return frt_cli_fail(FRT_EXIT_USAGE, "--backend must be auto, vulkan or cpu, got '%s'", optarg);
            break;
        case OPT_DEVICE: eng.device = optarg; break;
        case OPT_TILE:
            if (!frt_parse_u32(optarg, &tile) || !is_pow2(tile))
                return frt_cli_fail(FRT_EXIT_USAGE, "--tile must be a power of two (1, 2, 4, ... 256, ...), got '%s'",
                                    optarg);
            have_tile = true;
            break;
        case 'o': jb.dir = optarg; break;
        case OPT_FORMAT:
            if (strcmp(optarg, "f32") == 0)
                jb.format = FRT_FILE_F32;
            else if (strcmp(optarg, "npy") == 0)
                jb.format = FRT_FILE_NPY;
            else if (strcmp(optarg, "png") == 0)
                jb.format = FRT_FILE_PNG;
            else if (strcmp(optarg, "pgm") == 0)
                jb.format = FRT_FILE_PGM;
            else
                return frt_cli_fail(FRT_EXIT_USAGE, "--format must be f32, npy, png or pgm, got '%s'", optarg);
            format_text = optarg;
            break;
        case OPT_BITS:
            if (!frt_parse_u32(optarg, &jb.bits) || (jb.bits != 8 && jb.bits != 16))
                return frt_cli_fail(FRT_EXIT_USAGE, "--bits must be 8 or 16, got '%s'", optarg);
            have_bits = true;
            break;
        case OPT_RANGE:
            if (!parse_range(optarg, &jb.range_min, &jb.range_max))
                return frt_cli_fail(FRT_EXIT_USAGE,
                                    "--range must be MIN,MAX with numbers MIN < MAX (single precision), got '%s'",
                                    optarg);
            jb.range_min = (double)(float)jb.range_min; /* as the writers will use and record it */
            jb.range_max = (double)(float)jb.range_max;
            jb.range_given = true;
            break;
        case OPT_PYRAMID: jb.pyramid = true; break;
        case OPT_ONLY:
            if (!parse_share(optarg, &jb.share, &jb.shares))
                return frt_cli_fail(FRT_EXIT_USAGE, "--only must be I/K with whole numbers 0 <= I < K, got '%s'",
                                    optarg);
            break;
        case 'q': quiet = true; break;
        case 'h': tiles_help(); return FRT_EXIT_OK;
        case ':': return frt_cli_fail(FRT_EXIT_USAGE, "option '%s' needs a value", argv[optind - 1]);
        default: return frt_cli_fail(FRT_EXIT_USAGE, "unknown option '%s' (see --help)", argv[optind - 1]);
        }
    }
    if (optind < argc)
        return frt_cli_fail(FRT_EXIT_USAGE, "unexpected argument '%s' (see --help)", argv[optind]);
    if (!have_levels)
        return frt_cli_fail(FRT_EXIT_USAGE, "missing --levels N (1 to %u)", FRT_MAX_REGION_LEVELS);
    if (!jb.dir || !*jb.dir)
        return frt_cli_fail(FRT_EXIT_USAGE, "missing --out DIR");
    char dir[PATH_CAP - 64]; /* without trailing slashes, with room for "/ROW/COL.EXT" */
    if (strlen(jb.dir) >= sizeof dir)
        return frt_cli_fail(FRT_EXIT_USAGE, "--out '%s': the path is too long", jb.dir);
    strcpy(dir, jb.dir);
    for (size_t len = strlen(dir); len > 1 && dir[len - 1] == '/';)
        dir[--len] = '\0';
    jb.dir = dir;
    if (have_hurst && have_dim)
        return frt_cli_fail(FRT_EXIT_USAGE, "give --hurst or --dimension, not both (H = 3 - D)");
    if (have_dim)
        desc.hurst = 3.0 - dimension;
    if (eng.backend == FRT_BACKEND_CPU && eng.device)
        return frt_cli_fail(FRT_EXIT_USAGE, "--device needs the vulkan (or auto) backend");
    if ((uint64_t)tile > (UINT64_C(1) << desc.levels))
        return frt_cli_fail(FRT_EXIT_USAGE,
                            "--tile %u%s is larger than the grid: %u levels have 2^%u = %llu cells a side", tile,
                            have_tile ? "" : " (the default)", desc.levels, desc.levels,
                            (unsigned long long)(UINT64_C(1) << desc.levels));
    if (jb.pyramid && tile < 2) /* zoom 0 would be a grid of 0 levels */
        return frt_cli_fail(FRT_EXIT_USAGE, "--pyramid needs --tile 2 or more, got 1");
    if (jb.pyramid) {
        if (jb.format != FRT_FILE_DEFAULT && jb.format != FRT_FILE_PNG)
            return frt_cli_fail(FRT_EXIT_USAGE, "--pyramid writes PNG tiles; --format %s is not available with it",
                                format_text);
        jb.format = FRT_FILE_PNG;
    } else if (jb.format == FRT_FILE_DEFAULT) {
        jb.format = FRT_FILE_F32; /* lossless: tiles stitch into the grid exactly */
    }
    jb.quantised = jb.format == FRT_FILE_PNG || jb.format == FRT_FILE_PGM;
    if (have_bits && !jb.quantised)
        return frt_cli_fail(FRT_EXIT_USAGE, "--bits applies to png and pgm tiles, not %s",
                            frt_file_format_name(jb.format));
    if (jb.range_given && !jb.quantised)
        return frt_cli_fail(FRT_EXIT_USAGE,
                            "--range applies to png and pgm tiles; %s tiles keep the heights as they are",
                            frt_file_format_name(jb.format));
    if (jb.quantised && !jb.bits)
        jb.bits = 16;
    desc.region.width = desc.region.height = 1; /* more than FRT_MAX_LEVELS levels are valid for regions */
    if (frt_terrain_desc_resolved(&desc, &jb.terrain) != FRT_SUCCESS) {
        char why[256];
        frt_terrain_desc_check(&desc, why, sizeof why);
        return frt_cli_fail(FRT_EXIT_USAGE, "invalid parameters: %s", why);
    }
    memset(&jb.terrain.region, 0, sizeof jb.terrain.region);

    /* The layout. A file holds at most 2^32 samples (FRT_FILE_MAX_POINTS). */
    jb.tile = tile;
    jb.log2_tile = log2_u32(tile);
    jb.samples = jb.pyramid ? tile : tile + 1;
    if ((uint64_t)jb.samples * jb.samples > (UINT64_C(1) << 32))
        return frt_cli_fail(FRT_EXIT_USAGE, "--tile %u: a tile of %u x %u samples is more than a file holds (2^32)",
                            tile, jb.samples, jb.samples);
    const uint32_t n = jb.terrain.levels;
    jb.n_layers = jb.pyramid ? n - jb.log2_tile + 1 : 1;
    for (uint32_t z = 0; z < jb.n_layers; ++z) {
        layer *ly = &jb.layers[z];
        ly->levels = jb.pyramid ? jb.log2_tile + z : n;
        ly->per_side = (uint32_t)((UINT64_C(1) << ly->levels) >> jb.log2_tile);
        ly->first = jb.total;
        ly->count = (uint64_t)ly->per_side * ly->per_side;
        jb.total += ly->count;
    }
    if (jb.quantised && !jb.range_given) {
        int rc = derive_range(&jb);
        if (rc != FRT_EXIT_OK)
            return rc;
    }
    const size_t count = (size_t)jb.samples * jb.samples;
    float *field = malloc(count * sizeof *field);
    if (!field)
        return frt_cli_fail(FRT_EXIT_DEVICE, "cannot allocate %.1f MiB for a %u x %u tile on this host",
                            (double)count * 4.0 / 1048576.0, jb.samples, jb.samples);

    /* The directory, and an early check that it can be written, before any work. */
    int code = FRT_EXIT_OK;
    bool made_dir = mkdir(jb.dir, 0755) == 0;
    struct stat st;
    if (!made_dir && errno != EEXIST) {
        free(field);
        return frt_cli_fail(FRT_EXIT_IO, "cannot create the output directory '%s': %s", jb.dir, strerror(errno));
    }
    if (!made_dir && (stat(jb.dir, &st) != 0 || !S_ISDIR(st.st_mode))) {
        free(field);
        return frt_cli_fail(FRT_EXIT_IO, "'%s' exists and is not a directory", jb.dir);
    }
    char probe[PATH_CAP];
    dirs dr;
    memset(&dr, 0, sizeof dr);
    uint64_t made = 0;
    double t0 = frt_now_seconds();
    snprintf(probe, sizeof probe, "%s/index.json", jb.dir);
    if (!frt_cli_probe_writable(probe, &code))
        goto out;

    frt_progress_init(quiet);
    if ((code = engine_open(&eng)) != FRT_EXIT_OK)
        goto out;
    if ((code = make_tiles(&jb, &eng, &dr, field, count, &made)) != FRT_EXIT_OK)
        goto out;
    if ((code = write_index(&jb)) != FRT_EXIT_OK)
        goto out;
    if (!quiet) {
        const uint32_t side = grid_side(&jb.terrain, n);
        fprintf(stderr, "%s: %llu of %llu %s tiles", frt_cli_command, (unsigned long long)made,
                (unsigned long long)jb.total, frt_file_format_name(jb.format));
        if (jb.shares > 1)
            fprintf(stderr, " (share %llu/%llu)", (unsigned long long)jb.share, (unsigned long long)jb.shares);
        if (jb.pyramid)
            fprintf(stderr, ", zoom 0..%u of %u x %u", jb.n_layers - 1, jb.samples, jb.samples);
        else
            fprintf(stderr, " of %u x %u", jb.samples, jb.samples);
        fprintf(stderr,
                " from the %u x %u grid (levels %u, H %.3g, sigma %.6g, seed %llu) on %s [%s] in %.3f s -> %s/\n", side,
                side, n, jb.terrain.hurst, jb.terrain.sigma, (unsigned long long)jb.terrain.seed, eng.device_name,
                eng.backend_name, frt_now_seconds() - t0, jb.dir);
    }
out:
    dirs_free(&dr, code != FRT_EXIT_OK);
    if (code != FRT_EXIT_OK && made_dir)
        rmdir(jb.dir); /* only when still empty */
    frt_context_destroy(eng.ctx);
    free(field);
    return code;
}
