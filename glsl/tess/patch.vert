// Tessellation methods, vertex stage: vertex k of the draw is control point
// k % 16 of base patch k / 16 (placed by its instance); the draw is one patch
// of 16 control points per base patch, no vertex buffer. The base patch goes
// on to the control stage: a draw may cover only some of the patches
// (src/methods/tess.rs, `patches_per_draw`), and gl_PrimitiveID starts at 0
// in each.
#version 460

#include "common/scene.glsl"

layout(location = 0) out vec3 out_point;
layout(location = 1) flat out uint out_patch;

void main() {
    uint id = uint(gl_VertexIndex) / 16u;
    out_point = patch_point(id, uint(gl_VertexIndex) % 16u);
    out_patch = id;
}
