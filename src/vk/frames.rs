//! Frames in flight: a ring of slots, each with its own command pool,
//! command buffer and fence, so the host records frame k+1 while the GPU
//! still runs frame k, and whatever a frame leaves for the host (timestamps,
//! copied-out counters) stays in its slot until that slot comes round again.
//!
//! Submission takes the queue lock for the `vkQueueSubmit2` call only; waits
//! hold no lock. A wait that times out leaves its slot in flight: the slot
//! is waited for again before reuse, and dropping the ring with work still
//! running declares the device hung, so nothing the GPU may still use is
//! ever destroyed (see [`Context::mark_hung`]).

use super::context::{duration_ns, Context, Core};
use super::error::{VkError, VkResult, VkResultExt};
use ash::vk;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::Duration;

#[derive(Clone, Debug, PartialEq, Eq)]
enum SlotState {
    /// Nothing submitted, or its submission has finished.
    Idle,
    /// Between `begin` and `submit`.
    Recording,
    /// Submitted under this label; the fence tells when it is done.
    InFlight(String),
}

struct Slot {
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    state: SlotState,
}

/// The ring of frame slots.
pub struct FrameRing {
    core: Arc<Core>,
    slots: Vec<Slot>,
    next: usize,
    timeout: Duration,
}

impl FrameRing {
    /// A ring of `count` slots; fence waits give up after the context's
    /// fence timeout.
    pub fn new(ctx: &Context, count: usize) -> VkResult<Self> {
        if count == 0 {
            return Err(VkError::Usage(
                "a frame ring needs at least one slot".into(),
            ));
        }
        let mut ring = Self {
            core: ctx.core.clone(),
            slots: Vec::with_capacity(count),
            next: 0,
            timeout: ctx.fence_timeout(),
        };
        for i in 0..count {
            // Pushed one by one so a failure drops (destroys) the ones made.
            ring.slots.push(Slot::new(ctx, i)?);
        }
        Ok(ring)
    }

    /// Number of slots.
    pub fn len(&self) -> usize {
        self.slots.len()
    }

    /// Always false: a ring has at least one slot.
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }

    /// The slot the next [`FrameRing::begin`] will use.
    pub fn next_slot(&self) -> usize {
        self.next
    }

    /// Whether slot `i` has a submission that may still run.
    pub fn in_flight(&self, i: usize) -> bool {
        matches!(self.slots[i].state, SlotState::InFlight(_))
    }

    /// Waits (bounded by the fence timeout) for slot `i`'s submission, if
    /// any; afterwards everything that frame wrote is visible to the host.
    pub fn wait(&mut self, i: usize) -> VkResult<()> {
        let slot = &mut self.slots[i];
        let SlotState::InFlight(label) = &slot.state else {
            return Ok(());
        };
        let device = &self.core.device;
        match unsafe { device.wait_for_fences(&[slot.fence], true, duration_ns(self.timeout)) } {
            Ok(()) => {
                slot.state = SlotState::Idle;
                Ok(())
            }
            Err(vk::Result::TIMEOUT) => Err(VkError::FenceTimeout {
                label: label.clone(),
                timeout: self.timeout,
            }),
            Err(vk::Result::ERROR_DEVICE_LOST) => {
                self.core.hung.store(true, Ordering::SeqCst);
                Err(VkError::DeviceLost {
                    label: label.clone(),
                })
            }
            Err(result) => Err(VkError::Call {
                context: format!("vkWaitForFences({label})"),
                result,
            }),
        }
    }

    /// Waits for every slot in flight.
    pub fn wait_all(&mut self) -> VkResult<()> {
        (0..self.slots.len()).try_for_each(|i| self.wait(i))
    }

    /// Starts recording in the next slot, after waiting for the frame that
    /// used it last; returns the slot and its command buffer.
    pub fn begin(&mut self) -> VkResult<(usize, vk::CommandBuffer)> {
        let i = self.next;
        self.wait(i)?;
        let slot = &mut self.slots[i];
        if slot.state == SlotState::Recording {
            return Err(VkError::Usage(format!(
                "frame slot {i} is already recording"
            )));
        }
        let device = &self.core.device;
        unsafe { device.reset_command_pool(slot.pool, vk::CommandPoolResetFlags::empty()) }
            .ctx("vkResetCommandPool(frame slot)")?;
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        unsafe { device.begin_command_buffer(slot.cmd, &begin) }
            .ctx("vkBeginCommandBuffer(frame slot)")?;
        slot.state = SlotState::Recording;
        let cmd = slot.cmd;
        self.next = (i + 1) % self.slots.len();
        Ok((i, cmd))
    }

    /// Drops what was recorded in slot `i` without submitting it (its
    /// recording failed half way); the slot is free again.
    pub fn abandon(&mut self, i: usize) {
        let slot = &mut self.slots[i];
        if slot.state == SlotState::Recording {
            // Ending a half-recorded buffer may fail; the pool reset at the
            // next `begin` makes it recordable again either way.
            let _ = unsafe { self.core.device.end_command_buffer(slot.cmd) };
            slot.state = SlotState::Idle;
        }
    }

    /// Ends recording in slot `i` and submits it with the slot's fence.
    pub fn submit(&mut self, ctx: &Context, i: usize, label: &str) -> VkResult<()> {
        self.submit_with(ctx, i, label, &[], &[])
    }

    /// [`FrameRing::submit`], waiting for `waits` (each at its stages) and
    /// signalling `signals` (presentation: the image-acquired and
    /// rendering-done semaphores).
    pub fn submit_with(
        &mut self,
        ctx: &Context,
        i: usize,
        label: &str,
        waits: &[(vk::Semaphore, vk::PipelineStageFlags2)],
        signals: &[vk::Semaphore],
    ) -> VkResult<()> {
        let slot = &mut self.slots[i];
        if slot.state != SlotState::Recording {
            return Err(VkError::Usage(format!(
                "frame slot {i} was submitted without being recorded"
            )));
        }
        let device = &self.core.device;
        let ended = unsafe { device.end_command_buffer(slot.cmd) }
            .ctx(&format!("vkEndCommandBuffer({label})"));
        if let Err(e) = ended {
            slot.state = SlotState::Idle;
            return Err(e);
        }
        unsafe { device.reset_fences(&[slot.fence]) }.ctx("vkResetFences(frame slot)")?;
        let cmd_infos = [vk::CommandBufferSubmitInfo::default().command_buffer(slot.cmd)];
        let wait_infos: Vec<_> = waits
            .iter()
            .map(|&(s, stage)| {
                vk::SemaphoreSubmitInfo::default()
                    .semaphore(s)
                    .stage_mask(stage)
            })
            .collect();
        let signal_infos: Vec<_> = signals
            .iter()
            .map(|&s| {
                vk::SemaphoreSubmitInfo::default()
                    .semaphore(s)
                    .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            })
            .collect();
        let submit = [vk::SubmitInfo2::default()
            .command_buffer_infos(&cmd_infos)
            .wait_semaphore_infos(&wait_infos)
            .signal_semaphore_infos(&signal_infos)];
        let submitted =
            ctx.with_queue(|queue| unsafe { device.queue_submit2(queue, &submit, slot.fence) });
        match submitted {
            Ok(()) => {
                slot.state = SlotState::InFlight(label.to_owned());
                Ok(())
            }
            Err(result) => {
                slot.state = SlotState::Idle;
                Err(VkError::Call {
                    context: format!("submitting `{label}`"),
                    result,
                })
            }
        }
    }
}

impl Slot {
    fn new(ctx: &Context, index: usize) -> VkResult<Self> {
        let device = ctx.device();
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(ctx.info().queue_family)
            .flags(vk::CommandPoolCreateFlags::TRANSIENT);
        let pool = unsafe { device.create_command_pool(&info, None) }
            .ctx("vkCreateCommandPool(frame slot)")?;
        let mut slot = Slot {
            pool,
            cmd: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
            state: SlotState::Idle,
        };
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let made = unsafe { device.allocate_command_buffers(&alloc) }
            .ctx("vkAllocateCommandBuffers(frame slot)")
            .and_then(|cmds| {
                slot.cmd = cmds[0];
                unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
                    .ctx("vkCreateFence(frame slot)")
            });
        match made {
            Ok(fence) => slot.fence = fence,
            Err(e) => {
                slot.destroy(device);
                return Err(e);
            }
        }
        let name = format!("frame slot {index}");
        ctx.set_name(slot.pool, &name);
        ctx.set_name(slot.cmd, &name);
        ctx.set_name(slot.fence, &name);
        Ok(slot)
    }

    fn destroy(&self, device: &ash::Device) {
        unsafe {
            if self.fence != vk::Fence::null() {
                device.destroy_fence(self.fence, None);
            }
            // Destroying the pool frees its command buffer.
            device.destroy_command_pool(self.pool, None);
        }
    }
}

impl Drop for FrameRing {
    fn drop(&mut self) {
        for i in 0..self.slots.len() {
            if let Err(e) = self.wait(i) {
                log::error!("{e}");
                // Work that may still run keeps everything it uses.
                self.core.hung.store(true, Ordering::SeqCst);
            }
        }
        if self.core.hung.load(Ordering::SeqCst) {
            return;
        }
        for slot in &self.slots {
            slot.destroy(&self.core.device);
        }
    }
}
