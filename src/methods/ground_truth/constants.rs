//! The ground truth's constants shared with its shaders: its set 1 and its
//! counters. `tools/compile-shaders` writes them to
//! `glsl/ground_truth/constants.glsl` (see `src/constants.rs` for the macro
//! and the rules).

use crate::constants::shared_constants;

shared_constants! {
    /// Set 1 of the ground truth's grids: the visible patches and the counters
    /// that hold its indexed indirect draw.
    group {
        BIND_GRID_VISIBLE = 0;
        BIND_GRID_COUNTERS = 1;
        GRID_BINDINGS = 2;
    }
    /// Words of the ground truth's counters: patches culled, and from
    /// G_DRAW_ARGS one VkDrawIndexedIndirectCommand per part of the frame
    /// (G_ARGS_WORDS words each: index count, instance count = the part's
    /// visible patches, first index, vertex offset, first instance), for up
    /// to G_MAX_PARTS parts (the frame ring's MAX_FRAME_PARTS).
    group {
        G_CULLED = 0;
        G_DRAW_ARGS = 4;
        G_ARGS_WORDS = 5;
        G_MAX_PARTS = 64;
        GRID_WORDS = 324;
    }
}
