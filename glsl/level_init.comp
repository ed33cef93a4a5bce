// The level kernels' first step of a frame (one invocation): the schedule
// state zeroed, depth 0 holding the base patches, and the first round (the
// first chunk of base patches) with its dispatch arguments.
#version 460
#pragma use_vulkan_memory_model

#define USE_READY_WRITE
#include "common/ready.glsl"
#include "common/process.glsl"
#include "common/level.glsl"

layout(local_size_x = 1) in;

void main() {
    for (uint i = 0u; i < LEVEL_STATE_WORDS; ++i) {
        state[i] = 0u;
    }
    state[S_LEVEL_COUNT] = pc.patch_count;
    schedule(0u);
    write_ready_args(0u);
}
