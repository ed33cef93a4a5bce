//! cudatess's constants shared with its shaders: its set 1, its counters and
//! records, its vertex word, its workgroups and passes (the
//! PN triangles' words, which the ground truth and the shading read too, are
//! in `src/constants.rs`).
//! `tools/compile-shaders` writes them to `glsl/cudatess/constants.glsl`
//! (see `src/constants.rs` for the macro and the rules).

use crate::constants::shared_constants;

shared_constants! {
    /// Set 1 of `cudatess`: counters and the indexed
    /// indirect draw's arguments, the edge of each patch side, the factor of
    /// each edge, the per-patch records, the scan (counts, then offsets), the
    /// vertices and the indices it writes.
    group {
        BIND_CT_COUNTERS = 0;
        BIND_CT_EDGE_IDS = 1;
        BIND_CT_EDGE_FACTORS = 2;
        BIND_CT_PATCHES = 3;
        BIND_CT_SCAN = 4;
        BIND_CT_VERTICES = 5;
        BIND_CT_INDICES = 6;
        BIND_CT_PN_VERTICES = 7;
        BIND_CT_PN_TRIANGLES = 8;
        BIND_CT_PN_EDGE_IDS = 9;
        BIND_CT_PN_NETS = 10;
        CT_BINDINGS = 11;
    }
    /// Words of the cudatess counters: patches culled (frustum), error bits,
    /// the totals the scan found (vertices, indices), the largest factor,
    /// patches culled as back-facing, and from CT_DRAW_ARGS the
    /// VkDrawIndexedIndirectCommand of the draw.
    group {
        CT_CULLED = 0;
        CT_ERROR = 1;
        CT_VERTEX_TOTAL = 2;
        CT_INDEX_TOTAL = 3;
        CT_MAX_FACTOR_SEEN = 4;
        CT_BACKFACE = 5;
        CT_DRAW_ARGS = 8;
        CT_WORDS = 16;
    }
    /// cudatess error bits: the vertices or indices did not fit their buffers
    /// (the frame is drawn again with bigger ones).
    group {
        CT_ERR_VERTICES_FULL = 1;
        CT_ERR_INDICES_FULL = 2;
    }
    /// Per-patch record of cudatess: the patch's own factors along u and v (0:
    /// culled), the final factors of its edges 0-3 (u = 0, v = 0, u = 1, v = 1),
    /// its vertex and index counts.
    group {
        CT_REC_M = 0;
        CT_REC_N = 1;
        CT_REC_EDGES = 2;
        CT_REC_VERTICES = 6;
        CT_REC_INDICES = 7;
        CT_PATCH_WORDS = 8;
    }
    /// A cudatess vertex: position xyz, the base patch's (u, v), and the patch
    /// id (low CT_PATCH_BITS, src/constants.rs) with log2 of its larger factor
    /// and a transition bit (the vertex lies on an edge with a transition
    /// strip) above it.
    group {
        CT_VERTEX_WORDS = 6;
        CT_DEPTH_SHIFT = 24;
        CT_TRANSITION_SHIFT = 28;
    }
    /// cudatess factors are clamped to [1, CT_MAX_FACTOR] (the largest level
    /// of hardware tessellation, so the two compare).
    group {
        CT_MAX_FACTOR = 64;
    }
    /// cudatess workgroups: one invocation per patch (factors, counts,
    /// indices); CT_VERTEX_THREADS invocations per patch for the vertices; the
    /// scan's blocks of CT_SCAN_BLOCK entries (two per invocation).
    group {
        CT_GROUP_SIZE = 64;
        CT_VERTEX_THREADS = 8;
        CT_SCAN_GROUP_SIZE = 256;
        CT_SCAN_BLOCK = 512;
    }
    /// cudatess passes (CtPush.pass): the scan's block pass and its add pass.
    group {
        CT_SCAN_PASS_BLOCKS = 0;
        CT_SCAN_PASS_ADD = 1;
    }
    /// cudatess options (CtPush.options): interior vertices by forward
    /// differencing along rows instead of plain evaluation.
    group {
        CT_OPT_FORWARD_DIFF = 1;
    }
}
