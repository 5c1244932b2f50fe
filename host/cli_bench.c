/* cli_bench.c — `fracterra bench`: points per second per backend and grid size, median of several runs. */
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

static void bench_help(void)
{
    printf("Usage: fracterra bench [options]\n"
           "\n"
           "Generates each size on each backend once to warm up, then RUNS times, and prints the median.\n"
           "points/s counts every grid point (side^2) over the median time. For Vulkan, 'device' is the time of the\n"
           "dispatches by device timestamps and 'total' adds submission and the read-back into host memory.\n"
           "\n"
           "  --levels A[-B]      levels to measure (default 10-13)\n"
           "  --runs N            timed runs per case, at least 1 (default 5)\n"
           "  --backend B         all | vulkan | cpu (default all)\n"
           "  --device D          Vulkan device by index or name substring\n"
           "  --json              print JSON instead of a table\n");
}

typedef struct bench_row {
    const char *backend;
    char device[256];
    uint32_t levels, side;
    double device_s, total_s;
} bench_row;

int frt_cmd_bench(int argc, char **argv)
{
    frt_cli_command = "fracterra bench";
    enum { OPT_LEVELS = 256, OPT_RUNS, OPT_BACKEND, OPT_DEVICE, OPT_JSON };
    static const struct option opts[] = {{"levels", required_argument, 0, OPT_LEVELS},
                                         {"runs", required_argument, 0, OPT_RUNS},
                                         {"backend", required_argument, 0, OPT_BACKEND},
                                         {"device", required_argument, 0, OPT_DEVICE},
                                         {"json", no_argument, 0, OPT_JSON},
                                         {"help", no_argument, 0, 'h'},
                                         {0, 0, 0, 0}};
    uint32_t lo = 10, hi = 13, runs = 5;
    bool json = false, want_vk = true, want_cpu = true;
    const char *device = NULL;
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":h", opts, NULL)) != -1) {
        switch (c) {
        case OPT_LEVELS: {
            char buf[64];
            snprintf(buf, sizeof buf, "%s", optarg);
            char *dash = strchr(buf, '-');
            if (dash)
                *dash = '\0';
            if (!frt_parse_u32(buf, &lo) || (dash ? !frt_parse_u32(dash + 1, &hi) : ((hi = lo), false)) || lo < 1 ||
                hi > FRT_MAX_LEVELS || lo > hi)
                return frt_cli_fail(FRT_EXIT_USAGE, "--levels must be A or A-B with 1 <= A <= B <= %u, got '%s'",
                                    FRT_MAX_LEVELS, optarg);
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
        case 'h': bench_help(); return FRT_EXIT_OK;
        case ':': return frt_cli_fail(FRT_EXIT_USAGE, "option '%s' needs a value", argv[optind - 1]);
        default: return frt_cli_fail(FRT_EXIT_USAGE, "unknown option '%s' (see --help)", argv[optind - 1]);
        }
    }
    if (optind < argc)
        return frt_cli_fail(FRT_EXIT_USAGE, "unexpected argument '%s'", argv[optind]);

    frt_context *ctx = NULL;
    if (want_vk) {
        frt_context_desc cd;
        memset(&cd, 0, sizeof cd);
        cd.device = device;
        char err[1024];
        if (frt_context_create(&cd, &ctx, err, sizeof err) != FRT_SUCCESS) {
            if (!want_cpu)
                return frt_cli_fail(FRT_EXIT_DEVICE, "%s", err);
            fprintf(stderr, "%s: warning: Vulkan skipped: %s\n", frt_cli_command, err);
        }
    }
    size_t max_count = (size_t)frt_grid_side(hi) * frt_grid_side(hi);
    float *field = malloc(max_count * sizeof *field);
    double *dev_t = calloc(runs, sizeof *dev_t), *tot_t = calloc(runs, sizeof *tot_t);
    bench_row *rows = calloc(2 * (hi - lo + 1), sizeof *rows);
    if (!field || !dev_t || !tot_t || !rows) {
        frt_context_destroy(ctx);
        free(field), free(dev_t), free(tot_t), free(rows);
        return frt_cli_fail(FRT_EXIT_DEVICE, "cannot allocate %.0f MiB for the benchmark", max_count * 4.0 / 1048576.0);
    }
    int nrows = 0, code = FRT_EXIT_OK;
    for (uint32_t levels = lo; levels <= hi && code == FRT_EXIT_OK; ++levels) {
        frt_terrain_desc d;
        memset(&d, 0, sizeof d);
        d.levels = levels;
        size_t count = frt_heightfield_size(&d);
        for (int b = 0; b < 2; ++b) {
            bool vk = b == 0;
            if ((vk && !ctx) || (!vk && !want_cpu))
                continue;
            bench_row *row = &rows[nrows];
            row->backend = vk ? "vulkan" : "cpu";
            snprintf(row->device, sizeof row->device, "%s", vk ? frt_context_device(ctx)->name : "CPU reference");
            row->levels = levels;
            row->side = frt_grid_side(levels);
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
        printf("{\n  \"runs\": %u,\n  \"results\": [\n", runs);
        for (int i = 0; i < nrows; ++i) {
            double pts = (double)rows[i].side * rows[i].side;
            printf("    {\"backend\": \"%s\", \"device\": \"%s\", \"levels\": %u, \"side\": %u, "
                   "\"median_device_s\": %.6f, \"median_total_s\": %.6f, \"points_per_s_device\": %.4g, "
                   "\"points_per_s_total\": %.4g}%s\n",
                   rows[i].backend, rows[i].device, rows[i].levels, rows[i].side, rows[i].device_s, rows[i].total_s,
                   pts / rows[i].device_s, pts / rows[i].total_s, i + 1 < nrows ? "," : "");
        }
        printf("  ]\n}\n");
    } else {
        printf("median of %u runs; points/s = side^2 / time\n", runs);
        printf("%-7s %-32s %6s %6s %12s %12s %12s %12s %10s\n", "backend", "device", "levels", "side", "device ms",
               "total ms", "pts/s dev", "pts/s total", "cpu/this");
        for (int i = 0; i < nrows; ++i) {
            double pts = (double)rows[i].side * rows[i].side;
            char ratio[32] = "";
            for (int j = 0; j < nrows; ++j)
                if (strcmp(rows[j].backend, "cpu") == 0 && rows[j].levels == rows[i].levels && i != j)
                    snprintf(ratio, sizeof ratio, "%.2fx", rows[j].total_s / rows[i].total_s);
            printf("%-7s %-32.32s %6u %6u %12.2f %12.2f %12.3g %12.3g %10s\n", rows[i].backend, rows[i].device,
                   rows[i].levels, rows[i].side, rows[i].device_s * 1e3, rows[i].total_s * 1e3, pts / rows[i].device_s,
                   pts / rows[i].total_s, ratio);
        }
    }
    frt_context_destroy(ctx);
    free(field), free(dev_t), free(tot_t), free(rows);
    return code;
}
