// wedges_face_away() written once for both kinds of control point, like
// bezier_template.glsl: the includer defines BEZ_T, BEZ_FN(name) and
// BEZ_POINT(P, u, v), the drawn position of the surface of control points P
// at (u, v) (eval_patch, or eval_rational's projection); this file
// undefines all three at its end.

// Twin of cull::wedges_face_away: every wedge triangle of the ready node
// faces away from the eye (positions as drawn, from the base patch P).
bool BEZ_FN(wedges_face_away)(BEZ_T P[16], uvec2 q, vec3 eye, bool with_wedges) {
    NodeMesh mesh = node_mesh(q, with_wedges);
    bool away = true;
    for (uint e = 0u; e < 4u; ++e) {
        if (!mesh.wedge[e]) {
            continue;
        }
        uvec3 k = mesh.tris[2u + e];
        precise vec3 a = BEZ_POINT(P, mesh.uv[k.x].x, mesh.uv[k.x].y);
        precise vec3 b = BEZ_POINT(P, mesh.uv[k.y].x, mesh.uv[k.y].y);
        precise vec3 c = BEZ_POINT(P, mesh.uv[k.z].x, mesh.uv[k.z].y);
        precise vec3 n = cross3(b - a, c - a);
        away = away && dot3(n, a - eye) > 0.0;
    }
    return away;
}

#undef BEZ_T
#undef BEZ_FN
#undef BEZ_POINT
