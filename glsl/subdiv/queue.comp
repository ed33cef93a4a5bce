// `subdiv --kernel queue`: the recursive subdivision of every base patch down to l_max, in ONE
// dispatch of persistent workgroups: the Vulkan stand-in for the paper's
// work-graph recursion (§3.5).
//
// Work is shared the way a work graph shares its records: breadth first,
// through one global queue, in batches. Each workgroup keeps a deque of
// work items in shared memory and loops:
//   1. refill: when fewer than SUBDIV_REFILL_BELOW items are left, claim a
//      batch of base patches (one atomic) or pop a batch from the global
//      queue (one compare-and-swap on its head);
//   2. take the newest min(64, n) items, one per invocation, and process
//      each exactly as src/patch/oracle.rs `process` does
//      (common/process.glsl);
//   3. push the children onto the deque; append the ready nodes with one
//      atomic for the whole workgroup;
//   4. donate the oldest items beyond SUBDIV_KEEP (beyond half of the deque
//      while some workgroup is idle) to the global queue, one
//      compare-and-swap on its tail per batch;
//   5. publish the iteration's in-flight change with one atomic.
// So the global atomics are a handful per workgroup iteration, not per item
// or per lane, and a tree's breadth reaches every workgroup instead of one
// invocation walking a subtree alone.
//
// The queue (subdiv/queue.glsl) never makes anyone wait: a pop takes only
// the published slots at the head, a push only the free slots at the tail,
// and a refused push (the queue is full) keeps the items in the workgroup's
// deque and counts them as spills; it never draws a node early, which would
// open a crack. With the queue full the deque grows instead, and a
// workgroup then takes batches no larger than the deque can hold children
// for, newest (deepest) first, so it drains without overflowing.
//
// Termination: the low bits of counters[C_IN_FLIGHT] (IN_FLIGHT_MASK) start
// at the number of base patches (set by the host) and every processed item
// adds its children minus one, applied only after its children are in a
// deque or the queue, so the count never reads 0 while work exists. A
// workgroup without work marks itself idle and polls the count with one
// invocation, backing off between polls, and leaves when it reads 0.
//
// Forward progress: Vulkan promises none between workgroups, so nothing here
// waits on a workgroup that may not have started. Work lives only in the
// deques of running workgroups, in the queue, or in unclaimed base patches;
// an idle workgroup only polls while the count says some RUNNING workgroup
// still holds work, which that workgroup finishes by itself if nobody helps.
// A workgroup that starts late finds the work taken and leaves.
//
// Iteration cap: a workgroup that sees the in-flight count unchanged for
// pc.idle_poll_cap consecutive polls concludes that nothing anywhere is making
// progress, raises ERR_ITERATION_CAP and leaves; the host reports the error
// (and never hangs: its fence wait has a timeout too).
//
// Memory model: every word other workgroups synchronise on (the slots'
// sequence numbers, head, tail, the in-flight count) is only touched by
// atomics (GL_KHR_memory_scope_semantics, queue-family scope): a consumer
// reads a slot's sequence number with acquire before the item and frees it
// with release after; a producer reads it with acquire before writing the
// item and publishes it with release; the in-flight change is a release
// after the whole workgroup's writes (group_sync), and the workgroup that
// reads 0 with acquire sees every ready append.
//
// This is the queue design of commit a7d19dc, kept behind
// `--kernel queue` beside the depth-synchronous kernel (levels/persistent.comp)
// until a GPU run shows whether it wins anywhere (tools/gpu/kernel.txt).
#version 460
#pragma use_vulkan_memory_model
#extension GL_KHR_memory_scope_semantics : require

#define USE_READY_WRITE
#include "common/ready.glsl"
#include "common/process.glsl"
#include "queue.glsl"

layout(local_size_x = SUBDIV_GROUP_SIZE) in;

const uint GROUP = SUBDIV_GROUP_SIZE;
const uint LOCAL_MASK = SUBDIV_LOCAL_CAP - 1u;

const uint POLL_WORK = 0u;   // keep going
const uint POLL_DONE = 1u;   // nothing in flight anywhere: leave
const uint POLL_STUCK = 2u;  // no progress for the whole cap, or an error

// The workgroup's deque [s_lo, s_hi) of work items (indices wrap by mask):
// new items go on top, batches are taken from the top, donations from the
// bottom.
shared uvec2 s_items[SUBDIV_LOCAL_CAP];
shared uint s_lo;
shared uint s_hi;
shared bool s_bases_left;
// Broadcasts from invocation 0 to the workgroup.
shared uint s_count;
shared uint s_base;
shared uint s_aux;
shared bool s_from_bases;
shared uint s_done;
// Per slot of a queue batch: whether it is published (pop) or free (push).
shared bool s_ok[GROUP];
// Per iteration: ready nodes of the batch and where they go, and splits.
shared uint s_ready;
shared uint s_ready_base;
shared uint s_children;
// Statistics summed over the workgroup at the end.
shared uint s_stats[8];

// Invocation 0's own bookkeeping.
uint atomics = 0u;
uint polls = 0u;
uint retries = 0u;
uint spills = 0u;
uint pushed = 0u;
uint peak = 0u;
uint iterations = 0u;
uint stalls = 0u;
uint last_in_flight = 0xffffffffu;
uint backoff = 1u;
bool idle = false;

uint deque_count() {
    return s_hi - s_lo;
}

const int SYNC_SCOPE = gl_ScopeQueueFamily;
const int SYNC_STORAGE = gl_StorageSemanticsBuffer;

// Orders every invocation's buffer accesses before invocation 0's release
// (and its acquire before everyone's reads), as barrier() alone does not.
void group_sync() {
    controlBarrier(gl_ScopeWorkgroup, gl_ScopeWorkgroup,
        gl_StorageSemanticsBuffer | gl_StorageSemanticsShared, gl_SemanticsAcquireRelease);
}

uint load_relaxed_state(uint i) {
    return atomicLoad(queue_state[i], SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsRelaxed);
}

uint load_relaxed_counter(uint i) {
    return atomicLoad(counters[i], SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsRelaxed);
}

uint seq_acquire(uint slot) {
    return atomicLoad(queue_seqs[slot], SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsAcquire);
}

void seq_release(uint slot, uint value) {
    atomicStore(queue_seqs[slot], value, SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsRelease);
}

// Claims [expected, expected + n) of head or tail; the items themselves
// are ordered by the slots' sequence numbers, so relaxed is enough.
bool claim(uint word, uint expected, uint n) {
    return atomicCompSwap(queue_state[word], expected, expected + n, SYNC_SCOPE, SYNC_STORAGE,
        gl_SemanticsRelaxed, SYNC_STORAGE, gl_SemanticsRelaxed) == expected;
}

// Invocation 0: how many items to refill and from where (bases or queue).
void plan_refill(uint base_batch) {
    s_count = 0u;
    uint count = deque_count();
    if (count >= SUBDIV_REFILL_BELOW) {
        return;
    }
    if (s_bases_left) {
        // Never more than the deque has room for: claimed patches are this
        // workgroup's alone.
        uint claim = min(base_batch, pc.local_cap - count);
        uint first = atomicAdd(counters[C_NEXT_BASE], claim);
        atomics += 1u;
        if (first < pc.patch_count) {
            s_from_bases = true;
            s_base = first;
            s_count = min(claim, pc.patch_count - first);
        }
        if (first + claim >= pc.patch_count) {
            s_bases_left = false;
        }
        return;
    }
    uint h = load_relaxed_state(Q_HEAD);
    uint t = load_relaxed_state(Q_TAIL);
    s_from_bases = false;
    s_base = h;
    s_count = min(GROUP - count, t - h);
}

// Refills the deque: a batch of base patches, or the published slots at
// the queue's head (one compare-and-swap; a lost race is retried next
// iteration).
void refill(uint t, uint base_batch) {
    if (t == 0u) {
        plan_refill(base_batch);
    }
    barrier();
    uint k = s_count;
    if (k == 0u) {
        // Everyone has read s_count before invocation 0 writes it again.
        barrier();
        return;
    }
    uint h = s_base;
    if (s_from_bases) {
        // A batch may exceed the workgroup (pc.base_batch, tests).
        for (uint i = t; i < k; i += GROUP) {
            s_items[(s_hi + i) & LOCAL_MASK] = root_node(h + i);
        }
    } else {
        if (t < k) {
            s_ok[t] = int(seq_acquire(queue_slot(h + t)) - (h + t + 1u)) == 0;
        }
        barrier();
        if (t == 0u) {
            uint run = 0u;
            while (run < k && s_ok[run]) {
                run += 1u;
            }
            bool won = false;
            if (run > 0u) {
                won = claim(Q_HEAD, h, run);
                atomics += 1u;
                retries += won ? 0u : 1u;
            }
            s_count = won ? run : 0u;
        }
        barrier();
        k = s_count;
        if (t < k) {
            uint slot = queue_slot(h + t);
            // Published: this lane's acquire of the sequence number above.
            uvec2 item = queue_items[slot];
            // The item is read before the slot is handed to the next lap.
            seq_release(slot, h + t + pc.queue_capacity);
            s_items[(s_hi + t) & LOCAL_MASK] = item;
        }
    }
    barrier();
    if (t == 0u) {
        s_hi += k;
    }
    barrier();
}

// Invocation 0: how many of the oldest items to donate.
void plan_donation() {
    uint count = deque_count();
    uint keep = (view.flags & FLAG_QUEUE_STRESS) != 0u ? 0u : SUBDIV_KEEP;
    if (load_relaxed_counter(C_IDLE) > 0u) {
        // Someone waits: share half of what is here.
        keep = min(keep, (count + 1u) / 2u);
    }
    uint m = count > keep ? min(count - keep, GROUP) : 0u;
    s_count = m;
    if (m > 0u) {
        s_base = load_relaxed_state(Q_TAIL);
    }
}

// Donates the deque's oldest items to the global queue: the free slots at
// its tail, claimed with one compare-and-swap. Items the full queue refuses
// stay here (spills); a lost race is retried next iteration.
void donate(uint t) {
    if (t == 0u) {
        plan_donation();
    }
    barrier();
    uint m = s_count;
    if (m == 0u) {
        return;
    }
    uint tail = s_base;
    if (t < m) {
        s_ok[t] = int(seq_acquire(queue_slot(tail + t)) - (tail + t)) == 0;
    }
    barrier();
    if (t == 0u) {
        uint run = 0u;
        while (run < m && s_ok[run]) {
            run += 1u;
        }
        bool won = false;
        if (run > 0u) {
            won = claim(Q_TAIL, tail, run);
            atomics += 1u;
            retries += won ? 0u : 1u;
        }
        if (won) {
            pushed += run;
            // Occupancy just after the push, with the head read now (a
            // head read before the tail, as once here, is staler and made
            // the figure exceed the capacity under stress). The head cannot
            // pass tail + run (those slots are not published yet), so this
            // never wraps; a plain read can still be a little stale, and
            // only free slots were taken, so the capacity bounds it.
            uint occupied = tail + run - load_relaxed_state(Q_HEAD);
            peak = max(peak, min(occupied, pc.queue_capacity));
        }
        if (run < m && (won || run == 0u)) {
            // A slot that is not free holds an item of the previous lap: the
            // queue is full when that item is still queued (its position is
            // not below the head), else a consumer is still reading it, or
            // `tail` was stale: others pushed there and consumers may since
            // have moved the head past it. The distance is signed so that
            // last case reads as a retry, not as a wrapped, huge "full".
            uint head_now = load_relaxed_state(Q_HEAD);
            bool full = int((tail + run) - head_now) >= int(pc.queue_capacity);
            spills += full ? m - run : 0u;
            retries += full ? 0u : 1u;
        }
        s_count = won ? run : 0u;
    }
    barrier();
    uint k = s_count;
    if (t < k) {
        uint slot = queue_slot(tail + t);
        // The slot was freed: this lane's acquire of its sequence number.
        queue_items[slot] = s_items[(s_lo + t) & LOCAL_MASK];
        // The item is written before its slot is published.
        seq_release(slot, tail + t + 1u);
    }
    barrier();
    if (t == 0u) {
        s_lo += k;
    }
    barrier();
}

// Invocation 0, without work: polls the in-flight count once, after a
// growing pause, and says whether to go on.
uint poll_idle() {
    if (!idle) {
        idle = true;
        atomicAdd(counters[C_IDLE], 1u);
        atomics += 1u;
    }
    // A pause that does no memory traffic (and that the compiler keeps).
    uint spin = backoff;
    for (uint i = 0u; i < backoff; ++i) {
        spin = spin * 1664525u + 1013904223u;
    }
    if (spin == 0x9e3779b9u) {
        s_aux = spin;
    }
    backoff = min(backoff * 2u, 256u);
    polls += 1u;
    // Acquire: reading 0 makes every workgroup's ready appends visible.
    uint in_flight = atomicLoad(counters[C_IN_FLIGHT], SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsAcquire);
    if ((in_flight & IN_FLIGHT_MASK) == 0u) {
        return POLL_DONE;
    }
    if (in_flight == last_in_flight) {
        stalls += 1u;
        if (stalls > pc.idle_poll_cap) {
            atomicOr(counters[C_ERROR], ERR_ITERATION_CAP);
            return POLL_STUCK;
        }
    } else {
        stalls = 0u;
        last_in_flight = in_flight;
    }
    return POLL_WORK;
}

// Invocation 0: leaves the idle state after finding work.
void busy_again() {
    if (idle) {
        idle = false;
        atomicAdd(counters[C_IDLE], 0xffffffffu);
        atomics += 1u;
    }
    backoff = 1u;
}

// Batch size: up to a workgroup's worth, but never more than the deque can
// hold the children of: a split takes one item and adds up to
// SPLIT_MAX_CHILDREN, so n items need n * (SPLIT_MAX_CHILDREN - 1) free
// slots. With less room than one split needs the batch is empty and the
// workgroup only donates (or, the queue full too, waits for room).
uint batch_size(uint count) {
    uint room = pc.local_cap - count;
    return min(min(count, GROUP), room / (SPLIT_MAX_CHILDREN - 1u));
}

void add_stat(uint k, uint v) {
    if (v != 0u) {
        atomicAdd(s_stats[k], v);
    }
}

void flush_stat(uint index, uint k) {
    if (s_stats[k] != 0u) {
        atomicAdd(counters[index], s_stats[k]);
        atomics += 1u;
    }
}

void main() {
    uint t = gl_LocalInvocationIndex;
    if (t < 8u) {
        s_stats[t] = 0u;
    }
    if (t == 0u) {
        s_lo = 0u;
        s_hi = 0u;
        s_bases_left = true;
        s_done = POLL_WORK;
    }
    barrier();
    // Spread the base patches over the workgroups (tests may ask for a
    // first batch that fills the deque).
    uint base_batch = pc.base_batch != 0u ? min(pc.base_batch, pc.local_cap)
                                          : clamp(pc.patch_count / gl_NumWorkGroups.x, 1u, GROUP);
    uint full_stalls = 0u;
    bool with_wedges = (view.flags & FLAG_WEDGES) != 0u;
    uint processed = 0u, culled = 0u, backface = 0u, at_lmax = 0u;
    uint tris = 0u, wedges = 0u, deepest = 0u;

    for (;;) {
        refill(t, base_batch);
        if (t == 0u) {
            iterations += 1u;
            uint n = batch_size(deque_count());
            s_count = n;
            s_hi -= n;
            s_ready = 0u;
            s_children = 0u;
        }
        barrier();
        uint n = s_count;
        bool have = t < n;
        uvec2 item = have ? s_items[(s_hi + t) & LOCAL_MASK] : uvec2(0u);
        // Every item is read before children land in the same slots.
        barrier();

        uint outcome = OUT_CULLED;
        uint my_ready = 0u;
        if (have) {
            uvec2 kids[4];
            uint nk = 0u;
            outcome = process(item, kids, nk);
            processed += 1u;
            if (outcome == OUT_SPLIT) {
                // 4 children for a 1:4 split, 2 for 1:2 (SPLIT_MAX_CHILDREN
                // bounds both).
                uint at = atomicAdd(s_hi, nk);
                if (at + nk - s_lo > pc.local_cap) {
                    atomicOr(counters[C_ERROR], ERR_STACK_OVERFLOW);
                }
                for (uint k = 0u; k < nk; ++k) {
                    s_items[(at + k) & LOCAL_MASK] = kids[k];
                }
                atomicAdd(s_children, nk);
            } else if (outcome == OUT_CULLED) {
                culled += 1u;
            } else if (outcome == OUT_BACKFACE) {
                backface += 1u;
            } else {
                uint l = node_depth(item);
                deepest = max(deepest, l);
                at_lmax += l >= view.l_max ? 1u : 0u;
                uvec2 tw = ready_triangles(item, with_wedges);
                tris += tw.x;
                wedges += tw.y;
                my_ready = atomicAdd(s_ready, 1u);
            }
        }
        barrier();
        // The batch's ready nodes with one atomic.
        if (t == 0u && s_ready > 0u) {
            s_ready_base = atomicAdd(counters[C_READY_COUNT], s_ready);
            atomics += 1u;
        }
        barrier();
        if (have && outcome == OUT_READY) {
            uint idx = s_ready_base + my_ready;
            if (idx < pc.ready_capacity) {
                ready[idx] = item;
            } else {
                atomicOr(counters[C_ERROR], ERR_READY_FULL);
            }
        }
        donate(t);
        // The in-flight change, released after every invocation's children
        // are in the deque or the queue and its ready entries are written.
        group_sync();
        if (t == 0u) {
            if (n > 0u) {
                int delta = int(s_children) - int(n);
                atomicAdd(counters[C_IN_FLIGHT], uint(delta) + IN_FLIGHT_TICK, SYNC_SCOPE, SYNC_STORAGE,
                    gl_SemanticsRelease);
                atomics += 1u;
                busy_again();
                full_stalls = 0u;
            } else if (deque_count() == 0u) {
                s_done = poll_idle();
            } else if (++full_stalls > pc.idle_poll_cap) {
                // Too full to take even one split, and nobody takes the
                // donations: give up rather than spin forever.
                atomicOr(counters[C_ERROR], ERR_ITERATION_CAP);
                s_done = POLL_STUCK;
            }
            if ((load_relaxed_counter(C_ERROR) & ERR_STACK_OVERFLOW) != 0u) {
                s_done = POLL_STUCK;
            }
        }
        barrier();
        if (s_done != POLL_WORK) {
            break;
        }
    }

    add_stat(0u, processed);
    add_stat(1u, culled);
    add_stat(2u, backface);
    add_stat(3u, at_lmax);
    add_stat(4u, tris);
    add_stat(5u, wedges);
    atomicMax(s_stats[6], deepest);
    barrier();
    if (t == 0u) {
        flush_stat(C_PROCESSED, 0u);
        flush_stat(C_CULLED, 1u);
        flush_stat(C_BACKFACE, 2u);
        flush_stat(C_AT_LMAX, 3u);
        flush_stat(C_TRIANGLES, 4u);
        flush_stat(C_WEDGES, 5u);
        if (s_stats[6] != 0u) {
            atomicMax(counters[C_MAX_DEPTH], s_stats[6]);
            atomics += 1u;
        }
        atomicMax(counters[C_ITERATIONS_MAX], iterations);
        atomicMax(counters[C_QUEUE_PEAK], peak);
        // The four below, plus themselves.
        atomics += 6u;
        atomicAdd(counters[C_SPILLS], spills);
        atomicAdd(counters[C_QUEUE_PUSHED], pushed);
        atomicAdd(counters[C_QUEUE_RETRIES], retries);
        atomicAdd(counters[C_IDLE_POLLS], polls);
        if (s_done == POLL_DONE) {
            // In flight reached 0 after every ready append: the count is final.
            atomics += 1u;
            uint n = atomicLoad(counters[C_READY_COUNT], SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsRelaxed);
            write_ready_args(0u, min(n, pc.ready_capacity));
        }
        atomicAdd(counters[C_GLOBAL_ATOMICS], atomics);
    }
}
