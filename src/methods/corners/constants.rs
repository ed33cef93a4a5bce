//! `corners`' constants shared with its shaders: its set 1 and its cull's
//! workgroup. `tools/compile-shaders` finds this file by itself and writes
//! it to `glsl/corners/constants.glsl` (see `src/constants.rs` for the
//! macro and the rules).

use crate::constants::shared_constants;

shared_constants! {
    /// Set 1 of `corners`: the visible patches the cull appends, and the
    /// draw's VkDrawIndirectCommand (vertex count 6, instance count = the
    /// visible patches, first vertex, first instance).
    group {
        BIND_CORNERS_VISIBLE = 0;
        BIND_CORNERS_DRAW = 1;
        CORNERS_BINDINGS = 2;
    }
    /// Words of the draw arguments: the instance count the cull counts
    /// into, and the words in all.
    group {
        CORNERS_INSTANCES = 1;
        CORNERS_DRAW_WORDS = 4;
    }
    /// Invocations (one per base patch) in a workgroup of the cull.
    group {
        CORNERS_CULL_GROUP = 64;
    }
}
