// maps.glsl — roughness and amplitude that vary by area (docs/ALGORITHM.md §3.5), the same float32 steps in the
// same order as host/maps.c, so that the device and the CPU give the same bits. Shared by generate.comp and
// region.comp. FRT_MAPS (specialization constant 1) is 0 for pipelines without maps, which then carry none of this.
#ifndef FRT_MAPS_GLSL
#define FRT_MAPS_GLSL

layout(constant_id = 1) const uint FRT_MAPS = 0u;

// What the host uploads (host/generate_vk.c struct maps_info): the maps' addresses (0: absent) and sizes.
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer FrtMapInfo {
    uint64_t hurst;     // H per sample
    uint64_t amplitude; // factor per sample
    uint hw, hh, aw, ah;
    float sigma;
    uint pad;
};
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer FrtMapData { float v[]; };

// 2^-x for x in [0, 126): exact split, degree-7 polynomial on [0, 1) by Estrin's scheme, exact power of two.
float frt_exp2_neg(float x)
{
    const uint n = uint(x);
    precise float f = x - float(n);
    precise float f2 = f * f;
    precise float f4 = f2 * f2;
    precise float p01 = uintBitsToFloat(0x3F800000u) + uintBitsToFloat(0xBF317218u) * f;
    precise float p23 = uintBitsToFloat(0x3E75FDEAu) + uintBitsToFloat(0xBD635782u) * f;
    precise float p45 = uintBitsToFloat(0x3C1D8992u) + uintBitsToFloat(0xBAADFD6Fu) * f;
    precise float p67 = uintBitsToFloat(0x391A25F7u) + uintBitsToFloat(0xB7345847u) * f;
    precise float p = (p01 + f2 * p23) + f4 * (p45 + f2 * p67);
    precise float r = p * uintBitsToFloat((127u - n) << 23);
    return r;
}

// Bilinear sample at the level-l lattice point (i, j), i.e. at (i, j) / 2^l in the unit square.
float frt_map_sample(uint64_t data, uint w, uint h, uint level, uint i, uint j)
{
    const float scale = uintBitsToFloat((127u - level) << 23);
    precise float px = float(i) * scale;
    precise float py = float(j) * scale;
    precise float fx = px * float(w - 1u);
    precise float fy = py * float(h - 1u);
    const uint x0 = min(uint(fx), w - 2u), y0 = min(uint(fy), h - 2u);
    precise float tx = fx - float(x0);
    precise float ty = fy - float(y0);
    FrtMapData m = FrtMapData(data);
    const uint r0 = y0 * w + x0, r1 = r0 + w;
    precise float top = m.v[r0] + tx * (m.v[r0 + 1u] - m.v[r0]);
    precise float bottom = m.v[r1] + tx * (m.v[r1 + 1u] - m.v[r1]);
    precise float v = top + ty * (bottom - top);
    return v;
}

// The amplitude of the point created at `level` at lattice (i, j): `base` (sD, sS or sigma) without maps;
// sigma 2^-(e H(p)) with a roughness map (e = l - 1/2 for a diamond point, l for a square point); times A(p).
float frt_point_amplitude(uint64_t info, uint level, bool diamond, uint i, uint j, float base)
{
    if (FRT_MAPS == 0u)
        return base;
    FrtMapInfo mi = FrtMapInfo(info);
    precise float amp = base;
    if (mi.hurst != 0ul) {
        precise float e = diamond ? float(level) - 0.5 : float(level);
        precise float eh = e * frt_map_sample(mi.hurst, mi.hw, mi.hh, level, i, j);
        amp = mi.sigma * frt_exp2_neg(eh);
    }
    if (mi.amplitude != 0ul)
        amp = amp * frt_map_sample(mi.amplitude, mi.aw, mi.ah, level, i, j);
    return amp;
}

#endif
