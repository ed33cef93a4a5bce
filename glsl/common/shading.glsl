// Shading normals from the tangent patches in set 0 (BIND_SHADING): the
// normal every draw path lights with, continuous across patch edges next to
// extraordinary vertices where the geometry patches' own derivatives jump.
// src/scene/shading.rs holds the layout and the same evaluation in Rust
// (ShadingPatch::tangents and ::normal), in the same order of operations.
// Nothing here feeds a position or a decision, so nothing is `precise`.
// Include after scene.glsl.
#ifndef SHADING_GLSL
#define SHADING_GLSL

// Set 0's shading patches: SHADING_FLOATS per model patch, in model space.
layout(std430, set = SET_SCENE, binding = BIND_SHADING) readonly buffer Shading {
    float shading[];
};

vec3 shading_vector(uint o) {
    return vec3(shading[o], shading[o + 1u], shading[o + 2u]);
}

// The two tangent fields of model patch `model` at (u, v), in model space:
// Du = sum_j B3_j(v) sum_i B2_i(u) du[3j + i] (du: vectors 0..11),
// Dv = sum_j B2_j(v) sum_i B3_i(u) dv[4j + i] (dv: vectors 12..23).
void model_tangents(uint model, float u, float v, out vec3 tu, out vec3 tv) {
    uint o = model * SHADING_FLOATS;
    float su = 1.0 - u;
    float sv = 1.0 - v;
    float a2[3] = float[3](su * su, 2.0 * u * su, u * u);
    float b3[4] = float[4](sv * sv * sv, 3.0 * v * sv * sv, 3.0 * v * v * sv, v * v * v);
    tu = vec3(0.0);
    for (uint j = 0u; j < 4u; ++j) {
        uint r = o + 9u * j;
        vec3 row = shading_vector(r) * a2[0] + shading_vector(r + 3u) * a2[1]
            + shading_vector(r + 6u) * a2[2];
        tu += row * b3[j];
    }
    float a3[4] = float[4](su * su * su, 3.0 * u * su * su, 3.0 * u * u * su, u * u * u);
    float b2[3] = float[3](sv * sv, 2.0 * v * sv, v * v);
    tv = vec3(0.0);
    for (uint j = 0u; j < 3u; ++j) {
        uint r = o + 36u + 12u * j;
        vec3 row = (shading_vector(r) * a3[0] + shading_vector(r + 3u) * a3[1])
            + (shading_vector(r + 6u) * a3[2] + shading_vector(r + 9u) * a3[3]);
        tv += row * b2[j];
    }
}

// A model-space vector placed by the (non-identity) transform with rows r0..r2.
vec3 place_vector(vec4 r0, vec4 r1, vec4 r2, vec3 d) {
    return vec3(dot(r0.xyz, d), dot(r1.xyz, d), dot(r2.xyz, d));
}

// Unnormalised shading normal Du x Dv of base patch `patch_id` at its
// parameters (u, v); where it vanishes (a collapsed patch edge, a smoothed
// cage corner) the normal a little way towards the middle of the domain.
// Zero only where both are degenerate. What a tessellation method calls at
// its evaluated (u, v), like the draw paths' fragment shading does.
// The tangents are the model patch's, read with u and v swapped where the
// instance mirrors, placed in the world by the instance
// (ShadingPatch::transformed on the host).
vec3 shading_patch_normal(uint patch_id, float u, float v) {
    Instance t = instances[instance_of(patch_id)];
    uint m = t.source + (patch_id - t.first);
    bool mirrored = (t.flags & INSTANCE_MIRRORED) != 0u;
    bool placed = (t.flags & INSTANCE_IDENTITY) == 0u;
    vec3 n = vec3(0.0);
    for (int attempt = 0; attempt < 2; ++attempt) {
        vec3 a;
        vec3 b;
        model_tangents(m, mirrored ? v : u, mirrored ? u : v, a, b);
        vec3 tu = mirrored ? b : a;
        vec3 tv = mirrored ? a : b;
        if (placed) {
            tu = place_vector(t.rows[0], t.rows[1], t.rows[2], tu);
            tv = place_vector(t.rows[0], t.rows[1], t.rows[2], tv);
        }
        n = cross(tu, tv);
        float scale = dot(tu, tu) * dot(tv, tv);
        if (dot(n, n) > 1e-12 * scale && scale > 0.0) {
            return n;
        }
        u += (0.5 - u) * 1e-3;
        v += (0.5 - v) * 1e-3;
    }
    return n;
}

#endif
