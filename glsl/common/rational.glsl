// Rational bicubic Bézier patches (Schwarz and Stamminger 2009, §3): the
// weights in set 0, homogeneous evaluation and the rational normal. The CPU
// twin is src/patch/rational.rs, operation for operation. A patch's weights
// are only read when its flags say PATCH_RATIONAL; a polynomial scene binds
// sixteen ones. Include after scene.glsl.
#ifndef RATIONAL_GLSL
#define RATIONAL_GLSL

#include "scene.glsl"

// 16 weights per model patch, stored like its control points.
layout(std430, set = SET_SCENE, binding = BIND_WEIGHTS) readonly buffer PatchWeights {
    float patch_weights[];
};

bool patch_is_rational(uint id) {
    return flags_rational(patch_flags_of(id));
}

// Weight k of base patch `id` of instance `t` (as its control point k:
// mirrored instances swap u and v).
float patch_weight_in(Instance t, uint id, uint k) {
    return patch_weights[(t.source + (id - t.first)) * 16u + model_point_index(k, t.flags)];
}

// Weight k of base patch `id`.
float patch_weight(uint id, uint k) {
    return patch_weight_in(instances[instance_of(id)], id, k);
}

// The homogeneous control points (w p, w) of the points P of patch `id` of
// instance `t`; weights 1 where the patch is polynomial (then w p = p
// exactly). The loaders below differ only in the space P is in.
void weigh_points_in(Instance t, uint id, vec3 P[16], out vec4 H[16]) {
    bool rational = flags_rational(patch_flags_in(t, id));
    for (uint i = 0u; i < 16u; ++i) {
        float w = rational ? patch_weight_in(t, id, i) : 1.0;
        precise vec4 h = vec4(P[i].x * w, P[i].y * w, P[i].z * w, w);
        H[i] = h;
    }
}

// The homogeneous control points (w p, w) of patch `id` of instance `t`.
void load_homogeneous_in(Instance t, uint id, out vec4 H[16]) {
    vec3 P[16];
    load_patch_in(t, id, P);
    weigh_points_in(t, id, P, H);
}

// The homogeneous control points (w p, w) of patch `id` of instance `t`
// in model space (see load_model_patch_in).
void load_model_homogeneous_in(Instance t, uint id, out vec4 H[16]) {
    vec3 P[16];
    load_model_patch_in(t, id, P);
    weigh_points_in(t, id, P, H);
}

// The homogeneous control points of patch `id`.
void load_homogeneous(uint id, out vec4 H[16]) {
    load_homogeneous_in(instances[instance_of(id)], id, H);
}

// curve4(), eval_patch4(), curve_derivative4(): curve(), eval_patch() and
// curve_derivative() of patch.glsl on homogeneous points
// (bezier_template.glsl).
#define BEZ_T vec4
#define BEZ_FN(name) name##4
#include "bezier_template.glsl"

// The Cartesian point xyz / w.
precise vec3 project(vec4 h) {
    precise vec3 r = vec3(h.x / h.w, h.y / h.w, h.z / h.w);
    return r;
}

// The tangents t_u, t_v at v from the rows' homogeneous points pu and
// u-derivatives du at u, times b.w: t_u = (b_u.xyz - b_u.w p) / b.w (the
// paper's §3; the positive 1 / b.w is left out, it does not turn the
// normal). Shading only.
void column_tangents4(vec4 pu[4], vec4 du[4], float v, out vec3 su, out vec3 sv) {
    vec4 b = curve4(v, pu[0], pu[1], pu[2], pu[3]);
    vec4 bu = curve4(v, du[0], du[1], du[2], du[3]);
    vec4 bv = curve_derivative4(v, pu[0], pu[1], pu[2], pu[3]);
    vec3 p = b.xyz / b.w;
    su = bu.xyz - p * bu.w;
    sv = bv.xyz - p * bv.w;
}

// patch_normal4(): the rational normal t_u x t_v, taken a little way into
// the domain where a boundary collapses, as patch_normal does
// (normal_template.glsl).
#define BEZ_T vec4
#define BEZ_FN(name) name##4
#include "normal_template.glsl"

// The rational normal of base patch `id` at (u, v).
vec3 rational_patch_normal(uint id, float u, float v) {
    vec4 H[16];
    load_homogeneous(id, H);
    return patch_normal4(H, u, v);
}

#endif
