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

// Box–Muller on words w0, w1 (spec v1). `precise` forbids fused multiply-adds, as -ffp-contract=off does in C.
// Constants by bit pattern so no decimal rounding can differ: 2^-32, 2^-33, and the float nearest 2*pi.
// log/cos/sqrt precision is the device's: ALGORITHM.md §5 says what may differ.
float frt_gauss(uint w0, uint w1)
{
    precise float u = float(w0) * uintBitsToFloat(0x2F800000u) + uintBitsToFloat(0x2F000000u);
    precise float v = float(w1) * uintBitsToFloat(0x2F800000u);
    precise float r = sqrt(-2.0 * log(u));
    precise float a = uintBitsToFloat(0x40C90FDBu) * v;
    precise float g = r * cos(a);
    return g;
}

// g(level, i, j) of the contract.
float frt_noise(uint level, uint i, uint j, uvec2 key)
{
    uvec4 w = frt_philox4x32_10(uvec4(i, j, level, 0u), key);
    return frt_gauss(w.x, w.y);
}

#endif
