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
    if (levels == 0 || levels > FRT_MAX_REGION_LEVELS)
        return 0;
    return (1u << levels) + 1u;
}

static frt_result check_resolved(const frt_terrain_desc *d, char *why, size_t why_size);

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
    if (d.noise == FRT_NOISE_DEFAULT)
        d.noise = FRT_NOISE_GAUSS;
    if (d.noise_param == 0.0 && d.noise == FRT_NOISE_TRUNCATED)
        d.noise_param = 3.0;
    if (d.noise_param == 0.0 && d.noise == FRT_NOISE_CLT)
        d.noise_param = 4.0;
    if (out)
        *out = d;
    return check_resolved(&d, NULL, 0);
}

frt_result frt_terrain_desc_check(const frt_terrain_desc *desc, char *why, size_t why_size)
{
    frt_terrain_desc d;
    frt_terrain_desc_resolved(desc, &d);
    return check_resolved(&d, why, why_size);
}

static frt_result check_resolved(const frt_terrain_desc *dp, char *why, size_t why_size)
{
    const frt_terrain_desc d = *dp;
    const frt_region g = d.region;
    const bool has_region = g.width != 0 || g.height != 0 || g.x != 0 || g.y != 0;
    if (why && why_size)
        why[0] = '\0';
#define BAD(...)                                                                                                       \
    do {                                                                                                               \
        if (why && why_size)                                                                                           \
            snprintf(why, why_size, __VA_ARGS__);                                                                      \
        return FRT_ERROR_INVALID_ARGUMENT;                                                                             \
    } while (0)
    if (d.levels > FRT_MAX_REGION_LEVELS)
        BAD("%u levels: at most %u", d.levels, FRT_MAX_REGION_LEVELS);
    if (d.levels > FRT_MAX_LEVELS && !has_region)
        BAD("%u levels: a whole grid has at most %u; more need a region", d.levels, FRT_MAX_LEVELS);
    if (!(d.hurst > 0.0 && d.hurst < 1.0)) /* also rejects NaN */
        BAD("hurst %g: must lie in (0, 1)", d.hurst);
    if (!isfinite(d.sigma) || fabs(d.sigma) > 1e30) /* keeps every height finite in float32 */
        BAD("sigma %g: must be finite and at most 1e30 in magnitude", d.sigma);
    if (d.edge != FRT_EDGE_FFC && d.edge != FRT_EDGE_PERIODIC)
        BAD("unknown edge mode %d", (int)d.edge);
    switch (d.noise) { /* §2.8 */
    case FRT_NOISE_GAUSS:
    case FRT_NOISE_UNIFORM:
        if (d.noise_param != 0.0)
            BAD("noise parameter %g: the %s distribution takes none", d.noise_param,
                d.noise == FRT_NOISE_GAUSS ? "gauss" : "uniform");
        break;
    case FRT_NOISE_TRUNCATED:
        if (!(d.noise_param >= 1.0 && d.noise_param <= 6.0)) /* also rejects NaN */
            BAD("truncated noise K = %g: must lie in [1, 6]", d.noise_param);
        break;
    case FRT_NOISE_CLT:
        if (!(d.noise_param >= 1.0 && d.noise_param <= 16.0 && d.noise_param == floor(d.noise_param)))
            BAD("clt noise N = %g: must be a whole number 1..16", d.noise_param);
        break;
    default: BAD("unknown noise distribution %d", (int)d.noise);
    }
    if (has_region) {
        const uint64_t side = (uint64_t)frt_grid_side(d.levels) - (d.edge == FRT_EDGE_PERIODIC ? 1u : 0u);
        if (g.width == 0 || g.height == 0)
            BAD("region %u x %u: width and height must both be at least 1", g.width, g.height);
        if (d.edge == FRT_EDGE_PERIODIC) {
            if (g.x >= side || g.y >= side)
                BAD("region origin (%u, %u) lies outside the %llu x %llu periodic grid", g.x, g.y,
                    (unsigned long long)side, (unsigned long long)side);
            if (g.width > FRT_REGION_MAX_SIDE || g.height > FRT_REGION_MAX_SIDE)
                BAD("region %u x %u: a side is larger than %u", g.width, g.height, FRT_REGION_MAX_SIDE);
        } else if ((uint64_t)g.x + g.width > side || (uint64_t)g.y + g.height > side) {
            BAD("region %u,%u %u x %u reaches outside the %llu x %llu grid", g.x, g.y, g.width, g.height,
                (unsigned long long)side, (unsigned long long)side);
        }
    }
    if (d.coarse || d.coarse_levels) {
        if (!d.coarse || d.coarse_levels == 0)
            BAD("densify needs both the coarse heights and coarse_levels");
        if (d.coarse_levels > d.levels || d.coarse_levels > FRT_MAX_LEVELS)
            BAD("coarse grid of %u levels: at most the %u levels generated (and %u)", d.coarse_levels, d.levels,
                FRT_MAX_LEVELS);
        const size_t cs = frt_grid_side(d.coarse_levels) - (d.edge == FRT_EDGE_PERIODIC ? 1u : 0u);
        for (size_t i = 0; i < cs * cs; ++i)
            if (isinf(d.coarse[i]))
                BAD("coarse height at column %zu, row %zu is infinite (use NaN for no data)", i % cs, i / cs);
    }
    for (int which = 0; which < 2; ++which) {
        const frt_map *m = which ? &d.amplitude_map : &d.hurst_map;
        const char *name = which ? "amplitude map" : "roughness map";
        if (!m->data && !m->width && !m->height)
            continue;
        if (!m->data || m->width < 2 || m->height < 2)
            BAD("%s of %u x %u: needs data and at least 2 x 2 samples", name, m->width, m->height);
        if ((size_t)m->width * m->height > ((size_t)1 << 30))
            BAD("%s of %u x %u: more than 2^30 samples", name, m->width, m->height);
        for (size_t i = 0; i < (size_t)m->width * m->height; ++i) {
            const float v = m->data[i];
            if (!which && !(v > 0.0f && v < 1.0f))
                BAD("roughness map value %g at column %zu, row %zu: H must lie in (0, 1)", v, i % m->width,
                    i / m->width);
            if (which && !(fabs(v) * fabs(d.sigma) <= 1e30))
                BAD("amplitude map value %g at column %zu, row %zu: must be finite, |sigma x value| <= 1e30", v,
                    i % m->width, i / m->width);
        }
    }
#undef BAD
    return FRT_SUCCESS;
}

frt_result frt_terrain_extent(const frt_terrain_desc *desc, uint32_t *width, uint32_t *height)
{
    frt_terrain_desc d;
    uint32_t w = 0, h = 0;
    frt_result r = frt_terrain_desc_resolved(desc, &d);
    if (r == FRT_SUCCESS) {
        if (frt_region_is_set(&d.region)) {
            w = d.region.width;
            h = d.region.height;
        } else {
            w = h = frt_terrain_side(&d);
        }
    }
    if (width)
        *width = w;
    if (height)
        *height = h;
    return r;
}

const char *frt_noise_name(frt_noise_kind kind)
{
    switch (kind) {
    case FRT_NOISE_DEFAULT:
    case FRT_NOISE_GAUSS: return "gauss";
    case FRT_NOISE_TRUNCATED: return "truncated";
    case FRT_NOISE_CLT: return "clt";
    case FRT_NOISE_UNIFORM: return "uniform";
    }
    return "unknown";
}

bool frt_noise_has_param(frt_noise_kind kind)
{
    return kind == FRT_NOISE_TRUNCATED || kind == FRT_NOISE_CLT;
}

bool frt_region_is_set(const frt_region *g)
{
    return g->x || g->y || g->width || g->height;
}

/* Lattice boxes, finest first: level l's box holds the level-l lattice points (coordinates x / 2^(n-l)) that
 * level l + 1 reads. A level-l point at lattice x reads level l-1 at floor((x-1)/2) .. floor(x/2) + 1 (a copied
 * point its parent, a diamond its four corners, a square point its corners and the two recomputed diamonds). */
uint64_t frt_region_boxes(const frt_terrain_desc *d, frt_box *boxes)
{
    const bool periodic = d->edge == FRT_EDGE_PERIODIC;
    int64_t x0 = d->region.x, y0 = d->region.y;
    int64_t x1 = x0 + d->region.width - 1, y1 = y0 + d->region.height - 1;
    for (uint32_t l = d->levels;; --l) {
        boxes[l].x = x0;
        boxes[l].y = y0;
        boxes[l].width = (uint32_t)(x1 - x0 + 1);
        boxes[l].height = (uint32_t)(y1 - y0 + 1);
        if (l == 0)
            break;
        /* floor division of possibly negative (periodic) coordinates */
        x0 = (x0 - 1) >> 1;
        y0 = (y0 - 1) >> 1;
        x1 = (x1 >> 1) + 1;
        y1 = (y1 >> 1) + 1;
        if (!periodic) { /* the FFC lattice at level l - 1 is 0 .. 2^(l-1) */
            const int64_t last = (int64_t)1 << (l - 1);
            x0 = x0 < 0 ? 0 : x0;
            y0 = y0 < 0 ? 0 : y0;
            x1 = x1 > last ? last : x1;
            y1 = y1 > last ? last : y1;
        }
    }
    uint64_t scratch = 0;
    for (uint32_t l = 0; l < d->levels; ++l) {
        const uint64_t area = (uint64_t)boxes[l].width * boxes[l].height;
        scratch = area > scratch ? area : scratch;
    }
    return scratch;
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
    uint32_t w, h;
    if (frt_terrain_extent(desc, &w, &h) != FRT_SUCCESS || w == 0 || h == 0 || (size_t)w > SIZE_MAX / h)
        return 0;
    return (size_t)w * h;
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
