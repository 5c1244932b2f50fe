/* cli.c — the `fracterra` command: generate, tiles, render, info, devices, bench. Exit codes: usage(). */
#include "cli.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

const char *frt_cli_command = "fracterra";

int frt_cli_fail(int code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "%s: ", frt_cli_command);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return code;
}

bool frt_parse_u32(const char *s, uint32_t *out)
{
    if (!s || !*s || *s == '-' || *s == '+')
        return false;
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (errno || *end || v > UINT32_MAX)
        return false;
    *out = (uint32_t)v;
    return true;
}

bool frt_parse_u64(const char *s, uint64_t *out)
{
    if (!s || !*s || *s == '-' || *s == '+')
        return false;
    char *end;
    errno = 0;
    int base = (s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) ? 16 : 10;
    unsigned long long v = strtoull(s, &end, base);
    if (errno || *end || end == s)
        return false;
    *out = (uint64_t)v;
    return true;
}

bool frt_parse_double(const char *s, double *out)
{
    if (!s || !*s)
        return false;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno == ERANGE || *end || end == s || !isfinite(v))
        return false;
    *out = v;
    return true;
}

bool frt_parse_backend(const char *s, frt_backend *out)
{
    if (strcmp(s, "auto") == 0)
        *out = FRT_BACKEND_DEFAULT;
    else if (strcmp(s, "vulkan") == 0)
        *out = FRT_BACKEND_VULKAN;
    else if (strcmp(s, "cpu") == 0)
        *out = FRT_BACKEND_CPU;
    else
        return false;
    return true;
}

bool frt_parse_spacing(const char *s, double *dx, double *dy)
{
    char buf[128];
    if (!s || strlen(s) >= sizeof buf)
        return false;
    strcpy(buf, s);
    char *comma = strchr(buf, ',');
    if (comma)
        *comma = '\0';
    if (!frt_parse_double(buf, dx) || !(*dx > 0.0))
        return false;
    *dy = *dx;
    if (comma && (!frt_parse_double(comma + 1, dy) || !(*dy > 0.0)))
        return false;
    return true;
}

int frt_cli_terrain_option(int opt, const char *arg, frt_terrain_desc *d, double *dimension)
{
    switch (opt) {
    case FRT_OPT_HURST:
        if (!frt_parse_double(arg, &d->hurst) || !(d->hurst > 0.0 && d->hurst < 1.0))
            return frt_cli_fail(FRT_EXIT_USAGE, "--hurst must be a number with 0 < H < 1, got '%s'", arg);
        return FRT_EXIT_OK;
    case FRT_OPT_DIMENSION:
        if (!frt_parse_double(arg, dimension) || !(*dimension > 2.0 && *dimension < 3.0))
            return frt_cli_fail(FRT_EXIT_USAGE, "--dimension must be a number with 2 < D < 3, got '%s'", arg);
        return FRT_EXIT_OK;
    case FRT_OPT_SIGMA:
        if (!frt_parse_double(arg, &d->sigma) || d->sigma == 0.0 || fabs(d->sigma) > 1e30)
            return frt_cli_fail(FRT_EXIT_USAGE, "--sigma must be a non-zero number (|S| <= 1e30), got '%s'", arg);
        return FRT_EXIT_OK;
    case FRT_OPT_SEED:
        if (!frt_parse_u64(arg, &d->seed))
            return frt_cli_fail(FRT_EXIT_USAGE, "--seed must be an unsigned 64-bit integer, got '%s'", arg);
        d->seed_is_explicit = true;
        return FRT_EXIT_OK;
    case FRT_OPT_EDGE:
        if (strcmp(arg, "ffc") == 0)
            d->edge = FRT_EDGE_FFC;
        else if (strcmp(arg, "periodic") == 0)
            d->edge = FRT_EDGE_PERIODIC;
        else
            return frt_cli_fail(FRT_EXIT_USAGE, "--edge must be ffc or periodic, got '%s'", arg);
        return FRT_EXIT_OK;
    }
    return -1;
}

frt_file_format frt_cli_output_format(const char *path, unsigned allowed)
{
    frt_file_format f = frt_file_format_from_path(path);
    if (f != FRT_FILE_DEFAULT && (allowed >> f & 1u))
        return f;
    char list[128] = "";
    for (int i = 1; i <= FRT_FILE_PLY; ++i)
        if (allowed >> i & 1u) {
            strcat(list, list[0] ? ", ." : ".");
            strcat(list, frt_file_format_name((frt_file_format)i));
        }
    const char *dot = strrchr(path, '.');
    if (dot && strchr(dot, '/'))
        dot = NULL;
    if (f != FRT_FILE_DEFAULT)
        frt_cli_fail(FRT_EXIT_USAGE, "'%s': a .%s file cannot be written here; use %s", path, frt_file_format_name(f),
                     list);
    else
        frt_cli_fail(FRT_EXIT_USAGE, "cannot tell the format of '%s' (%s%s%s): use %s", path,
                     dot ? "unknown extension '" : "no extension", dot ? dot : "", dot ? "'" : "", list);
    return FRT_FILE_DEFAULT;
}

bool frt_cli_probe_writable(const char *path, int *exit_code)
{
    frt_atomic_file af;
    char err[1200];
    if (frt_atomic_open(&af, path, err, sizeof err) != FRT_SUCCESS) {
        *exit_code = frt_cli_fail(FRT_EXIT_IO, "%s", err);
        return false;
    }
    frt_atomic_abort(&af);
    return true;
}

static const char *type_name(VkPhysicalDeviceType t)
{
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
    }
}

static void usage(FILE *f)
{
    fprintf(f,
            "fracterra %s — fractal terrain by random midpoint displacement (FFC / diamond-square)\n"
            "\n"
            "Usage:\n"
            "  fracterra generate [options] -o FILE   generate a heightfield (see: fracterra generate --help)\n"
            "  fracterra tiles --levels N --out DIR   cut a grid of up to 2^30+1 a side into tiles, or an XYZ\n"
            "                                         pyramid of PNG tiles (see: fracterra tiles --help)\n"
            "  fracterra render IN -o OUT [options]   hillshade, colour relief or 1988-style profile plot\n"
            "  fracterra info FILE [--json] [--stats] what a heightfield file holds (see: fracterra info --help)\n"
            "  fracterra devices                      list Vulkan devices\n"
            "  fracterra bench [options]              measure points/second per backend\n"
            "  fracterra --version | --help\n"
            "\n"
            "Formats by extension: .png .pgm (16-bit grey), .f32 (+ .json sidecar), .npy, .obj .ply (meshes).\n"
            "Exit codes: 0 success, 2 bad arguments or input, 3 Vulkan or device failure, 4 file I/O failure.\n"
            "Manual: man fracterra (docs/fracterra.1).\n",
            FRT_VERSION_STRING);
}

static int cmd_devices(int argc, char **argv)
{
    frt_cli_command = "fracterra devices";
    if (argc > 1) {
        if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
            printf("Usage: fracterra devices\n\nLists the Vulkan devices: index (for --device), name, type, largest "
                   "device-local heap, largest allocation, largest storage-buffer binding, and whether fracterra "
                   "can use it.\n");
            return 0;
        }
        return frt_cli_fail(FRT_EXIT_USAGE, "unexpected argument '%s'", argv[1]);
    }
    uint32_t n = 0;
    frt_result r = frt_enumerate_devices(NULL, &n);
    if (r != FRT_SUCCESS || n == 0)
        return frt_cli_fail(FRT_EXIT_DEVICE,
                            "no Vulkan device found. For software Vulkan install Mesa lavapipe (Debian/Ubuntu: "
                            "apt-get install mesa-vulkan-drivers libvulkan1); --backend cpu needs none");
    frt_device_info *infos = calloc(n, sizeof *infos);
    if (!infos)
        return frt_cli_fail(FRT_EXIT_DEVICE, "out of memory");
    frt_enumerate_devices(infos, &n);
    printf("%-5s %-40s %-15s %10s %10s %10s %s\n", "index", "name", "type", "heap MiB", "alloc MiB", "bind MiB",
           "usable");
    for (uint32_t i = 0; i < n; ++i)
        printf("%-5u %-40s %-15s %10.0f %10.0f %10.0f %s\n", infos[i].index, infos[i].name, type_name(infos[i].type),
               (double)infos[i].device_local_heap_bytes / 1048576.0, (double)infos[i].max_allocation_bytes / 1048576.0,
               (double)infos[i].max_storage_buffer_range / 1048576.0, infos[i].usable ? "yes" : "no");
    free(infos);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return FRT_EXIT_USAGE;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "version") == 0) {
        printf("fracterra %s (noise spec v%d)\n", FRT_VERSION_STRING, FRT_SPEC_VERSION);
        return 0;
    }
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) {
        usage(stdout);
        return 0;
    }
    if (strcmp(cmd, "generate") == 0)
        return frt_cmd_generate(argc - 1, argv + 1);
    if (strcmp(cmd, "render") == 0)
        return frt_cmd_render(argc - 1, argv + 1);
    if (strcmp(cmd, "devices") == 0)
        return cmd_devices(argc - 1, argv + 1);
    if (strcmp(cmd, "bench") == 0)
        return frt_cmd_bench(argc - 1, argv + 1);
    if (strcmp(cmd, "tiles") == 0)
        return frt_cmd_tiles(argc - 1, argv + 1);
    if (strcmp(cmd, "info") == 0)
        return frt_cmd_info(argc - 1, argv + 1);
    return frt_cli_fail(FRT_EXIT_USAGE,
                        "unknown command '%s' (commands: generate, tiles, render, info, devices, bench; see --help)",
                        cmd);
}
