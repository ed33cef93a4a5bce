//! What a frame leaves in `cudatess`'s buffers, read back for its checks
//! and tests: per-patch records, the written vertices.

use crate::constants::{CT_PATCH_BITS, CT_PN_SHIFT};

/// One patch's record after a frame (`CT_REC_*`). A PN triangle's record
/// (after the patches') has `own` = its largest and smallest own factor and
/// `edges` = the final factors of its edges P0 → P1, P1 → P2, P2 → P0,
/// then its core factor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PatchRecord {
    /// Its own factors along u and v (0, 0: culled).
    pub own: [u32; 2],
    /// The final factors of its edges 0-3 (u = 0, v = 0, u = 1, v = 1).
    pub edges: [u32; 4],
    /// Vertices and indices its pattern has.
    pub counts: [u32; 2],
    /// Where its vertices and indices start (the scan's offsets).
    pub offsets: [u32; 2],
}

impl PatchRecord {
    /// Frustum-culled.
    pub fn culled(&self) -> bool {
        self.own[0] == 0
    }
}

/// One written vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CtVertex {
    /// Position.
    pub position: [f32; 3],
    /// The base patch's parameters.
    pub uv: [f32; 2],
    /// The packed word: patch id, depth, transition bit.
    pub word: u32,
}

impl CtVertex {
    /// The base patch (or PN triangle, see [`CtVertex::is_pn`]).
    pub fn patch(&self) -> u32 {
        self.word & ((1 << CT_PATCH_BITS) - 1)
    }

    /// Whether the vertex belongs to a PN triangle.
    pub fn is_pn(&self) -> bool {
        self.word & (1 << CT_PN_SHIFT) != 0
    }
}

/// What a frame left in the buffers, read back.
#[derive(Clone, Debug, Default)]
pub struct FrameData {
    /// Per patch, then per PN triangle.
    pub records: Vec<PatchRecord>,
    /// How many of `records` are patches (the rest are PN triangles).
    pub patches: usize,
    /// Every vertex written.
    pub vertices: Vec<CtVertex>,
    /// Every index written (absolute).
    pub indices: Vec<u32>,
    /// Per PN triangle, its converted net (`glsl/common/pn.glsl`: 10
    /// points, 6 normal coefficients; a culled triangle's stays as the
    /// conversion left it).
    pub pn_nets: Vec<[[f32; 4]; 16]>,
}
