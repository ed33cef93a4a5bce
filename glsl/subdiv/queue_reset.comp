// Puts the persistent kernel's queue in its empty state: slot i free for
// position i, head = tail = 0. Run when the queue is made and after a frame
// that ended abnormally (a queue that one frame emptied needs nothing: see
// subdiv/queue.glsl).
#version 460

#include "common/constants.glsl"
#include "queue.glsl"

layout(local_size_x = 64) in;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < pc.queue_capacity) {
        queue_seqs[i] = i;
    }
    if (i < QUEUE_STATE_WORDS) {
        queue_state[i] = 0u;
    }
}
