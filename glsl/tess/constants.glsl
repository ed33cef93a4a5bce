// Generated from src/methods/tess/constants.rs by tools/compile-shaders; do not edit.
// Every number the shaders share with the host is declared there, once: add
// or change a constant in src/methods/tess/constants.rs, then run
// `cargo run --release -p compile-shaders`, which rewrites this file and the
// SPIR-V. `--check` (CI) fails while this file differs from what it writes.
#ifndef TESS_CONSTANTS_GLSL
#define TESS_CONSTANTS_GLSL

// Set 1 of the tessellation methods: their counters, and what validation
// captures: the levels of every patch and the vertices on patch edges.
const uint BIND_TESS_COUNTERS = 0;
const uint BIND_TESS_LEVELS = 1;
const uint BIND_TESS_EDGE_VERTICES = 2;
const uint TESS_BINDINGS = 3;

// Words of the tessellation counters: patches frustum-culled, back-face
// culled and tessellated, and edge vertices captured (counted on past the
// capture's capacity).
const uint T_CULLED = 0;
const uint T_BACKFACE = 1;
const uint T_TESSELLATED = 2;
const uint T_EDGE_VERTICES = 3;
const uint TESS_WORDS = 8;

// Tessellation capture records: per patch outer levels 0-3, the
// metric's inner levels 0-1, the mixed bound, a culled flag and the
// inner levels drawn (raised where border strips were narrowed); per
// edge vertex the patch, the edge,
// the tessellator's coordinate along it and the position.
const uint TESS_LEVEL_WORDS = 10;
const uint TESS_EDGE_VERTEX_WORDS = 6;

// tess-reparam rounds re-parameterised edge samples to multiples of
// 1 / TESS_WARP_STEPS, so the patch across the edge gets exactly 1 - s.
const uint TESS_WARP_STEPS = 0x100000;

#endif
