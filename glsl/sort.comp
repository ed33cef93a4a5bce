// Sorts the ready list by (base patch, node bits), ascending: a bitonic sort
// over the list padded to a power of two (counters[C_SORT_LENGTH]) with the
// largest key. The persistent kernel appends ready nodes in an order that
// depends on thread timing; where two triangles meet at exactly the same
// depth the first one drawn wins, so a canonical order is what makes the
// same frame give the same image every run. Sorting by patch also keeps a
// patch's control points hot in caches while it is drawn.
//
// Passes (pc.mode), each one dispatch, recorded by src/draw/sort.rs:
//   FILL:   entries [count, length) get the largest key;
//   BLOCK:  each block of SORT_BLOCK entries runs the steps j < SORT_BLOCK of
//           stage k in shared memory (k = 0: every stage up to SORT_BLOCK);
//   GLOBAL: one compare-exchange step (k, j) over the whole list.
// Passes for stages beyond the list's length do nothing; the host records
// the passes for the list's capacity and the GPU knows the length.
#version 460

#define USE_READY_RW
#define USE_LIST_PUSH
#include "common/ready.glsl"

layout(local_size_x = SORT_GROUP_SIZE) in;

const uint MODE_FILL = 0u;
const uint MODE_BLOCK = 1u;
const uint MODE_GLOBAL = 2u;

shared uvec2 block[SORT_BLOCK];

bool less(uvec2 a, uvec2 b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
}

// Orders the pair (i, l = i + j) of stage k: ascending where bit k of i is
// clear, descending where it is set.
void order(inout uvec2 a, inout uvec2 b, uint i, uint k) {
    bool ascending = (i & k) == 0u;
    if (less(b, a) == ascending) {
        uvec2 t = a;
        a = b;
        b = t;
    }
}

void main() {
    uint len = counters[C_SORT_LENGTH];
    uint t = gl_GlobalInvocationID.x;
    if (pc.mode == MODE_FILL) {
        uint i = min(counters[C_READY_COUNT], pc.ready_capacity) + t;
        if (i < len) {
            ready[i] = uvec2(0xffffffffu);
        }
        return;
    }
    if (pc.k > len) {
        return;
    }
    if (pc.mode == MODE_GLOBAL) {
        uint i = 2u * pc.j * (t / pc.j) + (t % pc.j);
        uint l = i + pc.j;
        if (l < len) {
            uvec2 a = ready[i];
            uvec2 b = ready[l];
            order(a, b, i, pc.k);
            ready[i] = a;
            ready[l] = b;
        }
        return;
    }
    // MODE_BLOCK: the block of this workgroup, in shared memory.
    uint base = gl_WorkGroupID.x * SORT_BLOCK;
    uint lt = gl_LocalInvocationID.x;
    block[lt] = ready[base + lt];
    block[lt + SORT_GROUP_SIZE] = ready[base + lt + SORT_GROUP_SIZE];
    barrier();
    uint k_first = pc.k == 0u ? 2u : pc.k;
    uint k_last = pc.k == 0u ? SORT_BLOCK : pc.k;
    for (uint k = k_first; k <= k_last; k *= 2u) {
        for (uint j = min(k, SORT_BLOCK) / 2u; j > 0u; j /= 2u) {
            uint i = 2u * j * (lt / j) + (lt % j);
            uvec2 a = block[i];
            uvec2 b = block[i + j];
            order(a, b, base + i, k);
            block[i] = a;
            block[i + j] = b;
            barrier();
        }
    }
    ready[base + lt] = block[lt];
    ready[base + lt + SORT_GROUP_SIZE] = block[lt + SORT_GROUP_SIZE];
}
