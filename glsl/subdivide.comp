// The recursive subdivision of every base patch down to l_max, in ONE
// dispatch of persistent workgroups: the Vulkan stand-in for the paper's
// work-graph recursion (§3.5).
//
// Work items are QuadNodes. Each invocation keeps its own depth-first stack
// (a small deque in private memory): it pops the newest item, processes it
// exactly as src/patch/oracle.rs `process` does, and pushes the four children
// back on top, so a subtree of depth l_max never needs more than
// 3 * l_max + 1 = STACK_SIZE entries. Base patches are the implicit first
// items, claimed from a counter one subgroup batch at a time. Global atomics
// are few per item: ready-list appends and in-flight updates are aggregated
// per subgroup and per iteration. The global queue is only for balance: when
// some invocation is idle, a busy one donates the bottom (largest) item of
// its stack. A full queue (or a contended one) just keeps the item local and
// counts a spill; it never draws a node early, which would open a crack.
//
// Termination: the low bits of counters[C_IN_FLIGHT] (IN_FLIGHT_MASK) start
// at the number of base patches (set by the host) and every processed item
// adds +3 (split) or -1 (done), applied only after its children are on a
// stack or in the queue, so they never read 0 while work exists. An invocation without work polls the queue and
// the counter ONCE per outer iteration (no nested spin: the lanes of a
// subgroup run in lockstep, and a lane spinning on work its own subgroup must
// produce would never return) and leaves when the counter reads 0.
//
// Forward progress: Vulkan promises none between workgroups, so nothing here
// ever waits on a workgroup that may not have started. Work lives only in
// the stacks of running invocations, in the queue, or in unclaimed base
// patches; any running invocation can take queued or unclaimed work, and an
// invocation only waits (polls) while the counter says some other RUNNING
// invocation still holds work, which that invocation will finish by itself if
// nobody helps. A workgroup that starts late finds the work taken and exits.
// The host launches about as many workgroups as the device keeps resident,
// which makes the balance good, not the result correct.
//
// Iteration cap: an invocation that sees the in-flight counter unchanged for
// pc.idle_poll_cap consecutive polls concludes that nothing anywhere is making
// progress, raises ERR_ITERATION_CAP and leaves; the host reports the error
// (and never hangs: its fence wait has a timeout too).
#version 460
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_vote : require

#define USE_READY_WRITE
#include "common/ready.glsl"
#include "common/process.glsl"

layout(local_size_x = SUBDIV_GROUP_SIZE) in;

// Set 2: the work queue (src/methods/subdiv.rs).
layout(std430, set = SET_PRODUCER, binding = BIND_QUEUE_ITEMS) coherent buffer QueueItems {
    uvec2 queue_items[];
};
layout(std430, set = SET_PRODUCER, binding = BIND_QUEUE_SEQS) coherent buffer QueueSeqs {
    uint queue_seqs[];
};

// src/gpu/blocks.rs SubdivPush.
layout(push_constant) uniform SubdivPush {
    uint ready_capacity;  // entries in `ready`
    uint queue_capacity;  // entries in the work queue
    uint patch_count;     // base patches
    uint idle_poll_cap;   // polls without progress before giving up
} pc;

// Deque slots: STACK_SIZE (3 * L_MAX + 1) rounded up to a power of two, so
// that index & STACK_MASK wraps the deque.
const uint STACK_SLOTS = STACK_SIZE + 1u;
const uint STACK_MASK = STACK_SLOTS - 1u;

uint atomic_load(uint index) {
    return atomicAdd(counters[index], 0u);
}

// Bounded MPMC ring (sequence numbers per slot, after Vyukov): neither side
// ever waits for the other; a slot not yet published reads as empty, a slot
// not yet consumed reads as full. A few bounded retries on contention.
bool queue_push(uvec2 item) {
    uint cap = pc.queue_capacity;
    uint pos = atomic_load(C_QUEUE_TAIL);
    for (int tries = 0; tries < 4; ++tries) {
        uint slot = pos % cap;
        int dif = int(atomicAdd(queue_seqs[slot], 0u) - pos);
        if (dif == 0) {
            uint prev = atomicCompSwap(counters[C_QUEUE_TAIL], pos, pos + 1u);
            if (prev == pos) {
                queue_items[slot] = item;
                memoryBarrierBuffer();
                atomicExchange(queue_seqs[slot], pos + 1u);
                uint occupied = pos + 1u - atomic_load(C_QUEUE_HEAD);
                atomicMax(counters[C_QUEUE_PEAK], occupied);
                return true;
            }
            pos = prev;
        } else if (dif < 0) {
            return false;
        } else {
            pos = atomic_load(C_QUEUE_TAIL);
        }
    }
    return false;
}

bool queue_pop(out uvec2 item) {
    uint cap = pc.queue_capacity;
    item = uvec2(0u);
    uint pos = atomic_load(C_QUEUE_HEAD);
    for (int tries = 0; tries < 4; ++tries) {
        uint slot = pos % cap;
        int dif = int(atomicAdd(queue_seqs[slot], 0u) - (pos + 1u));
        if (dif == 0) {
            uint prev = atomicCompSwap(counters[C_QUEUE_HEAD], pos, pos + 1u);
            if (prev == pos) {
                memoryBarrierBuffer();
                item = queue_items[slot];
                memoryBarrierBuffer();
                atomicExchange(queue_seqs[slot], pos + cap);
                return true;
            }
            pos = prev;
        } else if (dif < 0) {
            return false;
        } else {
            pos = atomic_load(C_QUEUE_HEAD);
        }
    }
    return false;
}

// Adds `value` summed over the active lanes of the subgroup with one atomic.
void subgroup_add_counter(uint index, uint value) {
    uint sum = subgroupAdd(value);
    if (subgroupElect() && sum != 0u) {
        atomicAdd(counters[index], sum);
    }
}

void subgroup_max_counter(uint index, uint value) {
    uint m = subgroupMax(value);
    if (subgroupElect() && m != 0u) {
        atomicMax(counters[index], m);
    }
}

// One invocation's state across iterations: its depth-first deque
// [lo, hi) (slot = index & STACK_MASK), whether base patches may be left,
// its idle flag and stall count, and its statistics (summed per subgroup
// at the end).
struct Lane {
    uint lo;
    uint hi;
    bool bases_left;
    bool idle;
    uint stalls;
    uint last_in_flight;
    uint processed;
    uint culled;
    uint backface;
    uint at_lmax;
    uint spills;
    uint pushed;
    uint tris;
    uint wedges;
    uint deepest;
    uint iterations;
};

uvec2 stack[STACK_SLOTS];

// The next item: the top of the own stack, else a base patch (one claim per
// subgroup for all lanes that want one), else the global queue.
bool take_item(inout Lane st, out uvec2 item) {
    item = uvec2(0u);
    bool have = false;
    if (st.hi != st.lo) {
        st.hi -= 1u;
        item = stack[st.hi & STACK_MASK];
        have = true;
    }
    bool want_base = !have && st.bases_left;
    uvec4 want = subgroupBallot(want_base);
    uint n_want = subgroupBallotBitCount(want);
    if (n_want > 0u) {
        uint first = 0u;
        if (subgroupElect()) {
            first = atomicAdd(counters[C_NEXT_BASE], n_want);
        }
        first = subgroupBroadcastFirst(first);
        if (want_base) {
            uint id = first + subgroupBallotExclusiveBitCount(want);
            if (id < pc.patch_count) {
                item = uvec2(id, 0u);
                have = true;
            } else {
                st.bases_left = false;
            }
        }
    }
    if (!have && !st.bases_left) {
        have = queue_pop(item);
    }
    return have;
}

// Counts a processed item's outcome; a split pushes the children on the
// own stack. Returns false when the stack would overflow.
bool settle(inout Lane st, uvec2 item, uint outcome, uvec2 kids[4], bool with_wedges) {
    st.processed += 1u;
    if (outcome == OUT_SPLIT) {
        if (st.hi - st.lo + 4u > STACK_SLOTS) {
            atomicOr(counters[C_ERROR], ERR_STACK_OVERFLOW);
            return false;
        }
        for (int k = 3; k >= 0; --k) {
            stack[st.hi & STACK_MASK] = kids[k];
            st.hi += 1u;
        }
    } else if (outcome == OUT_CULLED) {
        st.culled += 1u;
    } else if (outcome == OUT_BACKFACE) {
        st.backface += 1u;
    } else {
        uint l = node_depth(item);
        st.deepest = max(st.deepest, l);
        st.at_lmax += l >= view.l_max ? 1u : 0u;
        uvec2 tw = ready_triangles(item, with_wedges);
        st.tris += tw.x;
        st.wedges += tw.y;
    }
    return true;
}

// Appends the subgroup's ready nodes with one atomic.
void append_ready(bool is_ready, uvec2 item) {
    uvec4 rb = subgroupBallot(is_ready);
    uint n_ready = subgroupBallotBitCount(rb);
    if (n_ready == 0u) {
        return;
    }
    uint base = 0u;
    if (subgroupElect()) {
        base = atomicAdd(counters[C_READY_COUNT], n_ready);
    }
    base = subgroupBroadcastFirst(base);
    if (is_ready) {
        uint idx = base + subgroupBallotExclusiveBitCount(rb);
        if (idx < pc.ready_capacity) {
            ready[idx] = item;
        } else {
            atomicOr(counters[C_ERROR], ERR_READY_FULL);
        }
    }
}

// Donates the bottom of a deep stack while someone is idle: one donor per
// subgroup and iteration (lanes of a subgroup run in lockstep, so several
// would only race for the same queue slot).
void donate(inout Lane st) {
    uint idle_now = 0u;
    if (subgroupElect()) {
        idle_now = atomic_load(C_IDLE);
    }
    idle_now = subgroupBroadcastFirst(idle_now);
    bool stress = (view.flags & FLAG_QUEUE_STRESS) != 0u;
    bool can_donate = (idle_now > 0u || stress) && st.hi - st.lo >= 2u;
    uvec4 donors = subgroupBallot(can_donate);
    if (can_donate && gl_SubgroupInvocationID == subgroupBallotFindLSB(donors)) {
        if (queue_push(stack[st.lo & STACK_MASK])) {
            st.lo += 1u;
            st.pushed += 1u;
        } else {
            st.spills += 1u;
        }
    }
}

// In-flight bookkeeping, after the children are on a stack or queued and
// after the ready entries are written: +3 per split, -1 per finished item,
// one atomic per subgroup that did any work, plus a progress tick in the
// top byte so the idle pollers see progress even when the deltas cancel.
void publish_progress(bool have, uint outcome) {
    memoryBarrierBuffer();
    int delta = have ? (outcome == OUT_SPLIT ? 3 : -1) : 0;
    int sum = subgroupAdd(delta);
    bool worked = subgroupAny(have);
    if (subgroupElect() && worked) {
        atomicAdd(counters[C_IN_FLIGHT], uint(sum) + IN_FLIGHT_TICK);
    }
}

const uint POLL_WORK = 0u;   // keep going
const uint POLL_DONE = 1u;   // nothing in flight anywhere: leave
const uint POLL_STUCK = 2u;  // no progress for the whole cap: give up

// An invocation without work: marks itself idle and polls the in-flight
// counter once (never spinning inside an iteration).
uint poll_idle(inout Lane st) {
    if (!st.idle) {
        st.idle = true;
        atomicAdd(counters[C_IDLE], 1u);
    }
    uint in_flight = atomic_load(C_IN_FLIGHT);
    if ((in_flight & IN_FLIGHT_MASK) == 0u) {
        return POLL_DONE;
    }
    if (in_flight == st.last_in_flight) {
        st.stalls += 1u;
        if (st.stalls > pc.idle_poll_cap) {
            atomicOr(counters[C_ERROR], ERR_ITERATION_CAP);
            return POLL_STUCK;
        }
    } else {
        st.stalls = 0u;
        st.last_in_flight = in_flight;
    }
    return POLL_WORK;
}

// The invocation's statistics into the counters, one atomic per subgroup.
void flush_stats(Lane st) {
    subgroup_add_counter(C_PROCESSED, st.processed);
    subgroup_add_counter(C_CULLED, st.culled);
    subgroup_add_counter(C_BACKFACE, st.backface);
    subgroup_add_counter(C_AT_LMAX, st.at_lmax);
    subgroup_add_counter(C_SPILLS, st.spills);
    subgroup_add_counter(C_QUEUE_PUSHED, st.pushed);
    subgroup_add_counter(C_TRIANGLES, st.tris);
    subgroup_add_counter(C_WEDGES, st.wedges);
    subgroup_max_counter(C_MAX_DEPTH, st.deepest);
    subgroup_max_counter(C_ITERATIONS_MAX, st.iterations);
}

void main() {
    Lane st = Lane(0u, 0u, true, false, 0u, 0xffffffffu, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
    bool with_wedges = (view.flags & FLAG_WEDGES) != 0u;
    bool normal_exit = false;
    for (;;) {
        st.iterations += 1u;
        uvec2 item;
        bool have = take_item(st, item);
        uint outcome = OUT_CULLED;
        if (have) {
            if (st.idle) {
                st.idle = false;
                atomicAdd(counters[C_IDLE], 0xffffffffu);
            }
            uvec2 kids[4];
            outcome = process(item, kids);
            if (!settle(st, item, outcome, kids, with_wedges)) {
                break;
            }
        }
        append_ready(have && outcome == OUT_READY, item);
        donate(st);
        publish_progress(have, outcome);
        if (!have) {
            uint poll = poll_idle(st);
            if (poll != POLL_WORK) {
                normal_exit = poll == POLL_DONE;
                break;
            }
        }
    }
    flush_stats(st);
    if (normal_exit && subgroupElect()) {
        memoryBarrierBuffer();
        write_ready_args(min(atomic_load(C_READY_COUNT), pc.ready_capacity));
    }
}
