/* cli_inputs.c — inputs of `fracterra generate` beyond numbers: the coarse grid to densify (--coarse), the maps that
 * vary roughness and amplitude by area, and the noise distribution (--noise). */
#include "cli.h"

#include <math.h>
#include <stdlib.h>

int frt_cli_read_field(const char *path, const char *what, float **out, frt_field_info *info)
{
    char err[1200];
    *out = NULL;
    frt_result r = frt_read_heightfield_info(path, info, err, sizeof err);
    if (r != FRT_SUCCESS)
        return frt_cli_fail(r == FRT_ERROR_IO ? FRT_EXIT_IO : FRT_EXIT_USAGE, "%s: %s", what, err);
    const size_t count = (size_t)info->width * info->height;
    float *h = malloc((count ? count : 1) * sizeof *h);
    if (!h)
        return frt_cli_fail(FRT_EXIT_IO, "%s: cannot allocate %.1f MiB for %u x %u heights", what,
                            (double)count * 4.0 / 1048576.0, info->width, info->height);
    r = frt_read_heightfield(path, h, count, info, err, sizeof err);
    if (r != FRT_SUCCESS) {
        free(h);
        return frt_cli_fail(r == FRT_ERROR_IO ? FRT_EXIT_IO : FRT_EXIT_USAGE, "%s: %s", what, err);
    }
    *out = h;
    return FRT_EXIT_OK;
}

int frt_cli_load_coarse(const char *path, bool periodic, bool fit_pad, float **grid, uint32_t *k, frt_field_info *info)
{
    int code = frt_cli_read_field(path, "--coarse", grid, info);
    if (code != FRT_EXIT_OK)
        return code;
    const uint32_t w = info->width, h = info->height, extra = periodic ? 0u : 1u, big = w > h ? w : h;
    uint32_t levels = 0;
    while (levels < FRT_MAX_LEVELS && (1u << levels) + extra < big)
        ++levels;
    if (levels == 0) /* k >= 1: at least the 3 x 3 (2 x 2 periodic) grid */
        levels = 1;
    const uint32_t side = (1u << levels) + extra;
    if (w == h && side == w) {
        *k = levels;
        return FRT_EXIT_OK;
    }
    if (!fit_pad || w < 2 || h < 2 || side < big) {
        free(*grid);
        *grid = NULL;
        if (side < big)
            return frt_cli_fail(FRT_EXIT_USAGE, "--coarse %s is %u x %u: larger than the largest coarse grid, %u x %u",
                                path, w, h, frt_grid_side(FRT_MAX_LEVELS), frt_grid_side(FRT_MAX_LEVELS));
        if (fit_pad)
            return frt_cli_fail(FRT_EXIT_USAGE, "--coarse %s is %u x %u: --fit pad needs at least 2 x 2 samples", path,
                                w, h);
        return frt_cli_fail(FRT_EXIT_USAGE,
                            "--coarse %s is %u x %u: densifying needs a square grid of 2^k%s samples per side (%s, for "
                            "example), k = 1..%u; %scrop or resample it first (e.g. gdalwarp -ts %u %u)",
                            path, w, h, periodic ? "" : " + 1", periodic ? "64 or 128" : "65 or 129", FRT_MAX_LEVELS,
                            periodic ? ""
                                     : "--fit pad mirrors its edges out to the next such size and keeps the "
                                       "output to the data's area, or ",
                            side, side);
    }
    /* --fit pad (FFC only, checked by the caller): the data at the top left of the (2^k+1)^2 grid, the rest NaN;
     * frt_cli_mirror_pad fills it once the estimate (which must see only the data) is done. */
    float *padded = malloc((size_t)side * side * sizeof *padded);
    if (!padded) {
        free(*grid);
        *grid = NULL;
        return frt_cli_fail(FRT_EXIT_IO, "--coarse %s: out of memory padding it to %u x %u", path, side, side);
    }
    for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x < side; ++x)
            padded[(size_t)y * side + x] = x < w && y < h ? (*grid)[(size_t)y * w + x] : NAN;
    free(*grid);
    *grid = padded;
    *k = levels;
    return FRT_EXIT_OK;
}

/* Reflection about the last data index (w - 1), repeated with period 2 (w - 1): 0 1 .. w-1 w-2 .. 1 0 1 .. */
static uint32_t mirror(uint32_t x, uint32_t w)
{
    const uint32_t period = 2 * (w - 1), m = x % period;
    return m < w ? m : period - m;
}

void frt_cli_mirror_pad(float *grid, uint32_t side, uint32_t w, uint32_t h)
{
    for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = y < h ? w : 0; x < side; ++x)
            grid[(size_t)y * side + x] = grid[(size_t)mirror(y, h) * side + mirror(x, w)];
}

int frt_cli_load_map(const char *path, frt_cli_map kind, float **data, frt_map *map)
{
    static const char *const names[] = {"--roughness-map", "--dimension-map", "--amplitude-map"};
    frt_field_info info;
    int code = frt_cli_read_field(path, names[kind], data, &info);
    if (code != FRT_EXIT_OK)
        return code;
    const size_t count = (size_t)info.width * info.height;
    const char *problem = NULL;
    size_t bad = 0;
    if (info.width < 2 || info.height < 2)
        problem = "a map needs at least 2 x 2 samples";
    for (size_t i = 0; !problem && i < count; ++i) {
        float v = (*data)[i];
        if (kind == FRT_CLI_MAP_DIMENSION) {
            if (!(v > 2.0f && v < 3.0f))
                problem = "a fractal dimension D must lie in (2, 3)", bad = i;
            else
                (*data)[i] = 3.0f - v; /* H = 3 - D, once, on the host */
        } else if (kind == FRT_CLI_MAP_HURST && !(v > 0.0f && v < 1.0f)) {
            problem = "H must lie in (0, 1)", bad = i;
        } else if (kind == FRT_CLI_MAP_AMPLITUDE && !isfinite(v)) {
            problem = "an amplitude factor must be finite", bad = i;
        }
    }
    if (problem) {
        const float v = count ? (*data)[bad] : 0.0f; /* as read: the loop stopped before converting it */
        free(*data);
        *data = NULL;
        if (info.width < 2 || info.height < 2)
            return frt_cli_fail(FRT_EXIT_USAGE, "%s %s is %u x %u: %s", names[kind], path, info.width, info.height,
                                problem);
        return frt_cli_fail(FRT_EXIT_USAGE, "%s %s: value %g at column %zu, row %zu: %s", names[kind], path, v,
                            bad % info.width, bad / info.width, problem);
    }
    map->data = *data;
    map->width = info.width;
    map->height = info.height;
    return FRT_EXIT_OK;
}

bool frt_parse_noise(const char *s, frt_noise_kind *kind, double *param)
{
    const char *colon = strchr(s, ':');
    const size_t len = colon ? (size_t)(colon - s) : strlen(s);
    for (frt_noise_kind k = FRT_NOISE_GAUSS; k <= FRT_NOISE_UNIFORM; ++k) {
        const char *name = frt_noise_name(k);
        if (strlen(name) == len && strncmp(s, name, len) == 0) {
            *kind = k;
            *param = 0.0;
            if (!colon)
                return true;
            return frt_noise_has_param(k) && frt_parse_double(colon + 1, param) && *param > 0.0;
        }
    }
    return false;
}
