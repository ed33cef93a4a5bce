// Subdivision of rational patches: the homogeneous sub-patch by blossoms and
// the criterion on its projected points. The twin of
// src/patch/homogeneous.rs, operation for operation (see there for why the
// shared-edge argument of §4.4 carries over to (w p, w)). Include after
// scene.glsl; the weights come from rational.glsl.
#ifndef RATIONAL_SUBDIV_GLSL
#define RATIONAL_SUBDIV_GLSL

#include "rational.glsl"

// bilerp4(), reconstruct4(): bilerp() and reconstruct() of patch.glsl on
// homogeneous control points (blossom_template.glsl).
#define BEZ_T vec4
#define BEZ_FN(name) name##4
#include "blossom_template.glsl"

// The projected surface point (HomPatch::eval).
precise vec3 eval_rational(vec4 H[16], float u, float v) {
    precise vec3 r = project(eval_patch4(H, u, v));
    return r;
}

// Boundary curve e, counter-clockwise (patch_edge on homogeneous points).
void patch_edge4(vec4 S[16], uint e, out vec4 c[4]) {
    if (e == EDGE_BOTTOM) {
        c = vec4[4](S[0], S[1], S[2], S[3]);
    } else if (e == EDGE_RIGHT) {
        c = vec4[4](S[3], S[7], S[11], S[15]);
    } else if (e == EDGE_TOP) {
        c = vec4[4](S[15], S[14], S[13], S[12]);
    } else {
        c = vec4[4](S[12], S[8], S[4], S[0]);
    }
}

// The box of the Cartesian control points (holds the surface: weights > 0).
void patch_bbox4(vec4 S[16], out vec3 lo, out vec3 hi) {
    lo = project(S[0]);
    hi = lo;
    for (int i = 1; i < 16; ++i) {
        precise vec3 p = project(S[i]);
        lo = min3(lo, p);
        hi = max3(hi, p);
    }
}

// Edge tier on a homogeneous boundary curve: the polynomial line test on
// the projected end points and the projected samples at 1/3 from each end.
bool edge_flat4(vec4 h[4], ViewParams vp) {
    precise vec3 a = project(h[0]);
    precise vec3 b = project(h[3]);
    precise vec3 mid = (a + b) * 0.5;
    precise float t2 = tolerance2(mid, vp);
    precise vec3 fwd = project(curve4(THIRD, h[0], h[1], h[2], h[3]));
    precise vec3 bwd = project(curve4(THIRD, h[3], h[2], h[1], h[0]));
    bool f = line_sample_flat(fwd, a, b, THIRD, t2, vp);
    bool r = line_sample_flat(bwd, b, a, THIRD, t2, vp);
    return f && r;
}

// Inner tier on the projected corners and samples.
bool inner_flat4(vec4 S[16], ViewParams vp) {
    vec3 s[4] = vec3[4](eval_rational(S, THIRD, THIRD), eval_rational(S, TWO_THIRDS, TWO_THIRDS),
                        eval_rational(S, TWO_THIRDS, THIRD), eval_rational(S, THIRD, TWO_THIRDS));
    return inner_flat_of(project(S[0]), project(S[3]), project(S[15]), project(S[12]), s, vp);
}

// Conservative back-face test (homogeneous::back_facing): the polynomial
// bound on the patch of weighted points relative to the eye,
// w (p - eye) = h.xyz - h.w * eye, with the eye at the origin.
bool back_facing4(vec4 S[16], vec3 eye) {
    vec3 Q[16];
    for (int i = 0; i < 16; ++i) {
        precise vec3 q = S[i].xyz - eye * S[i].w;
        Q[i] = q;
    }
    vec3 lo, hi;
    patch_bbox(Q, lo, hi);
    return back_facing(Q, lo, hi, vec3(0.0));
}

// wedges_face_away4(): wedges_face_away() of patch.glsl with the rational
// positions (wedges_template.glsl).
#define BEZ_T vec4
#define BEZ_FN(name) name##4
#define BEZ_POINT(P, u, v) eval_rational(P, u, v)
#include "wedges_template.glsl"

#endif
