/* desc.c — terrain descriptors: defaults, validation, sizes, per-level amplitudes, result strings. */
#include "internal.h"

#include <math.h>
#include <string.h>
#include <time.h>

const char *frt_result_string(frt_result r)
{
    switch (r) {
    case FRT_SUCCESS: return "success";
    case FRT_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case FRT_ERROR_BUFFER_TOO_SMALL: return "output buffer too small";
    case FRT_ERROR_UNSUPPORTED: return "unsupported by the device";
    case FRT_ERROR_TOO_LARGE: return "grid too large for the device or host";
    case FRT_ERROR_OUT_OF_MEMORY: return "out of memory";
    case FRT_ERROR_NO_DEVICE: return "no Vulkan device";
    case FRT_ERROR_VULKAN: return "Vulkan call failed";
    case FRT_ERROR_DEVICE_LOST: return "Vulkan device lost";
    case FRT_ERROR_IO: return "input/output error";
    }
    return "unknown result";
}

uint32_t frt_grid_side(uint32_t levels)
{
    if (levels == 0 || levels > FRT_MAX_LEVELS)
        return 0;
    return (1u << levels) + 1u;
}

frt_result frt_terrain_desc_resolved(const frt_terrain_desc *in, frt_terrain_desc *out)
{
    frt_terrain_desc d;
    if (in)
        d = *in;
    else
        memset(&d, 0, sizeof d);
    if (d.levels == 0)
        d.levels = FRT_DEFAULT_LEVELS;
    if (d.hurst == 0.0)
        d.hurst = FRT_DEFAULT_HURST;
    if (d.sigma == 0.0)
        d.sigma = FRT_DEFAULT_SIGMA;
    if (d.seed == 0 && !d.seed_is_explicit)
        d.seed = FRT_DEFAULT_SEED;
    d.seed_is_explicit = true;
    if (d.edge == FRT_EDGE_DEFAULT)
        d.edge = FRT_EDGE_FFC;
    if (out)
        *out = d;
    if (d.levels > FRT_MAX_LEVELS)
        return FRT_ERROR_INVALID_ARGUMENT;
    if (!(d.hurst > 0.0 && d.hurst < 1.0)) /* also rejects NaN */
        return FRT_ERROR_INVALID_ARGUMENT;
    if (!isfinite(d.sigma) || fabs(d.sigma) > 1e30) /* keeps every height finite in float32 */
        return FRT_ERROR_INVALID_ARGUMENT;
    if (d.edge != FRT_EDGE_FFC && d.edge != FRT_EDGE_PERIODIC)
        return FRT_ERROR_INVALID_ARGUMENT;
    return FRT_SUCCESS;
}

uint32_t frt_terrain_side(const frt_terrain_desc *desc)
{
    frt_terrain_desc d;
    if (frt_terrain_desc_resolved(desc, &d) != FRT_SUCCESS)
        return 0;
    uint32_t side = frt_grid_side(d.levels);
    return d.edge == FRT_EDGE_PERIODIC && side ? side - 1u : side;
}

size_t frt_heightfield_size(const frt_terrain_desc *desc)
{
    size_t side = frt_terrain_side(desc);
    if (side == 0 || side > SIZE_MAX / side)
        return 0;
    return side * side;
}

float frt_sigma_diamond(const frt_terrain_desc *r, uint32_t level)
{
    return (float)(r->sigma * exp2(-((double)level - 0.5) * r->hurst));
}

float frt_sigma_square(const frt_terrain_desc *r, uint32_t level)
{
    return (float)(r->sigma * exp2(-(double)level * r->hurst));
}

float frt_one_third(void)
{
    return frt_bits_float(FRT_ONE_THIRD_BITS);
}

double frt_now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
