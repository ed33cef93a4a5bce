// Method subdiv-indirect, between two depths: one invocation writes the
// dispatch arguments of depth pc.level from the number of nodes the previous
// dispatch appended, and the ready list's arguments for everything after
// the last depth (the last such pass wins). A depth with no nodes gets zero
// workgroups, so depths past the frame's deepest cost almost nothing.
#version 460

#include "common/ready.glsl"
#include "common/level.glsl"

layout(local_size_x = 1) in;

void main() {
    uint n = level_count(pc.level);
    uint groups = min((n + LEVEL_GROUP_SIZE - 1u) / LEVEL_GROUP_SIZE, pc.max_groups);
    uint a = L_ARGS + 4u * pc.level;
    levels[a] = groups;
    levels[a + 1u] = 1u;
    levels[a + 2u] = 1u;
    write_ready_args(ready_count(pc.ready_capacity));
}
