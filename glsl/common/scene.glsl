// Descriptor set 0, shared by every pass of every method: the view (one ViewParams per
// frame slot, chosen by a dynamic offset), the model patches, their flags and the
// instances that place them; the shading patches (BIND_SHADING) are in shading.glsl,
// the weights in rational.glsl. The Rust side is src/gpu/scene.rs and
// src/scene/instances.rs.
//
// A base patch's id is global: instance by instance, each instance's patches
// consecutive. Every read of a base patch goes through the functions here, which
// find its instance and apply its transform in one fixed operation order, the twin
// of Instance::point in src/scene/instances.rs.
#ifndef SCENE_GLSL
#define SCENE_GLSL

#include "patch.glsl"

layout(std140, set = SET_SCENE, binding = BIND_VIEW) uniform ViewBlock {
    ViewParams view;
};

// Model patches: 16 control points x 3 floats each, tightly packed.
layout(std430, set = SET_SCENE, binding = BIND_PATCHES) readonly buffer Patches {
    float patch_data[];
};

// Per model patch: PATCH_RATIONAL (for a scene without instances, the whole
// flags word).
layout(std430, set = SET_SCENE, binding = BIND_PATCH_FLAGS) readonly buffer PatchFlags {
    uint patch_flags[];
};

// An instance (INSTANCE_WORDS words): world coordinate i of a model point p is
// ((rows[i].x * p.x + rows[i].y * p.y) + rows[i].z * p.z) + rows[i].w.
struct Instance {
    vec4 rows[3];
    uint first;  // global id of its first patch
    uint source; // its first model patch
    uint count;
    uint flags;  // PATCH_TWO_SIDED | model << PATCH_MODEL_SHIFT | INSTANCE_*
    vec4 lo;     // box of its world control points (xyz), a little enlarged
    vec4 hi;
};

layout(std430, set = SET_SCENE, binding = BIND_INSTANCES) readonly buffer Instances {
    Instance instances[];
};

// The instance holding global patch `id`: the last one whose first id is at
// most `id` (twin of InstanceTable::locate).
uint instance_of(uint id) {
    uint lo = 0u;
    uint hi = uint(instances.length());
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (instances[mid].first <= id) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// The model point p placed by the (non-identity) transform with rows r0..r2.
vec3 place_point(vec4 r0, vec4 r1, vec4 r2, vec3 p) {
    precise float x = ((r0.x * p.x + r0.y * p.y) + r0.z * p.z) + r0.w;
    precise float y = ((r1.x * p.x + r1.y * p.y) + r1.z * p.z) + r1.w;
    precise float z = ((r2.x * p.x + r2.y * p.y) + r2.z * p.z) + r2.w;
    return vec3(x, y, z);
}

// Control point k of the model patch `m`, as stored.
vec3 model_point(uint m, uint k) {
    uint o = m * 48u + 3u * k;
    return vec3(patch_data[o], patch_data[o + 1u], patch_data[o + 2u]);
}

// The index in its model patch of base patch point k (u index k % 4, v
// index k / 4) of an instance with flags `flags`: mirrored instances swap
// u and v.
uint model_point_index(uint k, uint flags) {
    return (flags & INSTANCE_MIRRORED) != 0u ? 4u * (k % 4u) + k / 4u : k;
}

// Control point k of base patch `id` in the world.
vec3 patch_point(uint id, uint k) {
    Instance t = instances[instance_of(id)];
    vec3 p = model_point(t.source + (id - t.first), model_point_index(k, t.flags));
    if ((t.flags & INSTANCE_IDENTITY) != 0u) {
        return p;
    }
    return place_point(t.rows[0], t.rows[1], t.rows[2], p);
}

// The point p placed by instance t (unchanged by an identity).
vec3 place_in(Instance t, vec3 p) {
    if ((t.flags & INSTANCE_IDENTITY) != 0u) {
        return p;
    }
    return place_point(t.rows[0], t.rows[1], t.rows[2], p);
}

// The 16 control points of base patch `id` of instance `t` in model space,
// in the base patch's order (u and v swapped where the instance mirrors):
// for a caller that evaluates first and places the point after (the
// ground truth's vertices; neighbours in one instance still share their
// boundary's bits, model space and placement alike).
void load_model_patch_in(Instance t, uint id, out vec3 P[16]) {
    uint m = t.source + (id - t.first);
    for (uint k = 0u; k < 16u; ++k) {
        P[k] = model_point(m, model_point_index(k, t.flags));
    }
}

// The 16 control points of base patch `id` of instance `t` in the world.
void load_patch_in(Instance t, uint id, out vec3 P[16]) {
    uint m = t.source + (id - t.first);
    for (uint k = 0u; k < 16u; ++k) {
        P[k] = model_point(m, k);
    }
    if ((t.flags & INSTANCE_IDENTITY) == 0u) {
        for (uint k = 0u; k < 16u; ++k) {
            P[k] = place_point(t.rows[0], t.rows[1], t.rows[2], P[k]);
        }
    }
    if ((t.flags & INSTANCE_MIRRORED) != 0u) {
        for (uint j = 0u; j < 4u; ++j) {
            for (uint i = j + 1u; i < 4u; ++i) {
                vec3 a = P[4u * j + i];
                P[4u * j + i] = P[4u * i + j];
                P[4u * i + j] = a;
            }
        }
    }
}

// The base patch's 16 control points in the world.
void load_patch(uint id, out vec3 P[16]) {
    load_patch_in(instances[instance_of(id)], id, P);
}

// Whether the scene holds rational patches: false lets the compiler drop
// every rational path of a pipeline made for a polynomial scene (see
// SPEC_SCENE_RATIONAL; src/gpu/mod.rs Shaders sets it).
layout(constant_id = SPEC_SCENE_RATIONAL) const bool SCENE_RATIONAL = true;

// Whether a flags word marks its patch rational (always false in a
// pipeline for a polynomial scene).
bool flags_rational(uint flags) {
    return SCENE_RATIONAL && (flags & PATCH_RATIONAL) != 0u;
}

// The flags word of base patch `id` of instance `t`: the instance's
// (two-sided, model index) and its model patch's (rational).
uint patch_flags_in(Instance t, uint id) {
    uint own = t.flags & ~(INSTANCE_MIRRORED | INSTANCE_IDENTITY);
    return own | patch_flags[t.source + (id - t.first)];
}

// The flags word of base patch `id`.
uint patch_flags_of(uint id) {
    return patch_flags_in(instances[instance_of(id)], id);
}

#endif
