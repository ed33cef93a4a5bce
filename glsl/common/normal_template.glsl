// patch_normal() written once for both kinds of control point, like
// bezier_template.glsl (shading only): the includer defines BEZ_T and
// BEZ_FN(name), and before the include BEZ_FN(column_tangents)(pu, du, v,
// su, sv), the surface's two tangents at v from its rows' points pu and
// u-derivatives du at u; this file undefines BEZ_T and BEZ_FN.

// Unnormalised normal su x sv (shading only); where a boundary curve
// collapses to a point the normal is taken a little way into the domain.
vec3 BEZ_FN(patch_normal)(BEZ_T P[16], float u, float v) {
    vec3 n = vec3(0.0);
    for (int attempt = 0; attempt < 2; ++attempt) {
        BEZ_T du[4];
        BEZ_T pu[4];
        for (int j = 0; j < 4; ++j) {
            du[j] = BEZ_FN(curve_derivative)(u, P[4 * j], P[4 * j + 1], P[4 * j + 2], P[4 * j + 3]);
            pu[j] = BEZ_FN(curve)(u, P[4 * j], P[4 * j + 1], P[4 * j + 2], P[4 * j + 3]);
        }
        vec3 su, sv;
        BEZ_FN(column_tangents)(pu, du, v, su, sv);
        n = cross(su, sv);
        if (dot(n, n) > 1e-12 * dot(su, su) * dot(sv, sv) && dot(su, su) * dot(sv, sv) > 0.0) {
            return n;
        }
        u += (0.5 - u) * 1e-3;
        v += (0.5 - v) * 1e-3;
    }
    return n;
}

#undef BEZ_T
#undef BEZ_FN
