// The one descriptor set (set 0) and push-constant block every pass uses.
// A shader declares the buffers it touches by defining USE_<NAME> before
// including this file; unused bindings stay in the layout but are not
// declared (USE_READY_WRITE / USE_VERTICES_WRITE make the writable
// variants). The Rust side is src/gpu/mod.rs (SceneLayout, PushConstants).
#ifndef SCENE_GLSL
#define SCENE_GLSL

#include "patch.glsl"

layout(std140, set = 0, binding = BIND_VIEW) uniform ViewBlock {
    ViewParams view;
};

// Base patches: 16 control points x 3 floats each, tightly packed.
layout(std430, set = 0, binding = BIND_PATCHES) readonly buffer Patches {
    float patch_data[];
};

// Per patch: PATCH_TWO_SIDED | model index << PATCH_MODEL_SHIFT.
layout(std430, set = 0, binding = BIND_PATCH_FLAGS) readonly buffer PatchFlags {
    uint patch_flags[];
};

#if defined(USE_READY_WRITE)
layout(std430, set = 0, binding = BIND_READY) writeonly buffer Ready {
    uvec2 ready[];
};
#elif defined(USE_READY_RW)
layout(std430, set = 0, binding = BIND_READY) buffer Ready {
    uvec2 ready[];
};
#else
layout(std430, set = 0, binding = BIND_READY) readonly buffer Ready {
    uvec2 ready[];
};
#endif

layout(std430, set = 0, binding = BIND_COUNTERS) coherent buffer Counters {
    uint counters[];
};

#ifdef USE_QUEUE
layout(std430, set = 0, binding = BIND_QUEUE_ITEMS) coherent buffer QueueItems {
    uvec2 queue_items[];
};
layout(std430, set = 0, binding = BIND_QUEUE_SEQS) coherent buffer QueueSeqs {
    uint queue_seqs[];
};
#endif

// Fallback vertices, VERTEX_WORDS words each (see constants.glsl): written
// by the expansion pass, read by the vertex shader (which may not write
// storage buffers without vertexPipelineStoresAndAtomics).
#if defined(USE_VERTICES_WRITE)
layout(std430, set = 0, binding = BIND_VERTICES) writeonly buffer Vertices {
    uint vertex_words[];
};
#elif defined(USE_VERTICES)
layout(std430, set = 0, binding = BIND_VERTICES) readonly buffer Vertices {
    uint vertex_words[];
};
#endif

#ifdef USE_CAPTURE
// Debug capture of world positions (validation): one vec4 per vertex slot.
layout(std430, set = 0, binding = BIND_CAPTURE) writeonly buffer Capture {
    vec4 capture[];
};
#endif

layout(push_constant) uniform Push {
    mat4 view_proj;        // draw: world -> Vulkan clip space
    vec4 light_dir;        // draw: direction towards the light (xyz)
    uint shade;            // draw: SHADE_*
    uint ready_capacity;   // entries in `ready`
    uint queue_capacity;   // entries in the work queue
    uint patch_count;      // base patches
    uint idle_poll_cap;    // subdivide: polls without progress before giving up
    uint capture_enabled;  // draw: write world positions to `capture`
    uint sort_mode;        // sort.comp: which pass
    uint sort_k;           // sort.comp: bitonic stage
    uint sort_j;           // sort.comp: compare distance
    uint pad0;
} pc;

// The base patch's 16 control points.
void load_patch(uint id, out vec3 P[16]) {
    uint o = id * 48u;
    for (int i = 0; i < 16; ++i) {
        P[i] = vec3(patch_data[o + 3u * uint(i)], patch_data[o + 3u * uint(i) + 1u],
            patch_data[o + 3u * uint(i) + 2u]);
    }
}

#endif
