//! One-shot command buffers with bounded fence waits, and synchronization2
//! barrier helpers.

use super::context::{duration_ns, Context, Core, Pending, SubmitState};
use super::error::{VkError, VkResult, VkResultExt};
use super::memory::{Buffer, Image};
use ash::vk;
use std::time::{Duration, Instant};

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

/// Records a barrier on a whole buffer.
pub fn buffer_barrier(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    buffer: &Buffer,
    src: Access,
    dst: Access,
) {
    let barrier = [buffer_barrier_info(buffer.handle(), src, dst)];
    let dep = vk::DependencyInfo::default().buffer_memory_barriers(&barrier);
    unsafe { ctx.device().cmd_pipeline_barrier2(cmd, &dep) };
}

/// Records filling the whole of `buffer` with the word `value`, after every
/// earlier use of it and before every later one.
pub fn fill_buffer(ctx: &Context, cmd: vk::CommandBuffer, buffer: &Buffer, value: u32) {
    buffer_barrier(ctx, cmd, buffer, Access::ALL, Access::TRANSFER_WRITE);
    unsafe {
        ctx.device()
            .cmd_fill_buffer(cmd, buffer.handle(), 0, vk::WHOLE_SIZE, value)
    };
    buffer_barrier(ctx, cmd, buffer, Access::TRANSFER_WRITE, Access::ALL);
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
    let barrier = [image_barrier_info(src, dst, old_layout, new_layout)
        .image(image.handle())
        .subresource_range(image.full_range())];
    let dep = vk::DependencyInfo::default().image_memory_barriers(&barrier);
    unsafe { ctx.device().cmd_pipeline_barrier2(cmd, &dep) };
}

impl Context {
    /// Records `f` into a fresh command buffer, submits it and waits for it
    /// with the default fence timeout. When `f` fails, nothing is submitted:
    /// the half-recorded command buffer is discarded and `f`'s error returned.
    pub fn one_shot<R>(&self, f: impl FnOnce(vk::CommandBuffer) -> VkResult<R>) -> VkResult<R> {
        self.one_shot_with("one-shot command buffer", self.fence_timeout, f)
    }

    /// Like [`Context::one_shot`], with a label for errors and a timeout.
    pub fn one_shot_with<R>(
        &self,
        label: &str,
        timeout: Duration,
        f: impl FnOnce(vk::CommandBuffer) -> VkResult<R>,
    ) -> VkResult<R> {
        let (out, _) = self.one_shot_keeping(label, timeout, Vec::new(), |cmd, _| f(cmd))?;
        Ok(out)
    }

    /// One-shot submission of commands that use `keep` (e.g. a staging
    /// buffer): the buffers are handed back once the GPU is done with them,
    /// and kept alive in the pending list if the wait times out, so they are
    /// never freed under the GPU.
    pub(crate) fn one_shot_keeping<R>(
        &self,
        label: &str,
        timeout: Duration,
        keep: Vec<Buffer>,
        f: impl FnOnce(vk::CommandBuffer, &[Buffer]) -> VkResult<R>,
    ) -> VkResult<(R, Vec<Buffer>)> {
        let device = self.device();
        let submitted;
        // The pool and its command buffers need external synchronisation
        // while allocating, recording and freeing, the queue while
        // submitting; the wait itself holds no lock.
        let (cmd, fence, out) = {
            let mut state = self.lock_submit();
            reclaim_finished(&self.core, &mut state);
            let (cmd, fence) = begin_one_shot(self, &state, label)?;
            let recorded = f(cmd, &keep).and_then(|out| {
                unsafe { device.end_command_buffer(cmd) }
                    .ctx(&format!("vkEndCommandBuffer({label})"))?;
                Ok(out)
            });
            let out = match recorded {
                Ok(out) => out,
                Err(e) => {
                    // Never submit what was only partly recorded.
                    free_one_shot(device, &state, cmd, fence);
                    return Err(e);
                }
            };
            let cmd_infos = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
            let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmd_infos)];
            submitted = Instant::now();
            if let Err(e) = unsafe { device.queue_submit2(self.queue, &submit, fence) } {
                free_one_shot(device, &state, cmd, fence);
                return Err(VkError::Call {
                    context: format!("submitting `{label}`"),
                    result: e,
                });
            }
            (cmd, fence, out)
        };

        let allowance = self.take_compile_allowance();
        let wait = self
            .core
            .wait_fence(fence, timeout, allowance, label, &mut false);
        let error = match wait {
            Ok(()) => {
                free_one_shot(device, &self.lock_submit(), cmd, fence);
                return Ok((out, keep));
            }
            Err(vk::Result::ERROR_DEVICE_LOST) => {
                self.mark_hung();
                return Err(VkError::DeviceLost {
                    label: label.to_owned(),
                });
            }
            // Still executing: its command buffer, fence and resources
            // must survive until it ends; later calls reclaim them.
            Err(vk::Result::TIMEOUT) => VkError::FenceTimeout {
                label: label.to_owned(),
                timeout,
                allowance,
                waited: submitted.elapsed(),
                part: None,
            },
            // Unknown state: keep everything alive as if it still ran.
            Err(e) => VkError::Call {
                context: format!("vkWaitForFences({label})"),
                result: e,
            },
        };
        self.park(
            Pending {
                label: label.to_owned(),
                fence,
                cmd,
                keep_alive: keep,
                submitted,
            },
            timeout,
        );
        Err(error)
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
                reclaim_finished(&self.core, &mut state);
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
                waited: state
                    .pending
                    .iter()
                    .map(|p| p.submitted.elapsed())
                    .max()
                    .unwrap_or(timeout),
                allowance: Duration::ZERO,
                part: None,
            }),
            Err(e) => Err(VkError::Call {
                context: String::from("vkWaitForFences(pending)"),
                result: e,
            }),
        }
    }

    /// Keeps a submission whose wait did not end alive (its command buffer,
    /// fence and resources) until a later call sees it finish, and tells
    /// every resource that it may still use it (see [`Core::may_free`]).
    fn park(&self, pending: Pending, timeout: Duration) {
        let mut unfinished = self
            .core
            .unfinished
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        unfinished.push((pending.fence, timeout));
        drop(unfinished);
        self.lock_submit().pending.push(pending);
    }

    /// Number of timed-out submissions not yet known to have finished.
    pub fn pending_count(&self) -> usize {
        self.lock_submit().pending.len()
    }
}

/// Frees timed-out submissions that have since finished.
fn reclaim_finished(core: &Core, state: &mut SubmitState) {
    let device = &core.device;
    let pool = state.pool;
    state.pending.retain(|p| {
        let done = unsafe { device.get_fence_status(p.fence) }.unwrap_or(false);
        if done {
            core.forget_unfinished(p.fence);
            unsafe {
                device.destroy_fence(p.fence, None);
                device.free_command_buffers(pool, &[p.cmd]);
            }
        }
        !done
    });
}

/// Allocates a primary command buffer from the one-shot pool and a fence,
/// names both `label` and begins recording.
fn begin_one_shot(
    ctx: &Context,
    state: &SubmitState,
    label: &str,
) -> VkResult<(vk::CommandBuffer, vk::Fence)> {
    let device = ctx.device();
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
    ctx.set_name(cmd, label);
    ctx.set_name(fence, label);
    let begin =
        vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
    if let Err(e) = unsafe { device.begin_command_buffer(cmd, &begin) } {
        free_one_shot(device, state, cmd, fence);
        return Err(VkError::Call {
            context: format!("vkBeginCommandBuffer({label})"),
            result: e,
        });
    }
    Ok((cmd, fence))
}

/// Frees a one-shot command buffer and its fence (the pool lock is held).
fn free_one_shot(
    device: &ash::Device,
    state: &SubmitState,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
) {
    unsafe {
        device.destroy_fence(fence, None);
        device.free_command_buffers(state.pool, &[cmd]);
    }
}
