/* reference.c — the CPU reference generator: the contract of docs/ALGORITHM.md §3, written plainly.
 * Single-threaded and unoptimised on purpose: it is the yardstick every backend is tested against. */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

/* Mean of the existing neighbours W, E, N, S of square point (x, y) at spacing s, in the contract's order. */
static float square_mean(const float *h, uint32_t side, uint32_t x, uint32_t y, uint32_t s)
{
    const uint32_t last = side - 1;
    float nb[4];
    int n = 0;
    if (x >= s)
        nb[n++] = h[(size_t)y * side + (x - s)]; /* W */
    if (x + s <= last)
        nb[n++] = h[(size_t)y * side + (x + s)]; /* E */
    if (y >= s)
        nb[n++] = h[(size_t)(y - s) * side + x]; /* N */
    if (y + s <= last)
        nb[n++] = h[(size_t)(y + s) * side + x]; /* S */
    if (n == 4)
        return ((nb[0] + nb[1]) + (nb[2] + nb[3])) * 0.25f;
    /* n == 3: a border point (a corner is never a square point) */
    return ((nb[0] + nb[1]) + nb[2]) * frt_one_third();
}

/* Periodic mode (§3.1): side M = 2^n, coordinates mod M, every square point has 4 neighbours. */
static void generate_periodic(const frt_terrain_desc *d, float *out)
{
    const uint32_t n = d->levels, M = 1u << n, mask = M - 1u;
#define P(x, y) out[(size_t)((y)&mask) * M + ((x)&mask)]
    P(0u, 0u) = (float)d->sigma * frt_noise(d->seed, 0, 0, 0);
    for (uint32_t level = 1; level <= n; ++level) {
        const uint32_t s = 1u << (n - level);
        const float sd = frt_sigma_diamond(d, level), ss = frt_sigma_square(d, level);
        for (uint32_t y = s; y < M; y += 2 * s)
            for (uint32_t x = s; x < M; x += 2 * s) {
                float mean = ((P(x - s, y - s) + P(x + s, y - s)) + (P(x - s, y + s) + P(x + s, y + s))) * 0.25f;
                P(x, y) = mean + sd * frt_noise(d->seed, level, x / s, y / s);
            }
        for (uint32_t y = 0; y < M; y += s)
            for (uint32_t x = ((y / s) % 2 == 0) ? s : 0; x < M; x += 2 * s) {
                float mean = ((P(x - s, y) + P(x + s, y)) + (P(x, y - s) + P(x, y + s))) * 0.25f; /* W E N S */
                P(x, y) = mean + ss * frt_noise(d->seed, level, x / s, y / s);
            }
    }
#undef P
}

/* ---- Regions (§3.2): level by level, only the lattice boxes the window needs ---- */

/* One level of a region: the level-l points of box `db` from the level-(l-1) points of box `sb`. */
typedef struct region_level {
    const frt_terrain_desc *d;
    uint32_t level;
    const float *src;
    frt_box sb;
    int64_t last;   /* FFC: the lattice is 0 .. last = 2^l */
    uint32_t lmask; /* periodic: lattice coordinates mod 2^l */
    bool periodic;
    float sd, ss;
} region_level;

static float parent(const region_level *r, int64_t a, int64_t b) /* a, b even: the level-(l-1) point */
{
    return r->src[(size_t)((b >> 1) - r->sb.y) * r->sb.width + (size_t)((a >> 1) - r->sb.x)];
}

static float region_noise(const region_level *r, int64_t a, int64_t b)
{
    uint32_t i = (uint32_t)a, j = (uint32_t)b; /* two's complement: -1 -> 2^32 - 1, then masked */
    if (r->periodic) {
        i &= r->lmask;
        j &= r->lmask;
    }
    return frt_noise(r->d->seed, r->level, i, j);
}

static float diamond(const region_level *r, int64_t a, int64_t b) /* a, b odd */
{
    float mean =
        ((parent(r, a - 1, b - 1) + parent(r, a + 1, b - 1)) + (parent(r, a - 1, b + 1) + parent(r, a + 1, b + 1))) *
        0.25f;
    return mean + r->sd * region_noise(r, a, b);
}

static float corner_or_diamond(const region_level *r, int64_t a, int64_t b)
{
    return (a & 1) ? diamond(r, a, b) : parent(r, a, b);
}

static float square(const region_level *r, int64_t a, int64_t b) /* exactly one of a, b odd */
{
    float nb[4];
    int n = 0;
    if (r->periodic || a - 1 >= 0)
        nb[n++] = corner_or_diamond(r, a - 1, b); /* W */
    if (r->periodic || a + 1 <= r->last)
        nb[n++] = corner_or_diamond(r, a + 1, b); /* E */
    if (r->periodic || b - 1 >= 0)
        nb[n++] = corner_or_diamond(r, a, b - 1); /* N */
    if (r->periodic || b + 1 <= r->last)
        nb[n++] = corner_or_diamond(r, a, b + 1); /* S */
    float mean = n == 4 ? ((nb[0] + nb[1]) + (nb[2] + nb[3])) * 0.25f : ((nb[0] + nb[1]) + nb[2]) * frt_one_third();
    return mean + r->ss * region_noise(r, a, b);
}

static frt_result generate_region(const frt_terrain_desc *d, float *out)
{
    frt_box boxes[FRT_MAX_REGION_LEVELS + 1];
    frt_region_boxes(d, boxes);
    const uint32_t n = d->levels;
    size_t scratch = 0;
    for (uint32_t l = 0; l < n; ++l) {
        size_t area = (size_t)boxes[l].width * boxes[l].height;
        scratch = area > scratch ? area : scratch;
    }
    float *buf = malloc(2 * scratch * sizeof *buf);
    if (!buf)
        return FRT_ERROR_OUT_OF_MEMORY;
    const bool periodic = d->edge == FRT_EDGE_PERIODIC;
    for (uint32_t l = 0; l <= n; ++l) {
        const frt_box db = boxes[l];
        float *dst = l == n ? out : buf + (l & 1) * scratch;
        region_level r = {d,
                          l,
                          buf + ((l + 1) & 1) * scratch,
                          l ? boxes[l - 1] : db,
                          (int64_t)1 << l,
                          (uint32_t)(((uint64_t)1 << l) - 1),
                          periodic,
                          0.0f,
                          0.0f};
        if (l) {
            r.sd = frt_sigma_diamond(d, l);
            r.ss = frt_sigma_square(d, l);
        }
        for (uint32_t y = 0; y < db.height; ++y)
            for (uint32_t x = 0; x < db.width; ++x) {
                const int64_t a = db.x + x, b = db.y + y;
                float v;
                if (l == 0) /* FFC: a corner (a, b in 0..1); periodic: every point is (0, 0) */
                    v = (float)d->sigma * region_noise(&r, a, b);
                else if (!(a & 1) && !(b & 1))
                    v = parent(&r, a, b);
                else if ((a & 1) && (b & 1))
                    v = diamond(&r, a, b);
                else
                    v = square(&r, a, b);
                dst[(size_t)y * db.width + x] = v;
            }
    }
    free(buf);
    return FRT_SUCCESS;
}

frt_result frt_generate_cpu(const frt_terrain_desc *desc, float *out, size_t out_count, frt_run_info *info)
{
    double t0 = frt_now_seconds();
    frt_terrain_desc d;
    if (frt_terrain_desc_resolved(desc, &d) != FRT_SUCCESS)
        return FRT_ERROR_INVALID_ARGUMENT;
    size_t count = frt_heightfield_size(&d);
    if (count == 0)
        return FRT_ERROR_TOO_LARGE;
    if (!out || out_count < count)
        return FRT_ERROR_BUFFER_TOO_SMALL;

    if (frt_region_is_set(&d.region)) {
        frt_result r = generate_region(&d, out);
        if (r != FRT_SUCCESS)
            return r;
        goto done;
    }
    const uint32_t n = d.levels, side = frt_grid_side(n), full = side - 1;
    const float sigma = (float)d.sigma;
    memset(out, 0, count * sizeof *out);
    if (d.edge == FRT_EDGE_PERIODIC) {
        generate_periodic(&d, out);
        goto done;
    }

    /* Level 0: the four corners, noise at unit-square positions (0|1, 0|1). */
    for (uint32_t j = 0; j <= 1; ++j)
        for (uint32_t i = 0; i <= 1; ++i)
            out[(size_t)(j * full) * side + i * full] = sigma * frt_noise(d.seed, 0, i, j);

    for (uint32_t level = 1; level <= n; ++level) {
        const uint32_t s = 1u << (n - level);
        const float sd = frt_sigma_diamond(&d, level), ss = frt_sigma_square(&d, level);
        /* Diamond points: x/s and y/s both odd; parents are the four diagonal corners. */
        for (uint32_t y = s; y < full; y += 2 * s)
            for (uint32_t x = s; x < full; x += 2 * s) {
                float a = out[(size_t)(y - s) * side + (x - s)], b = out[(size_t)(y - s) * side + (x + s)];
                float c = out[(size_t)(y + s) * side + (x - s)], e = out[(size_t)(y + s) * side + (x + s)];
                float mean = ((a + b) + (c + e)) * 0.25f;
                out[(size_t)y * side + x] = mean + sd * frt_noise(d.seed, level, x / s, y / s);
            }
        /* Square points: exactly one of x/s, y/s odd; they read only corners and diamond points. */
        for (uint32_t y = 0; y <= full; y += s)
            for (uint32_t x = ((y / s) % 2 == 0) ? s : 0; x <= full; x += 2 * s)
                out[(size_t)y * side + x] =
                    square_mean(out, side, x, y, s) + ss * frt_noise(d.seed, level, x / s, y / s);
    }
done:
    if (info) {
        double t = frt_now_seconds() - t0;
        info->device_seconds = t;
        info->total_seconds = t;
        info->dispatches = 0;
    }
    return FRT_SUCCESS;
}
