// curve(), eval_patch() and curve_derivative() written once for both kinds of control point:
// Cartesian vec3 (patch.glsl) and homogeneous vec4 (rational.glsl), so the
// two cannot drift apart in their operation order. A template, not a
// header: no include guard; the includer defines BEZ_T (the point type) and
// BEZ_FN(name) (the function's name for that type), and this file
// undefines both at its end.

// Cubic curve, the paper's operation order (§3.4): reversal-symmetric for
// exact complements u0 and 1 - u0.
precise BEZ_T BEZ_FN(curve)(float u0, BEZ_T p0, BEZ_T p1, BEZ_T p2, BEZ_T p3) {
    precise float u1 = 1.0 - u0;
    precise float b0 = u1 * u1 * u1;
    precise float b1 = 3.0 * u1 * u0 * u1;
    precise float b2 = 3.0 * u0 * u1 * u0;
    precise float b3 = u0 * u0 * u0;
    precise BEZ_T r = (p0 * b0 + p1 * b1) + (p2 * b2 + p3 * b3);
    return r;
}

// Surface point, curve of curves: rows at u, then the column curve at v.
precise BEZ_T BEZ_FN(eval_patch)(BEZ_T P[16], float u, float v) {
    precise BEZ_T c0 = BEZ_FN(curve)(u, P[0], P[1], P[2], P[3]);
    precise BEZ_T c1 = BEZ_FN(curve)(u, P[4], P[5], P[6], P[7]);
    precise BEZ_T c2 = BEZ_FN(curve)(u, P[8], P[9], P[10], P[11]);
    precise BEZ_T c3 = BEZ_FN(curve)(u, P[12], P[13], P[14], P[15]);
    precise BEZ_T r = BEZ_FN(curve)(v, c0, c1, c2, c3);
    return r;
}

// Curve derivative (shading only).
BEZ_T BEZ_FN(curve_derivative)(float u0, BEZ_T p0, BEZ_T p1, BEZ_T p2, BEZ_T p3) {
    float u1 = 1.0 - u0;
    return ((p1 - p0) * (u1 * u1) + (p2 - p1) * (2.0 * u1 * u0) + (p3 - p2) * (u0 * u0)) * 3.0;
}

#undef BEZ_T
#undef BEZ_FN
