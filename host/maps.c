/* maps.c — roughness and amplitude that vary by area (docs/ALGORITHM.md §3.5): bilinear map sampling and 2^-x, both
 * from float32 +, -, x in a fixed order, so that the CPU and every shader give the same bits (shaders/maps.glsl). */
#include "internal.h"

#include <math.h>

/* 2^-f on [0, 1): degree-7 polynomial by Estrin's scheme, coefficients by bit pattern (§3.5 table). */
static const uint32_t EXP2_C[8] = {0x3F800000u, 0xBF317218u, 0x3E75FDEAu, 0xBD635782u,
                                   0x3C1D8992u, 0xBAADFD6Fu, 0x391A25F7u, 0xB7345847u};

float frt_exp2_neg(float x)
{
    /* x in [0, 126): n = trunc(x) and f = x - n exactly; 2^-x = P(f) * 2^-n, the power of two built from bits */
    const uint32_t n = (uint32_t)x;
    const float f = x - (float)n;
    float c[8];
    for (int i = 0; i < 8; ++i)
        c[i] = frt_bits_float(EXP2_C[i]);
    const float f2 = f * f, f4 = f2 * f2;
    const float p01 = c[0] + c[1] * f, p23 = c[2] + c[3] * f, p45 = c[4] + c[5] * f, p67 = c[6] + c[7] * f;
    const float p = (p01 + f2 * p23) + f4 * (p45 + f2 * p67);
    return p * frt_bits_float((127u - n) << 23);
}

float frt_map_sample(const frt_map *m, uint32_t level, uint32_t i, uint32_t j)
{
    /* the lattice point (i, j) of level l lies at (i, j) * 2^-l in the unit square */
    const float scale = frt_bits_float((127u - level) << 23);
    const float fx = ((float)i * scale) * (float)(m->width - 1), fy = ((float)j * scale) * (float)(m->height - 1);
    uint32_t x0 = (uint32_t)fx, y0 = (uint32_t)fy;
    x0 = x0 > m->width - 2 ? m->width - 2 : x0;
    y0 = y0 > m->height - 2 ? m->height - 2 : y0;
    const float tx = fx - (float)x0, ty = fy - (float)y0;
    const float *r0 = m->data + (size_t)y0 * m->width + x0, *r1 = r0 + m->width;
    const float top = r0[0] + tx * (r0[1] - r0[0]), bottom = r1[0] + tx * (r1[1] - r1[0]);
    return top + ty * (bottom - top);
}

float frt_point_amplitude(const frt_terrain_desc *d, uint32_t level, bool diamond, uint32_t i, uint32_t j,
                          float level_amp)
{
    float amp = level_amp;
    if (d->hurst_map.data) {
        const float e = diamond ? (float)level - 0.5f : (float)level; /* the exponent of 2^-eH (§3) */
        const float eh = e * frt_map_sample(&d->hurst_map, level, i, j);
        amp = (float)d->sigma * frt_exp2_neg(eh);
    }
    if (d->amplitude_map.data)
        amp = amp * frt_map_sample(&d->amplitude_map, level, i, j);
    return amp;
}
