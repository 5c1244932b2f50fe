/* cli_bench.c — `fracterra bench`: points per second per backend and grid size (or, with --region, per size of the
 * virtual grid a fixed window is cut from), median of several runs. */
#include "cli.h"

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* A window's side at most a whole grid's, so that every window fits the host's memory as a whole grid does. */
#define WINDOW_MAX_SIDE 32769u
#define MAX_CASES (FRT_MAX_REGION_LEVELS + 1u)

static void bench_help(void)
{
    printf("Usage: fracterra bench [options]\n"
           "\n"
           "Generates each size on each backend once to warm up, then RUNS times, and prints the median.\n"
           "points/s counts every grid point (side^2), or with --region the window's points, over the median time.\n"
           "For Vulkan, 'device' is the time of the dispatches by device timestamps and 'total' adds submission and\n"
           "the read-back into host memory.\n"
           "\n"
           "  --levels L          levels to measure: A, A-B or A,B,C,... (default 10-13; with --region\n"
           "                      12,16,20,24,28,30)\n"
           "  --region            measure regions: for each level, the --window centred in the (2^N+1)^2 grid,\n"
           "                      at X0 = (2^N+1-W)/2, Y0 = (2^N+1-H)/2 rounded down; levels up to %u\n"
           "  --window W[xH]      the window of --region (default 1024: 1024 x 1024; each side 1..%u)\n"
           "  --runs N            timed runs per case, at least 1 (default 5)\n"
           "  --backend B         all | vulkan | cpu (default all)\n"
           "  --device D          Vulkan device by index or name substring\n"
           "  --noise DIST        the displacement distribution (as generate --noise; default gauss)\n"
           "  --roughness-map F   measure with an H map (as generate); --amplitude-map F likewise\n"
           "  --amplitude-map F   measure with an amplitude map\n"
           "  --densify K         measure densifying: the coarse grid is every 2^(N-K)-th point of a field of K\n"
           "                      levels (made once on the CPU); levels K+1..N are timed\n"
           "  --json              print JSON instead of a table\n",
           FRT_MAX_REGION_LEVELS, WINDOW_MAX_SIDE);
}

typedef struct bench_row {
    const char *backend;
    char device[256];
    uint32_t levels, side;        /* side of the whole (virtual) grid */
    uint32_t x, y, width, height; /* what was generated: the window, or the whole grid at 0, 0 */
    double device_s, total_s;
} bench_row;

/* "A", "A-B" or "A,B,C": levels in 1..max, ascending without repeats, into lv (MAX_CASES entries). */
static bool parse_levels(const char *s, uint32_t max, uint32_t *lv, uint32_t *n)
{
    char buf[128];
    if (strlen(s) >= sizeof buf)
        return false;
    strcpy(buf, s);
    *n = 0;
    char *dash = strchr(buf, '-');
    if (dash) {
        uint32_t lo, hi;
        *dash = '\0';
        if (!frt_parse_u32(buf, &lo) || !frt_parse_u32(dash + 1, &hi) || lo < 1 || hi > max || lo > hi)
            return false;
        for (uint32_t l = lo; l <= hi; ++l)
            lv[(*n)++] = l;
        return true;
    }
    for (char *p = buf, *comma;; p = comma + 1) {
        comma = strchr(p, ',');
        if (comma)
            *comma = '\0';
        uint32_t l;
        if (!frt_parse_u32(p, &l) || l < 1 || l > max || (*n && l <= lv[*n - 1]) || *n == MAX_CASES)
            return false;
        lv[(*n)++] = l;
        if (!comma)
            return true;
    }
}

int frt_cmd_bench(int argc, char **argv)
{
    frt_cli_command = "fracterra bench";
    enum {
        OPT_LEVELS = 256,
        OPT_RUNS,
        OPT_BACKEND,
        OPT_DEVICE,
        OPT_JSON,
        OPT_REGION,
        OPT_WINDOW,
        OPT_NOISE,
        OPT_HMAP,
        OPT_AMAP,
        OPT_DENSIFY
    };
    static const struct option opts[] = {{"levels", required_argument, 0, OPT_LEVELS},
                                         {"runs", required_argument, 0, OPT_RUNS},
                                         {"backend", required_argument, 0, OPT_BACKEND},
                                         {"device", required_argument, 0, OPT_DEVICE},
                                         {"json", no_argument, 0, OPT_JSON},
                                         {"region", no_argument, 0, OPT_REGION},
                                         {"window", required_argument, 0, OPT_WINDOW},
                                         {"noise", required_argument, 0, OPT_NOISE},
                                         {"roughness-map", required_argument, 0, OPT_HMAP},
                                         {"amplitude-map", required_argument, 0, OPT_AMAP},
                                         {"densify", required_argument, 0, OPT_DENSIFY},
                                         {"help", no_argument, 0, 'h'},
                                         {0, 0, 0, 0}};
    uint32_t runs = 5, win_w = 1024, win_h = 1024, lv[MAX_CASES], nlv = 0;
    bool json = false, want_vk = true, want_cpu = true, region = false;
    const char *device = NULL, *levels_text = NULL, *window_text = NULL, *hmap = NULL, *amap = NULL;
    frt_noise_kind noise = FRT_NOISE_DEFAULT;
    const char *noise_text = "";
    double noise_param = 0.0;
    uint32_t densify = 0;
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":h", opts, NULL)) != -1) {
        switch (c) {
        case OPT_LEVELS: levels_text = optarg; break; /* checked below: the limit depends on --region */
        case OPT_REGION: region = true; break;
        case OPT_WINDOW: {
            char buf[64];
            snprintf(buf, sizeof buf, "%s", optarg);
            char *x = strchr(buf, 'x');
            if (x)
                *x = '\0';
            if (!frt_parse_u32(buf, &win_w) || (x ? !frt_parse_u32(x + 1, &win_h) : ((win_h = win_w), false)) ||
                win_w < 1 || win_h < 1 || win_w > WINDOW_MAX_SIDE || win_h > WINDOW_MAX_SIDE)
                return frt_cli_fail(FRT_EXIT_USAGE, "--window must be W or WxH with sides from 1 to %u, got '%s'",
                                    WINDOW_MAX_SIDE, optarg);
            window_text = optarg;
            break;
        }
        case OPT_RUNS:
            if (!frt_parse_u32(optarg, &runs) || runs < 1 || runs > 1000)
                return frt_cli_fail(FRT_EXIT_USAGE, "--runs must be an integer from 1 to 1000, got '%s'", optarg);
            break;
        case OPT_BACKEND:
            if (strcmp(optarg, "all") == 0)
                want_vk = want_cpu = true;
            else if (strcmp(optarg, "vulkan") == 0)
                want_vk = true, want_cpu = false;
            else if (strcmp(optarg, "cpu") == 0)
                want_vk = false, want_cpu = true;
            else
                return frt_cli_fail(FRT_EXIT_USAGE, "--backend must be all, vulkan or cpu, got '%s'", optarg);
            break;
        case OPT_DEVICE: device = optarg; break;
        case OPT_JSON: json = true; break;
        case OPT_NOISE:
            if (!frt_parse_noise(optarg, &noise, &noise_param))
                return frt_cli_fail(FRT_EXIT_USAGE,
                                    "--noise must be gauss, truncated[:K], clt[:N] or uniform, got '%s'", optarg);
            noise_text = optarg;
            break;
        case OPT_HMAP: hmap = optarg; break;
        case OPT_AMAP: amap = optarg; break;
        case OPT_DENSIFY:
            if (!frt_parse_u32(optarg, &densify) || densify < 1 || densify > FRT_MAX_LEVELS)
                return frt_cli_fail(FRT_EXIT_USAGE, "--densify must be an integer from 1 to %u, got '%s'",
                                    FRT_MAX_LEVELS, optarg);
            break;
        case 'h': bench_help(); return FRT_EXIT_OK;
        case ':': return frt_cli_fail(FRT_EXIT_USAGE, "option '%s' needs a value", argv[optind - 1]);
        default: return frt_cli_fail(FRT_EXIT_USAGE, "unknown option '%s' (see --help)", argv[optind - 1]);
        }
    }
    if (optind < argc)
        return frt_cli_fail(FRT_EXIT_USAGE, "unexpected argument '%s'", argv[optind]);
    if (window_text && !region)
        return frt_cli_fail(FRT_EXIT_USAGE, "--window applies to --region");
    const uint32_t max_levels = region ? FRT_MAX_REGION_LEVELS : FRT_MAX_LEVELS;
    if (!parse_levels(levels_text ? levels_text : region ? "12,16,20,24,28,30" : "10-13", max_levels, lv, &nlv))
        return frt_cli_fail(FRT_EXIT_USAGE, "--levels must be A, A-B or A,B,C,... ascending, from 1 to %u%s, got '%s'",
                            max_levels, region ? "" : " (up to 30 with --region)", levels_text);
    if (region && (win_w > frt_grid_side(lv[0]) || win_h > frt_grid_side(lv[0])))
        return frt_cli_fail(FRT_EXIT_USAGE, "--window %u x %u does not fit in the %u x %u grid of levels %u", win_w,
                            win_h, frt_grid_side(lv[0]), frt_grid_side(lv[0]), lv[0]);

    if (densify && densify > lv[0])
        return frt_cli_fail(FRT_EXIT_USAGE, "--densify %u is deeper than --levels %u", densify, lv[0]);
    frt_map hurst_map = {0}, amplitude_map = {0};
    float *hmap_h = NULL, *amap_h = NULL, *coarse_h = NULL;
    int load = hmap ? frt_cli_load_map(hmap, FRT_CLI_MAP_HURST, &hmap_h, &hurst_map) : FRT_EXIT_OK;
    if (load == FRT_EXIT_OK && amap)
        load = frt_cli_load_map(amap, FRT_CLI_MAP_AMPLITUDE, &amap_h, &amplitude_map);
    if (load == FRT_EXIT_OK && densify) { /* the coarse grid: a whole field of K levels (seed 1) */
        frt_terrain_desc cd = {0};
        cd.levels = densify;
        size_t cc = frt_heightfield_size(&cd);
        coarse_h = malloc(cc * sizeof *coarse_h);
        if (!coarse_h || frt_generate_cpu(&cd, coarse_h, cc, NULL) != FRT_SUCCESS)
            load = frt_cli_fail(FRT_EXIT_DEVICE, "cannot make the coarse grid");
    }
    if (load != FRT_EXIT_OK) {
        free(hmap_h), free(amap_h), free(coarse_h);
        return load;
    }
    frt_context *ctx = NULL;
    if (want_vk) {
        frt_context_desc cd;
        memset(&cd, 0, sizeof cd);
        cd.device = device;
        char err[1024];
        if (frt_context_create(&cd, &ctx, err, sizeof err) != FRT_SUCCESS) {
            if (!want_cpu) {
                free(hmap_h), free(amap_h), free(coarse_h);
                return frt_cli_fail(FRT_EXIT_DEVICE, "%s", err);
            }
            fprintf(stderr, "%s: warning: Vulkan skipped: %s\n", frt_cli_command, err);
        }
    }
    size_t max_count = region ? (size_t)win_w * win_h : (size_t)frt_grid_side(lv[nlv - 1]) * frt_grid_side(lv[nlv - 1]);
    float *field = malloc(max_count * sizeof *field);
    double *dev_t = calloc(runs, sizeof *dev_t), *tot_t = calloc(runs, sizeof *tot_t);
    bench_row *rows = calloc(2 * nlv, sizeof *rows);
    if (!field || !dev_t || !tot_t || !rows) {
        frt_context_destroy(ctx);
        free(field), free(dev_t), free(tot_t), free(rows), free(hmap_h), free(amap_h), free(coarse_h);
        return frt_cli_fail(FRT_EXIT_DEVICE, "cannot allocate %.0f MiB for the benchmark", max_count * 4.0 / 1048576.0);
    }
    int nrows = 0, code = FRT_EXIT_OK;
    for (uint32_t li = 0; li < nlv && code == FRT_EXIT_OK; ++li) {
        const uint32_t levels = lv[li], side = frt_grid_side(levels);
        frt_terrain_desc d;
        memset(&d, 0, sizeof d);
        d.levels = levels;
        d.noise = noise, d.noise_param = noise_param;
        d.hurst_map = hurst_map, d.amplitude_map = amplitude_map;
        if (densify)
            d.coarse = coarse_h, d.coarse_levels = densify;
        if (region) /* centred; the same window size at every level, so only the grid's depth changes */
            d.region = (frt_region){(side - win_w) / 2, (side - win_h) / 2, win_w, win_h};
        size_t count = frt_heightfield_size(&d);
        for (int b = 0; b < 2; ++b) {
            bool vk = b == 0;
            if ((vk && !ctx) || (!vk && !want_cpu))
                continue;
            bench_row *row = &rows[nrows];
            row->backend = vk ? "vulkan" : "cpu";
            snprintf(row->device, sizeof row->device, "%s", vk ? frt_context_device(ctx)->name : "CPU reference");
            row->levels = levels;
            row->side = side;
            row->x = d.region.x, row->y = d.region.y;
            row->width = region ? win_w : side, row->height = region ? win_h : side;
            frt_result r = FRT_SUCCESS;
            for (uint32_t i = 0; i <= runs && r == FRT_SUCCESS; ++i) { /* run 0 warms up */
                frt_run_info info;
                d.seed = i + 1;
                r = vk ? frt_generate(ctx, &d, field, count, &info) : frt_generate_cpu(&d, field, count, &info);
                if (i > 0) {
                    dev_t[i - 1] = info.device_seconds > 0 ? info.device_seconds : info.total_seconds;
                    tot_t[i - 1] = info.total_seconds;
                }
            }
            if (r != FRT_SUCCESS) {
                fprintf(stderr, "%s: warning: %s at levels %u skipped: %s\n", frt_cli_command, row->backend, levels,
                        vk ? frt_context_error(ctx) : frt_result_string(r));
                continue;
            }
            row->device_s = median(dev_t, (int)runs);
            row->total_s = median(tot_t, (int)runs);
            ++nrows;
            if (isatty(2))
                fprintf(stderr, "%s: %s levels %u done\n", frt_cli_command, row->backend, levels);
        }
    }
    if (json) {
        printf("{\n  \"runs\": %u,\n  \"mode\": \"%s\",\n  \"results\": [\n", runs, region ? "region" : "whole grid");
        for (int i = 0; i < nrows; ++i) {
            double pts = (double)rows[i].width * rows[i].height;
            printf("    {\"backend\": \"%s\", \"device\": \"%s\", \"levels\": %u, \"side\": %u, \"x\": %u, "
                   "\"y\": %u, \"width\": %u, \"height\": %u, \"median_device_s\": %.6f, \"median_total_s\": %.6f, "
                   "\"points_per_s_device\": %.4g, \"points_per_s_total\": %.4g}%s\n",
                   rows[i].backend, rows[i].device, rows[i].levels, rows[i].side, rows[i].x, rows[i].y, rows[i].width,
                   rows[i].height, rows[i].device_s, rows[i].total_s, pts / rows[i].device_s, pts / rows[i].total_s,
                   i + 1 < nrows ? "," : "");
        }
        printf("  ]\n}\n");
    } else {
        if (region)
            printf("median of %u runs; a %u x %u window centred in each grid; points/s = window points / time\n", runs,
                   win_w, win_h);
        else
            printf("median of %u runs; points/s = side^2 / time\n", runs);
        if (noise || hmap || amap || densify)
            printf("with%s%s%s%s%s%s%s\n", noise ? " --noise " : "", noise ? noise_text : "",
                   hmap ? " --roughness-map " : "", hmap ? hmap : "", amap ? " --amplitude-map " : "", amap ? amap : "",
                   densify ? " --densify (levels K+1..N timed)" : "");
        printf("%-7s %-32s %6s %10s %12s %12s %12s %12s %10s\n", "backend", "device", "levels",
               region ? "grid side" : "side", "device ms", "total ms", "pts/s dev", "pts/s total", "cpu/this");
        for (int i = 0; i < nrows; ++i) {
            double pts = (double)rows[i].width * rows[i].height;
            char ratio[32] = "";
            for (int j = 0; j < nrows; ++j)
                if (strcmp(rows[j].backend, "cpu") == 0 && rows[j].levels == rows[i].levels && i != j)
                    snprintf(ratio, sizeof ratio, "%.2fx", rows[j].total_s / rows[i].total_s);
            printf("%-7s %-32.32s %6u %10u %12.2f %12.2f %12.3g %12.3g %10s\n", rows[i].backend, rows[i].device,
                   rows[i].levels, rows[i].side, rows[i].device_s * 1e3, rows[i].total_s * 1e3, pts / rows[i].device_s,
                   pts / rows[i].total_s, ratio);
        }
    }
    frt_context_destroy(ctx);
    free(field), free(dev_t), free(tot_t), free(rows), free(hmap_h), free(amap_h), free(coarse_h);
    return code;
}
