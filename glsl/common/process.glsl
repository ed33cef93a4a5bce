// One work item of the subdivision, shared by every kernel that runs it
// (the persistent levels/persistent.comp, the per-depth levels/round.comp): the
// GPU twin of src/patch/oracle.rs `process`. Include after scene.glsl.
#ifndef PROCESS_GLSL
#define PROCESS_GLSL

#include "rational_subdiv.glsl"

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

// One work item: the GPU twin of oracle::process_any (see process_points).
// The patch's instance is looked up once for the whole item.
uint process(uvec2 q, out uvec2 kids[4], out uint nkids) {
    Instance t = instances[instance_of(node_patch(q))];
    uint flags = patch_flags_in(t, node_patch(q));
    if (flags_rational(flags)) {
        vec4 H[16];
        load_homogeneous_in(t, node_patch(q), H);
        return process_points4(q, H, flags, kids, nkids);
    }
    vec3 P[16];
    load_patch_in(t, node_patch(q), P);
    return process_points(q, P, flags, kids, nkids);
}

// The triangles a ready node draws (2 for the quad plus its wedges) and
// how many of them are wedges.
uvec2 ready_triangles(uvec2 q, bool with_wedges) {
    uint w = wedge_count(node_mesh(q, with_wedges));
    return uvec2(2u + w, w);
}

#endif
