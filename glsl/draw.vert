// Draw path B (fallback), vertex stage: pulls vertex gl_VertexIndex from the
// buffer expand.comp wrote; there is no vertex input state at all.
#version 460

#define USE_VERTICES
#include "common/ready.glsl"
#include "common/draw.glsl"

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec2 out_uv;
layout(location = 2) flat out uint out_patch;
layout(location = 3) flat out uint out_depth;
layout(location = 4) flat out uint out_wedge;

void main() {
    uint index = uint(gl_VertexIndex);
    // Draw arguments larger than the buffer (one chunk of the list; a
    // producer bug) must not read past it: such vertices collapse to one
    // point and draw nothing.
    if (index >= min(pc.capacity, FALLBACK_CHUNK_NODES) * VERTICES_PER_NODE) {
        gl_Position = vec4(0.0, 0.0, 2.0, 1.0);
        out_world = vec3(0.0);
        out_uv = vec2(0.0);
        out_patch = 0u;
        out_depth = 0u;
        out_wedge = 0u;
        return;
    }
    uint o = index * VERTEX_WORDS;
    vec3 p = vec3(uintBitsToFloat(vertex_words[o]), uintBitsToFloat(vertex_words[o + 1u]),
        uintBitsToFloat(vertex_words[o + 2u]));
    uint attrs = vertex_words[o + 4u];
    gl_Position = clip_position(p);
    out_world = p;
    out_uv = unpack_uv(attrs);
    out_patch = vertex_words[o + 3u];
    out_depth = unpack_depth(attrs);
    out_wedge = unpack_wedge(attrs);
}
