/* cli_generate.c — `fracterra generate`: parse, validate, generate on the chosen backend, write atomically. */
#include "cli.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void generate_help(void)
{
    printf("Usage: fracterra generate [options] -o FILE\n"
           "\n"
           "Generates a (2^N+1) x (2^N+1) heightfield by FFC random midpoint displacement (docs/ALGORITHM.md).\n"
           "\n"
           "  --levels N          refinement levels, grid side 2^N+1 (1..%u; default %u -> 513 x 513)\n"
           "  --hurst H           Hurst exponent, 0 < H < 1 (default %.1f); larger is smoother\n"
           "  --dimension D       fractal dimension, 2 < D < 3, H = 3 - D (not with --hurst)\n"
           "  --sigma S           amplitude, any non-zero real; negative inverts peaks and valleys (default 1)\n"
           "  --seed U64          noise key, decimal or 0x hex (default 1)\n"
           "  --backend B         auto | vulkan | cpu (default auto: Vulkan if a device exists, else CPU)\n"
           "  --device D          Vulkan device by index or name substring (see: fracterra devices)\n"
           "  -o, --output FILE   output; the extension picks the format:\n"
           "                        .png  16-bit greyscale, min..max -> 0..65535, parameters in text chunks\n"
           "                        .npy  float32 for numpy.load\n"
           "                        .f32  raw little-endian float32, row-major, with FILE.json sidecar\n"
           "  -q, --quiet         no summary line on stderr\n"
           "  -h, --help          this text\n"
           "\n"
           "The file appears only when complete: it is written to a temporary file and renamed, so a failure\n"
           "never leaves a partial file or replaces an existing one.\n",
           FRT_MAX_LEVELS, FRT_DEFAULT_LEVELS, FRT_DEFAULT_HURST);
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

int frt_cmd_generate(int argc, char **argv)
{
    frt_cli_command = "fracterra generate";
    enum { OPT_LEVELS = 256, OPT_HURST, OPT_DIMENSION, OPT_SIGMA, OPT_SEED, OPT_BACKEND, OPT_DEVICE };
    static const struct option opts[] = {{"levels", required_argument, 0, OPT_LEVELS},
                                         {"hurst", required_argument, 0, OPT_HURST},
                                         {"dimension", required_argument, 0, OPT_DIMENSION},
                                         {"sigma", required_argument, 0, OPT_SIGMA},
                                         {"seed", required_argument, 0, OPT_SEED},
                                         {"backend", required_argument, 0, OPT_BACKEND},
                                         {"device", required_argument, 0, OPT_DEVICE},
                                         {"output", required_argument, 0, 'o'},
                                         {"quiet", no_argument, 0, 'q'},
                                         {"help", no_argument, 0, 'h'},
                                         {0, 0, 0, 0}};
    frt_terrain_desc desc;
    memset(&desc, 0, sizeof desc);
    bool have_hurst = false, have_dim = false, quiet = false;
    double dimension = 0.0;
    frt_backend backend = FRT_BACKEND_DEFAULT;
    const char *device = NULL, *output = NULL;
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":o:qh", opts, NULL)) != -1) {
        switch (c) {
        case OPT_LEVELS:
            if (!frt_parse_u32(optarg, &desc.levels) || desc.levels < 1 || desc.levels > FRT_MAX_LEVELS)
                return frt_cli_fail(FRT_EXIT_USAGE, "--levels must be an integer from 1 to %u, got '%s'",
                                    FRT_MAX_LEVELS, optarg);
            break;
        case OPT_HURST:
            if (!frt_parse_double(optarg, &desc.hurst) || !(desc.hurst > 0.0 && desc.hurst < 1.0))
                return frt_cli_fail(FRT_EXIT_USAGE, "--hurst must be a number with 0 < H < 1, got '%s'", optarg);
            have_hurst = true;
            break;
        case OPT_DIMENSION:
            if (!frt_parse_double(optarg, &dimension) || !(dimension > 2.0 && dimension < 3.0))
                return frt_cli_fail(FRT_EXIT_USAGE, "--dimension must be a number with 2 < D < 3, got '%s'", optarg);
            have_dim = true;
            break;
        case OPT_SIGMA:
            if (!frt_parse_double(optarg, &desc.sigma) || desc.sigma == 0.0 || fabs(desc.sigma) > 1e30)
                return frt_cli_fail(FRT_EXIT_USAGE, "--sigma must be a non-zero number (|S| <= 1e30), got '%s'",
                                    optarg);
            break;
        case OPT_SEED:
            if (!frt_parse_u64(optarg, &desc.seed))
                return frt_cli_fail(FRT_EXIT_USAGE, "--seed must be an unsigned 64-bit integer, got '%s'", optarg);
            desc.seed_is_explicit = true;
            break;
        case OPT_BACKEND:
            if (!frt_parse_backend(optarg, &backend))
                return frt_cli_fail(FRT_EXIT_USAGE, "--backend must be auto, vulkan or cpu, got '%s'", optarg);
            break;
        case OPT_DEVICE: device = optarg; break;
        case 'o': output = optarg; break;
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
    if (!output)
        return frt_cli_fail(FRT_EXIT_USAGE, "missing -o FILE (.png, .npy or .f32)");
    frt_format format = frt_format_from_path(output);
    if (format == FRT_FORMAT_NONE) {
        const char *dot = strrchr(output, '.');
        return frt_cli_fail(FRT_EXIT_USAGE, "cannot tell the format of '%s'%s%s%s: use .png, .npy or .f32", output,
                            dot ? " (unknown extension '" : " (no extension", dot ? dot : "", dot ? "')" : ")");
    }
    if (backend == FRT_BACKEND_CPU && device)
        return frt_cli_fail(FRT_EXIT_USAGE, "--device needs the vulkan (or auto) backend");
    frt_terrain_desc resolved;
    if (frt_terrain_desc_resolved(&desc, &resolved) != FRT_SUCCESS)
        return frt_cli_fail(FRT_EXIT_USAGE, "invalid parameters");
    const uint32_t side = frt_grid_side(resolved.levels);
    const size_t count = frt_heightfield_size(&resolved);

    /* Open the outputs first: an unwritable target fails before any work. */
    char err[1200];
    frt_atomic_file main_file, sidecar;
    memset(&sidecar, 0, sizeof sidecar);
    if (frt_atomic_open(&main_file, output, err, sizeof err) != FRT_SUCCESS)
        return frt_cli_fail(FRT_EXIT_IO, "%s", err);
    char *sidecar_path = format == FRT_FORMAT_F32 ? frt_sidecar_path(output) : NULL;
    if (sidecar_path && frt_atomic_open(&sidecar, sidecar_path, err, sizeof err) != FRT_SUCCESS) {
        frt_atomic_abort(&main_file);
        free(sidecar_path);
        return frt_cli_fail(FRT_EXIT_IO, "%s", err);
    }
    free(sidecar_path);

    int code = FRT_EXIT_OK;
    float *field = malloc(count * sizeof *field);
    frt_context *ctx = NULL;
    bool use_cpu = backend == FRT_BACKEND_CPU;
    frt_run_info info;
    memset(&info, 0, sizeof info);
    frt_field_meta meta;
    memset(&meta, 0, sizeof meta);
    meta.desc = resolved;
    if (!field) {
        code = frt_cli_fail(FRT_EXIT_DEVICE, "cannot allocate %.1f MiB for a %u x %u grid on this host",
                            (double)count * 4.0 / 1048576.0, side, side);
        goto out;
    }
    if (!use_cpu) {
        ctx = open_vulkan(backend, device, &use_cpu, &code);
        if (code != FRT_EXIT_OK)
            goto out;
    }
    if (ctx) {
        if (!quiet && isatty(2))
            fprintf(stderr, "%s: %u x %u on %s ...\r", frt_cli_command, side, side, frt_context_device(ctx)->name);
        frt_result r = frt_generate(ctx, &resolved, field, count, &info);
        if (r == FRT_ERROR_TOO_LARGE && backend == FRT_BACKEND_DEFAULT && !device) {
            fprintf(stderr, "%s: warning: %s; using the CPU path\n", frt_cli_command, frt_context_error(ctx));
            use_cpu = true;
        } else if (r != FRT_SUCCESS) {
            code = frt_cli_fail(FRT_EXIT_DEVICE, "%s",
                                frt_context_error(ctx)[0] ? frt_context_error(ctx) : frt_result_string(r));
            goto out;
        } else {
            meta.backend = "vulkan";
            meta.device = frt_context_device(ctx)->name;
        }
    }
    if (use_cpu) {
        if (!quiet && isatty(2))
            fprintf(stderr, "%s: %u x %u on the CPU ...\r", frt_cli_command, side, side);
        frt_result r = frt_generate_cpu(&resolved, field, count, &info);
        if (r != FRT_SUCCESS) {
            code = frt_cli_fail(FRT_EXIT_USAGE, "%s", frt_result_string(r));
            goto out;
        }
        meta.backend = "cpu";
        meta.device = "CPU reference";
    }
    frt_field_minmax(field, count, &meta.min, &meta.max);

    frt_result wr = FRT_SUCCESS;
    err[0] = '\0';
    if (format == FRT_FORMAT_PNG)
        wr = frt_write_png16(main_file.fp, field, side, side, &meta, err, sizeof err);
    else if (format == FRT_FORMAT_NPY)
        wr = frt_write_npy(main_file.fp, field, side, side);
    else {
        wr = frt_write_f32(main_file.fp, field, count);
        char *json = frt_meta_json(&meta, side, side);
        if (wr == FRT_SUCCESS && (!json || fputs(json, sidecar.fp) == EOF))
            wr = FRT_ERROR_IO;
        free(json);
    }
    if (wr == FRT_SUCCESS)
        wr = frt_atomic_commit(&main_file, err, sizeof err);
    if (wr == FRT_SUCCESS && sidecar.fp)
        wr = frt_atomic_commit(&sidecar, err, sizeof err);
    if (wr != FRT_SUCCESS) {
        code = frt_cli_fail(FRT_EXIT_IO, "%s", err[0] ? err : "writing the output failed");
        goto out;
    }
    if (!quiet)
        fprintf(stderr, "%s: %u x %u (levels %u, H %.3g, sigma %.6g, seed %llu) on %s [%s] in %.3f s -> %s\n",
                frt_cli_command, side, side, resolved.levels, resolved.hurst, resolved.sigma,
                (unsigned long long)resolved.seed, meta.device, meta.backend, info.total_seconds, output);
out:
    frt_atomic_abort(&main_file); /* no-ops after a commit */
    frt_atomic_abort(&sidecar);
    frt_context_destroy(ctx);
    free(field);
    return code;
}
