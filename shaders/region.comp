// region.comp — one refinement level of a region (docs/ALGORITHM.md §3.2): the level-l lattice points of the box
// `dst` from the level-(l-1) points of the box `src`. One invocation per point: a point of both even coordinates
// copies its parent, a diamond point (both odd) averages its four parents, a square point averages W, E, N, S,
// recomputing the two that are diamond points of this level from their parents (the noise is a pure function of
// (level, i, j, seed), so the recomputation gives the same bits). host/reference.c generate_region is the plain
// version; the results are bit-identical.
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

#include "midpoint.glsl"
#include "philox.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(buffer_reference, std430, buffer_reference_align = 4) buffer Heights { float v[]; };

layout(push_constant, std430) uniform Push {
    uint64_t src;  // level l-1 box, row-major
    uint64_t dst;  // level l box, row-major
    ivec2 sorg;    // lattice coordinates of src[0]
    ivec2 dorg;    // lattice coordinates of dst[0]
    uvec2 key;     // (seed & 0xffffffff, seed >> 32)
    uint sw;       // src box width
    uint dw, dh;   // dst box size
    uint level;    // l
    uint last;     // FFC: the lattice is 0 .. last = 2^l
    uint lmask;    // periodic: 2^l - 1 (coordinates wrap); FFC: all ones
    uint periodic; // 1 on a torus (§3.1): every square point has 4 neighbours
    float sigma;   // level 0
    float amp_d;   // sD(l)
    float amp_s;   // sS(l)
} pc;

float g(ivec2 p) { return frt_noise(pc.level, uint(p.x) & pc.lmask, uint(p.y) & pc.lmask, pc.key); }

// p even: the level-(l-1) point p / 2 (arithmetic shift: floor for the periodic -1)
float parent(ivec2 p)
{
    ivec2 q = (p >> 1) - pc.sorg;
    return Heights(pc.src).v[uint(q.y) * pc.sw + uint(q.x)];
}

float diamond(ivec2 p) // p odd
{
    float m = frt_mean4(parent(p + ivec2(-1, -1)), parent(p + ivec2(1, -1)), parent(p + ivec2(-1, 1)),
                        parent(p + ivec2(1, 1)));
    return frt_displace(m, pc.amp_d, g(p));
}

float corner_or_diamond(ivec2 p) { return (p.x & 1) != 0 ? diamond(p) : parent(p); }

float square(ivec2 p) // exactly one coordinate odd
{
    const bool all4 = pc.periodic != 0u;
    float nb[4];
    int n = 0;
    if (all4 || p.x >= 1)
        nb[n++] = corner_or_diamond(p + ivec2(-1, 0)); // W
    if (all4 || uint(p.x) + 1u <= pc.last)
        nb[n++] = corner_or_diamond(p + ivec2(1, 0)); // E
    if (all4 || p.y >= 1)
        nb[n++] = corner_or_diamond(p + ivec2(0, -1)); // N
    if (all4 || uint(p.y) + 1u <= pc.last)
        nb[n++] = corner_or_diamond(p + ivec2(0, 1)); // S
    float m = n == 4 ? frt_mean4(nb[0], nb[1], nb[2], nb[3]) : frt_mean3(nb[0], nb[1], nb[2]);
    return frt_displace(m, pc.amp_s, g(p));
}

void main()
{
    const uvec2 id = gl_GlobalInvocationID.xy;
    if (id.x >= pc.dw || id.y >= pc.dh)
        return;
    const ivec2 p = pc.dorg + ivec2(id);
    float v;
    if (pc.level == 0u) {
        precise float s = pc.sigma * g(p); // FFC: a corner; periodic (lmask 0): the point (0, 0)
        v = s;
    } else if (((p.x | p.y) & 1) == 0) {
        v = parent(p);
    } else if ((p.x & p.y & 1) != 0) {
        v = diamond(p);
    } else {
        v = square(p);
    }
    Heights(pc.dst).v[id.y * pc.dw + id.x] = v;
}
