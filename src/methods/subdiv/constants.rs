//! The queue kernel's constants (`subdiv --kernel queue`) shared with its
//! shaders: its set 2 and the words of its state. `tools/compile-shaders`
//! writes them to `glsl/subdiv/constants.glsl` (see `src/constants.rs` for
//! the macro and the rules).

use crate::constants::shared_constants;

shared_constants! {
    /// Set 2 of the queue kernel: its work queue (items,
    /// a sequence number per slot, and the head and tail, which carry on from
    /// frame to frame).
    group {
        BIND_QUEUE_ITEMS = 0;
        BIND_QUEUE_SEQS = 1;
        BIND_QUEUE_STATE = 2;
        QUEUE_BINDINGS = 3;
    }
    /// Words of the queue's state buffer.
    group {
        Q_HEAD = 0;
        Q_TAIL = 1;
        QUEUE_STATE_WORDS = 4;
    }
}
