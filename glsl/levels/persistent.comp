// Method subdiv: the level schedule of subdiv-indirect (levels/level.glsl)
// in ONE dispatch of persistent workgroups, a grid barrier between rounds
// instead of a dispatch: the depth-synchronous persistent kernel
// (docs/ARCHITECTURE.md, "The persistent kernel", says why this design).
//
// Occupancy discovery first (after Sorensen et al.): every workgroup asks
// to join with one atomic; the first closes the window once no one else
// has joined for pc.join_polls polls (or all launched have), and only the
// ones that joined before that take part. They were all running at once,
// so a barrier among them never waits for a workgroup that has not
// started; latecomers (launched beyond what the device keeps resident)
// leave at once.
//
// Each round: the participants take the round's blocks in turn (copy the
// previous round's ready nodes, process this round's chunk), then arrive
// at the barrier (acquire-release); the last to arrive scans the totals,
// schedules the next round and releases the others (a release that
// advances the generation they poll with acquire), so it is also what
// orders every block's writes before the next round's reads.
//
// The barrier is one word, S_SYNC: the arrivals, the generation (rounds
// released) and an abort bit, so a waiting workgroup's poll is one load.
//
// Watchdog: a waiting workgroup that sees neither the generation nor the
// arrivals change for pc.watchdog_polls polls (a participant that stopped
// running: an unfair scheduler, a device that does not keep its promise)
// raises ERR_WATCHDOG and the abort bit, and every workgroup leaves; the
// host then redoes the frame with the per-depth rounds
// (src/methods/subdiv.rs).
#version 460
#pragma use_vulkan_memory_model

#define USE_READY_WRITE
#define LEVEL_KERNEL
#include "common/ready.glsl"
#include "common/process.glsl"
#include "level.glsl"

layout(local_size_x = LEVEL_GROUP_SIZE) in;

const uint NOT_JOINED = 0xffffffffu;

shared uint s_id;
shared uint s_participants;
shared bool s_last;
shared bool s_stop;
shared uint s_generation;
// Where pause_polling's spin result may go, so that the loop stays.
shared uint s_spin_sink;

// Invocation 0's own bookkeeping.
uint polls = 0u;
uint atomics = 0u;
uint backoff = 1u;

// A pause that does no memory traffic (and that the compiler keeps).
void pause_polling() {
    uint spin = backoff;
    for (uint i = 0u; i < backoff; ++i) {
        spin = spin * 1664525u + 1013904223u;
    }
    if (spin == 0x9e3779b9u) {
        s_spin_sink = spin;
    }
    backoff = min(backoff * 2u, 256u);
    polls += 1u;
}

// The round barrier's word (arrivals, generation, abort), with acquire.
uint load_sync() {
    return atomicLoad(state[S_SYNC], SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsAcquire);
}

void trip_watchdog() {
    atomicOr(counters[C_ERROR], ERR_WATCHDOG);
    atomicOr(state[S_SYNC], SYNC_ABORT, SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsAcquireRelease);
    atomics += 2u;
}

// Invocation 0 of the first to join: waits (boundedly) for the others,
// closes the window and publishes how many joined.
void close_window() {
    uint seen = 1u;
    uint unchanged = 0u;
    while (seen < pc.launched && unchanged < pc.join_polls) {
        pause_polling();
        uint now = atomicLoad(state[S_JOIN], SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsRelaxed)
            & ~JOIN_CLOSED;
        unchanged = now == seen ? unchanged + 1u : 0u;
        seen = now;
    }
    uint joined = atomicOr(state[S_JOIN], JOIN_CLOSED, SYNC_SCOPE, SYNC_STORAGE,
        gl_SemanticsAcquireRelease) & ~JOIN_CLOSED;
    atomics += 1u;
    if ((pc.faults & FAULT_NO_DISCOVERY) != 0u) {
        joined = pc.launched;
    }
    if ((pc.faults & FAULT_PHANTOM) != 0u) {
        joined += 1u;
    }
    atomicStore(state[S_PARTICIPANTS], joined, SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsRelease);
    s_participants = joined;
}

// Invocation 0 of a later joiner: waits for the window to close (one load
// a poll; a closer that never publishes trips the watchdog).
void await_window() {
    uint unchanged = 0u;
    for (;;) {
        uint n = atomicLoad(state[S_PARTICIPANTS], SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsAcquire);
        if (n != 0u) {
            s_participants = n;
            return;
        }
        if (++unchanged > pc.watchdog_polls) {
            trip_watchdog();
            s_stop = true;
            return;
        }
        pause_polling();
    }
}

// Whole workgroup: joins (or not) and learns the participants' count.
bool discover(uint t) {
    if (t == 0u) {
        s_stop = false;
        uint old = atomicAdd(state[S_JOIN], 1u, SYNC_SCOPE, SYNC_STORAGE, gl_SemanticsAcquireRelease);
        atomics += 1u;
        bool late = (old & JOIN_CLOSED) != 0u && (pc.faults & FAULT_NO_DISCOVERY) == 0u;
        s_id = late ? NOT_JOINED : old & ~JOIN_CLOSED;
        if (s_id == 0u) {
            close_window();
        } else if (s_id != NOT_JOINED) {
            await_window();
        }
        backoff = 1u;
    }
    group_sync();
    return s_id != NOT_JOINED && !s_stop;
}

// Invocation 0 of a workgroup that is not the last: waits for the round to
// be released (true) or for an abort (false), one load of S_SYNC a poll.
// The watchdog trips when neither the generation nor the arrivals change
// for pc.watchdog_polls polls.
bool await_release(uint generation) {
    uint arrived = 0xffffffffu;
    uint unchanged = 0u;
    for (;;) {
        pause_polling();
        uint w = load_sync();
        if ((w & SYNC_ABORT) != 0u) {
            return false;
        }
        if ((w & SYNC_GENERATION) != generation) {
            return true;
        }
        uint a = w & SYNC_ARRIVALS;
        unchanged = a == arrived ? unchanged + 1u : 0u;
        arrived = a;
        if (unchanged > pc.watchdog_polls) {
            trip_watchdog();
            return false;
        }
    }
}

// Whole workgroup: the grid barrier at the end of a round. Returns false
// when the kernel must stop (watchdog).
bool end_round(uint t) {
    group_sync();
    uint before = 0u;
    if (t == 0u) {
        s_last = arrive(s_participants, before);
        atomics += 1u;
    }
    group_sync();
    if (s_last) {
        finish_round(t);
        if (t == 0u) {
            release_round(before, s_participants);
            atomics += 1u + s_round_atomics;
        }
    } else if (t == 0u) {
        s_stop = !await_release(s_generation);
        backoff = 1u;
    }
    group_sync();
    return !s_stop;
}

void main() {
    process_occludes = pc.phase == PHASE_LATE;
    process_hide_all = (pc.faults & FAULT_HIDE_LATE) != 0u;
    uint t = gl_LocalInvocationIndex;
    if (discover(t)) {
        for (;;) {
            if (t == 0u) {
                uint w = load_sync();
                s_generation = w & SYNC_GENERATION;
                s_stop = (w & SYNC_ABORT) != 0u;
            }
            load_round(t);
            if (s_done || s_stop) {
                break;
            }
            uint work = max(round_blocks(), s_copy_blocks);
            for (uint b = s_id; b < work; b += s_participants) {
                if (b < s_copy_blocks) {
                    copy_block(b, t);
                }
                if (b < round_blocks()) {
                    process_block(b, t);
                }
            }
            if (!end_round(t)) {
                break;
            }
        }
    }
    if (t == 0u) {
        atomicAdd(counters[C_IDLE_POLLS], polls);
        atomicAdd(counters[C_GLOBAL_ATOMICS], atomics + 2u);
    }
}
