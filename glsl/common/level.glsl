// The level kernels' set 2, push block and round: subdiv's persistent kernel
// (subdivide.comp, rounds separated by a grid barrier inside one dispatch)
// and subdiv-indirect (subdivide_level.comp, one indirect dispatch per
// round) run exactly this code, so they write the same ready list in the
// same order. Host side: src/methods/levels.rs. Include after ready.glsl
// and process.glsl, in a shader that declares
// `#pragma use_vulkan_memory_model`.
//
// A round processes one chunk of at most pc.chunk nodes of one depth d,
// one block of LEVEL_GROUP_SIZE nodes per workgroup (per pass of the
// persistent kernel's block loop):
//   - each block writes its children, compacted within the block, into its
//     own BLOCK_SLOTS slots of depth d+1's region, its ready nodes into its
//     own slots of this round's ready scratch, and its two totals;
//   - the last workgroup to arrive (an acquire-release counter) scans the
//     totals (count -> scan; nobody waits for it) and schedules the next
//     round: the deepest depth with nodes left (depth first over chunks, so
//     every depth's region holds the children of one chunk of the depth
//     above and memory is bounded whatever the depth);
//   - the next round gathers its nodes through that scan (dense index ->
//     block by binary search -> slot) and copies this round's ready nodes
//     into the ready list at their scanned positions (scatter).
// Within a depth, nodes keep the order of their parents (children in child
// order), so the ready list's order is a function of the view and the
// chunk size alone: no sort, the same image run to run and between the two
// kernels. levels::canonical_ready (Rust) computes the same list.
#ifndef LEVEL_GLSL
#define LEVEL_GLSL

#extension GL_KHR_memory_scope_semantics : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require

// Written by one workgroup and read by others within a dispatch (the
// persistent kernel) or by the next round: coherent, and ordered by the
// acquire-release atomics on the state's synchronisation words.
layout(std430, set = SET_PRODUCER, binding = BIND_LEVEL_NODES) coherent buffer LevelNodes {
    uvec2 level_nodes[];
};
layout(std430, set = SET_PRODUCER, binding = BIND_LEVEL_SCANS) coherent buffer LevelScans {
    uint level_scans[];
};
layout(std430, set = SET_PRODUCER, binding = BIND_LEVEL_STATE) coherent buffer LevelState {
    uint state[];
};

// Depth 0 (set 0, written by level_init before the first round): per
// instance that survived culling, its index and the dense index of its
// first patch; state[S_ROOT_INSTANCES] entries.
layout(std430, set = SET_SCENE, binding = BIND_ROOTS) buffer Roots {
    uvec2 roots[];
};

// Occlusion culling's visibility, kept from frame to frame: one word per
// instance (1 where the last frame found it visible), a parity word, then
// two sets of one bit per cluster of up to VISIBILITY_CLUSTER consecutive
// base patches of one instance (root_cluster). A late phase zeroes the set the parity does not name, flips
// the parity (level_init) and sets the bit of every cluster with a root it
// finds visible (in view, not hidden, split or ready); the next frame's
// early phase reads that set, and draws only the patches of its instances
// whose cluster's bit is set; its late phase draws every other patch in
// view. Two sets, because a cluster's bit is the OR of its patches'
// verdicts: the set written is cleared first, the set read stays whole.
// Bits cost 1/128 byte per base patch and 2 bits per instance (13 bytes
// per car of 1,575 patches).
layout(std430, set = SET_SCENE, binding = BIND_VISIBILITY) buffer Visibility {
    uint visibility[];
};

// The parity word's index (after the instance words).
uint visibility_parity() {
    return uint(instances.length());
}

// Cluster c's bit in set `s` (0 or 1): (word, mask).
uvec2 cluster_bit(uint c, uint s) {
    uint first = visibility_parity() + 1u;
    uint words = (uint(visibility.length()) - first) / 2u;
    return uvec2(first + s * words + c / 32u, 1u << (c % 32u));
}

// Set in a root entry's instance index (late phase): the early phase listed
// that instance, so its patches whose bit is set are drawn already.
const uint ROOT_EARLY = 0x80000000u;

// src/gpu/blocks.rs LevelPush.
layout(push_constant) uniform LevelPush {
    uint patch_count;     // base patches: the nodes of depth 0
    uint chunk;           // nodes per round at most (a multiple of LEVEL_GROUP_SIZE)
    uint ready_capacity;  // entries in `ready`
    uint levels;          // depths with a region (1..levels), at least view.l_max
    uint watchdog_polls;  // persistent: polls without progress before giving up
    uint join_polls;      // persistent: polls of an unchanged join count before closing
    uint launched;        // persistent: workgroups launched
    uint faults;          // FAULT_* (tests)
    uint group_blocks;    // per-depth rounds: blocks per workgroup
    uint phase;           // PHASE_*: one pass, or a phase of occlusion culling
    uint pad0;
    uint pad1;
} pc;

const uint BLOCK = LEVEL_GROUP_SIZE;
const uint BLOCK_SLOTS = LEVEL_GROUP_SIZE * SPLIT_MAX_CHILDREN;
const int SYNC_SCOPE = gl_ScopeQueueFamily;
const int SYNC_STORAGE = gl_StorageSemanticsBuffer;

// ---------------------------------------------------------- synchronisation

// A workgroup-wide barrier that also orders buffer accesses, so that what
// every invocation wrote happens before invocation 0's device-scope
// release, and invocation 0's acquire before everyone's reads.
void group_sync() {
    controlBarrier(gl_ScopeWorkgroup, gl_ScopeWorkgroup,
        gl_StorageSemanticsBuffer | gl_StorageSemanticsShared, gl_SemanticsAcquireRelease);
}

// ------------------------------------------------------------- node memory

uint blocks_of(uint n) {
    return (n + BLOCK - 1u) / BLOCK;
}

// First slot of depth d's region (d >= 1): the children of one chunk.
uint level_region(uint d) {
    return (d - 1u) * pc.chunk * SPLIT_MAX_CHILDREN;
}

// First slot of ready scratch p (the rounds alternate between two).
uint ready_region(uint p) {
    return pc.levels * pc.chunk * SPLIT_MAX_CHILDREN + p * pc.chunk;
}

uint scan_words() {
    return pc.chunk / BLOCK + 1u;
}

// Depth d's block scan (d = 1..levels+1): exclusive child offsets of the
// blocks of the chunk that filled it, the total after the last.
uint level_scan(uint d) {
    return (d - 1u) * scan_words();
}

// Ready scan p: exclusive ready offsets of round p's blocks.
uint ready_scan(uint p) {
    return (pc.levels + 1u + p) * scan_words();
}

// This round's per-block statistics, LEVEL_BLOCK_STATS words per block
// (culled, back-facing, at l_max, triangles, wedges, occluded, deepest): the last
// workgroup sums them, so the counters take no atomics.
uint block_stats(uint b) {
    return (pc.levels + 3u) * scan_words() + b * LEVEL_BLOCK_STATS;
}

// Base patch j (dense index) of depth 0: the entry of the last surviving
// instance whose first dense index is at most j, then the patch's place in
// that instance.
uint root_entry(uint j) {
    uint lo = 0u;
    uint hi = state[S_ROOT_INSTANCES];
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (roots[mid].y <= j) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

uint root_patch(uint j) {
    uint r = root_entry(j);
    return instances[roots[r].x & ~ROOT_EARLY].first + (j - roots[r].y);
}

// The cluster of node j of depth 0 (root entry r): its instance's patches
// in runs of VISIBILITY_CLUSTER from the instance's first, numbered
// floor(first / VISIBILITY_CLUSTER) + instance + run. No cluster holds two
// instances' patches (a visible instance would draw a hidden one's early),
// and the numbers are distinct: instance i + 1's first lies past instance
// i's last, since floor((first + count) / n) >= floor(first / n) +
// floor((count - 1) / n). At most base patches / VISIBILITY_CLUSTER +
// instances + 1 clusters.
uint root_cluster(uint r, uint j) {
    uint i = roots[r].x & ~ROOT_EARLY;
    return instances[i].first / VISIBILITY_CLUSTER + i + (j - roots[r].y) / VISIBILITY_CLUSTER;
}

// Depth 0 under occlusion culling (pc.phase early or late): node j, base
// patch q, by its cluster's bit from the last frame (see the buffer above;
// the early phase reads the set the parity names, the late phase, after
// level_init flipped it, reads that same set and writes the other).
// Early: processed if the bit is set, else deferred. Late: deferred if the
// early phase drew it, after its boxes are tested again; processed
// otherwise; either way a visible root sets its cluster's bit.
//
// Split in two around the one call of process() in process_block, so that
// a kernel holds a single copy of the work item: root_test() before it,
// root_verdict() after.
struct RootTest {
    uint cluster;   // the root's cluster
    uint parity;    // the visibility set the early phase reads
    bool process;   // false: deferred without processing (early, bit clear)
    bool box_only;  // late: drawn early, only its boxes are tested again
};

RootTest root_test(uint j) {
    RootTest rt;
    uint r = root_entry(j);
    rt.cluster = root_cluster(r, j);
    rt.parity = visibility[visibility_parity()];
    bool late = pc.phase == PHASE_LATE;
    uvec2 read = cluster_bit(rt.cluster, late ? rt.parity ^ 1u : rt.parity);
    bool seen = (visibility[read.x] & read.y) != 0u;
    rt.process = late || seen;
    rt.box_only = late && seen && (roots[r].x & ROOT_EARLY) != 0u;
    return rt;
}

// The root's outcome after process() (or none: OUT_DEFERRED when
// !rt.process): the late phase books a visible root's cluster and defers
// what the early phase drew.
uint root_verdict(RootTest rt, uint outcome, inout uint nkids) {
    if (!rt.process) {
        return OUT_DEFERRED;
    }
    if (pc.phase != PHASE_LATE) {
        return outcome;
    }
    if (outcome == OUT_READY || outcome == OUT_SPLIT) {
        uvec2 write = cluster_bit(rt.cluster, rt.parity);
        atomicOr(visibility[write.x], write.y);
    }
    if (rt.box_only) {
        nkids = 0u;
        return OUT_DEFERRED;
    }
    return outcome;
}

// Node j (dense index) of depth d: a base patch at depth 0, else the slot
// its block's scan entry and rank within the block name.
uvec2 level_node(uint d, uint j) {
    if (d == 0u) {
        return root_node(root_patch(j));
    }
    uint s = level_scan(d);
    // scan[0] = 0 <= j < scan[blocks] = the depth's count.
    uint lo = 0u;
    uint hi = state[S_LEVEL_BLOCKS + d];
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (level_scans[s + mid] <= j) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return level_nodes[level_region(d) + lo * BLOCK_SLOTS + (j - level_scans[s + lo])];
}

// ------------------------------------------------------------ round state

// This round, as the last round's last workgroup left it (read by one
// invocation, shared with the workgroup).
shared uint s_level;
shared uint s_first;
shared uint s_count;
shared uint s_copy_blocks;
shared uint s_copy_base;
shared uint s_parity;
shared bool s_done;
// The last workgroup's scan and sums.
shared uint s_part[BLOCK];
shared uint s_sums[LEVEL_BLOCK_STATS][BLOCK];

uint round_blocks() {
    return blocks_of(s_count);
}

// Invocation 0 reads the round's state into shared memory; call with the
// whole workgroup after the round was published.
void load_round(uint t) {
    if (t == 0u) {
        s_level = state[S_LEVEL];
        s_first = state[S_FIRST];
        s_count = state[S_COUNT];
        s_copy_blocks = state[S_COPY_BLOCKS];
        s_copy_base = state[S_COPY_BASE];
        s_parity = state[S_ROUND] & 1u;
        s_done = state[S_DONE] != 0u;
    }
    // Extends invocation 0's acquire (the persistent kernel's) to the
    // buffer reads of the whole workgroup.
    group_sync();
}

// The position of this invocation in its block: subgroup-major, so that
// subgroup prefix sums run in node order whatever the device's mapping of
// invocations to subgroups.
uint block_lane() {
    return gl_SubgroupID * gl_SubgroupSize + gl_SubgroupInvocationID;
}

// Per subgroup: the totals of workgroup_scan's two vectors.
shared uvec4 s_scan_sub[2][BLOCK];

// Whole workgroup (uniform control flow): the inclusive sums of `a` and
// `b` over the workgroup in block_lane() order, and their totals (every
// invocation gets them): subgroup scans, then each subgroup adds the
// totals of the subgroups before it. Two barriers, whatever the size: a
// scan by doubling steps took two per step, and on a CPU device every
// barrier is a coroutine suspension that the driver compiles slowly.
void workgroup_scan(uvec4 a, uvec4 b, out uvec4 ia, out uvec4 ib, out uvec4 ta, out uvec4 tb) {
    ia = subgroupInclusiveAdd(a);
    ib = subgroupInclusiveAdd(b);
    if (gl_SubgroupInvocationID == gl_SubgroupSize - 1u) {
        s_scan_sub[0][gl_SubgroupID] = ia;
        s_scan_sub[1][gl_SubgroupID] = ib;
    }
    barrier();
    ta = uvec4(0u);
    tb = uvec4(0u);
    for (uint s = 0u; s < gl_NumSubgroups; ++s) {
        if (s == gl_SubgroupID) {
            ia += ta;
            ib += tb;
        }
        ta += s_scan_sub[0][s];
        tb += s_scan_sub[1][s];
    }
    barrier();
}

// What one node adds to its block's totals: children, ready, then the
// LEVEL_BLOCK_STATS statistics (the last one, the deepest ready depth, is
// a maximum).
const uint VALUES = 2u + LEVEL_BLOCK_STATS;
const uint V_CHILDREN = 0u;
const uint V_READY = 1u;
const uint V_DEEPEST = VALUES - 1u;

// Per subgroup, in two sets that alternate from block to block, so one
// barrier per block is enough.
shared uint s_sub[2][VALUES][BLOCK];
uint blocks_done = 0u;

// Whole workgroup: the exclusive prefix sums of v[V_CHILDREN] and
// v[V_READY] over the block (in block_lane order); invocation 0 also gets
// the block's totals.
uvec2 block_reduce(uint v[VALUES], out uint totals[VALUES]) {
    uint set = blocks_done & 1u;
    blocks_done += 1u;
    uint ec = subgroupExclusiveAdd(v[V_CHILDREN]);
    uint er = subgroupExclusiveAdd(v[V_READY]);
    uint sums[VALUES];
    for (uint k = 0u; k < V_DEEPEST; ++k) {
        sums[k] = subgroupAdd(v[k]);
    }
    sums[V_DEEPEST] = subgroupMax(v[V_DEEPEST]);
    if (subgroupElect()) {
        for (uint k = 0u; k < VALUES; ++k) {
            s_sub[set][k][gl_SubgroupID] = sums[k];
        }
    }
    barrier();
    for (uint s = 0u; s < gl_SubgroupID; ++s) {
        ec += s_sub[set][V_CHILDREN][s];
        er += s_sub[set][V_READY][s];
    }
    for (uint k = 0u; k < VALUES; ++k) {
        totals[k] = 0u;
    }
    if (gl_LocalInvocationIndex == 0u) {
        for (uint s = 0u; s < gl_NumSubgroups; ++s) {
            for (uint k = 0u; k < V_DEEPEST; ++k) {
                totals[k] += s_sub[set][k][s];
            }
            totals[V_DEEPEST] = max(totals[V_DEEPEST], s_sub[set][V_DEEPEST][s]);
        }
    }
    return uvec2(ec, er);
}

// The node's contribution to its block's totals; `nkids` children of a
// split (4 for 1:4, 2 for a 1:2 split).
void node_values(bool have, uvec2 q, uint outcome, uint nkids, out uint v[VALUES]) {
    for (uint k = 0u; k < VALUES; ++k) {
        v[k] = 0u;
    }
    if (!have) {
        return;
    }
    v[V_CHILDREN] = outcome == OUT_SPLIT ? nkids : 0u;
    v[2u] = outcome == OUT_CULLED || outcome == OUT_OCCLUDED ? 1u : 0u;
    v[3u] = outcome == OUT_BACKFACE ? 1u : 0u;
    v[7u] = outcome == OUT_OCCLUDED ? 1u : 0u;
    if (outcome == OUT_READY) {
        uint l = node_depth(q);
        uvec2 tw = ready_triangles(q, (view.flags & FLAG_WEDGES) != 0u);
        v[V_READY] = 1u;
        v[4u] = l >= view.l_max ? 1u : 0u;
        v[5u] = tw.x;
        v[6u] = tw.y;
        v[V_DEEPEST] = l;
    }
}

// Block b of this round's chunk: process its nodes, write the children
// into the block's slots of the next depth, the ready nodes into the
// block's slots of this round's scratch, and the block's totals. Whole
// workgroup (uniform control flow: the subgroup sums need every lane).
void process_block(uint b, uint t) {
    uint d = s_level;
    uint j = s_first + b * BLOCK + block_lane();
    bool have = j < s_first + s_count;
    uvec2 q = have ? level_node(d, j) : uvec2(0u);
    uvec2 kids[4] = uvec2[4](uvec2(0u), uvec2(0u), uvec2(0u), uvec2(0u));
    uint nkids = 0u;
    uint outcome = OUT_CULLED;
    bool root = have && d == 0u && pc.phase != PHASE_ALL;
    RootTest rt = RootTest(0u, 0u, true, false);
    if (root) {
        rt = root_test(j);
    }
    // The kernel's one call of the work item (see root_test).
    if (have && rt.process) {
        process_box_only = rt.box_only;
        outcome = process(q, kids, nkids);
        process_box_only = false;
    }
    if (root) {
        outcome = root_verdict(rt, outcome, nkids);
    }
    uint v[VALUES];
    node_values(have, q, outcome, nkids, v);
    uint totals[VALUES];
    uvec2 at = block_reduce(v, totals);
    // Depth d + 1 has a region when d < pc.levels, which the host sizes for
    // the deepest depth the split can reach (levels::levels_for); should a
    // node ever split beyond it, its children are dropped and the frame is
    // refused, rather than written over the next region or past the buffer.
    if (v[V_CHILDREN] > 0u && d >= pc.levels) {
        atomicOr(counters[C_ERROR], ERR_LEVEL_REGION);
    } else if (v[V_CHILDREN] > 0u) {
        uint base = level_region(d + 1u) + b * BLOCK_SLOTS + at.x;
        for (uint k = 0u; k < v[V_CHILDREN]; ++k) {
            level_nodes[base + k] = kids[k];
        }
    }
    if (v[V_READY] != 0u) {
        level_nodes[ready_region(s_parity) + b * BLOCK + at.y] = q;
    }
    if (t == 0u) {
        level_scans[level_scan(d + 1u) + b] = totals[V_CHILDREN];
        level_scans[ready_scan(s_parity) + b] = totals[V_READY];
        for (uint k = 0u; k < LEVEL_BLOCK_STATS; ++k) {
            level_scans[block_stats(b) + k] = totals[2u + k];
        }
    }
}

// Block b of the previous round's ready nodes into the ready list, at the
// positions its scan gave them. Whole workgroup.
void copy_block(uint b, uint t) {
    uint prev = s_parity ^ 1u;
    uint s = ready_scan(prev) + b;
    uint lo = level_scans[s];
    uint n = level_scans[s + 1u] - lo;
    if (t < n) {
        uint idx = s_copy_base + lo + t;
        if (idx < pc.ready_capacity) {
            ready[idx] = level_nodes[ready_region(prev) + b * BLOCK + t];
        }
    }
}

// --------------------------------------------------------------- schedule

// Invocation 0: the next round is a chunk of the deepest depth with nodes
// left (none: only the copy of `copy_blocks`, or nothing), and its
// dispatch arguments.
void schedule(uint copy_blocks) {
    uint level = 0u, first = 0u, n = 0u;
    for (int d = int(pc.levels); d >= 0; --d) {
        uint next = state[S_LEVEL_NEXT + uint(d)];
        uint count = state[S_LEVEL_COUNT + uint(d)];
        if (next < count) {
            level = uint(d);
            first = next;
            n = min(pc.chunk, count - next);
            state[S_LEVEL_NEXT + level] = next + n;
            state[S_SPLIT_ROUNDS] += count > pc.chunk ? 1u : 0u;
            break;
        }
    }
    state[S_LEVEL] = level;
    state[S_FIRST] = first;
    state[S_COUNT] = n;
    state[S_COPY_BLOCKS] = copy_blocks;
    // A per-depth round's workgroups take pc.group_blocks blocks each (more
    // than one where a workgroup's barriers are dear: a CPU device).
    uint work = max(blocks_of(n), copy_blocks);
    uint groups = (work + pc.group_blocks - 1u) / pc.group_blocks;
    state[S_ARGS] = groups;
    state[S_ARGS + 1u] = 1u;
    state[S_ARGS + 2u] = 1u;
    state[S_DONE] = groups == 0u ? 1u : 0u;
}

// Exclusive scan in place of level_scans[base .. base + n), the total
// written after them and returned. Whole workgroup (the last to arrive).
uint scan_in_place(uint base, uint n, uint t) {
    uint per = (n + BLOCK - 1u) / BLOCK;
    uint lo = min(t * per, n);
    uint hi = min(lo + per, n);
    uint sum = 0u;
    for (uint i = lo; i < hi; ++i) {
        sum += level_scans[base + i];
    }
    s_part[t] = sum;
    group_sync();
    if (t == 0u) {
        uint run = 0u;
        for (uint i = 0u; i < BLOCK; ++i) {
            uint v = s_part[i];
            s_part[i] = run;
            run += v;
        }
        level_scans[base + n] = run;
    }
    group_sync();
    uint run = s_part[t];
    for (uint i = lo; i < hi; ++i) {
        uint v = level_scans[base + i];
        level_scans[base + i] = run;
        run += v;
    }
    uint total = level_scans[base + n];
    group_sync();
    return total;
}

// Whole workgroup: this round's block statistics summed into the
// counters (plain: during a dispatch only a round's last workgroup writes
// them, one after the other).
void add_block_stats(uint nb, uint t) {
    for (uint k = 0u; k < LEVEL_BLOCK_STATS; ++k) {
        s_sums[k][t] = 0u;
    }
    for (uint b = t; b < nb; b += BLOCK) {
        for (uint k = 0u; k + 1u < LEVEL_BLOCK_STATS; ++k) {
            s_sums[k][t] += level_scans[block_stats(b) + k];
        }
        uint last = LEVEL_BLOCK_STATS - 1u;
        s_sums[last][t] = max(s_sums[last][t], level_scans[block_stats(b) + last]);
    }
    barrier();
    if (t == 0u) {
        uint sum[LEVEL_BLOCK_STATS];
        for (uint k = 0u; k < LEVEL_BLOCK_STATS; ++k) {
            sum[k] = 0u;
            for (uint i = 0u; i < BLOCK; ++i) {
                sum[k] = k + 1u < LEVEL_BLOCK_STATS ? sum[k] + s_sums[k][i] : max(sum[k], s_sums[k][i]);
            }
        }
        counters[C_CULLED] += sum[0];
        counters[C_BACKFACE] += sum[1];
        counters[C_AT_LMAX] += sum[2];
        counters[C_TRIANGLES] += sum[3];
        counters[C_WEDGES] += sum[4];
        counters[C_OCCLUDED] += sum[5];
        counters[C_MAX_DEPTH] = max(counters[C_MAX_DEPTH], sum[6]);
    }
    barrier();
}

// The last workgroup of a round: scans its block totals, books the chunk's
// children as the next depth's content, and schedules the next round. Whole
// workgroup, after the acquire that made every block's writes visible.
void finish_round(uint t) {
    uint d = s_level;
    uint n = s_count;
    uint nb = blocks_of(n);
    uint children = 0u, readies = 0u;
    if (n > 0u) {
        children = scan_in_place(level_scan(d + 1u), nb, t);
        readies = scan_in_place(ready_scan(s_parity), nb, t);
        add_block_stats(nb, t);
    }
    if (t == 0u) {
        uint found = state[S_READY];
        state[S_COPY_BASE] = found;
        state[S_READY] = found + readies;
        state[S_DEPTH_NODES + d] += n;
        counters[C_PROCESSED] += n;
        if (children > 0u && d < pc.levels) {
            // Depth d + 1 is empty: the schedule only comes back to depth d
            // once every deeper depth is used up.
            state[S_LEVEL_COUNT + d + 1u] = children;
            state[S_LEVEL_NEXT + d + 1u] = 0u;
            state[S_LEVEL_BLOCKS + d + 1u] = nb;
            state[S_PEAK_NODES] = max(state[S_PEAK_NODES], children);
        }
        state[S_ROUND] += 1u;
        schedule(readies > 0u ? nb : 0u);
        uint total = found + readies;
        counters[C_READY_COUNT] = total;
        if (total > pc.ready_capacity) {
            atomicOr(counters[C_ERROR], ERR_READY_FULL);
        }
        write_ready_args(ready_first(), min(total, pc.ready_capacity));
    }
    barrier();
}

// Invocation 0: arrives at the end of the round; true for the last of
// `expected` workgroups (it then sees every block's writes).
bool arrive(uint expected) {
    uint old = atomicAdd(state[S_ARRIVE], 1u, SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsAcquireRelease);
    return old + 1u == expected;
}

// Invocation 0 of the last workgroup: the counter is back at zero for the
// next round (published by the release that ends this round).
void rearm_arrive() {
    atomicStore(state[S_ARRIVE], 0u, SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsRelaxed);
}

#endif
