//! One-shot command buffers with bounded fence waits.

use super::context::{duration_ns, Context, Core, Pending, SubmitState};
use super::error::{VkError, VkResult, VkResultExt};
use super::memory::Buffer;
use ash::vk;
use std::time::{Duration, Instant};

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
                keep_alive: keep
                    .into_iter()
                    .map(|b| Box::new(b) as Box<dyn std::any::Any + Send>)
                    .collect(),
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
