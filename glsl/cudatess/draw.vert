// cudatess, stage 7: the indexed indirect draw of the vertices and indices
// the compute passes wrote; the vertex shader only pulls its vertex (the
// index is absolute) and hands the fragment stage what every draw path
// does: world position, base-patch (u, v), patch id; "depth" is log2 of
// the patch's larger factor and "wedge" the transition bit of the
// triangle's first (provoking) vertex, set only on transition strips.
#version 460

#define CT_ACCESS readonly
#include "common/cudatess.glsl"
#include "common/draw.glsl"

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec2 out_uv;
layout(location = 2) flat out uint out_patch;
layout(location = 3) flat out uint out_depth;
layout(location = 4) flat out uint out_wedge;

void main() {
    uint o = uint(gl_VertexIndex) * CT_VERTEX_WORDS;
    vec3 p = vec3(uintBitsToFloat(ct_vertices[o]), uintBitsToFloat(ct_vertices[o + 1u]),
        uintBitsToFloat(ct_vertices[o + 2u]));
    uint word = ct_vertices[o + 5u];
    gl_Position = clip_position(p);
    out_world = p;
    out_uv = vec2(uintBitsToFloat(ct_vertices[o + 3u]), uintBitsToFloat(ct_vertices[o + 4u]));
    // A PN triangle's id keeps its CT_PN_SHIFT bit (shade.glsl's SHADE_PN).
    out_patch = word & (((1u << CT_PATCH_BITS) - 1u) | (1u << CT_PN_SHIFT));
    out_depth = (word >> CT_DEPTH_SHIFT) & 15u;
    out_wedge = (word >> CT_TRANSITION_SHIFT) & 1u;
}
