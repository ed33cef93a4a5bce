// Descriptor set 1 of the ground truth's dense grids (src/methods/
// ground_truth.rs): the visible patches, and counters whose words
// G_DRAW_ARGS.. are the VkDrawIndexedIndirectCommand of the draw (the
// culling pass counts visible patches straight into its instance count).
#ifndef GRID_GLSL
#define GRID_GLSL

#include "common/scene.glsl"
#include "constants.glsl"

layout(std430, set = SET_PASS, binding = BIND_GRID_VISIBLE) buffer GridVisible {
    uint visible[];
};

layout(std430, set = SET_PASS, binding = BIND_GRID_COUNTERS) buffer GridCounters {
    uint grid_counters[];
};

#endif
