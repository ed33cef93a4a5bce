// The level kernels' set 2, push block and round: subdiv's persistent kernel
// (levels/persistent.comp, rounds separated by a grid barrier inside one dispatch)
// and subdiv-indirect (levels/round.comp, one indirect dispatch per
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
//     own slots of this round's ready scratch, and its totals;
//   - the last workgroup to arrive (an acquire-release counter) scans the
//     totals in one pass, every invocation a run of at most 64 blocks
//     (count -> scan; nobody waits for it), and schedules the next round:
//     the deepest depth with nodes left, one findMSB of a word (depth
//     first over chunks, so every depth's region holds the children of one
//     chunk of the depth above and memory is bounded whatever the depth);
//   - the next round gathers its nodes through that scan (dense index ->
//     block by a search, two per subgroup -> slot) and copies this round's
//     ready nodes into the ready list at their scanned positions (scatter).
// Within a depth, nodes keep the order of their parents (children in child
// order), so the ready list's order is a function of the view and the
// chunk size alone: no sort, the same image run to run and between the two
// kernels. levels::canonical_ready (Rust) computes the same list.
#ifndef LEVEL_GLSL
#define LEVEL_GLSL

#extension GL_KHR_memory_scope_semantics : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require

// Written by one workgroup and read by others within a dispatch (the
// persistent kernel) or by the next round: coherent, and ordered by the
// acquire-release atomics on the state's synchronisation word.
layout(std430, set = SET_PRODUCER, binding = BIND_LEVEL_NODES) coherent buffer LevelNodes {
    uvec2 level_nodes[];
};
layout(std430, set = SET_PRODUCER, binding = BIND_LEVEL_SCANS) coherent buffer LevelScans {
    uint level_scans[];
};
layout(std430, set = SET_PRODUCER, binding = BIND_LEVEL_STATE) coherent buffer LevelState {
    uint state[];
};

// Depth 0 (set 0), in three parts:
//   - roots[r], r < S_ROOT_INSTANCES (written by level_init): per instance
//     that survived culling, in instance order, its index (| ROOT_EARLY)
//     and the dense index of its first patch among the listed patches, or
//     under occlusion culling (pc.phase early or late) of its first
//     cluster among the listed clusters;
//   - under occlusion culling, the cluster filter's (levels/clusters.comp)
//     kept clusters: block b's in its BLOCK slots from cluster_slot(b, 0),
//     each (instance, its first patch in the instance);
//   - and the filter's block scan: roots[cluster_scan(b)].x the exclusive
//     offset of block b's kept clusters (the total at b = blocks), .y the
//     clusters it found hidden and, from bit 16, the atomics it issued.
// The filter's last workgroup reads the others' counts: coherent.
layout(std430, set = SET_SCENE, binding = BIND_ROOTS) coherent buffer Roots {
    uvec2 roots[];
};

// Occlusion culling's visibility, kept from frame to frame: one word per
// instance (1 where the last frame found it visible), a parity word, then
// two sets of one bit per cluster of up to VISIBILITY_CLUSTER consecutive
// base patches of one instance (cluster_id). A frame reads the set the
// parity names (last frame's verdict) and writes the other, which its
// early phase's first step zeroes: both phases set the bit of a cluster
// with a root they find visible (in view, not hidden, split or ready), and
// the late phase's filter clears the bit of a cluster the early phase drew
// whose box the early phase's depth hides. The late phase's first step
// flips the parity, so the next frame reads what this one wrote. A bit is
// the OR of its roots' verdicts, hence two sets: the one written starts
// empty, the one read stays whole. Bits cost 1/128 byte per base patch and
// 2 bits per instance (13 bytes per car of 1,575 patches).
layout(std430, set = SET_SCENE, binding = BIND_VISIBILITY) buffer Visibility {
    uint visibility[];
};

// Per model patch, the model-space box of its control points
// (InstanceTable::patch_boxes): 6 floats, lo then hi.
layout(std430, set = SET_SCENE, binding = BIND_PATCH_BOXES) readonly buffer PatchBoxes {
    float patch_boxes[];
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
// that instance, so its clusters whose bit is set are drawn already.
const uint ROOT_EARLY = 0x80000000u;

// src/methods/levels/push.rs LevelPush.
layout(push_constant) uniform LevelPush {
    uint patch_count;     // base patches: the nodes of depth 0
    uint chunk;           // nodes per round at most (a multiple of LEVEL_GROUP_SIZE)
    uint ready_capacity;  // entries in `ready`
    uint levels;          // depths with a region (1..levels), at least view.l_max
    uint watchdog_polls;  // persistent: polls without progress before giving up
    uint join_polls;      // persistent: polls of an unchanged join count before closing
    uint launched;        // persistent: workgroups launched
    uint faults;          // FAULT_* (tests)
    uint group_blocks;    // per-depth rounds and the cluster filter: blocks per workgroup
    uint phase;           // PHASE_*: one pass, or a phase of occlusion culling
    uint cluster_blocks;  // blocks of cluster slots in `roots`
    uint pad;
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

// Invocation 0: arrives at the end of a round (acquire-release on S_SYNC);
// true for the last of `expected` workgroups, which then sees every
// block's writes. `before` is the word as the arrival found it (its
// generation is the round's).
bool arrive(uint expected, out uint before) {
    before = atomicAdd(state[S_SYNC], 1u, SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsAcquireRelease);
    return (before & SYNC_ARRIVALS) + 1u == expected;
}

// Invocation 0 of the last of `expected` arrivals (`before` as arrive()
// gave it): the arrivals back at zero and the next generation, in one
// read-modify-write whose release publishes the round's finish to the
// pollers (acquire-release like every one on this word). An addition, so
// an abort bit a watchdog set meanwhile stays set.
void release_round(uint before, uint expected) {
    uint generation = before & SYNC_GENERATION;
    uint next = (generation + SYNC_GENERATION_ONE) & SYNC_GENERATION;
    atomicAdd(state[S_SYNC], next - generation - expected, SYNC_SCOPE, SYNC_STORAGE,
        gl_SemanticsAcquireRelease);
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
// (culled, back-facing, at l_max, triangles, wedges, occluded, processed,
// atomics, deepest): the last workgroup sums them, so the counters take no
// atomics.
uint block_stats(uint b) {
    return (pc.levels + 3u) * scan_words() + b * LEVEL_BLOCK_STATS;
}

// ----------------------------------------------------------------- depth 0

// Clusters of an instance of `count` patches.
uint clusters_of(uint count) {
    return (count + VISIBILITY_CLUSTER - 1u) / VISIBILITY_CLUSTER;
}

// The cluster of instance i that starts at its patch `local` (a multiple of
// VISIBILITY_CLUSTER), numbered floor(first / VISIBILITY_CLUSTER) + i +
// local / VISIBILITY_CLUSTER: distinct for every instance (instance i + 1's
// first lies past instance i's last, since floor((first + count) / n) >=
// floor(first / n) + floor((count - 1) / n)), and no cluster holds two
// instances' patches (a visible instance would draw a hidden one's early).
// At most base patches / VISIBILITY_CLUSTER + instances + 1 clusters.
uint cluster_id(uint i, uint local) {
    return instances[i].first / VISIBILITY_CLUSTER + i + local / VISIBILITY_CLUSTER;
}

// Slot k of the cluster filter's block b, and block b's scan entry.
uint cluster_slot(uint b, uint k) {
    return uint(instances.length()) + b * BLOCK + k;
}

uint cluster_scan(uint b) {
    return uint(instances.length()) + pc.cluster_blocks * BLOCK + b;
}

// The visibility set this phase reads (the last frame's verdict) and the
// one it writes (level_init flips the parity between the phases).
uint read_set() {
    uint parity = visibility[visibility_parity()];
    return pc.phase == PHASE_LATE ? parity ^ 1u : parity;
}

uint write_set() {
    return read_set() ^ 1u;
}

// ------------------------------------------------------- gathering a block

// What a block's dense indices are searched in.
const uint KEY_ROOTS = 0u;     // the instance entries' first dense index
const uint KEY_CLUSTERS = 1u;  // the cluster filter's block scan
const uint KEY_LEVEL = 2u;     // depth d's block scan, from level_scans[base]

uint search_key(uint kind, uint base, uint k) {
    if (kind == KEY_ROOTS) {
        return roots[k].y;
    }
    if (kind == KEY_CLUSTERS) {
        return roots[cluster_scan(k)].x;
    }
    return level_scans[base + k];
}

// The last k in [lo, hi) whose key is at most j (keys ascending, key(lo)
// at most j).
uint last_at_most(uint kind, uint base, uint lo, uint hi, uint j) {
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (search_key(kind, base, mid) <= j) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// Each lane's entry among the first n for its dense index j, where a
// subgroup's indices are consecutive (block_lane order): its first and
// last lanes search all n, the others only between the two entries those
// found (one or two, mostly): two searches of log2(n) dependent loads per
// subgroup instead of one per node. Whole subgroup (uniform control flow).
uint find_source(uint kind, uint base, uint n, uint j) {
    uint jf = subgroupMin(j);
    uint jl = subgroupMax(j);
    bool first = subgroupElect();
    bool last = gl_SubgroupInvocationID == subgroupMax(gl_SubgroupInvocationID);
    uint e = 0u;
    if (first || last) {
        e = last_at_most(kind, base, 0u, n, last ? jl : jf);
    }
    uint lo = subgroupMin(first ? e : 0xffffffffu);
    uint hi = subgroupMax(last ? e : 0u) + 1u;
    return last_at_most(kind, base, lo, hi, j);
}

// This round, as the last round's last workgroup left it (read by one
// invocation, shared with the workgroup).
shared uint s_level;
shared uint s_first;
shared uint s_count;
shared uint s_copy_blocks;
shared uint s_copy_base;
shared uint s_parity;
shared bool s_done;
shared uint s_level_blocks;    // the blocks of the chunk that filled s_level
shared uint s_root_instances;  // instance entries of depth 0
shared uint s_root_clusters;   // clusters of those (occlusion culling)
shared uint s_write_set;       // the visibility set this phase writes

// A depth-0 lane j: its base patch (global id), whether it has one (under
// occlusion culling a kept cluster takes VISIBILITY_CLUSTER lanes, and its
// instance's last cluster may hold fewer patches), and its cluster.
struct Root {
    uint id;
    bool present;
    uint cluster;
};

// Depth 0's lane j: without occlusion culling the j-th patch of the listed
// instances; with it, patch j % VISIBILITY_CLUSTER of kept cluster
// j / VISIBILITY_CLUSTER. Whole subgroup.
Root root_of(uint j) {
    if (pc.phase == PHASE_ALL) {
        uint r = find_source(KEY_ROOTS, 0u, s_root_instances, j);
        uvec2 e = roots[r];
        return Root(instances[e.x & ~ROOT_EARLY].first + (j - e.y), true, 0u);
    }
    uint k = j / VISIBILITY_CLUSTER;
    uint b = find_source(KEY_CLUSTERS, 0u, blocks_of(s_root_clusters), k);
    uvec2 c = roots[cluster_slot(b, k - roots[cluster_scan(b)].x)];
    uint local = c.y + j % VISIBILITY_CLUSTER;
    return Root(instances[c.x].first + local, local < instances[c.x].count, cluster_id(c.x, c.y));
}

// Node j (dense index) of depth d >= 1: the slot its block's scan entry and
// rank within the block name. Whole subgroup.
uvec2 level_node(uint d, uint j) {
    uint s = level_scan(d);
    uint b = find_source(KEY_LEVEL, s, s_level_blocks, j);
    return level_nodes[level_region(d) + b * BLOCK_SLOTS + (j - level_scans[s + b])];
}

// Sets (or clears) `mask` in visibility word `word` for every lane where
// `act` holds: one read-modify-write per distinct word among a subgroup's
// acting lanes (a subgroup's roots mostly share a cluster), and none where
// a relaxed load finds the bits so already (another subgroup of the
// cluster was first). The read-modify-writes this lane issued.
uint book_bits(bool act, uint word, uint mask, bool set) {
    uint atomics = 0u;
    if (act) {
        for (;;) {
            uint w = subgroupBroadcastFirst(word);
            if (word == w) {
                uint m = subgroupOr(mask);
                if (subgroupElect()) {
                    uint now = atomicLoad(visibility[w], SYNC_SCOPE, SYNC_STORAGE,
                        gl_SemanticsRelaxed);
                    if (set && (now & m) != m) {
                        atomicOr(visibility[w], m);
                        atomics = 1u;
                    } else if (!set && (now & m) != 0u) {
                        atomicAnd(visibility[w], ~m);
                        atomics = 1u;
                    }
                }
                break;
            }
        }
    }
    return atomics;
}

// ------------------------------------------------------------ round state

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
        s_level_blocks = state[S_LEVEL_BLOCKS + min(s_level, LEVEL_DEPTHS_MAX)];
        s_root_instances = state[S_ROOT_INSTANCES];
        s_root_clusters = state[S_ROOT_CLUSTERS];
        s_write_set = pc.phase == PHASE_ALL ? 0u : write_set();
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
// LEVEL_BLOCK_STATS statistics (the last, the deepest ready depth, is a
// maximum).
const uint VALUES = 2u + LEVEL_BLOCK_STATS;
const uint V_CHILDREN = 0u;
const uint V_READY = 1u;
const uint V_CULLED = 2u;
const uint V_BACKFACE = 3u;
const uint V_AT_LMAX = 4u;
const uint V_TRIANGLES = 5u;
const uint V_WEDGES = 6u;
const uint V_OCCLUDED = 7u;
const uint V_PROCESSED = 8u;
const uint V_ATOMICS = 9u;
const uint V_DEEPEST = VALUES - 1u;

// Per subgroup, in two sets that alternate from block to block, so one
// barrier per block is enough (a round's finish uses set 0 after a
// group_sync).
shared uint s_sub[2][VALUES][BLOCK];
uint blocks_done = 0u;

// The sum over the subgroups of what each one's elected lane wrote to
// s_sub[set][k] (the maximum for k = V_DEEPEST).
uint subgroup_total(uint set, uint k) {
    uint total = 0u;
    for (uint s = 0u; s < gl_NumSubgroups; ++s) {
        uint x = s_sub[set][k][s];
        total = k == V_DEEPEST ? max(total, x) : total + x;
    }
    return total;
}

// Whole workgroup: the exclusive prefix sums of v[V_CHILDREN] and
// v[V_READY] over the block (in block_lane order); invocation k < VALUES
// also gets the block's total of value k in `total`.
uvec2 block_reduce(uint v[VALUES], out uint total) {
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
    uint t = gl_LocalInvocationIndex;
    total = t < VALUES ? subgroup_total(set, t) : 0u;
    return uvec2(ec, er);
}

// The node's contribution to its block's totals; `nkids` children of a
// split (4 for 1:4, 2 for a 1:2 split); `atomics` the lane's visibility
// atomics.
void node_values(bool have, uvec2 q, uint outcome, uint nkids, uint atomics, out uint v[VALUES]) {
    for (uint k = 0u; k < VALUES; ++k) {
        v[k] = 0u;
    }
    v[V_ATOMICS] = atomics;
    if (!have) {
        return;
    }
    v[V_PROCESSED] = 1u;
    v[V_CHILDREN] = outcome == OUT_SPLIT ? nkids : 0u;
    v[V_CULLED] = outcome == OUT_CULLED || outcome == OUT_OCCLUDED ? 1u : 0u;
    v[V_BACKFACE] = outcome == OUT_BACKFACE ? 1u : 0u;
    v[V_OCCLUDED] = outcome == OUT_OCCLUDED ? 1u : 0u;
    if (outcome == OUT_READY) {
        uint l = node_depth(q);
        uvec2 tw = ready_triangles(q, (view.flags & FLAG_WEDGES) != 0u);
        v[V_READY] = 1u;
        v[V_AT_LMAX] = l >= view.l_max ? 1u : 0u;
        v[V_TRIANGLES] = tw.x;
        v[V_WEDGES] = tw.y;
        v[V_DEEPEST] = l;
    }
}

// Block b of this round's chunk: process its nodes, write the children
// into the block's slots of the next depth, the ready nodes into the
// block's slots of this round's scratch, and the block's totals. Whole
// workgroup (uniform control flow: the subgroup sums need every lane).
void process_block(uint b, uint t) {
    uint d = s_level;
    uint end = s_first + s_count;
    uint j = s_first + b * BLOCK + block_lane();
    bool have = j < end;
    // Lanes past the chunk search as its last node does.
    uint jc = min(j, end - 1u);
    uvec2 q;
    Root root = Root(0u, true, 0u);
    if (d == 0u) {
        root = root_of(jc);
        q = root_node(root.id);
        have = have && root.present;
    } else {
        q = level_node(d, jc);
    }
    uvec2 kids[4] = uvec2[4](uvec2(0u), uvec2(0u), uvec2(0u), uvec2(0u));
    uint nkids = 0u;
    uint outcome = OUT_CULLED;
    // The kernel's one call of the work item.
    if (have) {
        outcome = process(q, kids, nkids);
    }
    uint atomics = 0u;
    if (d == 0u && pc.phase != PHASE_ALL) {
        bool visible = have && (outcome == OUT_READY || outcome == OUT_SPLIT);
        uvec2 bit = cluster_bit(root.cluster, s_write_set);
        atomics = book_bits(visible, bit.x, bit.y, true);
    }
    uint v[VALUES];
    node_values(have, q, outcome, nkids, atomics, v);
    uint total;
    uvec2 at = block_reduce(v, total);
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
    if (t == V_CHILDREN) {
        level_scans[level_scan(d + 1u) + b] = total;
    } else if (t == V_READY) {
        level_scans[ready_scan(s_parity) + b] = total;
    } else if (t < VALUES) {
        level_scans[block_stats(b) + t - V_CULLED] = total;
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
// left (the highest bit of S_PENDING; none: only the copy of
// `copy_blocks`, or nothing), and its dispatch arguments.
void schedule(uint copy_blocks) {
    uint pending = state[S_PENDING];
    uint level = 0u, first = 0u, n = 0u;
    if (pending != 0u) {
        level = uint(findMSB(pending));
        uint next = state[S_LEVEL_NEXT + level];
        uint count = state[S_LEVEL_COUNT + level];
        first = next;
        n = min(pc.chunk, count - next);
        state[S_LEVEL_NEXT + level] = next + n;
        if (next + n == count) {
            state[S_PENDING] = pending & ~(1u << level);
        }
        state[S_SPLIT_ROUNDS] += count > pc.chunk ? 1u : 0u;
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

// Depth 0 holds `count` nodes (lanes): booked and scheduled. Invocation 0.
void schedule_depth0(uint count) {
    state[S_LEVEL_COUNT] = count;
    state[S_LEVEL_NEXT] = 0u;
    state[S_PENDING] = count > 0u ? 1u : 0u;
    schedule(0u);
}

// The round's totals, as its last workgroup found them: the statistics
// (after scan_round) and what finish_round decided.
shared uint s_stat[LEVEL_BLOCK_STATS];
shared uint s_args_first;
shared uint s_args_count;
shared bool s_finished;
// The visibility atomics the round's blocks issued (the caller counts them).
shared uint s_round_atomics;

// The counter each statistic goes to, in LEVEL_BLOCK_STATS order (the
// atomics go to the caller, the deepest depth is a maximum).
uint stat_counter(uint k) {
    const uint c[LEVEL_BLOCK_STATS] = uint[LEVEL_BLOCK_STATS](C_CULLED, C_BACKFACE, C_AT_LMAX,
        C_TRIANGLES, C_WEDGES, C_OCCLUDED, C_PROCESSED, C_GLOBAL_ATOMICS, C_MAX_DEPTH);
    return c[k];
}

// Whole workgroup (the last to arrive, after its acquire): one pass over
// the round's nb block totals. Every invocation sums a run of at most
// BLOCK blocks (the plan caps a chunk at LEVEL_MAX_CHUNK nodes), the
// workgroup scans the runs' children and ready counts and reduces their
// statistics into s_stat, and every invocation writes its run's exclusive
// offsets back. Returns the children and ready totals.
uvec2 scan_round(uint d, uint nb, uint t) {
    uint cs = level_scan(d + 1u);
    uint rs = ready_scan(s_parity);
    uint per = (nb + BLOCK - 1u) / BLOCK;
    uint lo = min(block_lane() * per, nb);
    uint hi = min(lo + per, nb);
    uvec2 own = uvec2(0u);
    uint st[LEVEL_BLOCK_STATS];
    for (uint k = 0u; k < LEVEL_BLOCK_STATS; ++k) {
        st[k] = 0u;
    }
    const uint last = LEVEL_BLOCK_STATS - 1u;
    for (uint i = lo; i < hi; ++i) {
        own += uvec2(level_scans[cs + i], level_scans[rs + i]);
        uint at = block_stats(i);
        for (uint k = 0u; k < last; ++k) {
            st[k] += level_scans[at + k];
        }
        st[last] = max(st[last], level_scans[at + last]);
    }
    // The statistics: subgroup sums, then one invocation per statistic.
    for (uint k = 0u; k < last; ++k) {
        st[k] = subgroupAdd(st[k]);
    }
    st[last] = subgroupMax(st[last]);
    if (subgroupElect()) {
        for (uint k = 0u; k < LEVEL_BLOCK_STATS; ++k) {
            s_sub[0][V_CULLED + k][gl_SubgroupID] = st[k];
        }
    }
    barrier();
    if (t < LEVEL_BLOCK_STATS) {
        s_stat[t] = subgroup_total(0u, V_CULLED + t);
    }
    uvec4 ia, ib, ta, tb;
    workgroup_scan(uvec4(own, 0u, 0u), uvec4(0u), ia, ib, ta, tb);
    uvec2 run = ia.xy - own;
    for (uint i = lo; i < hi; ++i) {
        uvec2 v = uvec2(level_scans[cs + i], level_scans[rs + i]);
        level_scans[cs + i] = run.x;
        level_scans[rs + i] = run.y;
        run += v;
    }
    if (t == 0u) {
        level_scans[cs + nb] = ta.x;
        level_scans[rs + nb] = ta.y;
    }
    return ta.xy;
}

// The last workgroup of a round: scans its block totals, books the chunk's
// children as the next depth's content and schedules the next round; once
// the schedule is done, writes the draw's arguments (whole workgroup). After
// the acquire that made every block's writes visible; s_round_atomics holds
// the round's visibility atomics after it.
void finish_round(uint t) {
    uint d = s_level;
    uint n = s_count;
    uint nb = blocks_of(n);
    uvec2 totals = uvec2(0u);
    if (n > 0u) {
        totals = scan_round(d, nb, t);
    }
    if (t == 0u) {
        uint processed = 0u;
        s_round_atomics = 0u;
        if (n > 0u) {
            for (uint k = 0u; k + 1u < LEVEL_BLOCK_STATS; ++k) {
                if (k + V_CULLED == V_ATOMICS) {
                    s_round_atomics = s_stat[k];
                } else {
                    counters[stat_counter(k)] += s_stat[k];
                }
            }
            uint deepest = LEVEL_BLOCK_STATS - 1u;
            counters[C_MAX_DEPTH] = max(counters[C_MAX_DEPTH], s_stat[deepest]);
            processed = s_stat[V_PROCESSED - V_CULLED];
        }
        state[S_VISIBILITY_ATOMICS] += s_round_atomics;
        uint found = state[S_READY];
        state[S_COPY_BASE] = found;
        state[S_READY] = found + totals.y;
        state[S_DEPTH_NODES + d] += processed;
        if (totals.x > 0u && d < pc.levels) {
            // Depth d + 1 is empty: the schedule only comes back to depth d
            // once every deeper depth is used up.
            state[S_LEVEL_COUNT + d + 1u] = totals.x;
            state[S_LEVEL_NEXT + d + 1u] = 0u;
            state[S_LEVEL_BLOCKS + d + 1u] = nb;
            state[S_PENDING] |= 1u << (d + 1u);
            state[S_PEAK_NODES] = max(state[S_PEAK_NODES], totals.x);
        }
        state[S_ROUND] += 1u;
        schedule(totals.y > 0u ? nb : 0u);
        uint total = found + totals.y;
        counters[C_READY_COUNT] = total;
        if (total > pc.ready_capacity) {
            atomicOr(counters[C_ERROR], ERR_READY_FULL);
        }
        s_finished = state[S_DONE] != 0u;
        s_args_first = ready_first();
        s_args_count = min(total, pc.ready_capacity);
    }
    group_sync();
    // The draw reads its arguments once the schedule is done; until then
    // they are the empty draw level_init wrote.
    if (s_finished) {
        write_ready_args_by(s_args_first, s_args_count, t, BLOCK);
    }
    group_sync();
}

#endif
