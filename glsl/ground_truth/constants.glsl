// Generated from src/methods/ground_truth/constants.rs by tools/compile-shaders; do not edit.
// Every number the shaders share with the host is declared there, once: add
// or change a constant in src/methods/ground_truth/constants.rs, then run
// `cargo run --release -p compile-shaders`, which rewrites this file and the
// SPIR-V. `--check` (CI) fails while this file differs from what it writes.
#ifndef GROUND_TRUTH_CONSTANTS_GLSL
#define GROUND_TRUTH_CONSTANTS_GLSL

// Set 1 of the ground truth's grids: the visible patches and the counters
// that hold its indexed indirect draw.
const uint BIND_GRID_VISIBLE = 0;
const uint BIND_GRID_COUNTERS = 1;
const uint GRID_BINDINGS = 2;

// Words of the ground truth's counters: patches culled, and from
// G_DRAW_ARGS one VkDrawIndexedIndirectCommand per part of the frame
// (G_ARGS_WORDS words each: index count, instance count = the part's
// visible patches, first index, vertex offset, first instance), for up
// to G_MAX_PARTS parts (the frame ring's MAX_FRAME_PARTS).
const uint G_CULLED = 0;
const uint G_DRAW_ARGS = 4;
const uint G_ARGS_WORDS = 5;
const uint G_MAX_PARTS = 64;
const uint GRID_WORDS = 324;

#endif
