// noise.comp — evaluates Philox words and noise for arbitrary (counter, key) pairs: the known-answer and
// CPU-vs-device tests run the very philox.glsl the generator uses.
// kind 0: words and the Gaussian of words 0, 1 (§2.1-2.2). kind 1..4: the distribution of §2.8 at level c.z,
// i = c.x, j = c.y (c.w unused), written to `gauss`.
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

#include "philox.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Counters { uvec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer Keys { uvec2 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) writeonly buffer Words { uvec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer Gauss { float v[]; };

layout(push_constant, std430) uniform Push {
    uint64_t counters;
    uint64_t keys;
    uint64_t words;
    uint64_t gauss;
    uint count;
    uint noise_kind; // 0: raw words and Gaussian; else §2.8 as frt_noise_params: kind, N, K as float, scale
    uint noise_n;
    float noise_k;
    float noise_scale;
} pc;

void main()
{
    uint k = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u;
    if (k >= pc.count)
        return;
    uvec4 c = Counters(pc.counters).v[k];
    uvec2 key = Keys(pc.keys).v[k];
    uvec4 w = frt_philox4x32_10(c, key);
    Words(pc.words).v[k] = w;
    if (pc.noise_kind == 0u)
        Gauss(pc.gauss).v[k] = frt_gauss(w.x, w.y);
    else
        Gauss(pc.gauss).v[k] =
            frt_noise_draw(pc.noise_kind, pc.noise_n, pc.noise_k, pc.noise_scale, c.z, c.x, c.y, key);
}
