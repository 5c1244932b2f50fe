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

/* The amplitude of a point created at `level` at lattice (i, j): the level's `base` (sD or sS, or sigma at level
 * 0) unless maps vary it by area (§3.5). */
static inline float amp_at(const frt_terrain_desc *d, bool maps, uint32_t level, bool diamond, uint32_t i, uint32_t j,
                           float base)
{
    return maps ? frt_point_amplitude(d, level, diamond, i, j, base) : base;
}

/* Densify (§3.4): a known height replaces the computed one; NaN (no data) keeps the computed one. */
static float keep_known(const float *known, size_t index, float computed)
{
    return known && known[index] == known[index] ? known[index] : computed;
}

/* Periodic mode (§3.1): side M = 2^n, coordinates mod M, every square point has 4 neighbours. Levels first..n;
 * `known` (NULL or the same M x M grid) overrides computed heights where it is not NaN. */
static void generate_periodic(const frt_terrain_desc *d, float *out, uint32_t first, const float *known)
{
    const uint32_t n = d->levels, M = 1u << n, mask = M - 1u;
    frt_noise_params np; /* §2.8 */
    frt_noise_params_init(&np, d);
    const bool maps = d->hurst_map.data || d->amplitude_map.data;
#define P(x, y) out[(size_t)((y)&mask) * M + ((x)&mask)]
    if (first == 0)
        P(0u, 0u) =
            keep_known(known, 0, amp_at(d, maps, 0, false, 0, 0, (float)d->sigma) * frt_noise_draw(&np, 0, 0, 0));
    for (uint32_t level = first ? first : 1; level <= n; ++level) {
        const uint32_t s = 1u << (n - level);
        const float sd = frt_sigma_diamond(d, level), ss = frt_sigma_square(d, level);
        for (uint32_t y = s; y < M; y += 2 * s)
            for (uint32_t x = s; x < M; x += 2 * s) {
                float mean = ((P(x - s, y - s) + P(x + s, y - s)) + (P(x - s, y + s) + P(x + s, y + s))) * 0.25f;
                P(x, y) = keep_known(known, (size_t)y * M + x,
                                     mean + amp_at(d, maps, level, true, x / s, y / s, sd) *
                                                frt_noise_draw(&np, level, x / s, y / s));
            }
        for (uint32_t y = 0; y < M; y += s)
            for (uint32_t x = ((y / s) % 2 == 0) ? s : 0; x < M; x += 2 * s) {
                float mean = ((P(x - s, y) + P(x + s, y)) + (P(x, y - s) + P(x, y + s))) * 0.25f; /* W E N S */
                P(x, y) = keep_known(known, (size_t)y * M + x,
                                     mean + amp_at(d, maps, level, false, x / s, y / s, ss) *
                                                frt_noise_draw(&np, level, x / s, y / s));
            }
    }
#undef P
}

/* FFC mode (§3): side 2^n + 1. Levels first..n, `known` as above. */
static void generate_ffc(const frt_terrain_desc *d, float *out, uint32_t first, const float *known)
{
    const uint32_t n = d->levels, side = frt_grid_side(n), full = side - 1;
    const float sigma = (float)d->sigma;
    frt_noise_params np; /* §2.8 */
    frt_noise_params_init(&np, d);
    const bool maps = d->hurst_map.data || d->amplitude_map.data;
    /* Level 0: the four corners, noise at unit-square positions (0|1, 0|1). */
    if (first == 0)
        for (uint32_t j = 0; j <= 1; ++j)
            for (uint32_t i = 0; i <= 1; ++i) {
                const size_t at = (size_t)(j * full) * side + i * full;
                out[at] = keep_known(known, at, amp_at(d, maps, 0, false, i, j, sigma) * frt_noise_draw(&np, 0, i, j));
            }

    for (uint32_t level = first ? first : 1; level <= n; ++level) {
        const uint32_t s = 1u << (n - level);
        const float sd = frt_sigma_diamond(d, level), ss = frt_sigma_square(d, level);
        /* Diamond points: x/s and y/s both odd; parents are the four diagonal corners. */
        for (uint32_t y = s; y < full; y += 2 * s)
            for (uint32_t x = s; x < full; x += 2 * s) {
                float a = out[(size_t)(y - s) * side + (x - s)], b = out[(size_t)(y - s) * side + (x + s)];
                float c = out[(size_t)(y + s) * side + (x - s)], e = out[(size_t)(y + s) * side + (x + s)];
                float mean = ((a + b) + (c + e)) * 0.25f;
                out[(size_t)y * side + x] = keep_known(known, (size_t)y * side + x,
                                                       mean + amp_at(d, maps, level, true, x / s, y / s, sd) *
                                                                  frt_noise_draw(&np, level, x / s, y / s));
            }
        /* Square points: exactly one of x/s, y/s odd; they read only corners and diamond points. */
        for (uint32_t y = 0; y <= full; y += s)
            for (uint32_t x = ((y / s) % 2 == 0) ? s : 0; x <= full; x += 2 * s)
                out[(size_t)y * side + x] =
                    keep_known(known, (size_t)y * side + x,
                               square_mean(out, side, x, y, s) + amp_at(d, maps, level, false, x / s, y / s, ss) *
                                                                     frt_noise_draw(&np, level, x / s, y / s));
    }
}

frt_result frt_coarse_complete(const frt_terrain_desc *d, float **completed)
{
    frt_terrain_desc dk = *d;
    dk.levels = d->coarse_levels;
    dk.region = (frt_region){0};
    const size_t side = frt_grid_side(dk.levels) - (d->edge == FRT_EDGE_PERIODIC ? 1u : 0u);
    float *c = malloc(side * side * sizeof *c);
    if (!c)
        return FRT_ERROR_OUT_OF_MEMORY;
    if (d->edge == FRT_EDGE_PERIODIC)
        generate_periodic(&dk, c, 0, d->coarse);
    else
        generate_ffc(&dk, c, 0, d->coarse);
    *completed = c;
    return FRT_SUCCESS;
}

void frt_coarse_box(const frt_terrain_desc *d, const float *completed, const frt_box *box, float *out)
{
    const uint32_t k = d->coarse_levels;
    const int64_t side = (int64_t)frt_grid_side(k) - (d->edge == FRT_EDGE_PERIODIC ? 1 : 0);
    for (uint32_t y = 0; y < box->height; ++y)
        for (uint32_t x = 0; x < box->width; ++x) {
            int64_t a = box->x + x, b = box->y + y;
            if (d->edge == FRT_EDGE_PERIODIC) /* side is a power of two: & wraps negative coordinates too */
                a &= side - 1, b &= side - 1;
            out[(size_t)y * box->width + x] = completed[(size_t)b * (size_t)side + (size_t)a];
        }
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
    const frt_noise_params *np; /* §2.8 */
    bool maps;                  /* §3.5 */
} region_level;

static float parent(const region_level *r, int64_t a, int64_t b) /* a, b even: the level-(l-1) point */
{
    return r->src[(size_t)((b >> 1) - r->sb.y) * r->sb.width + (size_t)((a >> 1) - r->sb.x)];
}

/* amp * g of the point at lattice (a, b), wrapped in periodic mode (two's complement: -1 -> 2^32 - 1, masked) */
static float region_step(const region_level *r, int64_t a, int64_t b, bool diamond, float base)
{
    uint32_t i = (uint32_t)a, j = (uint32_t)b;
    if (r->periodic) {
        i &= r->lmask;
        j &= r->lmask;
    }
    return amp_at(r->d, r->maps, r->level, diamond, i, j, base) * frt_noise_draw(r->np, r->level, i, j);
}

static float diamond(const region_level *r, int64_t a, int64_t b) /* a, b odd */
{
    float mean =
        ((parent(r, a - 1, b - 1) + parent(r, a + 1, b - 1)) + (parent(r, a - 1, b + 1) + parent(r, a + 1, b + 1))) *
        0.25f;
    return mean + region_step(r, a, b, true, r->sd);
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
    return mean + region_step(r, a, b, false, r->ss);
}

static frt_result generate_region(const frt_terrain_desc *d, float *out, const float *completed)
{
    frt_box boxes[FRT_MAX_REGION_LEVELS + 1];
    const size_t scratch = (size_t)frt_region_boxes(d, boxes);
    const uint32_t n = d->levels;
    float *buf = malloc(2 * scratch * sizeof *buf);
    if (!buf)
        return FRT_ERROR_OUT_OF_MEMORY;
    const bool periodic = d->edge == FRT_EDGE_PERIODIC;
    const uint32_t first = completed ? d->coarse_levels : 0;
    frt_noise_params np; /* §2.8 */
    frt_noise_params_init(&np, d);
    for (uint32_t l = first; l <= n; ++l) {
        const frt_box db = boxes[l];
        float *dst = l == n ? out : buf + (l & 1) * scratch;
        if (completed && l == first) { /* densify: level k's box is the completed coarse grid's */
            frt_coarse_box(d, completed, &db, dst);
            continue;
        }
        region_level r = {d,
                          l,
                          buf + ((l + 1) & 1) * scratch,
                          l ? boxes[l - 1] : db,
                          (int64_t)1 << l,
                          (uint32_t)(((uint64_t)1 << l) - 1),
                          periodic,
                          0.0f,
                          0.0f,
                          &np,
                          d->hurst_map.data || d->amplitude_map.data};
        if (l) {
            r.sd = frt_sigma_diamond(d, l);
            r.ss = frt_sigma_square(d, l);
        }
        for (uint32_t y = 0; y < db.height; ++y)
            for (uint32_t x = 0; x < db.width; ++x) {
                const int64_t a = db.x + x, b = db.y + y;
                float v;
                if (l == 0) /* FFC: a corner (a, b in 0..1); periodic: every point is (0, 0) */
                    v = region_step(&r, a, b, false, (float)d->sigma);
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

    float *completed = NULL;
    if (d.coarse) {
        frt_result r = frt_coarse_complete(&d, &completed);
        if (r != FRT_SUCCESS)
            return r;
    }
    frt_result r = FRT_SUCCESS;
    if (frt_region_is_set(&d.region)) {
        r = generate_region(&d, out, completed);
    } else if (completed) { /* the completed coarse grid at spacing 2^(n-k), then levels k+1..n */
        const uint32_t k = d.coarse_levels, step = 1u << (d.levels - k), side = frt_terrain_side(&d);
        const uint32_t cs = frt_grid_side(k) - (d.edge == FRT_EDGE_PERIODIC ? 1u : 0u);
        for (uint32_t y = 0; y < cs; ++y)
            for (uint32_t x = 0; x < cs; ++x)
                out[(size_t)(y * step) * side + x * step] = completed[(size_t)y * cs + x];
        if (d.edge == FRT_EDGE_PERIODIC)
            generate_periodic(&d, out, k + 1, NULL);
        else
            generate_ffc(&d, out, k + 1, NULL);
    } else if (d.edge == FRT_EDGE_PERIODIC) {
        generate_periodic(&d, out, 0, NULL);
    } else {
        generate_ffc(&d, out, 0, NULL);
    }
    free(completed);
    if (r != FRT_SUCCESS)
        return r;
    if (info) {
        double t = frt_now_seconds() - t0;
        info->device_seconds = t;
        info->total_seconds = t;
        info->dispatches = 0;
    }
    return FRT_SUCCESS;
}
