/* cli_frames.c — the thesis's "dynamic growth": the field after each refinement level, as numbered PNGs and an
 * animated GIF. The level-l grid is exactly every 2^(n-l)-th point of the final one (docs/ALGORITHM.md §3,
 * resolution independence), so the frames are cut from the final field rather than generated again. */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

#define GIF_MAX_SIDE 1025u     /* larger fields are subsampled: a 4097^2 x 13-frame GIF helps nobody */
#define GIF_DELAY_CS 60u       /* centiseconds per frame */
#define GIF_LAST_DELAY_CS 300u /* hold the finished terrain */

/* Frame `level` of an n-level field of side m: each point takes the value of the nearest lattice point of
 * spacing s = 2^(n-level), ties going up. An FFC field's last lattice point is its border; a periodic field's
 * (side 2^n) lies one step past the edge and wraps to 0. */
static uint32_t nearest(uint32_t x, uint32_t s, uint32_t m)
{
    uint32_t n = (x + s / 2) / s * s;
    return n >= m ? n - m : n;
}

static void frame_of(const float *field, uint32_t m, uint32_t s, float *out)
{
    for (uint32_t y = 0; y < m; ++y) {
        uint32_t ny = nearest(y, s, m);
        for (uint32_t x = 0; x < m; ++x)
            out[(size_t)y * m + x] = field[(size_t)ny * m + nearest(x, s, m)];
    }
}

int frt_write_frames(const char *dir, const char *gif, const float *field, uint32_t m, uint32_t levels,
                     const frt_write_desc *wd)
{
    const size_t count = (size_t)m * m;
    float min = field[0], max = field[0];
    for (size_t i = 1; i < count; ++i) {
        min = field[i] < min ? field[i] : min;
        max = field[i] > max ? field[i] : max;
    }
    /* Subsample the GIF by the smallest integer step that brings it to GIF_MAX_SIDE or less. */
    const uint32_t step = (m + GIF_MAX_SIDE - 1) / GIF_MAX_SIDE;
    const uint32_t gside = (m - 1) / step + 1;
    float *frame = malloc(count * sizeof *frame);
    uint8_t *indices = gif ? malloc((size_t)gside * gside) : NULL;
    if (!frame || (gif && !indices)) {
        free(frame);
        free(indices);
        return frt_cli_fail(FRT_EXIT_IO, "out of memory for the growth frames");
    }
    frt_write_desc fd = *wd;
    fd.bits = 16;
    fd.range_min = min; /* one fixed height scale: the final field's */
    fd.range_max = max;
    char err[1200], path[4096];
    int code = FRT_EXIT_OK;
    frt_gif_writer *g = NULL;
    if (gif) {
        uint8_t palette[768];
        for (int i = 0; i < 256; ++i)
            palette[3 * i] = palette[3 * i + 1] = palette[3 * i + 2] = (uint8_t)i;
        if (frt_gif_open(&g, gif, gside, gside, palette, err, sizeof err) != FRT_SUCCESS) {
            code = frt_cli_fail(FRT_EXIT_IO, "%s", err);
            goto out;
        }
    }
    frt_progress_begin("writing growth frames", levels + 1u);
    for (uint32_t level = 0; level <= levels; ++level) {
        frame_of(field, m, 1u << (levels - level), frame);
        if (dir) {
            snprintf(path, sizeof path, "%s/frame-%02u.png", dir, level);
            frt_result r = frt_write_heightfield(path, frame, m, m, &fd, err, sizeof err);
            if (r != FRT_SUCCESS) {
                code = frt_cli_fail(r == FRT_ERROR_IO ? FRT_EXIT_IO : FRT_EXIT_USAGE, "%s", err);
                goto out;
            }
        }
        if (g) {
            const double scale = max > min ? 255.0 / ((double)max - min) : 0.0;
            for (uint32_t y = 0; y < gside; ++y)
                for (uint32_t x = 0; x < gside; ++x)
                    indices[(size_t)y * gside + x] =
                        (uint8_t)(((double)frame[(size_t)y * step * m + (size_t)x * step] - min) * scale + 0.5);
            if (frt_gif_add_frame(g, indices, level == levels ? GIF_LAST_DELAY_CS : GIF_DELAY_CS, err, sizeof err) !=
                FRT_SUCCESS) {
                code = frt_cli_fail(FRT_EXIT_IO, "%s", err);
                goto out;
            }
        }
        frt_progress_set(level + 1u);
    }
    if (g) {
        frt_result r = frt_gif_commit(g, err, sizeof err);
        g = NULL;
        if (r != FRT_SUCCESS)
            code = frt_cli_fail(FRT_EXIT_IO, "%s", err);
    }
out:
    frt_progress_end();
    frt_gif_abort(g);
    free(frame);
    free(indices);
    return code;
}
