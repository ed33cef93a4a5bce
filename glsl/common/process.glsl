// One work item of the subdivision, shared by every kernel that runs it
// (the persistent levels/persistent.comp, the per-depth levels/round.comp): the
// GPU twin of src/patch/oracle.rs `process`. Include after scene.glsl.
#ifndef PROCESS_GLSL
#define PROCESS_GLSL

#include "rational_subdiv.glsl"
#include "texture.glsl"
#include "displace.glsl"

const uint OUT_CULLED = 0u;
const uint OUT_BACKFACE = 1u;
const uint OUT_READY = 2u;
const uint OUT_SPLIT = 3u;
const uint OUT_OCCLUDED = 4u;

#ifdef LEVEL_KERNEL
#include "hiz.glsl"
// The late phase of occlusion culling: nodes are also tested against the
// early phase's depth pyramid (set by the level kernels' main from their
// push block). A node is occluded when the box that the frustum test uses
// (control points and wedge pivots: everything it and its descendants
// draw) lies behind the pyramid.
bool process_occludes = false;
// Test-only (FAULT_HIDE_LATE): the late phase hides every node in view.
bool process_hide_all = false;
#endif

// Whether the node's box lo..hi (control points and wedge pivots) is
// hidden behind what the early phase drew.
bool node_occluded(vec3 lo, vec3 hi) {
#ifdef LEVEL_KERNEL
    return process_occludes && (process_hide_all || box_occluded(lo, hi, HIZ_NODE_SPAN));
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

// process_points() (process_template.glsl) on Cartesian control points.
#define BEZ_T vec3
#define BEZ_FN(name) name
#define BEZ_POINT(P, u, v) eval_patch(P, u, v)
#define BEZ_BACK_FACING(S, lo, hi, eye) back_facing(S, lo, hi, eye)
#include "process_template.glsl"

// process_points4(): the twin of oracle::process_rational, on the
// homogeneous control points. The sub-patch is the homogeneous one, the
// box that of its Cartesian control points (and the pivots), the criterion
// runs on projected points, and the back-face bound is the polynomial one
// on w (p - eye) (see src/patch/homogeneous.rs), which makes its own box.
#define BEZ_T vec4
#define BEZ_FN(name) name##4
#define BEZ_POINT(P, u, v) eval_rational(P, u, v)
#define BEZ_BACK_FACING(S, lo, hi, eye) back_facing4(S, eye)
#include "process_template.glsl"

// One work item of a displaced model (twin of oracle::process_displaced):
// the criterion's tolerance less the node's height variation (its edges'
// from the edge owners), the box grown by the largest displacement, no
// back-face test.
uint process_displaced(uvec2 q, vec3 P[16], Instance t, DispModel dm, out uvec2 kids[4],
                       out uint nkids) {
    kids = uvec2[4](uvec2(0u), uvec2(0u), uvec2(0u), uvec2(0u));
    nkids = 0u;
    uint id = node_patch(q);
    vec4 dom = node_domain(q);
    vec3 S[16];
    reconstruct(P, dom.x, dom.y, dom.z, dom.w, S);
    if ((view.flags & FLAG_FRUSTUM_CULL) != 0u) {
        vec3 lo, hi;
        patch_bbox(S, lo, hi);
        vec2 pivots[4];
        bvec4 has = wedge_pivots(q, pivots);
        for (uint e = 0u; e < 4u; ++e) {
            if (has[e]) {
                grow_box(lo, hi, eval_patch(P, pivots[e].x, pivots[e].y));
            }
        }
        precise vec3 g = vec3(dm.margin);
        precise vec3 glo = lo - g;
        precise vec3 ghi = hi + g;
        if (outside_frustum(glo, ghi, view)) {
            return OUT_CULLED;
        }
        if (node_occluded(glo, ghi)) {
            return OUT_OCCLUDED;
        }
    }
    bvec2 can = can_split(q);
    if (can.x || can.y) {
        uvec4 states = edge_states(q);
        bvec4 flat_now = bvec4(true);
        bool edges_flat = true;
        for (uint e = 0u; e < 4u; ++e) {
            if (states[e] == NODE_EDGE_PENDING) {
                vec3 c[4];
                patch_edge(S, e, c);
                flat_now[e] = edge_flat_within(c, view, displaced_edge_reach(t, id, dm, q, e));
                edges_flat = edges_flat && flat_now[e];
            }
        }
        bool inner_fails =
            edges_flat && !inner_flat_within(S, view, displaced_inner_reach(t, id, dm, q));
        bvec2 split = split_of(q, flat_now, inner_fails);
        if (split.x || split.y) {
            nkids = node_children(q, split, resolve_states(q, flat_now), kids);
            return OUT_SPLIT;
        }
    }
    return OUT_READY;
}

// One work item: the GPU twin of oracle::process_any (see process_points).
// The patch's instance is looked up once for the whole item.
uint process(uvec2 q, out uvec2 kids[4], out uint nkids) {
    Instance t = instances[instance_of(node_patch(q))];
    if ((t.flags & INSTANCE_LOD) != 0u) {
        // Drawn from a level of detail this frame (src/lod): the level
        // schedule never lists its roots; the queue kernel drops them here.
        return OUT_CULLED;
    }
    uint flags = patch_flags_in(t, node_patch(q));
    if (flags_rational(flags)) {
        vec4 H[16];
        load_homogeneous_in(t, node_patch(q), H);
        return process_points4(q, H, flags, kids, nkids);
    }
    vec3 P[16];
    load_patch_in(t, node_patch(q), P);
    DispModel dm;
    if (displaced_model(flags >> PATCH_MODEL_SHIFT, dm)) {
        return process_displaced(q, P, t, dm, kids, nkids);
    }
    return process_points(q, P, flags, kids, nkids);
}

// The triangles a ready node draws (2 for the quad plus its wedges) and
// how many of them are wedges.
uvec2 ready_triangles(uvec2 q, bool with_wedges) {
    uint w = wedge_count(node_mesh(q, with_wedges));
    return uvec2(2u + w, w);
}

#endif
