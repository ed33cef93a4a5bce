// Descriptor set 0, shared by every pass of every method: the view (one ViewParams per
// frame slot, chosen by a dynamic offset), the base patches and their flags; the shading
// patches (BIND_SHADING) are in shading.glsl. The Rust side is src/gpu/scene.rs.
#ifndef SCENE_GLSL
#define SCENE_GLSL

#include "patch.glsl"

layout(std140, set = SET_SCENE, binding = BIND_VIEW) uniform ViewBlock {
    ViewParams view;
};

// Base patches: 16 control points x 3 floats each, tightly packed.
layout(std430, set = SET_SCENE, binding = BIND_PATCHES) readonly buffer Patches {
    float patch_data[];
};

// Per patch: PATCH_TWO_SIDED | model index << PATCH_MODEL_SHIFT.
layout(std430, set = SET_SCENE, binding = BIND_PATCH_FLAGS) readonly buffer PatchFlags {
    uint patch_flags[];
};

// The base patch's 16 control points.
void load_patch(uint id, out vec3 P[16]) {
    uint o = id * 48u;
    for (int i = 0; i < 16; ++i) {
        P[i] = vec3(patch_data[o + 3u * uint(i)], patch_data[o + 3u * uint(i) + 1u],
            patch_data[o + 3u * uint(i) + 2u]);
    }
}

#endif
