// Tessellation methods, vertex stage: vertex k of the draw is control point
// k % 16 of base patch k / 16, handed on unchanged; the draw is one patch
// of 16 control points per base patch, no vertex buffer.
#version 460

#include "common/scene.glsl"

layout(location = 0) out vec3 out_point;

void main() {
    uint id = uint(gl_VertexIndex) / 16u;
    uint o = id * 48u + (uint(gl_VertexIndex) % 16u) * 3u;
    out_point = vec3(patch_data[o], patch_data[o + 1u], patch_data[o + 2u]);
}
