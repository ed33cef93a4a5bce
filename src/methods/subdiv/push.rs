//! The queue kernel's push block, twin of `SubdivPush` in
//! `glsl/subdiv/queue.glsl`.

use bytemuck::{Pod, Zeroable};

use crate::gpu::blocks::gpu_block;

/// Push constants of the queue kernel (`SubdivPush` in
/// `glsl/subdiv/queue.glsl`, `subdiv --kernel queue`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct SubdivPush {
    /// Entries in the ready list.
    pub ready_capacity: u32,
    /// Entries in the work queue.
    pub queue_capacity: u32,
    /// Base patches.
    pub patch_count: u32,
    /// Polls without any progress anywhere before the kernel gives up with
    /// `ERR_ITERATION_CAP`.
    pub idle_poll_cap: u32,
    /// Deque entries a workgroup uses (at most `SUBDIV_LOCAL_CAP`).
    pub local_cap: u32,
    /// Base patches per claim (0: spread over the workgroups).
    pub base_batch: u32,
    /// Padding to 16 bytes.
    pub pad: [u32; 2],
}
gpu_block!(
    SubdivPush,
    "SubdivPush",
    [
        ready_capacity,
        queue_capacity,
        patch_count,
        idle_poll_cap,
        local_cap,
        base_batch,
        pad
    ]
);
