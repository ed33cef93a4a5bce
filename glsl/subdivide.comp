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
#define USE_QUEUE
#include "common/scene.glsl"

layout(local_size_x = SUBDIV_GROUP_SIZE) in;

const uint STACK_MASK = 31u;  // deque slots: 32 >= STACK_SIZE

const uint OUT_CULLED = 0u;
const uint OUT_BACKFACE = 1u;
const uint OUT_READY = 2u;
const uint OUT_SPLIT = 3u;

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

// One work item: the GPU twin of oracle::process. Returns OUT_*; for
// OUT_SPLIT the children are in `kids`, in the order (0,0), (1,0), (0,1), (1,1).
uint process(uvec2 q, out uvec2 kids[4]) {
    kids = uvec2[4](uvec2(0u), uvec2(0u), uvec2(0u), uvec2(0u));
    vec3 P[16];
    load_patch(q.x, P);
    vec4 dom = node_domain(q);
    vec3 S[16];
    reconstruct(P, dom.x, dom.y, dom.z, dom.w, S);
    vec3 lo, hi;
    patch_bbox(S, lo, hi);
    vec2 pivot_u, pivot_v;
    bvec2 pivots = wedge_pivots(q, pivot_u, pivot_v);
    if ((view.flags & FLAG_FRUSTUM_CULL) != 0u) {
        // The box must also hold the wedge pivots of the node's outer edges:
        // its wedges and its descendants' reach them (see oracle::process).
        vec3 clo = lo, chi = hi;
        if (pivots.x) {
            vec3 p = eval_patch(P, pivot_u.x, pivot_u.y);
            clo = min3(clo, p);
            chi = max3(chi, p);
        }
        if (pivots.y) {
            vec3 p = eval_patch(P, pivot_v.x, pivot_v.y);
            clo = min3(clo, p);
            chi = max3(chi, p);
        }
        if (outside_frustum(clo, chi, view)) {
            return OUT_CULLED;
        }
    }
    uint l = node_depth(q);
    if (l < view.l_max) {
        uvec4 depths = edge_depths(q);
        bvec4 flat_now = bvec4(true);
        bool edges_flat = true;
        // Every pending edge is tested, no early exit: children inherit them.
        for (uint e = 0u; e < 4u; ++e) {
            if (depths[e] >= l) {
                vec3 c[4];
                patch_edge(S, e, c);
                flat_now[e] = edge_flat(c, view);
                edges_flat = edges_flat && flat_now[e];
            }
        }
        if (!edges_flat || !inner_flat(S, view)) {
            uvec4 r = resolve_depths(l, depths, flat_now);
            kids[0] = child_node(q, r, 0u, 0u);
            kids[1] = child_node(q, r, 1u, 0u);
            kids[2] = child_node(q, r, 0u, 1u);
            kids[3] = child_node(q, r, 1u, 1u);
            return OUT_SPLIT;
        }
    }
    // A back-facing node goes only if its wedges face away too (see
    // cull::wedges_face_away).
    bool one_sided = (patch_flags[q.x] & PATCH_TWO_SIDED) == 0u;
    bool with_wedges = (view.flags & FLAG_WEDGES) != 0u;
    if ((view.flags & FLAG_BACKFACE_CULL) != 0u && one_sided && back_facing(S, lo, hi, view.eye.xyz)
        && wedges_face_away(P, q, view.eye.xyz, with_wedges)) {
        return OUT_BACKFACE;
    }
    return OUT_READY;
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

void write_indirect_args() {
    memoryBarrierBuffer();
    uint n = min(atomic_load(C_READY_COUNT), pc.ready_capacity);
    counters[C_MESH_ARGS] = (n + MESH_NODES * TASK_MESH_GROUPS - 1u) / (MESH_NODES * TASK_MESH_GROUPS);
    counters[C_MESH_ARGS + 1u] = 1u;
    counters[C_MESH_ARGS + 2u] = 1u;
    counters[C_EXPAND_ARGS] = (n + EXPAND_GROUP_SIZE - 1u) / EXPAND_GROUP_SIZE;
    counters[C_EXPAND_ARGS + 1u] = 1u;
    counters[C_EXPAND_ARGS + 2u] = 1u;
    counters[C_DRAW_ARGS] = n * VERTICES_PER_NODE;
    counters[C_DRAW_ARGS + 1u] = 1u;
    counters[C_DRAW_ARGS + 2u] = 0u;
    counters[C_DRAW_ARGS + 3u] = 0u;
    // Sorting: the list padded to a power of two, at least one block.
    uint len = SORT_BLOCK;
    while (len < n) {
        len *= 2u;
    }
    counters[C_SORT_LENGTH] = len;
    counters[C_SORT_FILL_ARGS] = (len - n + SORT_GROUP_SIZE - 1u) / SORT_GROUP_SIZE;
    counters[C_SORT_FILL_ARGS + 1u] = 1u;
    counters[C_SORT_FILL_ARGS + 2u] = 1u;
    counters[C_SORT_GLOBAL_ARGS] = len / (2u * SORT_GROUP_SIZE);
    counters[C_SORT_GLOBAL_ARGS + 1u] = 1u;
    counters[C_SORT_GLOBAL_ARGS + 2u] = 1u;
    counters[C_SORT_BLOCK_ARGS] = len / SORT_BLOCK;
    counters[C_SORT_BLOCK_ARGS + 1u] = 1u;
    counters[C_SORT_BLOCK_ARGS + 2u] = 1u;
}

void main() {
    uvec2 stack[32];
    uint lo = 0u;  // deque [lo, hi), slot = index & STACK_MASK
    uint hi = 0u;
    bool bases_left = true;
    bool idle = false;
    uint stalls = 0u;
    uint last_in_flight = 0xffffffffu;
    bool normal_exit = false;
    bool with_wedges = (view.flags & FLAG_WEDGES) != 0u;

    uint n_processed = 0u, n_culled = 0u, n_backface = 0u, n_at_lmax = 0u;
    uint n_spills = 0u, n_pushed = 0u, n_tris = 0u, n_wedges = 0u;
    uint deepest = 0u, iterations = 0u;

    for (;;) {
        iterations += 1u;
        uvec2 item = uvec2(0u);
        bool have = false;
        if (hi != lo) {
            hi -= 1u;
            item = stack[hi & STACK_MASK];
            have = true;
        }

        // Base patches, one claim per subgroup for all lanes that want one.
        bool want_base = !have && bases_left;
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
                    bases_left = false;
                }
            }
        }

        if (!have && !bases_left) {
            have = queue_pop(item);
        }

        uint outcome = OUT_CULLED;
        uvec2 kids[4];
        if (have) {
            if (idle) {
                idle = false;
                atomicAdd(counters[C_IDLE], 0xffffffffu);
            }
            n_processed += 1u;
            outcome = process(item, kids);
            if (outcome == OUT_SPLIT) {
                if (hi - lo + 4u > 32u) {
                    atomicOr(counters[C_ERROR], ERR_STACK_OVERFLOW);
                    break;
                }
                for (int k = 3; k >= 0; --k) {
                    stack[hi & STACK_MASK] = kids[k];
                    hi += 1u;
                }
            } else if (outcome == OUT_CULLED) {
                n_culled += 1u;
            } else if (outcome == OUT_BACKFACE) {
                n_backface += 1u;
            } else {
                uint l = node_depth(item);
                deepest = max(deepest, l);
                n_at_lmax += l >= view.l_max ? 1u : 0u;
                NodeMesh mesh = node_mesh(item, with_wedges);
                uint w = (mesh.wedge.x ? 1u : 0u) + (mesh.wedge.y ? 1u : 0u);
                n_tris += 2u + w;
                n_wedges += w;
            }
        }

        // Ready nodes: one atomic per subgroup.
        bool is_ready = have && outcome == OUT_READY;
        uvec4 rb = subgroupBallot(is_ready);
        uint n_ready = subgroupBallotBitCount(rb);
        if (n_ready > 0u) {
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

        // Donate the bottom of a deep stack while someone is idle.
        uint idle_now = 0u;
        if (subgroupElect()) {
            idle_now = atomic_load(C_IDLE);
        }
        idle_now = subgroupBroadcastFirst(idle_now);
        // One donor per subgroup and iteration: lanes of a subgroup run in
        // lockstep, so several would only race for the same queue slot.
        bool stress = (view.flags & FLAG_QUEUE_STRESS) != 0u;
        bool can_donate = (idle_now > 0u || stress) && hi - lo >= 2u;
        uvec4 donors = subgroupBallot(can_donate);
        if (can_donate && gl_SubgroupInvocationID == subgroupBallotFindLSB(donors)) {
            if (queue_push(stack[lo & STACK_MASK])) {
                lo += 1u;
                n_pushed += 1u;
            } else {
                n_spills += 1u;
            }
        }

        // In-flight bookkeeping, after the children are on a stack or queued
        // and after the ready entries are written.
        // A subgroup that did any work also adds one progress tick in the top
        // byte, so the idle pollers see progress even when the deltas cancel.
        memoryBarrierBuffer();
        int delta = have ? (outcome == OUT_SPLIT ? 3 : -1) : 0;
        int sum = subgroupAdd(delta);
        bool worked = subgroupAny(have);
        if (subgroupElect() && worked) {
            atomicAdd(counters[C_IN_FLIGHT], uint(sum) + IN_FLIGHT_TICK);
        }

        if (!have) {
            if (!idle) {
                idle = true;
                atomicAdd(counters[C_IDLE], 1u);
            }
            uint in_flight = atomic_load(C_IN_FLIGHT);
            if ((in_flight & IN_FLIGHT_MASK) == 0u) {
                normal_exit = true;
                break;
            }
            if (in_flight == last_in_flight) {
                stalls += 1u;
                if (stalls > pc.idle_poll_cap) {
                    atomicOr(counters[C_ERROR], ERR_ITERATION_CAP);
                    break;
                }
            } else {
                stalls = 0u;
                last_in_flight = in_flight;
            }
        }
    }

    subgroup_add_counter(C_PROCESSED, n_processed);
    subgroup_add_counter(C_CULLED, n_culled);
    subgroup_add_counter(C_BACKFACE, n_backface);
    subgroup_add_counter(C_AT_LMAX, n_at_lmax);
    subgroup_add_counter(C_SPILLS, n_spills);
    subgroup_add_counter(C_QUEUE_PUSHED, n_pushed);
    subgroup_add_counter(C_TRIANGLES, n_tris);
    subgroup_add_counter(C_WEDGES, n_wedges);
    subgroup_max_counter(C_MAX_DEPTH, deepest);
    subgroup_max_counter(C_ITERATIONS_MAX, iterations);
    if (normal_exit && subgroupElect()) {
        write_indirect_args();
    }
}
