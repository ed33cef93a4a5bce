//! cudatess's compute passes' push block, twin of `CtPush` in
//! `glsl/cudatess/push.glsl`.

use bytemuck::{Pod, Zeroable};

use crate::gpu::blocks::gpu_block;

/// Push constants of cudatess's compute passes (`CtPush` in
/// `glsl/cudatess/push.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct CtPush {
    /// Base patches.
    pub patch_count: u32,
    /// Vertices the vertex buffer holds.
    pub vertex_capacity: u32,
    /// Indices the index buffer holds.
    pub index_capacity: u32,
    /// `CT_OPT_*`.
    pub options: u32,
    /// Scan: the level's first entry.
    pub scan_offset: u32,
    /// Scan: entries in the level.
    pub scan_count: u32,
    /// Scan: the first entry of the level its block sums go to (`u32::MAX`:
    /// none, the level fits one block).
    pub scan_sums: u32,
    /// Scan: `CT_SCAN_PASS_*`.
    pub pass: u32,
    /// PN triangles (their records and scan entries follow the patches').
    pub tri_count: u32,
    /// Padding to 16 bytes.
    pub pad: [u32; 3],
}
gpu_block!(
    CtPush,
    "CtPush",
    [
        patch_count,
        vertex_capacity,
        index_capacity,
        options,
        scan_offset,
        scan_count,
        scan_sums,
        pass,
        tri_count,
        pad
    ]
);
