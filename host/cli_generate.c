/* cli_generate.c — `fracterra generate`: parse, validate, generate on the chosen backend, write the outputs
 * (each atomically), a preview and growth frames. */
#include "cli.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

static void generate_help(void)
{
    printf(
        "Usage: fracterra generate [options] -o FILE [-o FILE ...]\n"
        "\n"
        "Generates a (2^N+1) x (2^N+1) heightfield by FFC random midpoint displacement (docs/ALGORITHM.md),\n"
        "or a window of one (--region).\n"
        "\n"
        "Terrain:\n"
        "  --levels N          refinement levels, grid side 2^N+1 (1..%u, or 1..%u with --region; default %u\n"
        "                      -> 513 x 513)\n"
        "  --hurst H           Hurst exponent, 0 < H < 1 (default %.1f); larger is smoother\n"
        "  --dimension D       fractal dimension, 2 < D < 3, H = 3 - D (not with --hurst)\n"
        "  --sigma S           amplitude, any non-zero real; negative inverts peaks and valleys (default 1)\n"
        "  --seed U64          noise key, decimal or 0x hex (default 1)\n"
        "  --edge E            ffc (default): (2^N+1)^2, border points average 3 neighbours;\n"
        "                      periodic: 2^N x 2^N on a torus, copies tile without seams\n"
        "  --region X0,Y0,W,H  only the W x H window at column X0, row Y0 of the grid, equal to that part of the\n"
        "                      whole grid; only its ancestors are computed, so N may be up to %u. FFC: the\n"
        "                      window lies inside the grid; periodic: X0, Y0 < 2^N and the window may wrap\n"
        "  --noise DIST        distribution of the displacements, each of unit variance (ALGORITHM.md §2.8):\n"
        "                      gauss (default) | truncated[:K] (|g| <= K, K in [1, 6], default 3: the\n"
        "                      report's chopped Gaussian) | clt[:N] (sum of N uniforms, 1..16, default 4) | uniform\n"
        "\n"
        "Real data (ALGORITHM.md §3.4-3.6):\n"
        "  --coarse FILE       densify known heights: a (2^k+1) x (2^k+1) grid (2^k x 2^k periodic) in any\n"
        "                      readable format (.tif GeoTIFF, .png, .pgm, .npy, .f32) placed at spacing 2^(N-k);\n"
        "                      its samples are kept exactly, no-data cells (NaN, the GeoTIFF nodata) are filled,\n"
        "                      levels k+1..N are generated. Other sizes are refused (crop or resample first),\n"
        "                      or:\n"
        "  --fit pad           take a --coarse grid of any size w x h (at least 2 x 2): it is placed at the top\n"
        "                      left of the smallest (2^k+1)^2 grid that holds it, the rest is filled by mirroring\n"
        "                      the data about its last row and column, and the output is the data's area alone,\n"
        "                      (w-1)*2^(N-k)+1 x (h-1)*2^(N-k)+1 (a --region must lie inside it); FFC only\n"
        "  --hurst auto        estimate H from the --coarse grid (variogram of its midpoint residuals)\n"
        "  --sigma auto        estimate sigma from the --coarse grid likewise; the estimates are printed and\n"
        "                      recorded in the outputs' metadata\n"
        "  --roughness-map F   H per location (values in (0, 1)), bilinear over the unit square (not with --hurst)\n"
        "  --dimension-map F   D per location (values in (2, 3)), H = 3 - D (not with --roughness-map)\n"
        "  --amplitude-map F   a factor on sigma per location, bilinear over the unit square\n"
        "\n"
        "Device:\n"
        "  --backend B         auto | vulkan | cpu (default auto: Vulkan if a device exists, else CPU)\n"
        "  --device D          Vulkan device by index or name substring (see: fracterra devices)\n"
        "\n"
        "Output (-o may be given several times; the extension picks the format):\n"
        "  -o, --output FILE   .png  greyscale PNG, min..max -> 0..65535, parameters in text chunks\n"
        "                      .pgm  Netpbm P5 greyscale, min..max -> 0..65535, parameters in comments\n"
        "                      .npy  float32 for numpy.load\n"
        "                      .f32  raw little-endian float32, row-major, with FILE.json sidecar\n"
        "                      .obj  Wavefront OBJ triangle mesh with normals (z up, north = +y)\n"
        "                      .ply  binary PLY triangle mesh with normals\n"
        "                      .tif  float32 GeoTIFF (GDAL); with a GeoTIFF --coarse, georeferenced like it with\n"
        "                            pixels 2^(N-k) times smaller\n"
        "  --bits 8|16         sample depth of .png and .pgm (default 16)\n"
        "  --mesh-stride K     meshes keep every K-th row and column, and the last (default 1)\n"
        "  --spacing D[,DY]    ground distance between columns (and rows), in height units (default 1);\n"
        "                      recorded in the metadata, used by meshes and by the preview's shading\n"
        "  --z-scale Z         meshes: vertex z = height * Z (default 1); recorded\n"
        "  --preview FILE.png  also write a shaded-relief picture (Horn hillshade, light from the north-west)\n"
        "  --preview-style S   hillshade | color (hypsometric colours over the hillshade; default hillshade)\n"
        "  --frames DIR        write the field after each level, DIR/frame-00.png ... frame-NN.png: 16-bit\n"
        "                      PNGs upsampled (nearest neighbour) to the final size on the final field's scale\n"
        "                      (whole grids only, not with --region)\n"
        "  --gif FILE.gif      the same frames as one animated GIF (at most 1025 pixels a side: larger\n"
        "                      fields are subsampled; not with --region)\n"
        "  -q, --quiet         no progress and no summary line on stderr\n"
        "  -h, --help          this text\n"
        "\n"
        "Every file appears only when complete: it is written to a temporary file and renamed, so a failure\n"
        "never leaves a partial file or replaces an existing one. Unwritable outputs are reported before any\n"
        "work is done.\n",
        FRT_MAX_LEVELS, FRT_MAX_REGION_LEVELS, FRT_DEFAULT_LEVELS, FRT_DEFAULT_HURST, FRT_MAX_REGION_LEVELS);
}

/* Opens the context for `backend`, or returns NULL with *use_cpu set for the auto fallback; on a hard failure
 * sets *exit_code. */
static frt_context *open_vulkan(frt_backend backend, const char *device, bool *use_cpu, int *exit_code)
{
    frt_context_desc cd;
    memset(&cd, 0, sizeof cd);
    cd.device = device;
    frt_context *ctx = NULL;
    char err[1024];
    frt_result r = frt_context_create(&cd, &ctx, err, sizeof err);
    if (r == FRT_SUCCESS)
        return ctx;
    if (backend == FRT_BACKEND_DEFAULT && !device) {
        fprintf(stderr, "%s: warning: no usable Vulkan device (%s); using the CPU path\n", frt_cli_command, err);
        *use_cpu = true;
        return NULL;
    }
    *exit_code = frt_cli_fail(FRT_EXIT_DEVICE, "%s", err);
    return NULL;
}

/* "X0,Y0,W,H": four whole numbers separated by commas, nothing else. */
static bool parse_region(const char *s, frt_region *g)
{
    char buf[128];
    if (strlen(s) >= sizeof buf)
        return false;
    strcpy(buf, s);
    uint32_t v[4];
    char *p = buf;
    for (int i = 0; i < 4; ++i) {
        char *comma = strchr(p, ',');
        if ((i < 3) != (comma != NULL))
            return false;
        if (comma)
            *comma = '\0';
        if (!frt_parse_u32(p, &v[i]))
            return false;
        p = comma ? comma + 1 : p;
    }
    g->x = v[0], g->y = v[1], g->width = v[2], g->height = v[3];
    return true;
}

/* The region against the grid of `d` (levels and edge resolved): one message naming the problem and the grid's
 * side, so that the user need not know the library's rules (docs/ALGORITHM.md §3.2). */
static int check_region(const frt_terrain_desc *d, const char *text)
{
    const frt_region g = d->region;
    const bool periodic = d->edge == FRT_EDGE_PERIODIC;
    const unsigned long long side = (1ull << d->levels) + (periodic ? 0u : 1u);
    if (g.width == 0 || g.height == 0)
        return frt_cli_fail(FRT_EXIT_USAGE, "--region %s: width and height must both be at least 1", text);
    if (periodic) {
        if (g.x >= side || g.y >= side)
            return frt_cli_fail(FRT_EXIT_USAGE,
                                "--region %s: the origin %u,%u lies outside the %llu x %llu periodic grid of levels "
                                "%u (X0 and Y0 must be below %llu; the window may wrap)",
                                text, g.x, g.y, side, side, d->levels, side);
        if (g.width > FRT_REGION_MAX_SIDE || g.height > FRT_REGION_MAX_SIDE)
            return frt_cli_fail(FRT_EXIT_USAGE, "--region %s: a side is larger than %u", text, FRT_REGION_MAX_SIDE);
    } else if ((uint64_t)g.x + g.width > side || (uint64_t)g.y + g.height > side) {
        return frt_cli_fail(FRT_EXIT_USAGE,
                            "--region %s reaches outside the %llu x %llu grid of levels %u (X0 + W and Y0 + H must be "
                            "at most %llu)",
                            text, side, side, d->levels, side);
    }
    if ((uint64_t)g.width * g.height > FRT_FILE_MAX_POINTS)
        return frt_cli_fail(FRT_EXIT_USAGE,
                            "--region %s: %u x %u is more than 2^32 heights, the most a fracterra file holds", text,
                            g.width, g.height);
    return FRT_EXIT_OK;
}

/* "X,Y": two finite numbers. */
static bool parse_origin(const char *s, double *x, double *y)
{
    const char *comma = strchr(s, ',');
    char buf[128];
    if (!comma || (size_t)(comma - s) >= sizeof buf)
        return false;
    memcpy(buf, s, (size_t)(comma - s));
    buf[comma - s] = '\0';
    return frt_parse_double(buf, x) && frt_parse_double(comma + 1, y);
}

/* Appends formatted text to the history line, truncating at its size. */
static void append(char *buf, size_t size, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
static void append(char *buf, size_t size, const char *fmt, ...)
{
    size_t used = strlen(buf);
    if (used + 1 >= size)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf + used, size - used, fmt, ap);
    va_end(ap);
}

/* --coarse, --hurst/--sigma auto and the maps: reads the files, estimates, fills `d` (resolved) and a history line
 * for the metadata; prints the estimates. Returns an exit code; the buffers are the caller's to free. */
static int load_inputs(frt_terrain_desc *d, const char *coarse, bool fit_pad, bool have_region, const char *hmap,
                       bool hmap_is_dimension, const char *amap, bool hurst_auto, bool sigma_auto, bool quiet,
                       float **coarse_h, float **hmap_h, float **amap_h, frt_field_info *cinfo, char *history,
                       size_t history_size)
{
    int code = FRT_EXIT_OK;
    uint32_t cs = 0; /* the coarse grid's side, padded or not */
    bool padded = false;
    if (coarse) {
        uint32_t k = 0;
        frt_progress_begin("reading the coarse grid", 0);
        code = frt_cli_load_coarse(coarse, d->edge == FRT_EDGE_PERIODIC, fit_pad, coarse_h, &k, cinfo);
        frt_progress_end();
        if (code != FRT_EXIT_OK)
            return code;
        if (k > d->levels)
            return frt_cli_fail(FRT_EXIT_USAGE,
                                "--coarse %s is %u x %u (k = %u levels): --levels must be at least %u to densify it",
                                coarse, cinfo->width, cinfo->height, k, k);
        d->coarse = *coarse_h;
        d->coarse_levels = k;
        cs = frt_grid_side(k) - (d->edge == FRT_EDGE_PERIODIC ? 1u : 0u);
        padded = cs != cinfo->width || cs != cinfo->height;
        size_t known = 0, cells = (size_t)cinfo->width * cinfo->height;
        for (size_t i = 0; i < (size_t)cs * cs; ++i) /* the padding is NaN until frt_cli_mirror_pad below */
            known += !isnan((*coarse_h)[i]);
        char pad[96] = "";
        if (padded)
            snprintf(pad, sizeof pad, ", mirrored to %u x %u by --fit pad", cs, cs);
        append(history, history_size, "densified from %s (%u x %u%s, k = %u, %zu known, %zu no-data) to %u levels",
               coarse, cinfo->width, cinfo->height, pad, k, known, cells - known, d->levels);
        if (known == 0)
            return frt_cli_fail(FRT_EXIT_USAGE, "--coarse %s holds no known height (every cell is no-data)", coarse);
    }
    if (hurst_auto || sigma_auto) {
        /* a periodic coarse grid (2^k)^2 is closed into (2^k+1)^2 by repeating its first row and column; a padded
         * one is still NaN outside the data, so the estimate sees the data alone */
        const uint32_t es = d->edge == FRT_EDGE_PERIODIC ? cs + 1 : cs;
        float *e = malloc((size_t)es * es * sizeof *e);
        if (!e)
            return frt_cli_fail(FRT_EXIT_IO, "out of memory for the estimate");
        for (uint32_t y = 0; y < es; ++y)
            for (uint32_t x = 0; x < es; ++x)
                e[(size_t)y * es + x] = (*coarse_h)[(size_t)(y % cs) * cs + x % cs];
        frt_roughness est;
        frt_result r = frt_estimate_roughness(e, es, &est);
        free(e);
        if (r != FRT_SUCCESS)
            return frt_cli_fail(FRT_EXIT_USAGE,
                                "--%s auto: %s has too few known heights with relief to estimate from (a %s grid needs "
                                "at least 9 x 9 and at least three refinement steps with 16 known residuals)",
                                hurst_auto ? "hurst" : "sigma", coarse,
                                d->edge == FRT_EDGE_PERIODIC ? "8 x 8" : "9 x 9");
        if (hurst_auto)
            d->hurst = est.hurst;
        const double sigma = sigma_auto ? exp2(est.log2_rms_centre + d->hurst * est.t_centre) : d->sigma;
        if (sigma_auto)
            d->sigma = sigma;
        if (!quiet)
            fprintf(stderr,
                    "%s: estimated from %s (%u levels, %llu residuals, variogram of midpoint residuals): %s%.4g "
                    "(D %.4g)%s, %ssigma %.6g\n",
                    frt_cli_command, coarse, est.coarse_levels, (unsigned long long)est.residuals,
                    hurst_auto ? "H " : "H (given) ", d->hurst, 3.0 - d->hurst,
                    est.clamped && hurst_auto ? " [clamped]" : "", sigma_auto ? "" : "(given) ", d->sigma);
        append(history, history_size,
               "; %s%s%s estimated from it (variogram of midpoint residuals, %llu residuals): H %.6g, "
               "sigma %.6g%s",
               hurst_auto ? "hurst" : "", hurst_auto && sigma_auto ? " and " : "", sigma_auto ? "sigma" : "",
               (unsigned long long)est.residuals, d->hurst, d->sigma, est.clamped && hurst_auto ? " (H clamped)" : "");
    }
    if (padded) {
        frt_cli_mirror_pad(*coarse_h, cs, cinfo->width, cinfo->height);
        /* the data's area of the grid at N levels: coarse sample (a, b) is grid point (a, b) * 2^(N-k) */
        const uint64_t s = UINT64_C(1) << (d->levels - d->coarse_levels);
        const uint64_t dw = (cinfo->width - 1) * s + 1, dh = (cinfo->height - 1) * s + 1;
        if (!have_region && dw * dh > FRT_FILE_MAX_POINTS)
            return frt_cli_fail(FRT_EXIT_USAGE,
                                "--coarse %s at --levels %u covers %llu x %llu heights: more than 2^32, the most a "
                                "fracterra file holds (use fewer levels, or --region)",
                                coarse, d->levels, (unsigned long long)dw, (unsigned long long)dh);
        if (!have_region) {
            d->region.x = d->region.y = 0;
            d->region.width = (uint32_t)dw, d->region.height = (uint32_t)dh;
        } else if ((uint64_t)d->region.x + d->region.width > dw || (uint64_t)d->region.y + d->region.height > dh) {
            return frt_cli_fail(FRT_EXIT_USAGE,
                                "--region %u,%u,%u,%u reaches outside the data's area, %llu x %llu at --levels %u "
                                "(--coarse %s is %u x %u, padded by --fit pad)",
                                d->region.x, d->region.y, d->region.width, d->region.height, (unsigned long long)dw,
                                (unsigned long long)dh, d->levels, coarse, cinfo->width, cinfo->height);
        }
    }
    if (hmap) {
        code = frt_cli_load_map(hmap, hmap_is_dimension ? FRT_CLI_MAP_DIMENSION : FRT_CLI_MAP_HURST, hmap_h,
                                &d->hurst_map);
        if (code != FRT_EXIT_OK)
            return code;
        append(history, history_size, "%s%s %s (%u x %u)", history[0] ? "; " : "",
               hmap_is_dimension ? "dimension map" : "roughness map", hmap, d->hurst_map.width, d->hurst_map.height);
    }
    if (amap) {
        code = frt_cli_load_map(amap, FRT_CLI_MAP_AMPLITUDE, amap_h, &d->amplitude_map);
        if (code != FRT_EXIT_OK)
            return code;
        append(history, history_size, "%samplitude map %s (%u x %u)", history[0] ? "; " : "", amap,
               d->amplitude_map.width, d->amplitude_map.height);
    }
    char why[256];
    if (frt_terrain_desc_check(d, why, sizeof why) != FRT_SUCCESS)
        return frt_cli_fail(FRT_EXIT_USAGE, "invalid parameters: %s", why);
    return FRT_EXIT_OK;
}

#define MAX_OUTPUTS 8
#define FMT_BIT(f) (1u << (f))
#define ALL_HEIGHTFIELDS                                                                                               \
    (FMT_BIT(FRT_FILE_PNG) | FMT_BIT(FRT_FILE_PGM) | FMT_BIT(FRT_FILE_F32) | FMT_BIT(FRT_FILE_NPY) |                   \
     FMT_BIT(FRT_FILE_OBJ) | FMT_BIT(FRT_FILE_PLY) | FMT_BIT(FRT_FILE_TIFF))

int frt_cmd_generate(int argc, char **argv)
{
    frt_cli_command = "fracterra generate";
    enum {
        OPT_LEVELS = 256,
        OPT_BACKEND,
        OPT_DEVICE,
        OPT_BITS,
        OPT_STRIDE,
        OPT_SPACING,
        OPT_ZSCALE,
        OPT_PREVIEW,
        OPT_PREVIEW_STYLE,
        OPT_FRAMES,
        OPT_GIF,
        OPT_REGION,
        OPT_NOISE,
        OPT_COARSE,
        OPT_HMAP,
        OPT_DMAP,
        OPT_AMAP,
        OPT_CRS,
        OPT_ORIGIN,
        OPT_FIT
    };
    static const struct option opts[] = {{"levels", required_argument, 0, OPT_LEVELS},
                                         {"hurst", required_argument, 0, FRT_OPT_HURST},
                                         {"dimension", required_argument, 0, FRT_OPT_DIMENSION},
                                         {"sigma", required_argument, 0, FRT_OPT_SIGMA},
                                         {"seed", required_argument, 0, FRT_OPT_SEED},
                                         {"backend", required_argument, 0, OPT_BACKEND},
                                         {"device", required_argument, 0, OPT_DEVICE},
                                         {"bits", required_argument, 0, OPT_BITS},
                                         {"mesh-stride", required_argument, 0, OPT_STRIDE},
                                         {"spacing", required_argument, 0, OPT_SPACING},
                                         {"z-scale", required_argument, 0, OPT_ZSCALE},
                                         {"preview", required_argument, 0, OPT_PREVIEW},
                                         {"preview-style", required_argument, 0, OPT_PREVIEW_STYLE},
                                         {"frames", required_argument, 0, OPT_FRAMES},
                                         {"gif", required_argument, 0, OPT_GIF},
                                         {"edge", required_argument, 0, FRT_OPT_EDGE},
                                         {"region", required_argument, 0, OPT_REGION},
                                         {"noise", required_argument, 0, OPT_NOISE},
                                         {"coarse", required_argument, 0, OPT_COARSE},
                                         {"fit", required_argument, 0, OPT_FIT},
                                         {"roughness-map", required_argument, 0, OPT_HMAP},
                                         {"dimension-map", required_argument, 0, OPT_DMAP},
                                         {"amplitude-map", required_argument, 0, OPT_AMAP},
                                         {"crs", required_argument, 0, OPT_CRS},
                                         {"origin", required_argument, 0, OPT_ORIGIN},
                                         {"output", required_argument, 0, 'o'},
                                         {"quiet", no_argument, 0, 'q'},
                                         {"help", no_argument, 0, 'h'},
                                         {0, 0, 0, 0}};
    frt_terrain_desc desc;
    memset(&desc, 0, sizeof desc);
    frt_write_desc wd;
    memset(&wd, 0, sizeof wd);
    bool have_hurst = false, have_dim = false, quiet = false, have_bits = false, have_stride = false,
         preview_color = false, hurst_auto = false, sigma_auto = false, have_levels = false, have_spacing = false;
    const char *coarse = NULL, *hmap = NULL, *amap = NULL, *noise = NULL, *crs = NULL;
    double origin_x = 0.0, origin_y = 0.0;
    bool have_origin = false;
    bool hmap_is_dimension = false, fit_pad = false;
    double dimension = 0.0;
    frt_backend backend = FRT_BACKEND_DEFAULT;
    const char *device = NULL, *outputs[MAX_OUTPUTS], *preview = NULL, *frames = NULL, *gif = NULL, *region = NULL;
    frt_file_format formats[MAX_OUTPUTS];
    unsigned n_outputs = 0;
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":o:qh", opts, NULL)) != -1) {
        switch (c) {
        case OPT_LEVELS:
            if (!frt_parse_u32(optarg, &desc.levels) || desc.levels < 1 || desc.levels > FRT_MAX_REGION_LEVELS)
                return frt_cli_fail(FRT_EXIT_USAGE,
                                    "--levels must be an integer from 1 to %u (or to %u with --region), got '%s'",
                                    FRT_MAX_LEVELS, FRT_MAX_REGION_LEVELS, optarg);
            have_levels = true;
            break;
        case FRT_OPT_HURST:
        case FRT_OPT_SIGMA:
            if (strcmp(optarg, "auto") == 0) { /* estimated from --coarse */
                hurst_auto |= c == FRT_OPT_HURST;
                sigma_auto |= c == FRT_OPT_SIGMA;
                have_hurst |= c == FRT_OPT_HURST;
                break;
            }
            /* fall through */
        case FRT_OPT_DIMENSION:
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
            noise = optarg;
            break;
        case OPT_COARSE: coarse = optarg; break;
        case OPT_FIT:
            if (strcmp(optarg, "pad") != 0)
                return frt_cli_fail(FRT_EXIT_USAGE,
                                    "--fit must be pad (mirror the edges out to the next 2^k + 1), got '%s'; to "
                                    "resample, use gdalwarp -ts first",
                                    optarg);
            fit_pad = true;
            break;
        case OPT_HMAP:
        case OPT_DMAP:
            if (hmap)
                return frt_cli_fail(FRT_EXIT_USAGE, "give one of --roughness-map and --dimension-map (H = 3 - D)");
            hmap = optarg;
            hmap_is_dimension = c == OPT_DMAP;
            break;
        case OPT_AMAP: amap = optarg; break;
        case OPT_CRS: crs = optarg; break;
        case OPT_ORIGIN:
            if (!parse_origin(optarg, &origin_x, &origin_y))
                return frt_cli_fail(FRT_EXIT_USAGE, "--origin must be X,Y (two finite numbers), got '%s'", optarg);
            have_origin = true;
            break;
        case OPT_BACKEND:
            if (!frt_parse_backend(optarg, &backend))
                return frt_cli_fail(FRT_EXIT_USAGE, "--backend must be auto, vulkan or cpu, got '%s'", optarg);
            break;
        case OPT_DEVICE: device = optarg; break;
        case OPT_BITS:
            if (!frt_parse_u32(optarg, &wd.bits) || (wd.bits != 8 && wd.bits != 16))
                return frt_cli_fail(FRT_EXIT_USAGE, "--bits must be 8 or 16, got '%s'", optarg);
            have_bits = true;
            break;
        case OPT_STRIDE:
            if (!frt_parse_u32(optarg, &wd.mesh_stride) || wd.mesh_stride < 1)
                return frt_cli_fail(FRT_EXIT_USAGE, "--mesh-stride must be a positive integer, got '%s'", optarg);
            have_stride = true;
            break;
        case OPT_SPACING:
            if (!frt_parse_spacing(optarg, &wd.spacing_x, &wd.spacing_y))
                return frt_cli_fail(FRT_EXIT_USAGE, "--spacing must be D or DX,DY with positive numbers, got '%s'",
                                    optarg);
            have_spacing = true;
            break;
        case OPT_ZSCALE:
            if (!frt_parse_double(optarg, &wd.z_scale) || wd.z_scale == 0.0)
                return frt_cli_fail(FRT_EXIT_USAGE, "--z-scale must be a non-zero number, got '%s'", optarg);
            break;
        case OPT_PREVIEW: preview = optarg; break;
        case OPT_PREVIEW_STYLE:
            if (strcmp(optarg, "hillshade") != 0 && strcmp(optarg, "color") != 0)
                return frt_cli_fail(FRT_EXIT_USAGE, "--preview-style must be hillshade or color, got '%s'", optarg);
            preview_color = strcmp(optarg, "color") == 0;
            break;
        case OPT_FRAMES: frames = optarg; break;
        case OPT_GIF: gif = optarg; break;
        case OPT_REGION:
            if (!parse_region(optarg, &desc.region))
                return frt_cli_fail(FRT_EXIT_USAGE,
                                    "--region must be X0,Y0,W,H: four whole numbers separated by commas, got '%s'",
                                    optarg);
            region = optarg;
            break;
        case 'o':
            if (n_outputs == MAX_OUTPUTS)
                return frt_cli_fail(FRT_EXIT_USAGE, "at most %d outputs (-o)", MAX_OUTPUTS);
            outputs[n_outputs++] = optarg;
            break;
        case 'q': quiet = true; break;
        case 'h': generate_help(); return FRT_EXIT_OK;
        case ':': return frt_cli_fail(FRT_EXIT_USAGE, "option '%s' needs a value", argv[optind - 1]);
        default: return frt_cli_fail(FRT_EXIT_USAGE, "unknown option '%s' (see --help)", argv[optind - 1]);
        }
    }
    if (optind < argc)
        return frt_cli_fail(FRT_EXIT_USAGE, "unexpected argument '%s' (see --help)", argv[optind]);
    if (have_hurst && have_dim)
        return frt_cli_fail(FRT_EXIT_USAGE, "give --hurst or --dimension, not both (H = 3 - D)");
    if (have_dim)
        desc.hurst = 3.0 - dimension;
    if (coarse && !have_levels)
        return frt_cli_fail(FRT_EXIT_USAGE, "--coarse needs --levels N: the levels of the densified grid (at least "
                                            "the coarse grid's k, for its side 2^k + 1)");
    if (fit_pad && !coarse)
        return frt_cli_fail(FRT_EXIT_USAGE, "--fit pad applies to a --coarse grid, and there is none");
    if (fit_pad && desc.edge == FRT_EDGE_PERIODIC)
        return frt_cli_fail(FRT_EXIT_USAGE,
                            "--fit pad needs --edge ffc: a padded grid does not wrap (a periodic --coarse grid must be "
                            "2^k x 2^k)");
    if ((hurst_auto || sigma_auto) && !coarse)
        return frt_cli_fail(FRT_EXIT_USAGE, "--%s auto estimates from known heights: it needs --coarse FILE",
                            hurst_auto ? "hurst" : "sigma");
    if (hmap && (have_hurst || have_dim))
        return frt_cli_fail(FRT_EXIT_USAGE, "%s gives H per location: not with --hurst or --dimension",
                            hmap_is_dimension ? "--dimension-map" : "--roughness-map");
    (void)noise;
    if (desc.levels > FRT_MAX_LEVELS && !region)
        return frt_cli_fail(FRT_EXIT_USAGE,
                            "--levels %u needs --region: a whole grid is limited to %u levels (%u x %u); a region "
                            "may come from a grid of up to %u",
                            desc.levels, FRT_MAX_LEVELS, frt_grid_side(FRT_MAX_LEVELS), frt_grid_side(FRT_MAX_LEVELS),
                            FRT_MAX_REGION_LEVELS);
    if (region && (frames || gif))
        return frt_cli_fail(FRT_EXIT_USAGE,
                            "%s does not apply to --region: the growth frames are those of a whole grid, and a "
                            "window holds no points of the coarse levels",
                            frames ? "--frames" : "--gif");
    if (n_outputs == 0 && !preview && !frames && !gif)
        return frt_cli_fail(FRT_EXIT_USAGE, "missing -o FILE (.png, .pgm, .npy, .f32, .obj or .ply)");
    bool quantised = false, mesh = false;
    for (unsigned i = 0; i < n_outputs; ++i) {
        formats[i] = frt_cli_output_format(outputs[i], ALL_HEIGHTFIELDS);
        if (formats[i] == FRT_FILE_DEFAULT)
            return FRT_EXIT_USAGE;
        quantised |= formats[i] == FRT_FILE_PNG || formats[i] == FRT_FILE_PGM;
        mesh |= formats[i] == FRT_FILE_OBJ || formats[i] == FRT_FILE_PLY;
        for (unsigned j = 0; j < i; ++j)
            if (strcmp(outputs[i], outputs[j]) == 0)
                return frt_cli_fail(FRT_EXIT_USAGE, "'%s' is given twice as an output", outputs[i]);
    }
    bool tiff = false;
    for (unsigned i = 0; i < n_outputs; ++i)
        tiff |= formats[i] == FRT_FILE_TIFF;
    if ((crs || have_origin) && !tiff)
        return frt_cli_fail(FRT_EXIT_USAGE, "%s applies to .tif outputs, and there is none",
                            crs ? "--crs" : "--origin");
    if (have_bits && !quantised)
        return frt_cli_fail(FRT_EXIT_USAGE, "--bits applies to .png and .pgm outputs, and there is none");
    if (have_stride && !mesh)
        return frt_cli_fail(FRT_EXIT_USAGE, "--mesh-stride applies to .obj and .ply outputs, and there is none");
    if (preview && frt_cli_output_format(preview, FMT_BIT(FRT_FILE_PNG)) == FRT_FILE_DEFAULT)
        return FRT_EXIT_USAGE;
    if (gif) {
        const char *dot = strrchr(gif, '.');
        if (!dot || strcasecmp(dot, ".gif") != 0)
            return frt_cli_fail(FRT_EXIT_USAGE, "--gif needs a file name ending in .gif, got '%s'", gif);
    }
    if (backend == FRT_BACKEND_CPU && device)
        return frt_cli_fail(FRT_EXIT_USAGE, "--device needs the vulkan (or auto) backend");
    frt_terrain_desc resolved;
    if (frt_terrain_desc_resolved(&desc, &resolved) != FRT_SUCCESS) {
        if (region && check_region(&resolved, region) != FRT_EXIT_OK)
            return FRT_EXIT_USAGE;
        char why[256];
        frt_terrain_desc_check(&resolved, why, sizeof why);
        return frt_cli_fail(FRT_EXIT_USAGE, "invalid parameters: %s", why);
    }
    if (region && check_region(&resolved, region) != FRT_EXIT_OK)
        return FRT_EXIT_USAGE;
    /* Unwritable targets fail before any work. */
    int code = FRT_EXIT_OK;
    for (unsigned i = 0; i < n_outputs; ++i)
        if (!frt_cli_probe_writable(outputs[i], &code))
            return code;
    if ((preview && !frt_cli_probe_writable(preview, &code)) || (gif && !frt_cli_probe_writable(gif, &code)))
        return code;
    bool made_frames_dir = false; /* removed again if the run fails and it is still empty */
    if (frames) {
        made_frames_dir = mkdir(frames, 0755) == 0;
        if (!made_frames_dir && errno != EEXIST)
            return frt_cli_fail(FRT_EXIT_IO, "cannot create the frames directory '%s': %s", frames, strerror(errno));
        char probe[4096];
        snprintf(probe, sizeof probe, "%s/frame-00.png", frames);
        if (!frt_cli_probe_writable(probe, &code)) {
            if (made_frames_dir)
                rmdir(frames);
            return code;
        }
    }

    frt_progress_init(quiet);
    float *field = NULL;
    frt_context *ctx = NULL;
    bool use_cpu = backend == FRT_BACKEND_CPU;
    frt_run_info info;
    memset(&info, 0, sizeof info);
    const char *backend_name = "cpu", *device_name = "CPU reference";
    char label[640]; /* a label, a region and a device name */
    float *coarse_h = NULL, *hmap_h = NULL, *amap_h = NULL;
    char history[1024] = "";
    double geotransform[6];
    frt_field_info cinfo;
    memset(&cinfo, 0, sizeof cinfo);
    if (coarse || hmap || amap) {
        code = load_inputs(&resolved, coarse, fit_pad, region != NULL, hmap, hmap_is_dimension, amap, hurst_auto,
                           sigma_auto, quiet, &coarse_h, &hmap_h, &amap_h, &cinfo, history, sizeof history);
        if (code != FRT_EXIT_OK)
            goto out;
        if (resolved.region.width && !region && (frames || gif)) {
            code = frt_cli_fail(FRT_EXIT_USAGE,
                                "%s does not apply to --fit pad: the output is the data's area of the grid, and the "
                                "growth frames are those of a whole grid",
                                frames ? "--frames" : "--gif");
            goto out;
        }
        if (coarse) {
            const double s = (double)(1u << (resolved.levels - resolved.coarse_levels));
            if (!have_spacing) { /* the coarse grid's spacing, divided */
                wd.spacing_x = cinfo.spacing_x / s;
                wd.spacing_y = cinfo.spacing_y / s;
            }
            if (cinfo.has_geotransform) { /* same pixel centres, pixels s times smaller; a region where it lies */
                const double *g = cinfo.geotransform;
                geotransform[1] = g[1] / s, geotransform[2] = g[2] / s;
                geotransform[4] = g[4] / s, geotransform[5] = g[5] / s;
                geotransform[0] = g[0] + 0.5 * (g[1] - geotransform[1]) + 0.5 * (g[2] - geotransform[2]);
                geotransform[3] = g[3] + 0.5 * (g[4] - geotransform[4]) + 0.5 * (g[5] - geotransform[5]);
                if (region) {
                    geotransform[0] += resolved.region.x * geotransform[1] + resolved.region.y * geotransform[2];
                    geotransform[3] += resolved.region.x * geotransform[4] + resolved.region.y * geotransform[5];
                }
                wd.geotransform = geotransform;
                wd.projection = cinfo.projection[0] ? cinfo.projection : NULL;
            }
        }
        wd.history = history;
    }
    if (crs || have_origin) {
        if (wd.geotransform) {
            code = frt_cli_fail(FRT_EXIT_USAGE,
                                "--coarse %s is georeferenced: its CRS and position are used, so %s "
                                "does not apply",
                                coarse, crs ? "--crs" : "--origin");
            goto out;
        }
        if (have_origin) { /* north up: (X, Y) is the centre of the top-left sample; a region where it lies */
            const double sx = wd.spacing_x > 0 ? wd.spacing_x : 1.0, sy = wd.spacing_y > 0 ? wd.spacing_y : 1.0;
            geotransform[0] = origin_x + (double)resolved.region.x * sx - 0.5 * sx;
            geotransform[1] = sx, geotransform[2] = 0.0;
            geotransform[3] = origin_y - (double)resolved.region.y * sy + 0.5 * sy;
            geotransform[4] = 0.0, geotransform[5] = -sy;
            wd.geotransform = geotransform;
        }
        wd.projection = crs;
    }
    /* The output is the region's window (given, or the data's area of a --fit pad grid), or the whole grid; `side`
     * is the whole (virtual) grid's. */
    const uint32_t side = frt_terrain_side(&resolved);
    uint32_t width = 0, height = 0;
    frt_terrain_extent(&resolved, &width, &height);
    const size_t count = frt_heightfield_size(&resolved);
    char where[128] = ""; /* " at X0,Y0 of the S x S grid" for a region */
    if (region)
        snprintf(where, sizeof where, " at %u,%u of the %u x %u grid", resolved.region.x, resolved.region.y, side,
                 side);
    else if (resolved.region.width)
        snprintf(where, sizeof where, " (the data's area of the %u x %u grid)", side, side);
    if (count && count <= SIZE_MAX / sizeof *field)
        field = malloc(count * sizeof *field);
    if (!field) {
        code = frt_cli_fail(FRT_EXIT_DEVICE, "cannot allocate %.1f MiB for %u x %u heights on this host",
                            (double)width * height * 4.0 / 1048576.0, width, height);
        goto out;
    }
    if (!use_cpu) {
        ctx = open_vulkan(backend, device, &use_cpu, &code);
        if (code != FRT_EXIT_OK)
            goto out;
    }
    if (ctx) {
        snprintf(label, sizeof label, "generating %u x %u%s on %s", width, height, where,
                 frt_context_device(ctx)->name);
        frt_progress_begin(label, 0);
        frt_result r = frt_generate(ctx, &resolved, field, count, &info);
        frt_progress_end();
        if (r == FRT_ERROR_TOO_LARGE && backend == FRT_BACKEND_DEFAULT && !device) {
            fprintf(stderr, "%s: warning: %s; using the CPU path\n", frt_cli_command, frt_context_error(ctx));
            use_cpu = true;
        } else if (r != FRT_SUCCESS) {
            code = frt_cli_fail(FRT_EXIT_DEVICE, "%s",
                                frt_context_error(ctx)[0] ? frt_context_error(ctx) : frt_result_string(r));
            goto out;
        } else {
            backend_name = "vulkan";
            device_name = frt_context_device(ctx)->name;
        }
    }
    if (use_cpu) {
        snprintf(label, sizeof label, "generating %u x %u%s on the CPU", width, height, where);
        frt_progress_begin(label, 0);
        frt_result r = frt_generate_cpu(&resolved, field, count, &info);
        frt_progress_end();
        if (r != FRT_SUCCESS) {
            code = frt_cli_fail(FRT_EXIT_USAGE, "%s", frt_result_string(r));
            goto out;
        }
    }
    wd.terrain = &resolved;
    wd.backend = backend_name;
    wd.device = device_name;

    char err[1200];
    for (unsigned i = 0; i < n_outputs; ++i) {
        snprintf(label, sizeof label, "writing %s", outputs[i]);
        frt_progress_begin(label, 0);
        frt_result wr = frt_write_heightfield(outputs[i], field, width, height, &wd, err, sizeof err);
        frt_progress_end();
        if (wr != FRT_SUCCESS) {
            code = frt_cli_fail(wr == FRT_ERROR_IO ? FRT_EXIT_IO : FRT_EXIT_USAGE, "%s", err);
            goto out;
        }
    }
    if (preview) {
        frt_hillshade_desc hd;
        memset(&hd, 0, sizeof hd);
        hd.spacing_x = wd.spacing_x;
        hd.spacing_y = wd.spacing_y;
        hd.color = preview_color;
        size_t bytes = frt_hillshade_size(width, height, &hd);
        uint8_t *pic = bytes ? malloc(bytes) : NULL;
        frt_result pr = pic ? frt_hillshade(field, width, height, &hd, pic, bytes) : FRT_ERROR_OUT_OF_MEMORY;
        if (pr == FRT_SUCCESS)
            pr = frt_write_picture(preview, pic, width, height, preview_color ? 3 : 1, err, sizeof err);
        else
            snprintf(err, sizeof err, "preview: %s", frt_result_string(pr));
        free(pic);
        if (pr != FRT_SUCCESS) {
            code = frt_cli_fail(pr == FRT_ERROR_IO ? FRT_EXIT_IO : FRT_EXIT_USAGE, "%s", err);
            goto out;
        }
    }
    if (frames || gif) { /* whole grids only (checked above): frames are cut from the final (2^n+1)^2 field */
        code = frt_write_frames(frames, gif, field, side, resolved.levels, &wd);
        if (code != FRT_EXIT_OK)
            goto out;
    }
    if (!quiet) {
        fprintf(stderr, "%s: %u x %u%s (levels %u, H %.3g, sigma %.6g, seed %llu) on %s [%s] in %.3f s",
                frt_cli_command, width, height, where, resolved.levels, resolved.hurst, resolved.sigma,
                (unsigned long long)resolved.seed, device_name, backend_name, info.total_seconds);
        const char *sep = " ->";
        for (unsigned i = 0; i < n_outputs; ++i, sep = ",")
            fprintf(stderr, "%s %s", sep, outputs[i]);
        if (preview)
            fprintf(stderr, "%s %s", sep, preview), sep = ",";
        if (frames)
            fprintf(stderr, "%s %s/ (%u frames)", sep, frames, resolved.levels + 1), sep = ",";
        if (gif)
            fprintf(stderr, "%s %s", sep, gif);
        fputc('\n', stderr);
    }
out:
    if (code != FRT_EXIT_OK && made_frames_dir)
        rmdir(frames); /* only succeeds when empty: frames already written are complete files and stay */
    frt_context_destroy(ctx);
    free(field);
    free(coarse_h);
    free(hmap_h);
    free(amap_h);
    return code;
}
