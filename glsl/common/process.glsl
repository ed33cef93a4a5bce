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
const uint OUT_OCCLUDED = 4u;
// A base patch left to the other phase of occlusion culling (drawn in the
// early phase, or not visible last frame): nothing drawn, nothing counted.
const uint OUT_DEFERRED = 5u;

#ifdef LEVEL_KERNEL
#include "hiz.glsl"
// The late phase of occlusion culling: nodes are also tested against the
// early phase's depth pyramid (set by the level kernels' main from their
// push block). A node is occluded when the box that the frustum test uses
// (control points and wedge pivots: everything it and its descendants
// draw) lies behind the pyramid.
bool process_occludes = false;
// Only the box tests: a base patch the early phase drew, processed again in
// the late phase to learn whether it is still visible (OUT_READY if it
// passes the frustum and occlusion tests, whatever the criterion says).
bool process_box_only = false;
#endif

// Whether the node, having passed the box tests, is only being tested.
bool box_test_only() {
#ifdef LEVEL_KERNEL
    return process_box_only;
#else
    return false;
#endif
}

// Whether the node's box lo..hi (control points and wedge pivots) is
// hidden behind what the early phase drew.
bool node_occluded(vec3 lo, vec3 hi) {
#ifdef LEVEL_KERNEL
    return process_occludes && box_occluded(lo, hi, HIZ_NODE_SPAN);
#else
    return false;
#endif
}

// Which directions q may still halve (twin of oracle::verdict): iso both
// or neither (at l_max), aniso each below l_max.
bvec2 can_split(uvec2 q) {
    if ((view.flags & FLAG_ANISO) != 0u) {
        return bvec2(node_du(q) < view.l_max, node_dv(q) < view.l_max);
    }
    bool can = node_depth(q) < view.l_max;
    return bvec2(can, can);
}

// The split the criterion asks for (twin of Verdict::split), given the edge
// results `flat_now` (pending edges only; others count as flat) and
// whether the inner tier failed; bvec2(false) for none.
bvec2 split_of(uvec2 q, bvec4 flat_now, bool inner_fails) {
    bool along_u = !flat_now[EDGE_BOTTOM] || !flat_now[EDGE_TOP];
    bool along_v = !flat_now[EDGE_LEFT] || !flat_now[EDGE_RIGHT];
    bvec2 want;
    if ((view.flags & FLAG_ANISO) != 0u) {
        want = bvec2(along_u || inner_fails, along_v || inner_fails);
    } else {
        bool any = (along_u || along_v) || inner_fails;
        want = bvec2(any, any);
    }
    bvec2 can = can_split(q);
    return bvec2(want.x && can.x, want.y && can.y);
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
// `t` is the patch's instance, `flags` its flags word.
uint process_rational(uvec2 q, Instance t, uint flags, out uvec2 kids[4], out uint nkids) {
    kids = uvec2[4](uvec2(0u), uvec2(0u), uvec2(0u), uvec2(0u));
    nkids = 0u;
    vec4 H[16];
    load_homogeneous_in(t, node_patch(q), H);
    vec4 dom = node_domain(q);
    vec4 S[16];
    reconstruct4(H, dom.x, dom.y, dom.z, dom.w, S);
    if ((view.flags & FLAG_FRUSTUM_CULL) != 0u) {
        vec3 lo, hi;
        patch_bbox4(S, lo, hi);
        vec2 pivots[4];
        bvec4 has = wedge_pivots(q, pivots);
        for (uint e = 0u; e < 4u; ++e) {
            if (has[e]) {
                grow_box(lo, hi, eval_rational(H, pivots[e].x, pivots[e].y));
            }
        }
        if (outside_frustum(lo, hi, view)) {
            return OUT_CULLED;
        }
        if (node_occluded(lo, hi)) {
            return OUT_OCCLUDED;
        }
    }
    if (box_test_only()) {
        return OUT_READY;
    }
    bvec2 can = can_split(q);
    if (can.x || can.y) {
        uvec4 states = edge_states(q);
        bvec4 flat_now = bvec4(true);
        bool edges_flat = true;
        for (uint e = 0u; e < 4u; ++e) {
            if (states[e] == NODE_EDGE_PENDING) {
                vec4 c[4];
                patch_edge4(S, e, c);
                flat_now[e] = edge_flat4(c, view);
                edges_flat = edges_flat && flat_now[e];
            }
        }
        bool inner_fails = edges_flat && !inner_flat4(S, view);
        bvec2 split = split_of(q, flat_now, inner_fails);
        if (split.x || split.y) {
            nkids = node_children(q, split, resolve_states(q, flat_now), kids);
            return OUT_SPLIT;
        }
    }
    bool one_sided = (flags & PATCH_TWO_SIDED) == 0u;
    bool with_wedges = (view.flags & FLAG_WEDGES) != 0u;
    if ((view.flags & FLAG_BACKFACE_CULL) != 0u && one_sided && back_facing4(S, view.eye.xyz)
        && wedges_face_away4(H, q, view.eye.xyz, with_wedges)) {
        return OUT_BACKFACE;
    }
    return OUT_READY;
}

// One work item: the GPU twin of oracle::process. Returns OUT_*; for
// OUT_SPLIT the children are kids[0..nkids), in the order (0,0), (1,0),
// (0,1), (1,1) of those the split makes (4 for 1:4, 2 for 1:2).
// Rational patches take process_rational; polynomial ones the code below.
// The patch's instance is looked up once for the whole item.
uint process(uvec2 q, out uvec2 kids[4], out uint nkids) {
    Instance t = instances[instance_of(node_patch(q))];
    uint flags = patch_flags_in(t, node_patch(q));
    if ((flags & PATCH_RATIONAL) != 0u) {
        return process_rational(q, t, flags, kids, nkids);
    }
    kids = uvec2[4](uvec2(0u), uvec2(0u), uvec2(0u), uvec2(0u));
    nkids = 0u;
    vec3 P[16];
    load_patch_in(t, node_patch(q), P);
    vec4 dom = node_domain(q);
    vec3 S[16];
    reconstruct(P, dom.x, dom.y, dom.z, dom.w, S);
    vec3 lo, hi;
    patch_bbox(S, lo, hi);
    if ((view.flags & FLAG_FRUSTUM_CULL) != 0u) {
        // The box must also hold the wedge pivots of the node's edges: its
        // wedges and its descendants' reach them (see oracle::process).
        vec2 pivots[4];
        bvec4 has = wedge_pivots(q, pivots);
        vec3 clo = lo, chi = hi;
        for (uint e = 0u; e < 4u; ++e) {
            if (has[e]) {
                grow_box(clo, chi, eval_patch(P, pivots[e].x, pivots[e].y));
            }
        }
        if (outside_frustum(clo, chi, view)) {
            return OUT_CULLED;
        }
        if (node_occluded(clo, chi)) {
            return OUT_OCCLUDED;
        }
    }
    if (box_test_only()) {
        return OUT_READY;
    }
    bvec2 can = can_split(q);
    if (can.x || can.y) {
        uvec4 states = edge_states(q);
        bvec4 flat_now = bvec4(true);
        bool edges_flat = true;
        // Every pending edge is tested, no early exit: children inherit them.
        for (uint e = 0u; e < 4u; ++e) {
            if (states[e] == NODE_EDGE_PENDING) {
                vec3 c[4];
                patch_edge(S, e, c);
                flat_now[e] = edge_flat(c, view);
                edges_flat = edges_flat && flat_now[e];
            }
        }
        bool inner_fails = edges_flat && !inner_flat(S, view);
        bvec2 split = split_of(q, flat_now, inner_fails);
        if (split.x || split.y) {
            nkids = node_children(q, split, resolve_states(q, flat_now), kids);
            return OUT_SPLIT;
        }
    }
    // A back-facing node goes only if its wedges face away too (see
    // cull::wedges_face_away).
    bool one_sided = (flags & PATCH_TWO_SIDED) == 0u;
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
    uint w = wedge_count(node_mesh(q, with_wedges));
    return uvec2(2u + w, w);
}

#endif
