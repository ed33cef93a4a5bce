// Method subdiv-indirect, the paper's execute-indirect variant (§4.1): one
// dispatch per depth. Every node of depth pc.level is processed exactly as
// the persistent kernel and the oracle do (common/process.glsl): culled,
// ready (appended to the ready list) or split (its four children appended to
// the other node buffer, as depth pc.level + 1). Appends take one atomic per
// subgroup. A depth whose children do not fit the node buffer sets
// ERR_LEVEL_FULL and keeps counting, so the host knows what was needed and
// never draws an incomplete frame.
//
// Depth 0 reads the base patches themselves (node i is patch i); a
// dispatch has at most pc.max_groups workgroups and its invocations loop
// over the rest.
#version 460
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#define USE_READY_WRITE
#include "common/ready.glsl"
#include "common/process.glsl"
#include "common/level.glsl"

layout(local_size_x = LEVEL_GROUP_SIZE) in;

uvec2 node_at(uint d, uint i) {
    if (d == 0u) {
        return uvec2(i, 0u);
    }
    return (d & 1u) == 1u ? nodes_odd[i] : nodes_even[i];
}

// Appends the subgroup's children (4 per splitting lane) with one atomic.
void append_children(bool split, uvec2 kids[4]) {
    uvec4 b = subgroupBallot(split);
    uint n = subgroupBallotBitCount(b);
    if (n == 0u) {
        return;
    }
    uint d = pc.level + 1u;
    uint base = 0u;
    if (subgroupElect()) {
        base = atomicAdd(levels[L_COUNTS + d], 4u * n);
    }
    base = subgroupBroadcastFirst(base);
    if (!split) {
        return;
    }
    uint first = base + 4u * subgroupBallotExclusiveBitCount(b);
    if (first + 4u > level_capacity(d)) {
        atomicOr(counters[C_ERROR], ERR_LEVEL_FULL);
        return;
    }
    for (uint k = 0u; k < 4u; ++k) {
        if ((d & 1u) == 1u) {
            nodes_odd[first + k] = kids[k];
        } else {
            nodes_even[first + k] = kids[k];
        }
    }
}

// Appends the subgroup's ready nodes with one atomic.
void append_ready(bool is_ready, uvec2 q) {
    uvec4 b = subgroupBallot(is_ready);
    uint n = subgroupBallotBitCount(b);
    if (n == 0u) {
        return;
    }
    uint base = 0u;
    if (subgroupElect()) {
        base = atomicAdd(counters[C_READY_COUNT], n);
    }
    base = subgroupBroadcastFirst(base);
    if (is_ready) {
        uint idx = base + subgroupBallotExclusiveBitCount(b);
        if (idx < pc.ready_capacity) {
            ready[idx] = q;
        } else {
            atomicOr(counters[C_ERROR], ERR_READY_FULL);
        }
    }
}

void add_counter(uint index, uint value) {
    uint sum = subgroupAdd(value);
    if (subgroupElect() && sum != 0u) {
        atomicAdd(counters[index], sum);
    }
}

void main() {
    uint d = pc.level;
    uint count = level_count(d);
    uint stride = gl_NumWorkGroups.x * LEVEL_GROUP_SIZE;
    bool with_wedges = (view.flags & FLAG_WEDGES) != 0u;
    uint processed = 0u, culled = 0u, backface = 0u, at_lmax = 0u, tris = 0u, wedges = 0u;
    uint deepest = 0u;
    // Every lane runs the same number of rounds, so the subgroup operations
    // inside see all lanes; lanes past the end take part with no item.
    uint rounds = (count + stride - 1u) / stride;
    for (uint r = 0u; r < rounds; ++r) {
        uint i = gl_GlobalInvocationID.x + r * stride;
        bool have = i < count;
        uvec2 q = have ? node_at(d, i) : uvec2(0u);
        uvec2 kids[4];
        uint outcome = OUT_CULLED;
        if (have) {
            outcome = process(q, kids);
            processed += 1u;
            culled += outcome == OUT_CULLED ? 1u : 0u;
            backface += outcome == OUT_BACKFACE ? 1u : 0u;
            if (outcome == OUT_READY) {
                deepest = max(deepest, d);
                at_lmax += d >= view.l_max ? 1u : 0u;
                uvec2 tw = ready_triangles(q, with_wedges);
                tris += tw.x;
                wedges += tw.y;
            }
        }
        append_children(have && outcome == OUT_SPLIT, kids);
        append_ready(have && outcome == OUT_READY, q);
    }
    add_counter(C_PROCESSED, processed);
    add_counter(C_CULLED, culled);
    add_counter(C_BACKFACE, backface);
    add_counter(C_AT_LMAX, at_lmax);
    add_counter(C_TRIANGLES, tris);
    add_counter(C_WEDGES, wedges);
    uint m = subgroupMax(deepest);
    if (subgroupElect() && m != 0u) {
        atomicMax(counters[C_MAX_DEPTH], m);
    }
}
