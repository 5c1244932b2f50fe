/* estimate.c — H and sigma of a known grid, for densifying real data with its own roughness (docs/ALGORITHM.md
 * §3.6): the variogram of the grid's own midpoint residuals, level by level, fitted by weighted least squares. */
#include "internal.h"

#include <math.h>

enum { MIN_RESIDUALS = 16 }; /* a level (diamond or square step) enters the fit with at least this many residuals */

typedef struct level_sum {
    double sum2; /* sum of squared residuals */
    uint64_t count;
} level_sum;

/* Residual of the point (x, y) created at spacing s: its height minus the contract's mean of its parents (§3), in
 * double; NaN if any of them is missing. `diamond`: the four diagonal parents, else the existing W, E, N, S. */
static double residual(const float *h, uint32_t side, uint32_t x, uint32_t y, uint32_t s, bool diamond)
{
    const uint32_t last = side - 1;
    double v = h[(size_t)y * side + x], sum = 0.0;
    int n = 0;
    if (diamond) {
        sum = (double)h[(size_t)(y - s) * side + (x - s)] + h[(size_t)(y - s) * side + (x + s)] +
              h[(size_t)(y + s) * side + (x - s)] + h[(size_t)(y + s) * side + (x + s)];
        n = 4;
    } else {
        if (x >= s)
            sum += h[(size_t)y * side + (x - s)], ++n;
        if (x + s <= last)
            sum += h[(size_t)y * side + (x + s)], ++n;
        if (y >= s)
            sum += h[(size_t)(y - s) * side + x], ++n;
        if (y + s <= last)
            sum += h[(size_t)(y + s) * side + x], ++n;
    }
    return v - sum / n; /* NaN propagates */
}

frt_result frt_estimate_roughness(const float *h, uint32_t side, frt_roughness *out)
{
    if (!h || !out)
        return FRT_ERROR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    uint32_t k = 0;
    while (k < FRT_MAX_LEVELS && (1u << k) + 1u < side)
        ++k;
    if (side < 3 || (1u << k) + 1u != side)
        return FRT_ERROR_INVALID_ARGUMENT;

    /* sums[2l]: diamond step of level l (t = l - 1/2); sums[2l + 1]: square step (t = l) */
    level_sum sums[2 * (FRT_MAX_LEVELS + 1)];
    memset(sums, 0, sizeof sums);
    const uint32_t full = side - 1;
    for (uint32_t l = 1; l <= k; ++l) {
        const uint32_t s = 1u << (k - l);
        for (uint32_t y = s; y < full; y += 2 * s)
            for (uint32_t x = s; x < full; x += 2 * s) {
                double r = residual(h, side, x, y, s, true);
                if (isfinite(r))
                    sums[2 * l].sum2 += r * r, sums[2 * l].count++;
            }
        for (uint32_t y = 0; y <= full; y += s)
            for (uint32_t x = ((y / s) % 2 == 0) ? s : 0; x <= full; x += 2 * s) {
                double r = residual(h, side, x, y, s, false);
                if (isfinite(r))
                    sums[2 * l + 1].sum2 += r * r, sums[2 * l + 1].count++;
            }
    }
    /* Var(residual) = sigma^2 2^(-2tH): fit log2 of the RMS residual = log2 sigma - H t, weights = counts (the
     * variance of a log sample variance is about 2/count). */
    double sw = 0, st = 0, sy = 0, stt = 0, sty = 0;
    uint32_t steps = 0;
    for (uint32_t l = 1; l <= k; ++l)
        for (int sq = 0; sq <= 1; ++sq) {
            const level_sum *e = &sums[2 * l + (uint32_t)sq];
            if (e->count < MIN_RESIDUALS || !(e->sum2 > 0.0))
                continue;
            const double w = (double)e->count, t = sq ? (double)l : (double)l - 0.5;
            const double y = 0.5 * log2(e->sum2 / (double)e->count);
            sw += w, st += w * t, sy += w * y, stt += w * t * t, sty += w * t * y;
            ++steps;
            out->residuals += e->count;
        }
    const double det = sw * stt - st * st;
    if (steps < 3 || !(det > 0.0))
        return FRT_ERROR_INVALID_ARGUMENT; /* too few known points, or a flat grid */
    const double slope = (sw * sty - st * sy) / det, intercept = (sy - slope * st) / sw;
    double H = -slope;
    out->clamped = !(H >= FRT_ROUGHNESS_MIN_HURST && H <= FRT_ROUGHNESS_MAX_HURST);
    if (out->clamped) /* keep the line through the weighted centre of the data when H is clamped */
        H = H < FRT_ROUGHNESS_MIN_HURST || isnan(H) ? FRT_ROUGHNESS_MIN_HURST : FRT_ROUGHNESS_MAX_HURST;
    const double tc = st / sw, yc = sy / sw;
    out->hurst = H;
    out->t_centre = tc;
    out->log2_rms_centre = yc;
    out->sigma = out->clamped ? exp2(yc + H * tc) : exp2(intercept);
    out->steps = steps;
    out->coarse_levels = k;
    return isfinite(out->sigma) && out->sigma > 0.0 ? FRT_SUCCESS : FRT_ERROR_INVALID_ARGUMENT;
}
