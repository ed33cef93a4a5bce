//! The level kernels' push block, twin of `LevelPush` in
//! `glsl/levels/level.glsl`.

use bytemuck::{Pod, Zeroable};

use crate::gpu::blocks::gpu_block;

/// Push constants of the level kernels: the persistent one, the per-depth
/// rounds and their first step (`LevelPush` in `glsl/levels/level.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct LevelPush {
    /// Base patches (the nodes of depth 0).
    pub patch_count: u32,
    /// Nodes per round at most (a multiple of `LEVEL_GROUP_SIZE`).
    pub chunk: u32,
    /// Entries in the ready list.
    pub ready_capacity: u32,
    /// Depths with a region in the node memory.
    pub levels: u32,
    /// Persistent kernel: polls without progress before its watchdog trips.
    pub watchdog_polls: u32,
    /// Persistent kernel: polls of an unchanged join count before the
    /// occupancy window closes.
    pub join_polls: u32,
    /// Persistent kernel: workgroups launched.
    pub launched: u32,
    /// `FAULT_*` bits (tests).
    pub faults: u32,
    /// Per-depth rounds: blocks per workgroup.
    pub group_blocks: u32,
    /// `PHASE_*`: one pass, or a phase of occlusion culling.
    pub phase: u32,
    /// Blocks of 64 cluster slots the roots buffer holds after its
    /// instance entries (occlusion culling's cluster filter).
    pub cluster_blocks: u32,
    /// Padding to 16 bytes.
    pub pad: u32,
}
gpu_block!(
    LevelPush,
    "LevelPush",
    [
        patch_count,
        chunk,
        ready_capacity,
        levels,
        watchdog_polls,
        join_polls,
        launched,
        faults,
        group_blocks,
        phase,
        cluster_blocks,
        pad
    ]
);
