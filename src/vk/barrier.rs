//! Synchronization2 barriers: the access scopes a barrier joins
//! ([`Access`]), the barrier structures the pass layer and the immediate
//! helpers share, and the global barriers (buffer and image barriers are
//! `memory`'s, beside the resources they name).

use super::context::Context;
use ash::vk;

/// A pipeline stage paired with the memory access made there: one side of a
/// barrier.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Access {
    /// The stage(s).
    pub stage: vk::PipelineStageFlags2,
    /// The access(es).
    pub access: vk::AccessFlags2,
}

impl Access {
    /// Nothing before (first use of a resource).
    pub const NONE: Self = Self::new(vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
    /// Any command, any read or write: the safe, slow default.
    pub const ALL: Self = Self::new(
        vk::PipelineStageFlags2::ALL_COMMANDS,
        vk::AccessFlags2::from_raw(
            vk::AccessFlags2::MEMORY_READ.as_raw() | vk::AccessFlags2::MEMORY_WRITE.as_raw(),
        ),
    );
    /// Shader storage writes in compute.
    pub const COMPUTE_WRITE: Self = Self::new(
        vk::PipelineStageFlags2::COMPUTE_SHADER,
        vk::AccessFlags2::SHADER_STORAGE_WRITE,
    );
    /// Shader storage reads and writes in compute.
    pub const COMPUTE_READ_WRITE: Self = Self::new(
        vk::PipelineStageFlags2::COMPUTE_SHADER,
        vk::AccessFlags2::from_raw(
            vk::AccessFlags2::SHADER_STORAGE_READ.as_raw()
                | vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw(),
        ),
    );
    /// Shader reads (storage or uniform) in compute.
    pub const COMPUTE_READ: Self = Self::new(
        vk::PipelineStageFlags2::COMPUTE_SHADER,
        vk::AccessFlags2::from_raw(
            vk::AccessFlags2::SHADER_STORAGE_READ.as_raw()
                | vk::AccessFlags2::UNIFORM_READ.as_raw(),
        ),
    );
    /// Indirect command reads (draw/dispatch arguments).
    pub const INDIRECT_READ: Self = Self::new(
        vk::PipelineStageFlags2::DRAW_INDIRECT,
        vk::AccessFlags2::INDIRECT_COMMAND_READ,
    );
    /// Copy/fill/clear writes.
    pub const TRANSFER_WRITE: Self = Self::new(
        vk::PipelineStageFlags2::ALL_TRANSFER,
        vk::AccessFlags2::TRANSFER_WRITE,
    );
    /// Copy reads.
    pub const TRANSFER_READ: Self = Self::new(
        vk::PipelineStageFlags2::ALL_TRANSFER,
        vk::AccessFlags2::TRANSFER_READ,
    );
    /// Host reads after the fence (mapped readback).
    pub const HOST_READ: Self =
        Self::new(vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ);
    /// Colour attachment writes.
    pub const COLOR_ATTACHMENT_WRITE: Self = Self::new(
        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
    );
    /// Depth attachment reads and writes.
    pub const DEPTH_ATTACHMENT: Self = Self::new(
        vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw()
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
        ),
        vk::AccessFlags2::from_raw(
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ.as_raw()
                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw(),
        ),
    );

    /// Pairs a stage with an access.
    pub const fn new(stage: vk::PipelineStageFlags2, access: vk::AccessFlags2) -> Self {
        Self { stage, access }
    }

    /// Both scopes together.
    pub fn union(self, other: Self) -> Self {
        Self::new(self.stage | other.stage, self.access | other.access)
    }

    /// Neither a stage nor an access.
    pub fn is_none(self) -> bool {
        self.stage.is_empty() && self.access.is_empty()
    }

    /// Whether this scope includes all of `other`'s (all commands cover
    /// every stage; memory read and write together cover every access).
    /// Conservative: answers no where unsure, which costs a barrier.
    pub fn covers(self, other: Self) -> bool {
        let stage = self.stage.contains(vk::PipelineStageFlags2::ALL_COMMANDS)
            || self.stage.contains(other.stage);
        let any = vk::AccessFlags2::MEMORY_READ | vk::AccessFlags2::MEMORY_WRITE;
        let access = self.access.contains(any) || self.access.contains(other.access);
        stage && access
    }
}

/// A barrier on a whole buffer, not yet recorded (the one builder the
/// immediate helpers here and the pass layer share).
pub(crate) fn buffer_barrier_info(
    buffer: vk::Buffer,
    src: Access,
    dst: Access,
) -> vk::BufferMemoryBarrier2<'static> {
    vk::BufferMemoryBarrier2::default()
        .src_stage_mask(src.stage)
        .src_access_mask(src.access)
        .dst_stage_mask(dst.stage)
        .dst_access_mask(dst.access)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .buffer(buffer)
        .offset(0)
        .size(vk::WHOLE_SIZE)
}

/// An image layout transition without its image and range, not yet
/// recorded.
pub(crate) fn image_barrier_info(
    src: Access,
    dst: Access,
    old_layout: vk::ImageLayout,
    new_layout: vk::ImageLayout,
) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .src_stage_mask(src.stage)
        .src_access_mask(src.access)
        .dst_stage_mask(dst.stage)
        .dst_access_mask(dst.access)
        .old_layout(old_layout)
        .new_layout(new_layout)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
}

/// A global memory barrier, not yet recorded.
pub(crate) fn memory_barrier_info(src: Access, dst: Access) -> vk::MemoryBarrier2<'static> {
    vk::MemoryBarrier2::default()
        .src_stage_mask(src.stage)
        .src_access_mask(src.access)
        .dst_stage_mask(dst.stage)
        .dst_access_mask(dst.access)
}

/// Records a global memory barrier (all resources).
pub fn memory_barrier(ctx: &Context, cmd: vk::CommandBuffer, src: Access, dst: Access) {
    let barrier = [memory_barrier_info(src, dst)];
    let dep = vk::DependencyInfo::default().memory_barriers(&barrier);
    unsafe { ctx.device().cmd_pipeline_barrier2(cmd, &dep) };
}

/// Makes every earlier device write visible to host reads after the fence.
pub fn host_read_barrier(ctx: &Context, cmd: vk::CommandBuffer) {
    memory_barrier(ctx, cmd, Access::ALL, Access::HOST_READ);
}
