// generate.comp — one refinement level of FFC midpoint displacement (diamond and square steps in one dispatch).
// Level 0 writes the four corners. For level l >= 1 each invocation owns a BLOCK x BLOCK block of the cells of
// the level-(l-1) lattice; it creates their centres (diamond points) and their top and left edge midpoints
// (square points), plus bottom/right edge midpoints on the last row/column. A square point's neighbour centre
// in the cell above or to the left belongs to another invocation, so it is recomputed here from its corners:
// the noise is a pure function of (level, i, j, seed), so no synchronisation is needed within a level.
// The heightfield is reached through a buffer device address, so it is not bound by maxStorageBufferRange.
// The formulas are docs/ALGORITHM.md §3; host/reference.c is the plain version.
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

#include "maps.glsl"
#include "midpoint.glsl"
#include "philox.glsl"

#ifndef BLOCK
#define BLOCK 1
#endif

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(buffer_reference, std430, buffer_reference_align = 4) buffer Heights { float v[]; };

layout(push_constant, std430) uniform Push {
    uint64_t grid; // address of h[0]; h[y*side + x]
    uint side;     // 2^n + 1
    uint level;    // l
    uint shift;    // log2 of the spacing s = 2^(n - l)
    uint cells;    // cells per side of the coarser lattice: 2^(l-1)
    uvec2 key;     // (seed & 0xffffffff, seed >> 32)
    float amp_d;   // sD(l); at level 0, sigma
    float amp_s;   // sS(l)
    uint mask;     // periodic (a torus, §3.1): side - 1, coordinates wrap; FFC: all ones, a no-op
    uint lmask;    // periodic: 2^l - 1, noise lattice coordinates wrap; FFC: all ones
    uint noise_n;    // §2.8, as frt_noise_params: N, K as float, S_K or sqrt(12/N); the kind is FRT_NOISE_KIND
    float noise_k;
    float noise_scale;
    uint64_t maps; // §3.5: address of the maps' FrtMapInfo (used when FRT_MAPS is 1)
} pc;

bool periodic() { return pc.mask != 0xFFFFFFFFu; }

// Grids up to 32769^2 keep every index below 2^31 (the host checks), so a 32-bit index is enough.
// Unsigned arithmetic wraps mod 2^32, a multiple of the periodic side, so (x - s) & mask is x - s mod side.
int at(uint x, uint y) { return int((y & pc.mask) * pc.side + (x & pc.mask)); }

float noise(uint i, uint j)
{
    return frt_noise_draw(FRT_NOISE_KIND, pc.noise_n, pc.noise_k, pc.noise_scale, pc.level, i & pc.lmask, j & pc.lmask,
                          pc.key);
}

// mean + amp * g(i, j); the amplitude varies by area with maps (§3.5)
float displace(float mean, float amp, bool diamond, uint i, uint j)
{
    return frt_displace(mean, frt_point_amplitude(pc.maps, pc.level, diamond, i & pc.lmask, j & pc.lmask, amp),
                        noise(i, j));
}
float mean4(float a, float b, float c, float d) { return frt_mean4(a, b, c, d); }
float mean3(float a, float b, float c) { return frt_mean3(a, b, c); }

void main()
{
    Heights h = Heights(pc.grid);
    if (pc.level == 0u) {
        uvec2 ij = gl_GlobalInvocationID.xy;
        const uint corners = periodic() ? 1u : 2u; // periodic: the single point (0, 0)
        if (ij.x < corners && ij.y < corners) {
            precise float v =
                frt_point_amplitude(pc.maps, 0u, false, ij.x & pc.lmask, ij.y & pc.lmask, pc.amp_d) * noise(ij.x, ij.y);
            h.v[at(ij.x * (pc.side - 1u), ij.y * (pc.side - 1u))] = v;
        }
        return;
    }
    const uint s = 1u << pc.shift, s2 = s << 1, C = pc.cells;
    const uint cx0 = gl_GlobalInvocationID.x * BLOCK, cy0 = gl_GlobalInvocationID.y * BLOCK;
    if (cx0 >= C || cy0 >= C)
        return; // the host uses BLOCK > 1 only when BLOCK divides C

    float cor[BLOCK + 1][BLOCK + 1];
    for (uint r = 0; r <= BLOCK; ++r)
        for (uint q = 0; q <= BLOCK; ++q)
            cor[r][q] = h.v[at((cx0 + q) * s2, (cy0 + r) * s2)];

    float ctr[BLOCK][BLOCK];
    for (uint r = 0; r < BLOCK; ++r)
        for (uint q = 0; q < BLOCK; ++q)
            ctr[r][q] = displace(mean4(cor[r][q], cor[r][q + 1], cor[r + 1][q], cor[r + 1][q + 1]), pc.amp_d, true,
                                 2u * (cx0 + q) + 1u, 2u * (cy0 + r) + 1u);

    // Centres of the neighbouring cells above and to the left, recomputed (they exist unless on an FFC border;
    // in periodic mode the row above row 0 is the last row, through `at` and `noise` wrapping).
    const bool has_up = cy0 > 0u || periodic(), has_left = cx0 > 0u || periodic();
    float up[BLOCK], left[BLOCK];
    if (has_up) {
        float a[BLOCK + 1];
        for (uint q = 0; q <= BLOCK; ++q)
            a[q] = h.v[at((cx0 + q) * s2, (cy0 - 1u) * s2)];
        for (uint q = 0; q < BLOCK; ++q)
            up[q] = displace(mean4(a[q], a[q + 1], cor[0][q], cor[0][q + 1]), pc.amp_d, true, 2u * (cx0 + q) + 1u,
                             2u * cy0 - 1u);
    }
    if (has_left) {
        float b[BLOCK + 1];
        for (uint r = 0; r <= BLOCK; ++r)
            b[r] = h.v[at((cx0 - 1u) * s2, (cy0 + r) * s2)];
        for (uint r = 0; r < BLOCK; ++r)
            left[r] = displace(mean4(b[r], cor[r][0], b[r + 1], cor[r + 1][0]), pc.amp_d, true, 2u * cx0 - 1u,
                               2u * (cy0 + r) + 1u);
    }

    for (uint r = 0; r < BLOCK; ++r) {
        const uint j = 2u * (cy0 + r);
        for (uint q = 0; q < BLOCK; ++q) {
            const uint i = 2u * (cx0 + q);
            h.v[at((i + 1u) * s, (j + 1u) * s)] = ctr[r][q];
            // top midpoint: W, E corners; N centre of the cell above; S this centre
            float top;
            if (r > 0u)
                top = mean4(cor[r][q], cor[r][q + 1], ctr[r - 1][q], ctr[r][q]);
            else if (has_up)
                top = mean4(cor[r][q], cor[r][q + 1], up[q], ctr[r][q]);
            else
                top = mean3(cor[r][q], cor[r][q + 1], ctr[r][q]);
            h.v[at((i + 1u) * s, j * s)] = displace(top, pc.amp_s, false, i + 1u, j);
            // left midpoint: W centre of the cell to the left; E this centre; N, S corners
            float lm;
            if (q > 0u)
                lm = mean4(ctr[r][q - 1], ctr[r][q], cor[r][q], cor[r + 1][q]);
            else if (has_left)
                lm = mean4(left[r], ctr[r][q], cor[r][q], cor[r + 1][q]);
            else
                lm = mean3(ctr[r][q], cor[r][q], cor[r + 1][q]);
            h.v[at(i * s, (j + 1u) * s)] = displace(lm, pc.amp_s, false, i, j + 1u);
        }
    }
    if (periodic())
        return; // the bottom and right edges are the top and left ones of the cells on the other side
    if (cy0 + BLOCK == C) { // bottom border midpoints: W, E, N exist
        for (uint q = 0; q < BLOCK; ++q) {
            const uint i = 2u * (cx0 + q) + 1u;
            float m = mean3(cor[BLOCK][q], cor[BLOCK][q + 1], ctr[BLOCK - 1][q]);
            h.v[at(i * s, 2u * C * s)] = displace(m, pc.amp_s, false, i, 2u * C);
        }
    }
    if (cx0 + BLOCK == C) { // right border midpoints: W, N, S exist
        for (uint r = 0; r < BLOCK; ++r) {
            const uint j = 2u * (cy0 + r) + 1u;
            float m = mean3(ctr[r][BLOCK - 1], cor[r][BLOCK], cor[r + 1][BLOCK]);
            h.v[at(2u * C * s, j * s)] = displace(m, pc.amp_s, false, 2u * C, j);
        }
    }
}
