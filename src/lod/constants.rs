//! The levels of detail's constants shared with their shaders
//! (`glsl/lod/`): the set of their draw and cull passes, the level table,
//! the counters. `tools/compile-shaders` writes them to
//! `glsl/lod/constants.glsl` (see `src/constants.rs` for the macro and the
//! rules).

use crate::constants::shared_constants;

shared_constants! {
    /// Set 1 of the level passes (draw and cull): the vertices, each
    /// instance's level this frame, the level table, the indirect draws,
    /// the counters, and the depth pyramid the cull tests against.
    group {
        BIND_LOD_VERTICES = 0;
        BIND_LOD_CHOICE = 1;
        BIND_LOD_RANGES = 2;
        BIND_LOD_DRAWS = 3;
        BIND_LOD_COUNTERS = 4;
        BIND_LOD_HIZ = 5;
        LOD_BINDINGS = 6;
    }
    /// An instance's word of BIND_LOD_CHOICE: 0 where the frame does not
    /// draw it from a level (its patches, or out of view), else its
    /// level's row of the level table + 1.
    group {
        LOD_NONE = 0;
    }
    /// A row of the level table: first index, index count, vertex offset
    /// (an i32's bits) and the level's ordinal in its model (0 the finest).
    group {
        LOD_RANGE_WORDS = 4;
    }
    /// Words of the counters: instances drawn from a level, their
    /// triangles, instances hidden from the depth pyramid, then per level
    /// ordinal (instances, triangles).
    group {
        LOD_DRAWN = 0;
        LOD_TRIANGLES = 1;
        LOD_OCCLUDED = 2;
        LOD_BY_LEVEL = 4;
        /// Level ordinals the counters keep apart (a model's levels beyond
        /// it are counted with the last).
        LOD_MAX_LEVELS = 16;
        LOD_COUNTER_WORDS = 36;
    }
    /// Invocations per workgroup of the level cull (one per instance).
    group {
        LOD_CULL_GROUP = 64;
    }
}
