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

#include "maps.glsl"
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
    uint noise_n;    // §2.8, as frt_noise_params: N, K as float, S_K or sqrt(12/N); the kind is FRT_NOISE_KIND
    float noise_k;
    float noise_scale;
    uint64_t maps; // §3.5: address of the maps' FrtMapInfo (used when FRT_MAPS is 1)
} pc;

float g(ivec2 p)
{
    return frt_noise_draw(FRT_NOISE_KIND, pc.noise_n, pc.noise_k, pc.noise_scale, pc.level, uint(p.x) & pc.lmask,
                          uint(p.y) & pc.lmask, pc.key);
}

// The amplitude at lattice point p (wrapped in periodic mode), §3.5
float amp(ivec2 p, bool diamond, float base)
{
    return frt_point_amplitude(pc.maps, pc.level, diamond, uint(p.x) & pc.lmask, uint(p.y) & pc.lmask, base);
}

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
    return frt_displace(m, amp(p, true, pc.amp_d), g(p));
}

// The mean of the existing ones of W, E, N, S in that order (§3): all four, or three on an FFC border.
float square_mean(bool hw, float w, bool he, float e, bool hn, float n, bool hs, float s)
{
    float nb[4];
    int k = 0;
    if (hw)
        nb[k++] = w;
    if (he)
        nb[k++] = e;
    if (hn)
        nb[k++] = n;
    if (hs)
        nb[k++] = s;
    return k == 4 ? frt_mean4(nb[0], nb[1], nb[2], nb[3]) : frt_mean3(nb[0], nb[1], nb[2]);
}

bool in_box(ivec2 p) { return uint(p.x - pc.dorg.x) < pc.dw && uint(p.y - pc.dorg.y) < pc.dh; }

void store(ivec2 p, float v) { Heights(pc.dst).v[uint(p.y - pc.dorg.y) * pc.dw + uint(p.x - pc.dorg.x)] = v; }

// One invocation per 2 x 2 quad of the level's lattice with its corner q at even coordinates: q copies its parent,
// q + (1, 1) is a diamond point D, q + (1, 0) and q + (0, 1) are square points. The quad computes D once and
// recomputes only the diamond above (U) and to the left (L); every lane takes the same path except at the box's and
// the lattice's edges (llvmpipe runs both sides of a divergent branch, so a point-per-invocation kernel pays for
// every kind of point in every lane). Only points inside the box are computed and stored, so every parent read
// lies in the previous level's box (§3.2).
void main()
{
    const ivec2 q = ((pc.dorg >> 1) << 1) + 2 * ivec2(gl_GlobalInvocationID.xy);
    const ivec2 pd = q + ivec2(1, 1), px = q + ivec2(1, 0), py = q + ivec2(0, 1);
    const bool c_in = in_box(q), d_in = in_box(pd), x_in = in_box(px), y_in = in_box(py);
    if (!(c_in || d_in || x_in || y_in))
        return;
    if (pc.level == 0u) { // FFC: the corners; periodic (lmask 0): every point is (0, 0)
        const ivec2 pts[4] = ivec2[4](q, px, py, pd);
        const bool ins[4] = bool[4](c_in, x_in, y_in, d_in);
        for (int k = 0; k < 4; ++k)
            if (ins[k]) {
                precise float v = amp(pts[k], false, pc.sigma) * g(pts[k]);
                store(pts[k], v);
            }
        return;
    }
    const bool all4 = pc.periodic != 0u;
    if (c_in)
        store(q, parent(q));
    // D is the S neighbour of px and the E neighbour of py; it exists unless q is on the FFC lattice's last row or
    // column, and then neither px's S nor py's E exists either.
    const bool has_d = all4 || (uint(q.x) < pc.last && uint(q.y) < pc.last);
    float D = 0.0;
    if (has_d && (d_in || x_in || y_in))
        D = diamond(pd);
    if (d_in)
        store(pd, D);
    if (x_in) { // (odd, even): W, E parents; N the diamond above; S = D
        const bool hn = all4 || q.y >= 1, he = all4 || uint(q.x) + 2u <= pc.last;
        const float U = hn ? diamond(q + ivec2(1, -1)) : 0.0;
        const float E = he ? parent(q + ivec2(2, 0)) : 0.0;
        const float m = square_mean(true, parent(q), he, E, hn, U, has_d, D);
        store(px, frt_displace(m, amp(px, false, pc.amp_s), g(px)));
    }
    if (y_in) { // (even, odd): W the diamond to the left; E = D; N, S parents
        const bool hw = all4 || q.x >= 1, hs = all4 || uint(q.y) + 2u <= pc.last;
        const float L = hw ? diamond(q + ivec2(-1, 1)) : 0.0;
        const float S = hs ? parent(q + ivec2(0, 2)) : 0.0;
        const float m = square_mean(hw, L, has_d, D, true, parent(q), hs, S);
        store(py, frt_displace(m, amp(py, false, pc.amp_s), g(py)));
    }
}
