//! The tessellation methods' constants shared with their shaders: set 1,
//! the counters, the capture records and tess-reparam's rounding.
//! `tools/compile-shaders` writes them to `glsl/tess/constants.glsl` (see
//! `src/constants.rs` for the macro and the rules).

use crate::constants::shared_constants;

shared_constants! {
    /// Set 1 of the tessellation methods: their counters, and what validation
    /// captures: the levels of every patch and the vertices on patch edges.
    group {
        BIND_TESS_COUNTERS = 0;
        BIND_TESS_LEVELS = 1;
        BIND_TESS_EDGE_VERTICES = 2;
        TESS_BINDINGS = 3;
    }
    /// Words of the tessellation counters: patches frustum-culled, back-face
    /// culled and tessellated, and edge vertices captured (counted on past the
    /// capture's capacity).
    group {
        T_CULLED = 0;
        T_BACKFACE = 1;
        T_TESSELLATED = 2;
        T_EDGE_VERTICES = 3;
        TESS_WORDS = 8;
    }
    /// Tessellation capture records: per patch outer levels 0-3, the
    /// metric's inner levels 0-1, the mixed bound, a culled flag and the
    /// inner levels drawn (raised where border strips were narrowed); per
    /// edge vertex the patch, the edge,
    /// the tessellator's coordinate along it and the position.
    group {
        TESS_LEVEL_WORDS = 10;
        TESS_EDGE_VERTEX_WORDS = 6;
    }
    /// tess-reparam rounds re-parameterised edge samples to multiples of
    /// 1 / TESS_WARP_STEPS, so the patch across the edge gets exactly 1 - s.
    group {
        TESS_WARP_STEPS = 0x0010_0000;
    }
}
