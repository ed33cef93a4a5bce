//! One-shot command buffers with bounded fence waits, and synchronization2
//! barrier helpers.

use super::context::{duration_ns, Context, Pending, SubmitState};
use super::error::{VkError, VkResult, VkResultExt};
use super::memory::{Buffer, Image};
use ash::vk;
use std::time::Duration;

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
}

/// Records a barrier on a whole buffer.
pub fn buffer_barrier(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    buffer: &Buffer,
    src: Access,
    dst: Access,
) {
    let barrier = [vk::BufferMemoryBarrier2::default()
        .src_stage_mask(src.stage)
        .src_access_mask(src.access)
        .dst_stage_mask(dst.stage)
        .dst_access_mask(dst.access)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .buffer(buffer.handle())
        .offset(0)
        .size(vk::WHOLE_SIZE)];
    let dep = vk::DependencyInfo::default().buffer_memory_barriers(&barrier);
    unsafe { ctx.device().cmd_pipeline_barrier2(cmd, &dep) };
}

/// Records a global memory barrier (all resources).
pub fn memory_barrier(ctx: &Context, cmd: vk::CommandBuffer, src: Access, dst: Access) {
    let barrier = [vk::MemoryBarrier2::default()
        .src_stage_mask(src.stage)
        .src_access_mask(src.access)
        .dst_stage_mask(dst.stage)
        .dst_access_mask(dst.access)];
    let dep = vk::DependencyInfo::default().memory_barriers(&barrier);
    unsafe { ctx.device().cmd_pipeline_barrier2(cmd, &dep) };
}

/// Makes every earlier device write visible to host reads after the fence.
pub fn host_read_barrier(ctx: &Context, cmd: vk::CommandBuffer) {
    memory_barrier(ctx, cmd, Access::ALL, Access::HOST_READ);
}

/// Records an image layout transition (whole image, all mips and layers).
pub fn image_barrier(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    image: &Image,
    old_layout: vk::ImageLayout,
    new_layout: vk::ImageLayout,
    src: Access,
    dst: Access,
) {
    let barrier = [vk::ImageMemoryBarrier2::default()
        .src_stage_mask(src.stage)
        .src_access_mask(src.access)
        .dst_stage_mask(dst.stage)
        .dst_access_mask(dst.access)
        .old_layout(old_layout)
        .new_layout(new_layout)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image.handle())
        .subresource_range(image.full_range())];
    let dep = vk::DependencyInfo::default().image_memory_barriers(&barrier);
    unsafe { ctx.device().cmd_pipeline_barrier2(cmd, &dep) };
}

impl Context {
    /// Records `f` into a fresh command buffer, submits it and waits for it
    /// with the default fence timeout.
    pub fn one_shot<R>(&self, f: impl FnOnce(vk::CommandBuffer) -> R) -> VkResult<R> {
        self.one_shot_with("one-shot command buffer", self.fence_timeout, f)
    }

    /// Like [`Context::one_shot`], with a label for errors and a timeout.
    pub fn one_shot_with<R>(
        &self,
        label: &str,
        timeout: Duration,
        f: impl FnOnce(vk::CommandBuffer) -> R,
    ) -> VkResult<R> {
        self.submit_keeping(label, timeout, Vec::new(), f)
    }

    /// One-shot submission that keeps `keep_alive` alive until the GPU is
    /// done with it, even when the wait times out.
    pub(crate) fn submit_keeping<R>(
        &self,
        label: &str,
        timeout: Duration,
        keep_alive: Vec<Buffer>,
        f: impl FnOnce(vk::CommandBuffer) -> R,
    ) -> VkResult<R> {
        let device = self.device();
        // Held throughout: the pool, its command buffers and the queue all
        // need external synchronisation.
        let mut state = self.lock_submit();
        reclaim_finished(device, &mut state);

        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(state.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let cmd =
            unsafe { device.allocate_command_buffers(&alloc) }.ctx("vkAllocateCommandBuffers")?[0];
        let fence = match unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) } {
            Ok(fence) => fence,
            Err(e) => {
                unsafe { device.free_command_buffers(state.pool, &[cmd]) };
                return Err(VkError::Call {
                    context: String::from("vkCreateFence"),
                    result: e,
                });
            }
        };
        self.set_name(cmd, label);
        self.set_name(fence, label);
        let cleanup = |state: &SubmitState| unsafe {
            device.destroy_fence(fence, None);
            device.free_command_buffers(state.pool, &[cmd]);
        };

        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        if let Err(e) = unsafe { device.begin_command_buffer(cmd, &begin) } {
            cleanup(&state);
            return Err(VkError::Call {
                context: format!("vkBeginCommandBuffer({label})"),
                result: e,
            });
        }
        let out = f(cmd);
        let cmd_infos = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmd_infos)];
        let submitted = unsafe {
            device
                .end_command_buffer(cmd)
                .and_then(|()| device.queue_submit2(self.queue, &submit, fence))
        };
        if let Err(e) = submitted {
            cleanup(&state);
            return Err(VkError::Call {
                context: format!("submitting `{label}`"),
                result: e,
            });
        }

        match unsafe { device.wait_for_fences(&[fence], true, duration_ns(timeout)) } {
            Ok(()) => {
                cleanup(&state);
                Ok(out)
            }
            Err(vk::Result::TIMEOUT) => {
                // Still executing: its command buffer, fence and resources
                // must survive until it ends; later calls reclaim them.
                state.pending.push(Pending {
                    label: label.to_owned(),
                    fence,
                    cmd,
                    keep_alive,
                });
                Err(VkError::FenceTimeout {
                    label: label.to_owned(),
                    timeout,
                })
            }
            Err(vk::Result::ERROR_DEVICE_LOST) => {
                self.core
                    .hung
                    .store(true, std::sync::atomic::Ordering::SeqCst);
                Err(VkError::DeviceLost {
                    label: label.to_owned(),
                })
            }
            Err(e) => Err(VkError::Call {
                context: format!("vkWaitForFences({label})"),
                result: e,
            }),
        }
    }

    /// Waits up to `timeout` for submissions whose earlier wait timed out,
    /// then frees them. Call before dropping resources they used.
    pub fn wait_pending(&self, timeout: Duration) -> VkResult<()> {
        let device = self.device();
        let mut state = self.lock_submit();
        let fences: Vec<vk::Fence> = state.pending.iter().map(|p| p.fence).collect();
        if fences.is_empty() {
            return Ok(());
        }
        match unsafe { device.wait_for_fences(&fences, true, duration_ns(timeout)) } {
            Ok(()) => {
                reclaim_finished(device, &mut state);
                Ok(())
            }
            Err(vk::Result::TIMEOUT) => Err(VkError::FenceTimeout {
                label: state
                    .pending
                    .iter()
                    .map(|p| p.label.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
                timeout,
            }),
            Err(e) => Err(VkError::Call {
                context: String::from("vkWaitForFences(pending)"),
                result: e,
            }),
        }
    }

    /// Number of timed-out submissions not yet known to have finished.
    pub fn pending_count(&self) -> usize {
        self.lock_submit().pending.len()
    }
}

/// Frees timed-out submissions that have since finished.
fn reclaim_finished(device: &ash::Device, state: &mut SubmitState) {
    let pool = state.pool;
    state.pending.retain(|p| {
        let done = unsafe { device.get_fence_status(p.fence) }.unwrap_or(false);
        if done {
            unsafe {
                device.destroy_fence(p.fence, None);
                device.free_command_buffers(pool, &[p.cmd]);
            }
        }
        !done
    });
}
