// noise.comp — evaluates Philox words and Gaussians for arbitrary (counter, key) pairs: the known-answer and
// CPU-vs-device tests run the very philox.glsl the generator uses.
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
} pc;

void main()
{
    uint k = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u;
    if (k >= pc.count)
        return;
    uvec4 w = frt_philox4x32_10(Counters(pc.counters).v[k], Keys(pc.keys).v[k]);
    Words(pc.words).v[k] = w;
    Gauss(pc.gauss).v[k] = frt_gauss(w.x, w.y);
}
