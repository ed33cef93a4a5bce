//! The ground truth's culling pass's push block, twin of `GridPush` in
//! `glsl/ground_truth/cull.comp`.

use bytemuck::{Pod, Zeroable};

use crate::gpu::blocks::gpu_block;

/// Push constants of the ground truth's culling pass (`GridPush` in
/// `glsl/ground_truth/cull.comp`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GridPush {
    /// Base patches.
    pub patch_count: u32,
    /// Indices per patch (6 per grid cell).
    pub indices_per_patch: u32,
    /// Base patches one part of the frame draws.
    pub patches_per_part: u32,
    /// Padding to 16 bytes.
    pub pad: u32,
}
gpu_block!(
    GridPush,
    "GridPush",
    [patch_count, indices_per_patch, patches_per_part, pad]
);
