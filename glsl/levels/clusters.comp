// Occlusion culling's cluster filter: between a phase's first step
// (levels/init.comp) and its rounds, it makes depth 0 of the phase out of
// whole clusters (VISIBILITY_CLUSTER consecutive patches of one instance),
// so that a phase's rounds touch only the patches it draws: one invocation
// per cluster of the instances the phase listed (roots[r].y: the
// instance's first dense cluster), a block of LEVEL_GROUP_SIZE clusters per
// workgroup pass (pc.group_blocks blocks per workgroup).
//   - Early phase: keeps the clusters whose bit the last frame set.
//   - Late phase: a cluster the early phase drew (its instance flagged
//     ROOT_EARLY, its bit set) is not processed again; its patches' boxes
//     (each model patch's box placed by the instance) are tested against
//     the pyramid of what the early phase drew instead, until one is not
//     hidden (mostly the first, where something is seen: a cost per
//     cluster, not per patch), and a cluster whose every patch is hidden
//     has its bit cleared in the set this frame writes (where the early
//     phase's visible roots set it), so the next frame's early phase leaves
//     it to its late phase. Every other cluster is kept.
// A block compacts its kept clusters (instance, first patch in the
// instance) into its own slots after the instance entries and writes its
// count; the last workgroup to arrive scans the counts in place (the
// rounds find a lane's cluster through them, as they find a node of depth
// d through level_scans), books depth 0 (VISIBILITY_CLUSTER lanes per kept
// cluster) and schedules the first round. Host side: src/methods/levels.rs.
#version 460
#pragma use_vulkan_memory_model

#define USE_READY_WRITE
#define LEVEL_KERNEL
#include "common/ready.glsl"
#include "common/process.glsl"
#include "level.glsl"

layout(local_size_x = LEVEL_GROUP_SIZE) in;

// A patch box is tested as the late phase tests a root (at most 4 x 4
// texels): its box holds the root's, and the test is monotone in the box,
// so a cluster this test hides the late phase's rounds find hidden too.
// (A finer test would hide clusters the rounds then find visible, and the
// cluster would go back and forth between the phases frame after frame.)
const uint HIZ_PATCH_SPAN = HIZ_NODE_SPAN;

shared bool s_last;
// The visibility atomics this workgroup's blocks issued.
shared uint s_filter_atomics;

// Whether instance i's patches may leave its model's boxes (a deforming
// model: its instance holds everything, Instance::unbounded).
bool unbounded(uint i) {
    return instances[i].lo.x < -1.0e38;
}

// The world box of model patch m's box placed by instance i: the box of its
// 8 placed corners (an affine map keeps the box's image in their hull),
// widened by a relative 1e-5 of the magnitudes the placement sums for the
// roundings of placing the control points themselves.
void placed_patch_box(uint i, uint m, out vec3 lo, out vec3 hi) {
    uint o = 6u * m;
    vec3 a = vec3(patch_boxes[o], patch_boxes[o + 1u], patch_boxes[o + 2u]);
    vec3 b = vec3(patch_boxes[o + 3u], patch_boxes[o + 4u], patch_boxes[o + 5u]);
    if ((instances[i].flags & INSTANCE_IDENTITY) != 0u) {
        lo = a;
        hi = b;
        return;
    }
    vec4 r0 = instances[i].rows[0];
    vec4 r1 = instances[i].rows[1];
    vec4 r2 = instances[i].rows[2];
    lo = vec3(3.0e38);
    hi = vec3(-3.0e38);
    for (uint c = 0u; c < 8u; ++c) {
        vec3 p = vec3((c & 1u) != 0u ? b.x : a.x, (c & 2u) != 0u ? b.y : a.y,
            (c & 4u) != 0u ? b.z : a.z);
        vec3 w = place_point(r0, r1, r2, p);
        lo = min(lo, w);
        hi = max(hi, w);
    }
    vec3 m3 = max(abs(a), abs(b));
    vec3 pad = 1.0e-6 * vec3(dot(abs(r0.xyz), m3) + abs(r0.w), dot(abs(r1.xyz), m3) + abs(r1.w),
        dot(abs(r2.xyz), m3) + abs(r2.w));
    lo -= pad;
    hi += pad;
}

// Whether no patch of instance i's cluster from its patch `local` can be
// seen: each one's box outside the frustum or behind the pyramid (tested
// one by one until one is neither).
bool cluster_hidden(uint i, uint local) {
    bool frustum = (view.flags & FLAG_FRUSTUM_CULL) != 0u;
    uint end = min(local + VISIBILITY_CLUSTER, instances[i].count);
    for (uint p = local; p < end; ++p) {
        vec3 lo, hi;
        placed_patch_box(i, instances[i].source + p, lo, hi);
        bool out_of_view = frustum && outside_frustum(lo, hi, view);
        if (!out_of_view && !box_occluded(lo, hi, HIZ_PATCH_SPAN)) {
            return false;
        }
    }
    return true;
}

// Block b of the listed clusters: decide, compact the kept ones, write the
// block's counts. Whole workgroup.
void filter_block(uint b, uint t) {
    uint n = s_root_clusters;
    uint k = b * BLOCK + block_lane();
    bool have = k < n;
    uint kc = min(k, n - 1u);
    uint r = find_source(KEY_ROOTS, 0u, s_root_instances, kc);
    uvec2 e = roots[r];
    uint i = e.x & ~ROOT_EARLY;
    uint local = (kc - e.y) * VISIBILITY_CLUSTER;
    uint c = cluster_id(i, local);
    uvec2 read = cluster_bit(c, s_write_set ^ 1u);
    bool seen = (visibility[read.x] & read.y) != 0u;
    bool keep;
    bool hidden = false;
    if (pc.phase == PHASE_LATE) {
        bool drawn = (e.x & ROOT_EARLY) != 0u && seen;
        keep = have && !drawn;
        if (have && drawn && !unbounded(i)) {
            // FAULT_HIDE_LATE (tests): the late phase finds everything hidden.
            hidden = (pc.faults & FAULT_HIDE_LATE) != 0u || cluster_hidden(i, local);
        }
    } else {
        keep = have && seen;
    }
    uvec2 bit = cluster_bit(c, s_write_set);
    uint atomics = book_bits(hidden, bit.x, bit.y, false);
    uvec4 ia, ib, ta, tb;
    workgroup_scan(uvec4(keep ? 1u : 0u, hidden ? 1u : 0u, atomics, 0u), uvec4(0u), ia, ib, ta, tb);
    if (keep) {
        roots[cluster_slot(b, ia.x - 1u)] = uvec2(i, local);
    }
    if (t == 0u) {
        roots[cluster_scan(b)] = uvec2(ta.x, ta.y | ta.z << 16u);
        s_filter_atomics += ta.z;
    }
}

// The last workgroup: the blocks' kept counts scanned in place (every
// invocation a run of at most 64 blocks: scenes up to 4,096 blocks of 64
// clusters), the phase's figures, depth 0 booked and the first round
// scheduled. Whole workgroup, after the acquire.
void finish_filter(uint t) {
    uint nb = blocks_of(s_root_clusters);
    uint per = (nb + BLOCK - 1u) / BLOCK;
    uint lo = min(block_lane() * per, nb);
    uint hi = min(lo + per, nb);
    uvec3 own = uvec3(0u);
    for (uint b = lo; b < hi; ++b) {
        uvec2 e = roots[cluster_scan(b)];
        own += uvec3(e.x, e.y & 0xffffu, e.y >> 16u);
    }
    uvec4 ia, ib, ta, tb;
    workgroup_scan(uvec4(own, 0u), uvec4(0u), ia, ib, ta, tb);
    uint run = ia.x - own.x;
    for (uint b = lo; b < hi; ++b) {
        uint v = roots[cluster_scan(b)].x;
        roots[cluster_scan(b)].x = run;
        run += v;
    }
    if (t == 0u) {
        uint kept = ta.x;
        roots[cluster_scan(nb)] = uvec2(kept, 0u);
        if (pc.phase == PHASE_LATE) {
            state[S_CLUSTERS_LATE] += kept;
            state[S_CLUSTERS_TESTED] += s_root_clusters - kept;
            state[S_CLUSTERS_HIDDEN] += ta.y;
            state[S_VISIBILITY_ATOMICS] += ta.z;
        } else {
            state[S_CLUSTERS_EARLY] += kept;
        }
        schedule_depth0(kept * VISIBILITY_CLUSTER);
    }
}

void main() {
    uint t = gl_LocalInvocationIndex;
    if (t == 0u) {
        s_filter_atomics = 0u;
    }
    load_round(t);
    uint nb = blocks_of(s_root_clusters);
    for (uint b = gl_WorkGroupID.x; b < nb; b += gl_NumWorkGroups.x) {
        filter_block(b, t);
    }
    group_sync();
    uint before = 0u;
    if (t == 0u) {
        s_last = arrive(gl_NumWorkGroups.x, before);
        // The arrival, this count, the last one's release, and the bits of
        // the hidden clusters (one atomic per word a subgroup cleared).
        atomicAdd(counters[C_GLOBAL_ATOMICS], s_filter_atomics + (s_last ? 3u : 2u));
    }
    group_sync();
    if (s_last) {
        finish_filter(t);
        if (t == 0u) {
            release_round(before, gl_NumWorkGroups.x);
        }
    }
}
