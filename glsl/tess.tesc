// Tessellation methods, control stage: the patch's tessellation levels
// (glsl/common/tess.glsl). Invocation 0 decides for the patch; every
// invocation hands its control point on.
//
// Outer level k belongs to the edge the evaluation stage sees as: 0 u = 0,
// 1 v = 0, 2 u = 1, 3 v = 1; each edge's points are taken in the direction
// of its parameter, and its level depends on them and the view only, so the
// patch across the edge, which holds the same points (possibly reversed),
// writes the same level bit for bit. Inner levels add the mixed derivative
// (their eq. 12); frustum- and back-face-culled patches get level 0 and
// are not drawn.
#version 460

#include "common/tess.glsl"
#include "common/draw.glsl"

layout(vertices = 16) out;

layout(location = 0) in vec3 in_point[];
layout(location = 0) out vec3 out_point[];

// For the evaluation stage: the second-derivative bounds at the start (x)
// and end (y) of each outer edge in its parameter's direction, and the
// mixed-derivative bound.
layout(location = 1) patch out vec4 edge_start;
layout(location = 2) patch out vec4 edge_end;
layout(location = 3) patch out float mixed;
// The base patch: the evaluation stage's own gl_PrimitiveID cannot be
// trusted for it (lavapipe restarts it every 256 patches of a draw).
layout(location = 4) patch out uint patch_id;

void write_levels(vec4 outer, vec2 inner) {
    gl_TessLevelOuter[0] = outer.x;
    gl_TessLevelOuter[1] = outer.y;
    gl_TessLevelOuter[2] = outer.z;
    gl_TessLevelOuter[3] = outer.w;
    gl_TessLevelInner[0] = inner.x;
    gl_TessLevelInner[1] = inner.y;
}

void capture(uint id, vec4 outer, vec2 inner, float m, bool culled) {
    if (pc.capture_enabled == 0u) {
        return;
    }
    uint o = id * TESS_LEVEL_WORDS;
    tess_levels[o] = outer.x;
    tess_levels[o + 1u] = outer.y;
    tess_levels[o + 2u] = outer.z;
    tess_levels[o + 3u] = outer.w;
    tess_levels[o + 4u] = inner.x;
    tess_levels[o + 5u] = inner.y;
    tess_levels[o + 6u] = m;
    tess_levels[o + 7u] = culled ? 1.0 : 0.0;
}

void main() {
    out_point[gl_InvocationID] = in_point[gl_InvocationID];
    if (gl_InvocationID != 0) {
        return;
    }
    uint id = uint(gl_PrimitiveID);
    patch_id = id;
    vec3 P[16];
    for (int i = 0; i < 16; ++i) {
        P[i] = in_point[i];
    }

    vec3 lo, hi;
    patch_bbox(P, lo, hi);
    bool frustum = (view.flags & FLAG_FRUSTUM_CULL) != 0u && outside_frustum(lo, hi, view);
    bool one_sided = (patch_flags_of(id) & PATCH_TWO_SIDED) == 0u;
    bool away = !frustum && (view.flags & FLAG_BACKFACE_CULL) != 0u && one_sided
        && back_facing(P, lo, hi, view.eye.xyz);
    if (frustum || away) {
        atomicAdd(tess_counters[frustum ? T_CULLED : T_BACKFACE], 1u);
        write_levels(vec4(0.0), vec2(0.0));
        edge_start = vec4(0.0);
        edge_end = vec4(0.0);
        mixed = 0.0;
        capture(id, vec4(0.0), vec2(0.0), 0.0, true);
        return;
    }
    atomicAdd(tess_counters[T_TESSELLATED], 1u);

    vec3 e0[4] = vec3[4](P[0], P[4], P[8], P[12]);
    vec3 e1[4] = vec3[4](P[0], P[1], P[2], P[3]);
    vec3 e2[4] = vec3[4](P[3], P[7], P[11], P[15]);
    vec3 e3[4] = vec3[4](P[12], P[13], P[14], P[15]);
    vec2 b0 = edge_bounds(e0);
    vec2 b1 = edge_bounds(e1);
    vec2 b2 = edge_bounds(e2);
    vec2 b3 = edge_bounds(e3);
    vec4 outer = vec4(edge_level(e0, b0), edge_level(e1, b1), edge_level(e2, b2), edge_level(e3, b3));

    // Inner levels: the bounds over the whole net, plus the mixed term, at
    // the tolerance of the nearest control point.
    precise float m = mixed_bound(P, TESS_REPARAM != 0u);
    precise float tol = tolerance_at(patch_depth(P));
    precise float u0 = u_bound(P, 0) + m;
    precise float u1 = u_bound(P, 1) + m;
    precise float v0 = v_bound(P, 0) + m;
    precise float v1 = v_bound(P, 1) + m;
    vec2 inner = vec2(tess_level(density(u0, u1), tol), tess_level(density(v0, v1), tol));

    write_levels(outer, inner);
    edge_start = vec4(b0.x, b1.x, b2.x, b3.x);
    edge_end = vec4(b0.y, b1.y, b2.y, b3.y);
    mixed = m;
    capture(id, outer, inner, m, false);
}
