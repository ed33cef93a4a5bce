// Generated from src/methods/subdiv/constants.rs by tools/compile-shaders; do not edit.
// Every number the shaders share with the host is declared there, once: add
// or change a constant in src/methods/subdiv/constants.rs, then run
// `cargo run --release -p compile-shaders`, which rewrites this file and the
// SPIR-V. `--check` (CI) fails while this file differs from what it writes.
#ifndef SUBDIV_CONSTANTS_GLSL
#define SUBDIV_CONSTANTS_GLSL

// Set 2 of the queue kernel: its work queue (items,
// a sequence number per slot, and the head and tail, which carry on from
// frame to frame).
const uint BIND_QUEUE_ITEMS = 0;
const uint BIND_QUEUE_SEQS = 1;
const uint BIND_QUEUE_STATE = 2;
const uint QUEUE_BINDINGS = 3;

// Words of the queue's state buffer.
const uint Q_HEAD = 0;
const uint Q_TAIL = 1;
const uint QUEUE_STATE_WORDS = 4;

#endif
