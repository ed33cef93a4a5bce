// One work item of the subdivision, shared by every kernel that runs it
// (the persistent subdivide.comp, the per-depth subdivide_level.comp): the
// GPU twin of src/patch/oracle.rs `process`. Include after scene.glsl.
#ifndef PROCESS_GLSL
#define PROCESS_GLSL

#include "rational_subdiv.glsl"

const uint OUT_CULLED = 0u;
const uint OUT_BACKFACE = 1u;
const uint OUT_READY = 2u;
const uint OUT_SPLIT = 3u;

// The four children of q with the edge decisions `flat_now`.
void split_node(uvec2 q, uvec4 depths, bvec4 flat_now, out uvec2 kids[4]) {
    uvec4 r = resolve_depths(node_depth(q), depths, flat_now);
    kids[0] = child_node(q, r, 0u, 0u);
    kids[1] = child_node(q, r, 1u, 0u);
    kids[2] = child_node(q, r, 0u, 1u);
    kids[3] = child_node(q, r, 1u, 1u);
}

// Grows the box lo..hi to hold p.
void grow_box(inout vec3 lo, inout vec3 hi, vec3 p) {
    lo = min3(lo, p);
    hi = max3(hi, p);
}

// One work item of a rational patch: the twin of oracle::process_rational.
// The homogeneous sub-patch, the box of its Cartesian control points (and
// the pivots) for the frustum, the criterion on projected points, and the
// polynomial back-face bound on w (p - eye) (see src/patch/homogeneous.rs).
uint process_rational(uvec2 q, out uvec2 kids[4]) {
    kids = uvec2[4](uvec2(0u), uvec2(0u), uvec2(0u), uvec2(0u));
    vec4 H[16];
    load_homogeneous(q.x, H);
    vec4 dom = node_domain(q);
    vec4 S[16];
    reconstruct4(H, dom.x, dom.y, dom.z, dom.w, S);
    if ((view.flags & FLAG_FRUSTUM_CULL) != 0u) {
        vec3 lo, hi;
        patch_bbox4(S, lo, hi);
        vec2 pivot_u, pivot_v;
        bvec2 pivots = wedge_pivots(q, pivot_u, pivot_v);
        if (pivots.x) {
            grow_box(lo, hi, eval_rational(H, pivot_u.x, pivot_u.y));
        }
        if (pivots.y) {
            grow_box(lo, hi, eval_rational(H, pivot_v.x, pivot_v.y));
        }
        if (outside_frustum(lo, hi, view)) {
            return OUT_CULLED;
        }
    }
    uint l = node_depth(q);
    if (l < view.l_max) {
        uvec4 depths = edge_depths(q);
        bvec4 flat_now = bvec4(true);
        bool edges_flat = true;
        for (uint e = 0u; e < 4u; ++e) {
            if (depths[e] >= l) {
                vec4 c[4];
                patch_edge4(S, e, c);
                flat_now[e] = edge_flat4(c, view);
                edges_flat = edges_flat && flat_now[e];
            }
        }
        if (!edges_flat || !inner_flat4(S, view)) {
            split_node(q, depths, flat_now, kids);
            return OUT_SPLIT;
        }
    }
    bool one_sided = (patch_flags[q.x] & PATCH_TWO_SIDED) == 0u;
    bool with_wedges = (view.flags & FLAG_WEDGES) != 0u;
    if ((view.flags & FLAG_BACKFACE_CULL) != 0u && one_sided && back_facing4(S, view.eye.xyz)
        && wedges_face_away4(H, q, view.eye.xyz, with_wedges)) {
        return OUT_BACKFACE;
    }
    return OUT_READY;
}

// One work item: the GPU twin of oracle::process. Returns OUT_*; for
// OUT_SPLIT the children are in `kids`, in the order (0,0), (1,0), (0,1), (1,1).
// Rational patches take process_rational; polynomial ones the code below.
uint process(uvec2 q, out uvec2 kids[4]) {
    if (patch_is_rational(q.x)) {
        return process_rational(q, kids);
    }
    kids = uvec2[4](uvec2(0u), uvec2(0u), uvec2(0u), uvec2(0u));
    vec3 P[16];
    load_patch(q.x, P);
    vec4 dom = node_domain(q);
    vec3 S[16];
    reconstruct(P, dom.x, dom.y, dom.z, dom.w, S);
    vec3 lo, hi;
    patch_bbox(S, lo, hi);
    vec2 pivot_u, pivot_v;
    bvec2 pivots = wedge_pivots(q, pivot_u, pivot_v);
    if ((view.flags & FLAG_FRUSTUM_CULL) != 0u) {
        // The box must also hold the wedge pivots of the node's outer edges:
        // its wedges and its descendants' reach them (see oracle::process).
        vec3 clo = lo, chi = hi;
        if (pivots.x) {
            grow_box(clo, chi, eval_patch(P, pivot_u.x, pivot_u.y));
        }
        if (pivots.y) {
            grow_box(clo, chi, eval_patch(P, pivot_v.x, pivot_v.y));
        }
        if (outside_frustum(clo, chi, view)) {
            return OUT_CULLED;
        }
    }
    uint l = node_depth(q);
    if (l < view.l_max) {
        uvec4 depths = edge_depths(q);
        bvec4 flat_now = bvec4(true);
        bool edges_flat = true;
        // Every pending edge is tested, no early exit: children inherit them.
        for (uint e = 0u; e < 4u; ++e) {
            if (depths[e] >= l) {
                vec3 c[4];
                patch_edge(S, e, c);
                flat_now[e] = edge_flat(c, view);
                edges_flat = edges_flat && flat_now[e];
            }
        }
        if (!edges_flat || !inner_flat(S, view)) {
            split_node(q, depths, flat_now, kids);
            return OUT_SPLIT;
        }
    }
    // A back-facing node goes only if its wedges face away too (see
    // cull::wedges_face_away).
    bool one_sided = (patch_flags[q.x] & PATCH_TWO_SIDED) == 0u;
    bool with_wedges = (view.flags & FLAG_WEDGES) != 0u;
    if ((view.flags & FLAG_BACKFACE_CULL) != 0u && one_sided && back_facing(S, lo, hi, view.eye.xyz)
        && wedges_face_away(P, q, view.eye.xyz, with_wedges)) {
        return OUT_BACKFACE;
    }
    return OUT_READY;
}

// The triangles a ready node draws (2 for the quad plus its wedges) and
// how many of them are wedges.
uvec2 ready_triangles(uvec2 q, bool with_wedges) {
    NodeMesh mesh = node_mesh(q, with_wedges);
    uint w = (mesh.wedge.x ? 1u : 0u) + (mesh.wedge.y ? 1u : 0u);
    return uvec2(2u + w, w);
}

#endif
