//! `corners`' cull push block, twin of `CornersCullPush` in
//! `glsl/corners/cull.comp`; `tests/blocks.rs` checks the two agree
//! through the registry entry's `blocks`.

use bytemuck::{Pod, Zeroable};

use crate::gpu::blocks::gpu_block;

/// Push constants of `corners`' cull (`CornersCullPush` in
/// `glsl/corners/cull.comp`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct CornersCullPush {
    /// Base patches.
    pub patch_count: u32,
    /// Padding to 16 bytes.
    pub pad: [u32; 3],
}
gpu_block!(CornersCullPush, "CornersCullPush", [patch_count, pad]);
