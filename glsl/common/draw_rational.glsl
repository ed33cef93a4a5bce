// Drawn positions for both ready-list draw paths (draw.mesh, expand.comp),
// rational patches included: a patch flagged PATCH_RATIONAL evaluates its
// homogeneous surface at the node mesh's dyadic parameters and divides
// (oracle::node_positions_rational); every other patch takes
// node_positions() of draw.glsl exactly as before. Include after draw.glsl.
#ifndef DRAW_RATIONAL_GLSL
#define DRAW_RATIONAL_GLSL

#extension GL_EXT_control_flow_attributes : require

#include "draw.glsl"
#include "rational_subdiv.glsl"
#include "texture.glsl"
#include "displace.glsl"

void patch_node_positions(uint id, NodeMesh mesh, out vec3 pos[NODE_MESH_SLOTS]) {
    Instance t = instances[instance_of(id)];
    if (flags_rational(patch_flags_in(t, id))) {
        vec4 H[16];
        load_homogeneous_in(t, id, H);
        for (uint s = 0u; s < NODE_MESH_SLOTS; ++s) {
            pos[s] = slot_used(mesh, s) ? eval_rational(H, mesh.uv[s].x, mesh.uv[s].y) : pos[0];
        }
        return;
    }
    vec3 P[16];
    load_patch_in(t, id, P);
    node_positions(P, mesh, pos);
    // A displaced model's vertices move by n̂·d, each evaluated by the
    // owner of the point (twin of Displaced::node_positions).
    DispModel dm;
    if (displaced_model(patch_flags_in(t, id) >> PATCH_MODEL_SHIFT, dm)) {
        for (uint s = 0u; s < NODE_MESH_SLOTS; ++s) {
            if (slot_used(mesh, s)) {
                precise vec3 p = pos[s] + displacement_offset(t, id, dm, mesh.uv[s]);
                pos[s] = p;
            }
        }
    }
}

// Base patch `id`'s drawn point at (u, v), rational patches divided.
vec3 patch_surface_point(uint id, vec2 uv) {
    if (patch_is_rational(id)) {
        vec4 H[16];
        load_homogeneous(id, H);
        return eval_rational(H, uv.x, uv.y);
    }
    vec3 P[16];
    load_patch(id, P);
    return eval_patch(P, uv.x, uv.y);
}

// Whether the triangle a b c, as wound, faces the eye (cull.rs's test of
// the wedges, negated).
bool faces_eye(vec3 a, vec3 b, vec3 c, vec3 eye) {
    precise vec3 ab = b - a;
    precise vec3 ac = c - a;
    precise vec3 n = cross3(ab, ac);
    precise vec3 to_a = a - eye;
    precise float side = dot3(n, to_a);
    return !(side > 0.0);
}

// The point across edge e of the node with domain `dom` (a, b, c, d), as
// far from the edge as the node is wide: the quad triangle's third corner
// mirrored in the edge. Exact: the parameters are dyadic.
vec2 across_edge(vec4 dom, uint e) {
    if (e == 0u) {
        return vec2(dom.y, dom.z + (dom.z - dom.w));
    }
    if (e == 1u) {
        return vec2(dom.y + (dom.y - dom.x), dom.z);
    }
    if (e == 2u) {
        return vec2(dom.x, dom.w + (dom.w - dom.z));
    }
    return vec2(dom.x + (dom.x - dom.y), dom.w);
}

// The coarse neighbour across edge e of node q, whose crack the wedge on
// that edge closes, as a square node of the edge's flat depth with a
// corner at the wedge's pivot: its quad triangle along the edge, in the
// parameters of q's base patch (beyond its domain at a patch border, where
// the patch's extension stands in for the next one). Exact: the
// parameters are dyadic.
void neighbour_triangle(uvec2 q, uint e, vec2 pivot, out vec2 t[3]) {
    float s = pow2_neg(edge_states(q)[e]);
    vec4 dom = node_domain(q);
    if (e == 0u) {
        t = vec2[3](vec2(pivot.x, dom.z - s), vec2(pivot.x + s, dom.z), vec2(pivot.x, dom.z));
    } else if (e == 1u) {
        t = vec2[3](vec2(dom.y, pivot.y), vec2(dom.y + s, pivot.y + s), vec2(dom.y, pivot.y + s));
    } else if (e == 2u) {
        t = vec2[3](vec2(pivot.x, dom.w), vec2(pivot.x + s, dom.w), vec2(pivot.x + s, dom.w + s));
    } else {
        t = vec2[3](vec2(dom.x - s, pivot.y), vec2(dom.x, pivot.y), vec2(dom.x, pivot.y + s));
    }
}

// The WEDGE_* code of triangle slot t of node q's mesh drawn at `pos`
// (wedge::wedge_code is the twin; shade() uses it on two-sided models). A
// wedge's own winding says little (it folds over where the fine polyline
// dips below the coarse chord), so it is lit from the front when the
// surface on either side of its edge faces the eye: the node's quad
// triangle along the edge, or across the edge a triangle as large
// (across_edge) or the coarse neighbour's (neighbour_triangle). At a
// silhouette the node can lie wholly beyond it, facing away, while its
// wedge shows in front of the neighbour's front surface. At a patch border
// the two across-edge triangles lie on the patch's extension, which only
// stands in for the next patch where both agree: trusting either alone
// darkened 62 wedge pixels around the valence-64 pole under MSAA
// (tests/shading_msaa.rs). Lighting only, but both draw paths must agree
// on it, so the tests are precise.
uint wedge_code(uvec2 q, NodeMesh mesh, vec3 pos[NODE_MESH_SLOTS], uint t, vec3 eye) {
    if (t < 2u || !mesh.wedge[t - 2u]) {
        return WEDGE_NONE;
    }
    uint e = t - 2u;
    uvec3 k = mesh.tris[e >> 1u];
    if (faces_eye(pos[k.x], pos[k.y], pos[k.z], eye)) {
        return WEDGE_LIT_FRONT;
    }
    vec2 across = across_edge(node_domain(q), e);
    bool inside = across.x >= 0.0 && across.x <= 1.0 && across.y >= 0.0 && across.y <= 1.0;
    uint id = node_patch(q);
    uvec3 w = mesh.tris[t];
    vec2 n[3];
    neighbour_triangle(q, e, mesh.uv[4u + e], n);
    // One evaluation in a loop the compiler keeps: four inlined copies of
    // the surface point (and its rational twin) made up most of the draw
    // shaders' code, which lavapipe compiled for over a minute.
    vec2 at[4] = vec2[4](across, n[0], n[1], n[2]);
    vec3 p[4];
    [[dont_unroll]] for (uint i = 0u; i < 4u; ++i) {
        p[i] = patch_surface_point(id, at[i]);
    }
    bool mirror = faces_eye(pos[w.x], pos[w.y], p[0], eye);
    bool coarse = faces_eye(p[1], p[2], p[3], eye);
    return (inside && (mirror || coarse)) || (mirror && coarse) ? WEDGE_LIT_FRONT : WEDGE_LIT_BACK;
}

#endif
