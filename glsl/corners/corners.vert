// Method `corners`, the worked example of docs/ARCHITECTURE.md ("Adding a
// method"): every visible base patch drawn as the two triangles of its four
// corner control points, which lie on the surface. Instance i is the
// patch visible[i] (appended by cull.comp), vertex v its corner
// CORNER[v], read placed by its instance (patch_point), so two patches that
// share a corner share its bits and the coarse mesh is closed wherever the
// cage is. Shaded by draw_vert.frag like the ground truth.
#version 460

#include "corners.glsl"
#include "common/draw.glsl"

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec2 out_uv;
layout(location = 2) flat out uint out_patch;
layout(location = 3) flat out uint out_depth;
layout(location = 4) flat out uint out_wedge;

// Control point k = 4 v + u: the triangles (0,0)-(1,0)-(1,1) and
// (0,0)-(1,1)-(0,1), counter-clockwise in (u, v) like the other methods'.
const uint CORNER[6] = uint[6](0u, 3u, 15u, 0u, 15u, 12u);

void main() {
    uint id = visible[gl_InstanceIndex];
    uint k = CORNER[gl_VertexIndex];
    vec3 p = patch_point(id, k);
    gl_Position = clip_position(p);
    out_world = p;
    out_uv = vec2(float(k % 4u) / 3.0, float(k / 4u) / 3.0);
    out_patch = id;
    out_depth = 0u;
    out_wedge = 0u;
}
