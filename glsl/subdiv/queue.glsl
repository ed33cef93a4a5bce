// Set 2 and the push block of the queue kernel (`subdiv --kernel queue`,
// glsl/subdiv/queue.comp, src/methods/subdiv/): a bounded ring of QuadNodes with one sequence
// number per slot (after Vyukov's bounded MPMC queue), and its head and
// tail. Slot s is free for position p when seq[s] == p and holds the item
// of position p when seq[s] == p + 1; a consumer frees it for the next lap
// with seq[s] = p + capacity. Positions are u32 and the capacity a power of
// two, so they wrap consistently, and a queue left empty by one frame is a
// valid empty queue for the next: nothing is reset between frames.
#ifndef QUEUE_GLSL
#define QUEUE_GLSL

#include "constants.glsl"

layout(std430, set = SET_PRODUCER, binding = BIND_QUEUE_ITEMS) coherent buffer QueueItems {
    uvec2 queue_items[];
};
layout(std430, set = SET_PRODUCER, binding = BIND_QUEUE_SEQS) coherent buffer QueueSeqs {
    uint queue_seqs[];
};
layout(std430, set = SET_PRODUCER, binding = BIND_QUEUE_STATE) coherent buffer QueueState {
    uint queue_state[];
};

// src/methods/subdiv/push.rs SubdivPush.
layout(push_constant) uniform SubdivPush {
    uint ready_capacity;  // entries in `ready`
    uint queue_capacity;  // entries in the work queue (a power of two)
    uint patch_count;     // base patches
    uint idle_poll_cap;   // polls without progress before giving up
    uint local_cap;       // deque entries used (at most SUBDIV_LOCAL_CAP; tests lower it)
    uint base_batch;      // base patches per claim (0: spread over the workgroups)
    uint pad0;
    uint pad1;
} pc;

uint queue_slot(uint pos) {
    return pos & (pc.queue_capacity - 1u);
}

#endif
