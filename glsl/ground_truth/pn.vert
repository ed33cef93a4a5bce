// Ground truth for PN triangles: instance k is PN triangle k, vertex
// j * (grid + 1) - j (j - 1) / 2 + i its sample at (i / grid, j / grid),
// i + j <= grid, on the net the host converted (src/scene/pn.rs; the same
// buffers and layout as cudatess's set 1, so pn.glsl and cudatess/draw.frag's
// PN shading serve both). Samples on an edge come from the edge's own four
// points through the reversal-symmetric curve() at exact parameters (the
// grid is a power of two), so shared edges meet bit for bit; interior
// samples are the cubic in Bernstein form.
#version 460

#define CT_ACCESS readonly
#include "common/cudatess.glsl"
#include "common/pn.glsl"
#include "common/draw.glsl"

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec2 out_uv;
layout(location = 2) flat out uint out_patch;
layout(location = 3) flat out uint out_depth;
layout(location = 4) flat out uint out_wedge;

// Point s of g along edge k of triangle `tri`.
vec3 edge_sample(uint tri, uint k, uint s, uint g) {
    uvec4 idx = pn_edge_indices(k);
    precise vec3 p = curve(ct_edge_param(s, g), pn_point(tri, idx.x), pn_point(tri, idx.y),
        pn_point(tri, idx.z), pn_point(tri, idx.w));
    return p;
}

void main() {
    uint tri = uint(gl_InstanceIndex);
    uint g = pc.grid;
    uint i = uint(gl_VertexIndex);
    uint j = 0u;
    while (i > g - j) {
        i -= g + 1u - j;
        j += 1u;
    }
    float step = 1.0 / float(g);
    vec2 uv = vec2(float(i) * step, float(j) * step);
    vec3 p;
    if (j == 0u) {
        p = edge_sample(tri, 0u, i, g);
    } else if (i + j == g) {
        p = edge_sample(tri, 1u, j, g);
    } else if (i == 0u) {
        p = edge_sample(tri, 2u, g - j, g);
    } else {
        p = pn_eval(tri, uv);
    }
    gl_Position = clip_position(p);
    out_world = p;
    out_uv = uv;
    out_patch = tri | (1u << CT_PN_SHIFT);
    out_depth = uint(findMSB(g));
    out_wedge = 0u;
}
