// One work item on the control points of a base patch, written once for
// both kinds of control point (like bezier_template.glsl): the GPU twin of
// oracle::process on Cartesian vec3 points and of oracle::process_rational
// on homogeneous vec4 ones, which differ only in the operations the
// includer names. It defines BEZ_T, BEZ_FN(name), BEZ_POINT(P, u, v) (the
// drawn position: eval_patch, or eval_rational's projection) and
// BEZ_BACK_FACING(S, lo, hi, eye) (the back-face bound on sub-patch S whose
// Cartesian control-point box is lo..hi); this file undefines all four.

// Returns OUT_*; for OUT_SPLIT the children are kids[0..nkids), in the
// order (0,0), (1,0), (0,1), (1,1) of those the split makes (4 for 1:4, 2
// for 1:2). P: the node's base patch, `flags` its flags word.
uint BEZ_FN(process_points)(uvec2 q, BEZ_T P[16], uint flags, out uvec2 kids[4], out uint nkids) {
    kids = uvec2[4](uvec2(0u), uvec2(0u), uvec2(0u), uvec2(0u));
    nkids = 0u;
    vec4 dom = node_domain(q);
    BEZ_T S[16];
    BEZ_FN(reconstruct)(P, dom.x, dom.y, dom.z, dom.w, S);
    vec3 lo, hi;
    BEZ_FN(patch_bbox)(S, lo, hi);
    if ((view.flags & FLAG_FRUSTUM_CULL) != 0u) {
        // The box must also hold the wedge pivots of the node's edges: its
        // wedges and its descendants' reach them (see oracle::process).
        vec2 pivots[4];
        bvec4 has = wedge_pivots(q, pivots);
        vec3 clo = lo, chi = hi;
        for (uint e = 0u; e < 4u; ++e) {
            if (has[e]) {
                grow_box(clo, chi, BEZ_POINT(P, pivots[e].x, pivots[e].y));
            }
        }
        if (outside_frustum(clo, chi, view)) {
            return OUT_CULLED;
        }
        if (node_occluded(clo, chi)) {
            return OUT_OCCLUDED;
        }
    }
    bvec2 can = can_split(q);
    if (can.x || can.y) {
        uvec4 states = edge_states(q);
        bvec4 flat_now = bvec4(true);
        bool edges_flat = true;
        // Every pending edge is tested, no early exit: children inherit them.
        for (uint e = 0u; e < 4u; ++e) {
            if (states[e] == NODE_EDGE_PENDING) {
                BEZ_T c[4];
                BEZ_FN(patch_edge)(S, e, c);
                flat_now[e] = BEZ_FN(edge_flat)(c, view);
                edges_flat = edges_flat && flat_now[e];
            }
        }
        bool inner_fails = edges_flat && !BEZ_FN(inner_flat)(S, view);
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
    if ((view.flags & FLAG_BACKFACE_CULL) != 0u && one_sided && BEZ_BACK_FACING(S, lo, hi, view.eye.xyz)
        && BEZ_FN(wedges_face_away)(P, q, view.eye.xyz, with_wedges)) {
        return OUT_BACKFACE;
    }
    return OUT_READY;
}

#undef BEZ_T
#undef BEZ_FN
#undef BEZ_POINT
#undef BEZ_BACK_FACING
