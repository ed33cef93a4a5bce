// Set 2 and the push block of the per-depth kernel (method subdiv-indirect,
// src/methods/subdiv_indirect.rs): nodes of odd depths in one buffer, of
// even depths (from 2) in the other, so a dispatch reads one and writes the
// other; the level buffer holds every depth's node count and dispatch
// arguments. Include after ready.glsl.
#ifndef LEVEL_GLSL
#define LEVEL_GLSL

layout(std430, set = SET_PRODUCER, binding = BIND_NODES_ODD) buffer NodesOdd {
    uvec2 nodes_odd[];
};
layout(std430, set = SET_PRODUCER, binding = BIND_NODES_EVEN) buffer NodesEven {
    uvec2 nodes_even[];
};
layout(std430, set = SET_PRODUCER, binding = BIND_LEVELS) buffer Levels {
    uint levels[];
};

// src/gpu/blocks.rs LevelPush.
layout(push_constant) uniform LevelPush {
    uint level;           // the depth processed (argument pass: prepared)
    uint patch_count;     // base patches: the nodes of depth 0
    uint odd_capacity;    // entries of nodes_odd
    uint even_capacity;   // entries of nodes_even
    uint ready_capacity;  // entries in `ready`
    uint max_groups;      // most workgroups per dispatch
    uint pad0;
    uint pad1;
} pc;

// Entries of the buffer that holds depth d.
uint level_capacity(uint d) {
    return (d & 1u) == 1u ? pc.odd_capacity : pc.even_capacity;
}

// Nodes of depth d to process (never more than their buffer holds).
uint level_count(uint d) {
    return d == 0u ? pc.patch_count : min(levels[L_COUNTS + d], level_capacity(d));
}

#endif
