// philox.glsl — Philox4x32-10 and the contract's Gaussian transform, shared by every shader.
// Must stay bit-for-bit the same as host/philox.c: docs/ALGORITHM.md §2.
#ifndef FRT_PHILOX_GLSL
#define FRT_PHILOX_GLSL

// Random123's philox4x32 with 10 rounds; the key is bumped by the Weyl constants before rounds 2..10.
uvec4 frt_philox4x32_10(uvec4 c, uvec2 k)
{
    for (int round = 0; round < 10; ++round) {
        if (round > 0)
            k += uvec2(0x9E3779B9u, 0xBB67AE85u);
        uint hi0, lo0, hi1, lo1;
        umulExtended(0xD2511F53u, c.x, hi0, lo0);
        umulExtended(0xCD9E8D57u, c.z, hi1, lo1);
        c = uvec4(hi1 ^ c.y ^ k.x, lo1, hi0 ^ c.w ^ k.y, lo0);
    }
    return c;
}

// The Gaussian transform of spec v2 (ALGORITHM.md §2.2-2.5): float32 +, -, * and exact bit operations only, so
// the result is the same bits as host/philox.c on any IEEE-754 device. `precise` (SPIR-V NoContraction) on every
// float forbids fused multiply-adds and reordering, as -ffp-contract=off does in C. Each line is one step of the
// spec in the spec's order. Constants by bit pattern (names and decimals as in ALGORITHM.md's tables).
#define FRT_Q0 uintBitsToFloat(0xBF80000Fu)
#define FRT_Q1 uintBitsToFloat(0x3F2AA17Bu)
#define FRT_Q2 uintBitsToFloat(0xBF00F4EDu)
#define FRT_Q3 uintBitsToFloat(0x3EB41874u)
#define FRT_Q4 uintBitsToFloat(0xBF2E1D73u)
#define FRT_Q5 uintBitsToFloat(0xBF979F02u)
#define FRT_Q6 uintBitsToFloat(0xC07C4797u)
#define FRT_Q7 uintBitsToFloat(0xC09E7E3Cu)
#define FRT_Q8 uintBitsToFloat(0xC05F292Au)
#define FRT_L2_HI uintBitsToFloat(0x3FB17180u)
#define FRT_L2_LO uintBitsToFloat(0x3797F7D2u)
#define FRT_C1 uintBitsToFloat(0xBF9DE9E6u)
#define FRT_C2 uintBitsToFloat(0x3E81E0D8u)
#define FRT_C3 uintBitsToFloat(0xBCAAD95Bu)
#define FRT_C4 uintBitsToFloat(0x3A6A7BF7u)
#define FRT_S0 uintBitsToFloat(0x3FC90FDBu)
#define FRT_S1 uintBitsToFloat(0xBF255E12u)
#define FRT_S2 uintBitsToFloat(0x3DA34052u)
#define FRT_S3 uintBitsToFloat(0xBB998CC7u)

// §2.3: -2 ln u for u in [2^-33, 1]: u = 2^e * m, m in (0.5, 1] from the bits, f = m - 1, Q(f) by Estrin's scheme.
float frt_neg2_ln(float u)
{
    const uint b = floatBitsToUint(u);
    const uint eb = (b - 1u) & 0xFF800000u;
    precise float m = uintBitsToFloat(b - eb + 0x3F000000u);
    precise float k = float(126 - int(eb >> 23));
    precise float f = m - 1.0;
    precise float f2 = f * f;
    precise float f4 = f2 * f2;
    precise float a0 = FRT_Q0 + f * FRT_Q1;
    precise float a1 = FRT_Q2 + f * FRT_Q3;
    precise float a2 = FRT_Q4 + f * FRT_Q5;
    precise float a3 = FRT_Q6 + f * FRT_Q7;
    precise float b0 = a0 + f2 * a1;
    precise float b1 = a2 + f2 * a3;
    precise float q = b0 + f4 * (b1 + f4 * FRT_Q8);
    precise float x = (k * FRT_L2_HI + (k * FRT_L2_LO - 2.0 * f)) - f2 * q;
    return x;
}

// §2.4: sqrt x for x in [0, 46]: integer seed for 1/sqrt max(x, 2^-40), two Newton steps 1.5 y - (h y)(y y), x * y,
// one residual correction.
float frt_sqrt_nr(float x)
{
    precise float y = uintBitsToFloat(0x5F3759DFu - (max(floatBitsToUint(x), 0x2B800000u) >> 1));
    precise float h = 0.5 * x;
    y = 1.5 * y - (h * y) * (y * y);
    y = 1.5 * y - (h * y) * (y * y);
    precise float r = x * y;
    precise float rc = r + (0.5 * y) * (x - r * r);
    return rc;
}

// §2.5: cos(2 pi v) for v in [0, 1]: 4v = quadrant q + t exactly, t in [-1/2, 1/2], polynomials in s = t^2.
float frt_cos_2pi(float v)
{
    precise float w = v * 4.0;
    int q = int(w); // signed: one instruction on SIMD CPUs, and w is in [0, 4]
    precise float t = w - float(q);
    if (t > 0.5) {
        t = t - 1.0;
        q += 1;
    }
    precise float s = t * t;
    precise float c = 1.0 + s * (FRT_C1 + s * (FRT_C2 + s * (FRT_C3 + s * FRT_C4)));
    precise float sn = t * (FRT_S0 + s * (FRT_S1 + s * (FRT_S2 + s * FRT_S3)));
    precise float r = (q & 1) != 0 ? sn : c; // quadrants 0..3: c, -sn, -c, sn
    precise float sr = ((q + 1) & 2) != 0 ? -r : r;
    return sr;
}

// Box-Muller on words w0, w1: sqrt(-2 ln u) * cos(2 pi v). Constants 2^-32 and 2^-33 by bit pattern.
float frt_gauss(uint w0, uint w1)
{
    precise float u = float(w0) * uintBitsToFloat(0x2F800000u) + uintBitsToFloat(0x2F000000u);
    precise float v = float(w1) * uintBitsToFloat(0x2F800000u);
    precise float g = frt_sqrt_nr(frt_neg2_ln(u)) * frt_cos_2pi(v);
    return g;
}

// g(level, i, j) of the contract: the Gaussian (§2.2).
float frt_noise(uint level, uint i, uint j, uvec2 key)
{
    uvec4 w = frt_philox4x32_10(uvec4(i, j, level, 0u), key);
    return frt_gauss(w.x, w.y);
}

// The distributions of §2.8; host/philox.c frt_noise_draw is the same code, step for step. kind is frt_noise_kind
// (1 gauss, 2 truncated, 3 clt, 4 uniform = clt with n = 1), n = N, k = K rounded to float, scale = S_K or
// sqrt(12/N). The first Philox call (4th counter word 0) is shared: it is the gauss value, truncated's attempt 0
// and clt's uniforms 0..3.
const uint FRT_NOISE_TRUNCATED = 2u;
// The generator's shaders pass `kind` as this specialization constant, so that each pipeline holds only its own
// path: llvmpipe runs both sides of every branch and one pass of every loop under an execution mask even when the
// condition is uniform, and a loop around the draw stops LLVM from interleaving independent draws; a run-time kind
// made the gauss path 2.5 to 3 times slower there. The pipelines set it to 1 (gauss), 2 (truncated) or 3 (clt and
// uniform): host/internal.h frt_noise_slot.
layout(constant_id = 0) const uint FRT_NOISE_KIND = 1u;
float frt_noise_draw(uint kind, uint n, float k, float scale, uint level, uint i, uint j, uvec2 key)
{
    uvec4 w = frt_philox4x32_10(uvec4(i, j, level, 0u), key);
    if (kind < FRT_NOISE_TRUNCATED) // gauss
        return frt_gauss(w.x, w.y);
    if (kind == FRT_NOISE_TRUNCATED) {
        // rejection with the attempt t in the counter's 4th word; all 64 rejected (p < 1e-31 for K >= 1): 0
        precise float g = frt_gauss(w.x, w.y);
        for (uint t = 1u; abs(g) > k && t < 64u; ++t) {
            w = frt_philox4x32_10(uvec4(i, j, level, t), key);
            g = frt_gauss(w.x, w.y);
        }
        if (abs(g) > k)
            g = 0.0;
        precise float r = g * scale;
        return r;
    }
    // clt, uniform: u_m = float(word m mod 4 of the call with 4th counter word m / 4) * 2^-32, summed left to right
    // Four words per Philox call, taken in order without dynamic indexing (the same sums as one word at a time).
    precise float s = 0.0; // 0 + u_0 = u_0 exactly
    const float scale32 = uintBitsToFloat(0x2F800000u);
    for (uint q = 0u; 4u * q < n; ++q) {
        if (q > 0u)
            w = frt_philox4x32_10(uvec4(i, j, level, q), key);
        const uint left = n - 4u * q;
        s = s + float(w.x) * scale32;
        if (left > 1u)
            s = s + float(w.y) * scale32;
        if (left > 2u)
            s = s + float(w.z) * scale32;
        if (left > 3u)
            s = s + float(w.w) * scale32;
    }
    precise float r = (s - float(n) * 0.5) * scale; // N / 2 is exact
    return r;
}

#endif
