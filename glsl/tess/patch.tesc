// Tessellation methods, control stage: the patch's tessellation levels
// (glsl/tess/tess.glsl). Invocation 0 decides for the patch; every
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

#include "tess.glsl"
#include "common/draw.glsl"

layout(vertices = 16) out;

layout(location = 0) in vec3 in_point[];
layout(location = 1) flat in uint in_patch[];
layout(location = 0) out vec3 out_point[];

// For the evaluation stage: the second-derivative bounds at the start (x)
// and end (y) of each outer edge in its parameter's direction, and the
// mixed-derivative bound.
layout(location = 1) patch out vec4 edge_start;
layout(location = 2) patch out vec4 edge_end;
layout(location = 3) patch out float mixed;
// The base patch, from the vertex stage: gl_PrimitiveID counts from each
// draw's first patch, and the evaluation stage's cannot be trusted at all
// (lavapipe restarts it every 256 patches of a draw).
layout(location = 4) patch out uint patch_id;

void write_levels(vec4 outer, vec2 inner) {
    gl_TessLevelOuter[0] = outer.x;
    gl_TessLevelOuter[1] = outer.y;
    gl_TessLevelOuter[2] = outer.z;
    gl_TessLevelOuter[3] = outer.w;
    gl_TessLevelInner[0] = inner.x;
    gl_TessLevelInner[1] = inner.y;
}

// The border strips' widths for the evaluation stage (tess/tess.glsl,
// "border strips"): per outer edge k the width δ_k of its strip, and per
// direction the inner ring the tessellator uses (1 / segments; 0 where
// the direction is left as the tessellator spaces it).
layout(location = 5) patch out vec4 strip;
layout(location = 6) patch out vec2 ring;

// One direction's narrowing: strips of widths `lo` and `hi` (each at most
// `natural`, the tessellator's) on either side of an inner level `level`.
// Where either is narrower, the level becomes the fewest segments whose
// inner gaps, spread over [lo, 1 - hi], are no wider than 1 / level was
// (two more than the gaps: the rings); a side not narrowed keeps its
// width. `ring` is 0 where nothing moves.
void narrow_direction(inout float level, float natural, float lo, float hi, out float ring,
    out float strip_lo, out float strip_hi) {
    ring = 0.0;
    strip_lo = 0.0;
    strip_hi = 0.0;
    if (lo >= natural && hi >= natural) {
        return;
    }
    // The gaps, (1 - lo - hi) / (segs - 2), no wider than before.
    float segs = ceil((1.0 - lo - hi) * level) + 2.0;
    segs = min(segs, TESS_MAX_LEVEL);
    level = segs;
    ring = 1.0 / segs;
    strip_lo = lo;
    strip_hi = hi;
}

// Narrows the strips whose error the inner ring's natural width does not
// keep within `tol`, and raises that direction's inner level so the inner
// grid, now spread over [δ_lo, 1 - δ_hi], is as fine as before; `m` is
// the mixed bound.
void narrow_strips(vec3 P[16], vec4 outer, inout vec2 inner, float m, float tol) {
    strip = vec4(0.0);
    ring = vec2(0.0);
    bool single_quad = max(max(outer.x, outer.y), max(outer.z, outer.w)) <= 1.0
        && max(inner.x, inner.y) <= 1.0;
    if (single_quad) {
        return;
    }
    float uu = max(u_bound(P, 0), u_bound(P, 1));
    float vv = max(v_bound(P, 0), v_bound(P, 1));
    // The tessellator's natural strip widths across u and across v.
    vec2 natural = vec2(1.0 / inner_segments(inner.x), 1.0 / inner_segments(inner.y));
    // Along-edge spans: the edge's segments against the inner ring's.
    vec4 span = vec4(max(1.0 / ceil(outer.x), 1.0 / inner.y), max(1.0 / ceil(outer.y), 1.0 / inner.x),
        max(1.0 / ceil(outer.z), 1.0 / inner.y), max(1.0 / ceil(outer.w), 1.0 / inner.x));
    vec4 w = vec4(strip_width(P, 0u, natural.x, uu, m, span.x, tol),
        strip_width(P, 1u, natural.y, vv, m, span.y, tol),
        strip_width(P, 2u, natural.x, uu, m, span.z, tol),
        strip_width(P, 3u, natural.y, vv, m, span.w, tol));
    const float floor_width = 1.0 / 1024.0;
    w = max(min(w, natural.xyxy), vec4(floor_width));
    narrow_direction(inner.x, natural.x, w.x, w.z, ring.x, strip.x, strip.z);
    narrow_direction(inner.y, natural.y, w.y, w.w, ring.y, strip.y, strip.w);
}

void capture(uint id, vec4 outer, vec2 inner, float m, bool culled, vec2 drawn_inner) {
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
    tess_levels[o + 8u] = drawn_inner.x;
    tess_levels[o + 9u] = drawn_inner.y;
}

void main() {
    out_point[gl_InvocationID] = in_point[gl_InvocationID];
    if (gl_InvocationID != 0) {
        return;
    }
    uint id = in_patch[0];
    patch_id = id;
    vec3 P[16];
    for (int i = 0; i < 16; ++i) {
        P[i] = in_point[i];
    }

    displaced_patch_begin(id, instances[instance_of(id)]);
    vec3 lo, hi;
    patch_bbox(P, lo, hi);
    if (g_displaced) {
        // The displaced surface reaches beyond the net, and its bumps face
        // every way: grown box, no back-face test.
        lo -= vec3(g_dm.margin);
        hi += vec3(g_dm.margin);
    }
    // An instance drawn from a level of detail (src/lod) counts as culled.
    bool frustum = ((view.flags & FLAG_FRUSTUM_CULL) != 0u && outside_frustum(lo, hi, view))
        || (instances[instance_of(id)].flags & INSTANCE_LOD) != 0u;
    bool one_sided = (patch_flags_of(id) & PATCH_TWO_SIDED) == 0u && !g_displaced;
    bool away = !frustum && (view.flags & FLAG_BACKFACE_CULL) != 0u && one_sided
        && back_facing(P, lo, hi, view.eye.xyz);
    if (frustum || away) {
        atomicAdd(tess_counters[frustum ? T_CULLED : T_BACKFACE], 1u);
        write_levels(vec4(0.0), vec2(0.0));
        edge_start = vec4(0.0);
        edge_end = vec4(0.0);
        mixed = 0.0;
        strip = vec4(0.0);
        ring = vec2(0.0);
        capture(id, vec4(0.0), vec2(0.0), 0.0, true, vec2(0.0));
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
    if (g_displaced) {
        outer = vec4(displaced_edge_level(0u, outer.x, tolerance_at(edge_depth(e0))),
            displaced_edge_level(1u, outer.y, tolerance_at(edge_depth(e1))),
            displaced_edge_level(2u, outer.z, tolerance_at(edge_depth(e2))),
            displaced_edge_level(3u, outer.w, tolerance_at(edge_depth(e3))));
    }

    // Inner levels: the bounds over the whole net, plus the mixed term, at
    // the tolerance of the nearest control point.
    precise float m = mixed_bound(P, TESS_REPARAM != 0u);
    precise float tol = tolerance_at(patch_depth(P));
    precise float u0 = u_bound(P, 0) + m;
    precise float u1 = u_bound(P, 1) + m;
    precise float v0 = v_bound(P, 0) + m;
    precise float v1 = v_bound(P, 1) + m;
    vec2 inner = vec2(tess_level(density(u0, u1), tol), tess_level(density(v0, v1), tol));
    if (g_displaced) {
        inner = displaced_inner_levels(inner, outer, tol);
    }

    vec2 metric_inner = inner;
    narrow_strips(P, outer, inner, m, tol);

    write_levels(outer, inner);
    edge_start = vec4(b0.x, b1.x, b2.x, b3.x);
    edge_end = vec4(b0.y, b1.y, b2.y, b3.y);
    mixed = m;
    capture(id, outer, metric_inner, m, false, inner);
}
