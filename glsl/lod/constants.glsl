// Generated from src/lod/constants.rs by tools/compile-shaders; do not edit.
// Every number the shaders share with the host is declared there, once: add
// or change a constant in src/lod/constants.rs, then run
// `cargo run --release -p compile-shaders`, which rewrites this file and the
// SPIR-V. `--check` (CI) fails while this file differs from what it writes.
#ifndef LOD_CONSTANTS_GLSL
#define LOD_CONSTANTS_GLSL

// Set 1 of the level passes (draw and cull): the vertices, each
// instance's level this frame, the level table, the indirect draws,
// the counters, and the depth pyramid the cull tests against.
const uint BIND_LOD_VERTICES = 0;
const uint BIND_LOD_CHOICE = 1;
const uint BIND_LOD_RANGES = 2;
const uint BIND_LOD_DRAWS = 3;
const uint BIND_LOD_COUNTERS = 4;
const uint BIND_LOD_HIZ = 5;
const uint LOD_BINDINGS = 6;

// An instance's word of BIND_LOD_CHOICE: 0 where the frame does not
// draw it from a level (its patches, or out of view), else its
// level's row of the level table + 1.
const uint LOD_NONE = 0;

// A row of the level table: first index, index count, vertex offset
// (an i32's bits) and the level's ordinal in its model (0 the finest).
const uint LOD_RANGE_WORDS = 4;

// Words of the counters: instances drawn from a level, their
// triangles, instances hidden from the depth pyramid, then per level
// ordinal (instances, triangles).
const uint LOD_DRAWN = 0;
const uint LOD_TRIANGLES = 1;
const uint LOD_OCCLUDED = 2;
const uint LOD_BY_LEVEL = 4;
// Level ordinals the counters keep apart (a model's levels beyond
// it are counted with the last).
const uint LOD_MAX_LEVELS = 16;
const uint LOD_COUNTER_WORDS = 36;

// Invocations per workgroup of the level cull (one per instance).
const uint LOD_CULL_GROUP = 64;

#endif
