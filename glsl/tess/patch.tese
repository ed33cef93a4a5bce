// Tessellation methods, evaluation stage: the point of the base patch at
// the tessellator's (u, v), or for `tess-reparam` at the re-parameterised
// (ū, v̄) of Buchenau and Guthe §4, evaluated with the shared precise
// eval_patch, and shaded by draw_vert.frag like the ground truth's grid.
//
// On an outer edge the position depends only on the tessellator's
// coordinate along it, the edge's control points and (for the re-
// parameterisation) the bounds the control stage computed from those
// points: the patch across the edge gets the same point bit for bit (see
// mirror_exact and warp in tess/tess.glsl; eval_patch reduces exactly to
// the boundary curve, and curve() is reversal-symmetric).
#version 460

#include "tess.glsl"
#include "common/draw.glsl"

layout(quads, equal_spacing, cw) in;

layout(location = 0) in vec3 in_point[];
layout(location = 1) patch in vec4 edge_start;
layout(location = 2) patch in vec4 edge_end;
layout(location = 3) patch in float mixed;
layout(location = 4) patch in uint patch_id;
layout(location = 5) patch in vec4 strip;
layout(location = 6) patch in vec2 ring;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec2 out_uv;
layout(location = 2) flat out uint out_patch;
layout(location = 3) flat out uint out_depth;
layout(location = 4) flat out uint out_wedge;

// The norm of the second derivative along one direction at one side of the
// patch, a cubic in the other parameter: its net is the second differences
// 6 ((q0 + q2) - 2 q1) of each of the four rows (or columns).
float side_bound(float t, vec3 a0, vec3 a1, vec3 a2, vec3 b0, vec3 b1, vec3 b2,
    vec3 c0, vec3 c1, vec3 c2, vec3 d0, vec3 d1, vec3 d2) {
    vec3 s = curve(t, (a0 + a2) - a1 * 2.0, (b0 + b2) - b1 * 2.0, (c0 + c2) - c1 * 2.0,
        (d0 + d2) - d1 * 2.0);
    return 6.0 * length(s);
}

// Interior samples: each direction warped by the bounds at its two sides
// along the iso-line through the sample, plus the mixed bound (eq. 28-30).
vec2 warp_inner(vec3 P[16], float u, float v) {
    float au = side_bound(v, P[0], P[1], P[2], P[4], P[5], P[6], P[8], P[9], P[10], P[12], P[13], P[14]);
    float bu = side_bound(v, P[1], P[2], P[3], P[5], P[6], P[7], P[9], P[10], P[11], P[13], P[14], P[15]);
    float av = side_bound(u, P[0], P[4], P[8], P[1], P[5], P[9], P[2], P[6], P[10], P[3], P[7], P[11]);
    float bv = side_bound(u, P[4], P[8], P[12], P[5], P[9], P[13], P[6], P[10], P[14], P[7], P[11], P[15]);
    return vec2(warp(u, au + mixed, bu + mixed), warp(v, av + mixed, bv + mixed));
}

void capture_edge(uint id, uint edge, float t, vec3 p) {
    uint k = atomicAdd(tess_counters[T_EDGE_VERTICES], 1u);
    if (k >= pc.capacity) {
        return;
    }
    uint o = k * TESS_EDGE_VERTEX_WORDS;
    tess_edge_vertices[o] = id;
    tess_edge_vertices[o + 1u] = edge;
    tess_edge_vertices[o + 2u] = floatBitsToUint(t);
    tess_edge_vertices[o + 3u] = floatBitsToUint(p.x);
    tess_edge_vertices[o + 4u] = floatBitsToUint(p.y);
    tess_edge_vertices[o + 5u] = floatBitsToUint(p.z);
}

void main() {
    vec3 P[16];
    for (int i = 0; i < 16; ++i) {
        P[i] = in_point[i];
    }
    precise float u = mirror_exact(gl_TessCoord.x);
    precise float v = mirror_exact(gl_TessCoord.y);
    bool u_side = u == 0.0 || u == 1.0;
    bool v_side = v == 0.0 || v == 1.0;
    // Outer edge k (0: u = 0, 1: v = 0, 2: u = 1, 3: v = 1) of a vertex
    // strictly inside one; 4 for corners and interior vertices.
    uint edge = u_side == v_side ? 4u : (u_side ? (u == 0.0 ? 0u : 2u) : (v == 0.0 ? 1u : 3u));
    vec2 uv = vec2(u, v);
    bool interior = !u_side && !v_side;
    // Interior samples of a narrowed direction moved off the border strips
    // (tess/tess.glsl, "border strips"); edge vertices never move.
    if (interior && ring.x > 0.0) {
        uv.x = narrow(u, ring.x, strip.x, strip.z);
    }
    if (interior && ring.y > 0.0) {
        uv.y = narrow(v, ring.y, strip.y, strip.w);
    }
    DispModel dm;
    bool displaced = patch_displacement(patch_id, dm);
    if (TESS_REPARAM != 0u && !displaced) {
        if (edge == 0u || edge == 2u) {
            uv.y = warp(v, edge_start[edge], edge_end[edge]);
        } else if (edge == 1u || edge == 3u) {
            uv.x = warp(u, edge_start[edge], edge_end[edge]);
        } else if (interior) {
            uv = warp_inner(P, uv.x, uv.y);
        }
    }
    uint id = patch_id;
    precise vec3 p = eval_patch(P, uv.x, uv.y);
    if (displaced) {
        // Every vertex by its point's owner (common/displace.glsl): a
        // shared edge's vertices move alike from both sides.
        precise vec3 moved = p + displacement_offset(instances[instance_of(id)], id, dm, uv);
        p = moved;
    }
    if (pc.capture_enabled != 0u && edge < 4u) {
        capture_edge(id, edge, (edge & 1u) == 0u ? gl_TessCoord.y : gl_TessCoord.x, p);
    }
    gl_Position = clip_position(p);
    out_world = p;
    out_uv = uv;
    out_patch = id;
    // The depth heat map shows log2 of the larger inner level: the depth a
    // uniform subdivision to the same density would reach.
    out_depth = uint(findMSB(uint(max(gl_TessLevelInner[0], gl_TessLevelInner[1]))));
    out_wedge = 0u;
}
