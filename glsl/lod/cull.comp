// Levels of detail (src/lod), the cull before their draw: one invocation
// per instance. An instance the host chose to draw from a level this frame
// (BIND_LOD_CHOICE: its level's row + 1, 0 otherwise, out of view
// included) gets an indexed indirect draw of that level, its instance
// count 0 where its box lies behind the depth pyramid of everything the
// method drew (occlusion culling on): whatever it holds would fail the
// depth test there (glsl/common/hiz.glsl), so culling it changes no pixel.
// Every other instance's draw is empty. The counters (zeroed by the host)
// keep what was drawn and hidden, for the frame's figures.
#version 460

#include "common/scene.glsl"
#include "common/ops.glsl"
#include "constants.glsl"

#define HIZ_SET SET_PASS
#define HIZ_BINDING BIND_LOD_HIZ
#include "common/hiz.glsl"

layout(local_size_x = LOD_CULL_GROUP) in;

layout(std430, set = SET_PASS, binding = BIND_LOD_CHOICE) readonly buffer LodChoice {
    uint lod_choice[];
};

layout(std430, set = SET_PASS, binding = BIND_LOD_RANGES) readonly buffer LodRanges {
    uint lod_ranges[];
};

// VkDrawIndexedIndirectCommand per instance: index count, instance count,
// first index, vertex offset, first instance.
layout(std430, set = SET_PASS, binding = BIND_LOD_DRAWS) writeonly buffer LodDraws {
    uint lod_draws[];
};

layout(std430, set = SET_PASS, binding = BIND_LOD_COUNTERS) buffer LodCounters {
    uint lod_counters[];
};

// src/lod/gpu.rs LodCullPush.
layout(push_constant) uniform LodCullPush {
    uint instance_count;
    uint occlusion;  // 1: test against the pyramid
    uint pad0;
    uint pad1;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.instance_count) {
        return;
    }
    uint choice = lod_choice[i];
    uvec4 range = uvec4(0u);
    bool drawn = false;
    if (choice != LOD_NONE) {
        uint r = (choice - 1u) * LOD_RANGE_WORDS;
        range = uvec4(lod_ranges[r], lod_ranges[r + 1u], lod_ranges[r + 2u], lod_ranges[r + 3u]);
        bool hidden = pc.occlusion != 0u
            && box_occluded(instances[i].lo.xyz, instances[i].hi.xyz, HIZ_INSTANCE_SPAN);
        drawn = !hidden;
        if (hidden) {
            atomicAdd(lod_counters[LOD_OCCLUDED], 1u);
        } else {
            uint triangles = range.y / 3u;
            uint level = LOD_BY_LEVEL + 2u * min(range.w, LOD_MAX_LEVELS - 1u);
            atomicAdd(lod_counters[LOD_DRAWN], 1u);
            atomicAdd(lod_counters[LOD_TRIANGLES], triangles);
            atomicAdd(lod_counters[level], 1u);
            atomicAdd(lod_counters[level + 1u], triangles);
        }
    }
    uint d = 5u * i;
    lod_draws[d] = range.y;
    lod_draws[d + 1u] = drawn ? 1u : 0u;
    lod_draws[d + 2u] = range.x;
    lod_draws[d + 3u] = range.z;
    lod_draws[d + 4u] = i;
}
