// Generated from src/methods/corners/constants.rs by tools/compile-shaders; do not edit.
// Every number the shaders share with the host is declared there, once: add
// or change a constant in src/methods/corners/constants.rs, then run
// `cargo run --release -p compile-shaders`, which rewrites this file and the
// SPIR-V. `--check` (CI) fails while this file differs from what it writes.
#ifndef CORNERS_CONSTANTS_GLSL
#define CORNERS_CONSTANTS_GLSL

// Set 1 of `corners`: the visible patches the cull appends, and the
// draw's VkDrawIndirectCommand (vertex count 6, instance count = the
// visible patches, first vertex, first instance).
const uint BIND_CORNERS_VISIBLE = 0;
const uint BIND_CORNERS_DRAW = 1;
const uint CORNERS_BINDINGS = 2;

// Words of the draw arguments: the instance count the cull counts
// into, and the words in all.
const uint CORNERS_INSTANCES = 1;
const uint CORNERS_DRAW_WORDS = 4;

// Invocations (one per base patch) in a workgroup of the cull.
const uint CORNERS_CULL_GROUP = 64;

#endif
