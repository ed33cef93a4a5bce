// Sorts the ready list by (base patch, node bits), ascending. Producers
// append ready nodes in an order that depends on thread timing; where two
// triangles meet at exactly the same depth the first one drawn wins, so a
// canonical order is what makes the same frame give the same image every
// run. Keys are unique (a node's patch, depth, m and n identify it), so the
// order is a function of the ready set alone. Sorting by patch also keeps a
// patch's control points hot in caches while it is drawn.
//
// A merge sort sized by the list's actual length n: the producer writes the
// dispatch arguments of every pass (write_ready_args), a merge pass whose
// runs already span the list gets none, and the direction of every pass
// follows from n here, so the last pass that runs lands in `ready`.
// Recorded by src/draw/sort.rs (only the queue kernel needs it: the level
// kernels write the list in a canonical order):
//   BLOCK: each workgroup sorts a block of SORT_BLOCK entries in shared
//          memory (a bitonic network; entries past the end count as the
//          largest key and are not written back);
//   MERGE: one invocation per entry merges pairs of sorted runs of width
//          pc.k into runs of 2 * pc.k, finding where its output comes from
//          by a binary search along the merge path.
// Passes alternate between `ready` and `sort_temp`.
#version 460

#define USE_READY_RW
#define USE_SORT_TEMP
#define USE_LIST_PUSH
#include "common/ready.glsl"

layout(local_size_x = SORT_GROUP_SIZE) in;

const uint MODE_BLOCK = 0u;
const uint MODE_MERGE = 1u;

shared uvec2 block[SORT_BLOCK];

bool less(uvec2 a, uvec2 b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
}

// Merge passes n entries need: runs start at SORT_BLOCK and double until
// one spans the list (src/draw/sort.rs merge_passes).
uint passes_needed(uint n) {
    uint p = 0u;
    for (uint run = SORT_BLOCK; run < n; run *= 2u) {
        p += 1u;
    }
    return p;
}

// Whether this pass reads `sort_temp` (else `ready`) and so writes the
// other: the block pass starts where an even number of merges ends in
// `ready`, merge pass i (runs of SORT_BLOCK << i) reads what pass i - 1 wrote.
bool from_temp = false;

uvec2 read_src(uint i) {
    return from_temp ? sort_temp[i] : ready[i];
}

void write_dst(uint i, uvec2 v) {
    if (from_temp) {
        ready[i] = v;
    } else {
        sort_temp[i] = v;
    }
}

// The block pass reads `ready`; it writes `sort_temp` when an odd number
// of merges follows, else back into `ready`.
void write_block(uint i, uvec2 v, uint passes) {
    if (passes % 2u == 1u) {
        sort_temp[i] = v;
    } else {
        ready[i] = v;
    }
}

// Orders the pair (i, i + j) of bitonic stage k: ascending where bit k of
// i is clear, descending where it is set.
void order(uint i, uint j, uint k) {
    uvec2 a = block[i];
    uvec2 b = block[i + j];
    if (less(b, a) == ((i & k) == 0u)) {
        block[i] = b;
        block[i + j] = a;
    }
}

void sort_block(uint n, uint passes) {
    uint base = gl_WorkGroupID.x * SORT_BLOCK;
    uint lt = gl_LocalInvocationID.x;
    for (uint h = 0u; h < 2u; ++h) {
        uint i = lt + h * SORT_GROUP_SIZE;
        block[i] = base + i < n ? ready[base + i] : uvec2(0xffffffffu);
    }
    barrier();
    for (uint k = 2u; k <= SORT_BLOCK; k *= 2u) {
        for (uint j = k / 2u; j > 0u; j /= 2u) {
            order(2u * j * (lt / j) + (lt % j), j, k);
            barrier();
        }
    }
    for (uint h = 0u; h < 2u; ++h) {
        uint i = lt + h * SORT_GROUP_SIZE;
        if (base + i < n) {
            write_block(base + i, block[i], passes);
        }
    }
}

void merge(uint n) {
    uint i = gl_GlobalInvocationID.x;
    if (i >= n) {
        return;
    }
    uint w = pc.k;
    uint a0 = (i / (2u * w)) * (2u * w);
    uint a_len = min(w, n - a0);
    uint b0 = a0 + a_len;
    uint b_len = min(w, n - b0);
    uint k = i - a0;
    // How many of the first k outputs of the pair come from run A.
    uint lo = k > b_len ? k - b_len : 0u;
    uint hi = min(k, a_len);
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        if (less(read_src(a0 + mid), read_src(b0 + k - mid - 1u))) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    uint a = lo;
    uint b = k - a;
    bool take_a = b >= b_len || (a < a_len && less(read_src(a0 + a), read_src(b0 + b)));
    write_dst(i, take_a ? read_src(a0 + a) : read_src(b0 + b));
}

void main() {
    uint n = ready_count(pc.ready_capacity);
    uint passes = passes_needed(n);
    if (pc.mode == MODE_BLOCK) {
        sort_block(n, passes);
    } else {
        // Merge pass i reads sort_temp when passes - i is odd.
        uint i = findMSB(pc.k / SORT_BLOCK);
        from_temp = (passes - i) % 2u == 1u;
        merge(n);
    }
}
