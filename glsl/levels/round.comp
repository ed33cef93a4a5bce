// Method subdiv-indirect, the paper's execute-indirect variant (§4.1): one
// round of the level schedule per vkCmdDispatchIndirect (levels/level.glsl).
// Workgroup w takes blocks w, w + workgroups, ... (pc.group_blocks of them
// at most): copies block b of the previous round's ready nodes into the
// ready list and processes block b of this round's chunk, exactly as the
// persistent kernel and the oracle do (common/process.glsl); the last
// workgroup to arrive scans the blocks' totals (and sums their statistics
// into the counters) and writes the next round's arguments. Nobody waits
// for anybody: the last to arrive does the work.
#version 460
#pragma use_vulkan_memory_model

#define USE_READY_WRITE
#define LEVEL_KERNEL
#include "common/ready.glsl"
#include "common/process.glsl"
#include "level.glsl"

layout(local_size_x = LEVEL_GROUP_SIZE) in;

shared bool s_last;

void main() {
    process_occludes = pc.phase == PHASE_LATE;
    process_hide_all = (pc.faults & FAULT_HIDE_LATE) != 0u;
    uint t = gl_LocalInvocationIndex;
    load_round(t);
    uint work = max(round_blocks(), s_copy_blocks);
    for (uint b = gl_WorkGroupID.x; b < work; b += gl_NumWorkGroups.x) {
        if (b < s_copy_blocks) {
            copy_block(b, t);
        }
        if (b < round_blocks()) {
            process_block(b, t);
        }
    }
    group_sync();
    uint before = 0u;
    if (t == 0u) {
        s_last = arrive(gl_NumWorkGroups.x, before);
    }
    group_sync();
    if (s_last) {
        finish_round(t);
        if (t == 0u) {
            release_round(before, gl_NumWorkGroups.x);
            // Every workgroup's arrival, the release, this count and the
            // blocks' visibility bits: the round's only read-modify-writes
            // on global memory.
            atomicAdd(counters[C_GLOBAL_ATOMICS], gl_NumWorkGroups.x + 2u + s_round_atomics);
        }
    }
}
