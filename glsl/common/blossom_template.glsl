// bilerp() and reconstruct() written once for both kinds of control point:
// Cartesian vec3 (patch.glsl) and homogeneous vec4 (rational_subdiv.glsl,
// component by component), so the two cannot drift apart in their
// operation order. A template like bezier_template.glsl: the includer
// defines BEZ_T and BEZ_FN(name), and this file undefines both at its end.

// Bilinear interpolation, pairwise: (P00 + P11) + (P10 + P01).
precise BEZ_T BEZ_FN(bilerp)(float u0, float v0, BEZ_T p00, BEZ_T p10, BEZ_T p01, BEZ_T p11) {
    precise float u1 = 1.0 - u0;
    precise float v1 = 1.0 - v0;
    precise BEZ_T w00 = p00 * (u1 * v1);
    precise BEZ_T w10 = p10 * (u0 * v1);
    precise BEZ_T w01 = p01 * (u1 * v0);
    precise BEZ_T w11 = p11 * (u0 * v0);
    precise BEZ_T r = (w00 + w11) + (w10 + w01);
    return r;
}

// Sub-patch of P over [a,b]x[c,d] from tensor-product blossoms (§3.3.2):
// output point (u 2j+i, v 2l+k) = s(U[j], U[j], U[i] | V[l], V[l], V[k]).
void BEZ_FN(reconstruct)(BEZ_T P[16], float a, float b, float c, float d, out BEZ_T S[16]) {
    float U[2] = float[2](a, b);
    float V[2] = float[2](c, d);
    precise BEZ_T D[36];  // [l][k][3x3]
    for (int l = 0; l < 2; ++l)
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i)
                    D[(2 * l + k) * 9 + 3 * j + i] = BEZ_FN(bilerp)(U[k], V[l],
                        P[4 * j + i], P[4 * j + i + 1], P[4 * (j + 1) + i], P[4 * (j + 1) + i + 1]);
    precise BEZ_T E[16];  // [l][k][2x2]
    for (int l = 0; l < 2; ++l)
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) {
                    int o = (2 * l + k) * 9;
                    E[(2 * l + k) * 4 + 2 * j + i] = BEZ_FN(bilerp)(U[k], V[l],
                        D[o + 3 * j + i], D[o + 3 * j + i + 1], D[o + 3 * (j + 1) + i], D[o + 3 * (j + 1) + i + 1]);
                }
    for (int l = 0; l < 2; ++l)
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) {
                    int o = (2 * l + j) * 4;
                    S[4 * (2 * l + k) + 2 * j + i] = BEZ_FN(bilerp)(U[i], V[k], E[o], E[o + 1], E[o + 2], E[o + 3]);
                }
}

#undef BEZ_T
#undef BEZ_FN
