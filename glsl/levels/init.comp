// The level kernels' first step of a pass (one workgroup): the schedule
// state zeroed; depth 0, listed in BIND_ROOTS in instance order: the
// patches of every instance whose box is not outside the frustum (a culled
// instance's patches would each be culled by their own box, which lies
// inside the instance's: only the work is saved); and the first round (the
// first chunk of depth 0) with its dispatch arguments. The CPU twin is
// levels::canonical_ready.
//
// With occlusion culling a frame runs twice (pc.phase), and depth 0 is
// made by the cluster filter (levels/clusters.comp), which this step
// prepares: the instances are listed with the dense index of their first
// cluster, and the arguments are the filter's. The early phase lists the
// instances the last frame found visible (BIND_VISIBILITY) and zeroes the
// cluster set this frame writes (level.glsl, the visibility buffer). The
// late phase tests every instance in view against the depth pyramid of
// what the early phase drew, records the verdict for the next frame, and
// lists the visible ones, flagging those the early phase listed
// (ROOT_EARLY): of them the filter takes only the clusters the early phase
// did not draw. The late phase keeps the frame's totals (ready nodes so
// far: its list continues the early one; rounds, nodes per depth) and its
// draw starts where the early list ends (C_READY_FIRST); it flips the
// visibility parity, so the next frame reads what this one wrote.
#version 460
#pragma use_vulkan_memory_model

#define USE_READY_WRITE
#define LEVEL_KERNEL
#include "common/ready.glsl"
#include "common/process.glsl"
#include "level.glsl"

layout(local_size_x = LEVEL_GROUP_SIZE) in;

shared bool s_early_done;
shared uint s_first_ready;

// The early phase's start of the cluster bits' turn: zeroes the set this
// frame writes (the one the parity does not name). Whole workgroup.
void clear_written_visibility(uint t) {
    uint parity = visibility[visibility_parity()];
    uint first = visibility_parity() + 1u;
    uint words = (uint(visibility.length()) - first) / 2u;
    uint next = first + (parity ^ 1u) * words;
    for (uint w = t; w < words; w += LEVEL_GROUP_SIZE) {
        visibility[next + w] = 0u;
    }
}

void main() {
    uint t = gl_LocalInvocationID.x;
    bool early = pc.phase == PHASE_EARLY;
    bool late = pc.phase == PHASE_LATE;
    bool clustered = pc.phase != PHASE_ALL;
    if (t == 0u) {
        s_early_done = state[S_DONE] != 0u;
    }
    group_sync();
    // Every pass starts the schedule afresh; the frame's first pass also
    // its totals.
    for (uint i = t; i < LEVEL_STATE_WORDS; i += LEVEL_GROUP_SIZE) {
        if (!late || i < S_DEPTH_NODES) {
            state[i] = 0u;
        }
    }
    if (early) {
        clear_written_visibility(t);
    }
    bool frustum = (view.flags & FLAG_FRUSTUM_CULL) != 0u;
    uint n = uint(instances.length());
    uint listed = 0u;   // instances of this pass's depth 0
    uint dense = 0u;    // their patches, or their clusters (occlusion culling)
    uvec2 culled = uvec2(0u);    // out of view: instances, patches
    uvec2 occluded = uvec2(0u);  // hidden (late phase): instances, patches
    uint fresh = 0u;    // listed instances the early phase did not list
    // Instances in block_lane() order, the order workgroup_scan sums in, so
    // that depth 0 lists them in instance order.
    uint lane = block_lane();
    for (uint first = 0u; first < n; first += LEVEL_GROUP_SIZE) {
        uint i = first + lane;
        // An instance drawn from a level of detail this frame has no
        // patches to process (src/lod).
        uint count = i < n && (instances[i].flags & INSTANCE_LOD) == 0u ? instances[i].count : 0u;
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
            // Listed again when the early phase drew it: its clusters the
            // early phase did not draw are this phase's.
            keep = in_view && !hidden;
            early_flag = drawn ? ROOT_EARLY : 0u;
            hidden = hidden && !drawn;
        }
        bool counted_out = out_of_view && !late;  // counted once a frame
        uint units = clustered ? clusters_of(count) : count;
        // (listed, dense, culled instances, their patches) and (hidden
        // instances, their patches, fresh): only the first two need their
        // running sums.
        uvec4 a = uvec4(keep ? 1u : 0u, keep ? units : 0u, counted_out ? 1u : 0u,
            counted_out ? count : 0u);
        uvec4 b = uvec4(hidden ? 1u : 0u, hidden ? count : 0u, keep && early_flag == 0u ? 1u : 0u, 0u);
        uvec4 ia, ib, ta, tb;
        workgroup_scan(a, b, ia, ib, ta, tb);
        if (keep) {
            roots[listed + ia.x - 1u] = uvec2(i | early_flag, dense + ia.y - units);
        }
        listed += ta.x;
        dense += ta.y;
        culled += ta.zw;
        occluded += tb.xy;
        fresh += tb.z;
    }
    group_sync();
    if (t == 0u) {
        if (late) {
            // The next frame's early phase reads the set this frame wrote.
            uint parity = visibility_parity();
            visibility[parity] = visibility[parity] ^ 1u;
            state[S_EARLY_ROUNDS] = state[S_ROUND];
            state[S_NEW_INSTANCES] = fresh;
            if (!s_early_done) {
                state[S_EARLY_UNFINISHED] = 1u;
            }
        } else {
            state[S_EARLY_INSTANCES] = early ? listed : 0u;
            state[S_NEW_INSTANCES] = early ? 0u : listed;
        }
        state[S_ROOT_INSTANCES] = listed;
        state[S_CULLED_INSTANCES] += culled.x;
        state[S_CULLED_INSTANCE_PATCHES] += culled.y;
        state[S_OCCLUDED_INSTANCES] += occluded.x;
        state[S_OCCLUDED_INSTANCE_PATCHES] += occluded.y;
        // Culled and occluded patches are culled patches of the frame.
        counters[C_CULLED] += culled.y + occluded.y;
        counters[C_OCCLUDED] += occluded.y;
        uint first_ready = late ? state[S_READY] : 0u;
        counters[C_READY_FIRST] = first_ready;
        s_first_ready = first_ready;
        if (clustered) {
            // The cluster filter's arguments; it books depth 0.
            state[S_ROOT_CLUSTERS] = dense;
            // At most SYNC_ARRIVALS workgroups arrive at its barrier; they
            // take blocks in turn.
            uint groups = min((blocks_of(dense) + pc.group_blocks - 1u) / pc.group_blocks,
                SYNC_ARRIVALS);
            state[S_ARGS] = groups;
            state[S_ARGS + 1u] = 1u;
            state[S_ARGS + 2u] = 1u;
            state[S_DONE] = groups == 0u ? 1u : 0u;
        } else {
            schedule_depth0(dense);
        }
    }
    group_sync();
    // The draw's arguments: nothing until the schedule is done.
    write_ready_args_by(s_first_ready, s_first_ready, t, LEVEL_GROUP_SIZE);
}
