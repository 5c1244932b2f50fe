// midpoint.glsl — the contract's means and displacement (docs/ALGORITHM.md §3), shared by generate.comp and
// region.comp. `precise` forbids fused multiply-adds and reordering, as -ffp-contract=off does in host/reference.c.
#ifndef FRT_MIDPOINT_GLSL
#define FRT_MIDPOINT_GLSL

// mean + amp * g, in that order
float frt_displace(float mean, float amp, float g)
{
    precise float d = amp * g;
    precise float r = mean + d;
    return r;
}
// ((a + b) + (c + d)) * 0.25: four neighbours in the contract's order
float frt_mean4(float a, float b, float c, float d)
{
    precise float s = (a + b) + (c + d);
    precise float m = s * 0.25;
    return m;
}
// ((a + b) + c) * (float nearest 1/3): a border square point's three neighbours
float frt_mean3(float a, float b, float c)
{
    precise float s = (a + b) + c;
    precise float m = s * uintBitsToFloat(0x3EAAAAABu);
    return m;
}

#endif
