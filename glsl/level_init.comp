// The level kernels' first step of a pass (one workgroup): the schedule
// state zeroed; depth 0, listed in BIND_ROOTS in instance order: the
// patches of every instance whose box is not outside the frustum (a culled
// instance's patches would each be culled by their own box, which lies
// inside the instance's: only the work is saved); and the first round (the
// first chunk of depth 0) with its dispatch arguments. The CPU twin is
// levels::canonical_ready.
//
// With occlusion culling a frame runs twice (pc.phase): the early phase
// takes the instances the last frame found visible (BIND_VISIBILITY), and
// of them draws the patches the last frame found visible (process_root in
// level.glsl); the late phase tests every instance in view against the
// depth pyramid of what the early phase drew, records the verdict for the
// next frame, and takes the visible ones, flagging those the early phase
// listed (ROOT_EARLY): their patches drawn already are only tested again. The late phase
// keeps the frame's totals (ready nodes so far: its list continues the
// early one; rounds, nodes per depth) and its draw starts where the early
// list ends (C_READY_FIRST).
#version 460
#pragma use_vulkan_memory_model

#define USE_READY_WRITE
#define LEVEL_KERNEL
#include "common/ready.glsl"
#include "common/process.glsl"
#include "common/level.glsl"

layout(local_size_x = LEVEL_GROUP_SIZE) in;

// Whether state word i is the schedule's working state (zeroed by every
// pass) rather than a total of the frame (zeroed by its first pass only).
bool schedule_word(uint i) {
    return i < S_READY || i == S_DONE || (i >= S_LEVEL_COUNT && i < S_DEPTH_NODES);
}

shared bool s_early_done;

// The late phase's start of the cluster bits' turn (level.glsl): zeroes the
// set the parity does not name, then flips the parity, so that this
// phase's rounds read the set the early phase read and write the other.
// Whole workgroup.
void clear_next_visibility(uint t) {
    uint parity = visibility[visibility_parity()];
    uint first = visibility_parity() + 1u;
    uint words = (uint(visibility.length()) - first) / 2u;
    uint next = first + (parity ^ 1u) * words;
    for (uint w = t; w < words; w += LEVEL_GROUP_SIZE) {
        visibility[next + w] = 0u;
    }
    group_sync();
    if (t == 0u) {
        visibility[visibility_parity()] = parity ^ 1u;
    }
}

void main() {
    uint t = gl_LocalInvocationID.x;
    bool early = pc.phase == PHASE_EARLY;
    bool late = pc.phase == PHASE_LATE;
    if (t == 0u) {
        s_early_done = state[S_DONE] != 0u;
    }
    group_sync();
    for (uint i = t; i < LEVEL_STATE_WORDS; i += LEVEL_GROUP_SIZE) {
        if (!late || schedule_word(i)) {
            state[i] = 0u;
        }
    }
    bool frustum = (view.flags & FLAG_FRUSTUM_CULL) != 0u;
    uint n = uint(instances.length());
    uint listed = 0u;   // instances of this pass's depth 0
    uint dense = 0u;    // their patches
    uvec2 culled = uvec2(0u);    // out of view: instances, patches
    uvec2 occluded = uvec2(0u);  // hidden (late phase): instances, patches
    uint fresh = 0u;    // listed instances the early phase did not list
    // Instances in block_lane() order, the order workgroup_scan sums in, so
    // that depth 0 lists them in instance order.
    uint lane = block_lane();
    for (uint first = 0u; first < n; first += LEVEL_GROUP_SIZE) {
        uint i = first + lane;
        uint count = i < n ? instances[i].count : 0u;
        bool out_of_view = count > 0u && frustum
            && outside_frustum(instances[i].lo.xyz, instances[i].hi.xyz, view);
        bool in_view = count > 0u && !out_of_view;
        bool keep = in_view;
        bool hidden = false;
        uint early_flag = 0u;
        if (early && i < n) {
            keep = in_view && visibility[i] != 0u;
        } else if (late && i < n) {
            bool drawn = visibility[i] != 0u;
            hidden = in_view
                && box_occluded(instances[i].lo.xyz, instances[i].hi.xyz, HIZ_INSTANCE_SPAN);
            visibility[i] = in_view && !hidden ? 1u : 0u;
            // Listed again when the early phase drew it: its patches that
            // were not visible last frame are this phase's (process_root).
            keep = in_view && !hidden;
            early_flag = drawn ? ROOT_EARLY : 0u;
            hidden = hidden && !drawn;
        }
        bool counted_out = out_of_view && !late;  // counted once a frame
        // (listed, dense, culled instances, their patches) and (hidden
        // instances, their patches, fresh): only the first two need their
        // running sums.
        uvec4 a = uvec4(keep ? 1u : 0u, keep ? count : 0u, counted_out ? 1u : 0u,
            counted_out ? count : 0u);
        uvec4 b = uvec4(hidden ? 1u : 0u, hidden ? count : 0u, keep && early_flag == 0u ? 1u : 0u, 0u);
        uvec4 ia, ib, ta, tb;
        workgroup_scan(a, b, ia, ib, ta, tb);
        if (keep) {
            roots[listed + ia.x - 1u] = uvec2(i | early_flag, dense + ia.y - count);
        }
        listed += ta.x;
        dense += ta.y;
        culled += ta.zw;
        occluded += tb.xy;
        fresh += tb.z;
    }
    if (late) {
        clear_next_visibility(t);
    }
    group_sync();
    if (t == 0u) {
        state[S_ROOT_INSTANCES] = listed;
        state[S_CULLED_INSTANCES] += culled.x;
        state[S_CULLED_INSTANCE_PATCHES] += culled.y;
        state[S_OCCLUDED_INSTANCES] += occluded.x;
        state[S_OCCLUDED_INSTANCE_PATCHES] += occluded.y;
        if (early) {
            state[S_EARLY_INSTANCES] = listed;
        } else {
            state[S_NEW_INSTANCES] = fresh;
        }
        if (late && !s_early_done) {
            state[S_EARLY_UNFINISHED] = 1u;
        }
        state[S_LEVEL_COUNT] = dense;
        // Culled and occluded patches are culled patches of the frame.
        counters[C_CULLED] += culled.y + occluded.y;
        counters[C_OCCLUDED] += occluded.y;
        uint first_ready = late ? state[S_READY] : 0u;
        counters[C_READY_FIRST] = first_ready;
        schedule(0u);
        write_ready_args(first_ready, first_ready);
    }
}
