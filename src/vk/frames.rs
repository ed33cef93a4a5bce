//! Frames in flight: a ring of slots, each with its own command pool,
//! command buffers and fences, so the host records frame k+1 while the GPU
//! still runs frame k, and whatever a frame leaves for the host (timestamps,
//! copied-out counters) stays in its slot until that slot comes round again.
//!
//! A frame may be recorded in parts ([`FrameRing::next_part`]): each part
//! is its own command buffer and submission with its own fence, all
//! submitted together and executed in order, and the host waits for them
//! one by one. Long work (the ground truth of a large scene) is split so
//! that no single wait approaches the fence timeout on a slow device, and a
//! waiting user sees the parts finish ([`FrameRing::set_progress`]).
//!
//! Submission takes the queue lock for the `vkQueueSubmit2` calls only;
//! waits hold no lock. A wait that times out leaves its slot in flight: the
//! slot is waited for again before reuse, and dropping the ring with work
//! still running declares the device hung, so nothing the GPU may still use
//! is ever destroyed (see [`Context::mark_hung`]).

use super::context::{Context, Core};
use super::error::{VkError, VkResult, VkResultExt};
use ash::vk;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The most parts one frame may be recorded in.
pub const MAX_FRAME_PARTS: u32 = 64;

#[derive(Clone, Debug, PartialEq, Eq)]
enum SlotState {
    /// Nothing submitted, or its submission has finished.
    Idle,
    /// Between `begin` and `submit`.
    Recording,
    /// Submitted under this label, in `parts` parts; the fences tell when
    /// each is done.
    InFlight {
        label: String,
        submitted: Instant,
        parts: usize,
        /// How long each part's wait may take.
        timeout: Duration,
        /// And beyond that for the driver's compile of pipelines the frame
        /// runs for the first time (see `Context::take_compile_allowance`).
        allowance: Duration,
    },
}

/// One part of a frame: a command buffer and the fence of its submission.
struct Part {
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
}

struct Slot {
    pool: vk::CommandPool,
    /// Made on demand; part 0 always exists.
    parts: Vec<Part>,
    /// The part being recorded (while `Recording`).
    current: usize,
    state: SlotState,
}

/// How far the wait for a frame in parts has come, for a progress display.
#[derive(Clone, Copy, Debug)]
pub struct Progress<'a> {
    /// What was submitted.
    pub label: &'a str,
    /// Parts finished.
    pub done: u32,
    /// Parts in all.
    pub total: u32,
    /// Since the frame was submitted.
    pub elapsed: Duration,
}

/// Told how the wait for a frame in more than one part progresses: once
/// before the first part is waited for, then after each part.
pub type ProgressSink = Box<dyn FnMut(&Progress<'_>)>;

/// The ring of frame slots.
pub struct FrameRing {
    core: Arc<Core>,
    slots: Vec<Slot>,
    next: usize,
    timeout: Duration,
    progress: Option<ProgressSink>,
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
            progress: None,
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
        matches!(self.slots[i].state, SlotState::InFlight { .. })
    }

    /// The compile allowance slot `i`'s submission in flight was given
    /// (zero when none is in flight: see `Context::take_compile_allowance`).
    pub fn compile_allowance(&self, i: usize) -> Duration {
        match self.slots[i].state {
            SlotState::InFlight { allowance, .. } => allowance,
            _ => Duration::ZERO,
        }
    }

    /// Where the waits for frames in more than one part report (`None`:
    /// nowhere).
    pub fn set_progress(&mut self, sink: Option<ProgressSink>) {
        self.progress = sink;
    }

    /// Waits (each part bounded by the fence timeout) for slot `i`'s
    /// submission, if any; afterwards everything that frame wrote is
    /// visible to the host.
    pub fn wait(&mut self, i: usize) -> VkResult<()> {
        let SlotState::InFlight {
            label,
            submitted,
            parts,
            timeout,
            allowance,
        } = self.slots[i].state.clone()
        else {
            return Ok(());
        };
        let total = parts as u32;
        let mut report = |done: u32| {
            if let Some(sink) = self.progress.as_mut().filter(|_| total > 1) {
                sink(&Progress {
                    label: &label,
                    done,
                    total,
                    elapsed: submitted.elapsed(),
                });
            }
        };
        report(0);
        // One notice for the frame, not one per part.
        let mut noticed = false;
        for (k, part) in self.slots[i].parts[..parts].iter().enumerate() {
            let waited = self
                .core
                .wait_fence(part.fence, timeout, allowance, &label, &mut noticed);
            match waited {
                Ok(()) => report(k as u32 + 1),
                Err(vk::Result::TIMEOUT) => {
                    return Err(VkError::FenceTimeout {
                        label: label.clone(),
                        timeout,
                        allowance,
                        waited: submitted.elapsed(),
                        part: (total > 1).then_some((k as u32 + 1, total)),
                    })
                }
                Err(vk::Result::ERROR_DEVICE_LOST) => {
                    self.core.hung.store(true, Ordering::SeqCst);
                    return Err(VkError::DeviceLost { label });
                }
                Err(result) => {
                    return Err(VkError::Call {
                        context: format!("vkWaitForFences({label})"),
                        result,
                    })
                }
            }
        }
        self.slots[i].state = SlotState::Idle;
        Ok(())
    }

    /// Waits for every slot in flight.
    pub fn wait_all(&mut self) -> VkResult<()> {
        (0..self.slots.len()).try_for_each(|i| self.wait(i))
    }

    /// Starts recording in the next slot, after waiting for the frame that
    /// used it last; returns the slot and its (first part's) command buffer.
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
        slot.current = 0;
        let cmd = slot.parts[0].cmd;
        begin_recording(device, cmd)?;
        slot.state = SlotState::Recording;
        self.next = (i + 1) % self.slots.len();
        Ok((i, cmd))
    }

    /// Ends the part being recorded in slot `i` and starts the next one
    /// (submitted with the others by [`FrameRing::submit`]); returns its
    /// command buffer. At most [`MAX_FRAME_PARTS`] parts.
    pub fn next_part(&mut self, ctx: &Context, i: usize) -> VkResult<vk::CommandBuffer> {
        let slot = &mut self.slots[i];
        if slot.state != SlotState::Recording {
            return Err(VkError::Usage(format!("frame slot {i} is not recording")));
        }
        if slot.current + 1 >= MAX_FRAME_PARTS as usize {
            return Err(VkError::Usage(format!(
                "a frame is recorded in at most {MAX_FRAME_PARTS} parts"
            )));
        }
        let device = ctx.device();
        unsafe { device.end_command_buffer(slot.parts[slot.current].cmd) }
            .ctx("vkEndCommandBuffer(frame part)")?;
        slot.current += 1;
        if slot.parts.len() <= slot.current {
            let part = Part::new(ctx, slot.pool, i, slot.current)?;
            slot.parts.push(part);
        }
        let cmd = slot.parts[slot.current].cmd;
        begin_recording(device, cmd)?;
        Ok(cmd)
    }

    /// Drops what was recorded in slot `i` without submitting it (its
    /// recording failed half way); the slot is free again.
    pub fn abandon(&mut self, i: usize) {
        let slot = &mut self.slots[i];
        if slot.state == SlotState::Recording {
            // Ending a half-recorded buffer may fail; the pool reset at the
            // next `begin` makes it recordable again either way.
            let _ = unsafe {
                self.core
                    .device
                    .end_command_buffer(slot.parts[slot.current].cmd)
            };
            slot.state = SlotState::Idle;
        }
    }

    /// Ends recording in slot `i` and submits its parts, each with its
    /// fence.
    pub fn submit(&mut self, ctx: &Context, i: usize, label: &str) -> VkResult<()> {
        self.submit_with(ctx, i, label, &[], &[])
    }

    /// [`FrameRing::submit`], the first part waiting for `waits` (each at
    /// its stages) and the last signalling `signals` (presentation: the
    /// image-acquired and rendering-done semaphores).
    pub fn submit_with(
        &mut self,
        ctx: &Context,
        i: usize,
        label: &str,
        waits: &[(vk::Semaphore, vk::PipelineStageFlags2)],
        signals: &[vk::Semaphore],
    ) -> VkResult<()> {
        self.submit_full(ctx, i, label, waits, signals, self.timeout)
    }

    fn submit_full(
        &mut self,
        ctx: &Context,
        i: usize,
        label: &str,
        waits: &[(vk::Semaphore, vk::PipelineStageFlags2)],
        signals: &[vk::Semaphore],
        timeout: Duration,
    ) -> VkResult<()> {
        let slot = &mut self.slots[i];
        if slot.state != SlotState::Recording {
            return Err(VkError::Usage(format!(
                "frame slot {i} was submitted without being recorded"
            )));
        }
        let device = &self.core.device;
        let allowance = ctx.take_compile_allowance();
        let parts = &slot.parts[..=slot.current];
        let ended = unsafe { device.end_command_buffer(parts[parts.len() - 1].cmd) }
            .ctx(&format!("vkEndCommandBuffer({label})"));
        if let Err(e) = ended {
            slot.state = SlotState::Idle;
            return Err(e);
        }
        let fences: Vec<vk::Fence> = parts.iter().map(|p| p.fence).collect();
        unsafe { device.reset_fences(&fences) }.ctx("vkResetFences(frame slot)")?;
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
        let last = parts.len() - 1;
        let submitted = ctx.with_queue(|queue| {
            for (k, part) in parts.iter().enumerate() {
                let cmd_infos = [vk::CommandBufferSubmitInfo::default().command_buffer(part.cmd)];
                let mut submit = vk::SubmitInfo2::default().command_buffer_infos(&cmd_infos);
                if k == 0 {
                    submit = submit.wait_semaphore_infos(&wait_infos);
                }
                if k == last {
                    submit = submit.signal_semaphore_infos(&signal_infos);
                }
                // A failure after the first part leaves the earlier parts
                // running: the slot then counts as in flight up to here.
                if let Err(result) = unsafe { device.queue_submit2(queue, &[submit], part.fence) } {
                    return Err((k, result));
                }
            }
            Ok(())
        });
        let (count, result) = match submitted {
            Ok(()) => (parts.len(), Ok(())),
            Err((k, result)) => (
                k,
                Err(VkError::Call {
                    context: format!("submitting `{label}` (part {} of {})", k + 1, last + 1),
                    result,
                }),
            ),
        };
        slot.state = if count == 0 {
            SlotState::Idle
        } else {
            SlotState::InFlight {
                label: label.to_owned(),
                submitted: Instant::now(),
                parts: count,
                timeout,
                allowance,
            }
        };
        result
    }
}

fn begin_recording(device: &ash::Device, cmd: vk::CommandBuffer) -> VkResult<()> {
    let begin =
        vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
    unsafe { device.begin_command_buffer(cmd, &begin) }.ctx("vkBeginCommandBuffer(frame slot)")
}

impl Part {
    /// A command buffer from `pool` and a fence, named for slot `slot`'s
    /// part `k`.
    fn new(ctx: &Context, pool: vk::CommandPool, slot: usize, k: usize) -> VkResult<Self> {
        let device = ctx.device();
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let cmd = unsafe { device.allocate_command_buffers(&alloc) }
            .ctx("vkAllocateCommandBuffers(frame slot)")?[0];
        let fence = match unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) } {
            Ok(f) => f,
            Err(result) => {
                unsafe { device.free_command_buffers(pool, &[cmd]) };
                return Err(VkError::Call {
                    context: "vkCreateFence(frame slot)".into(),
                    result,
                });
            }
        };
        let name = if k == 0 {
            format!("frame slot {slot}")
        } else {
            format!("frame slot {slot}, part {}", k + 1)
        };
        ctx.set_name(cmd, &name);
        ctx.set_name(fence, &name);
        Ok(Part { cmd, fence })
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
            parts: Vec::new(),
            current: 0,
            state: SlotState::Idle,
        };
        match Part::new(ctx, pool, index, 0) {
            Ok(part) => slot.parts.push(part),
            Err(e) => {
                slot.destroy(device);
                return Err(e);
            }
        }
        ctx.set_name(slot.pool, &format!("frame slot {index}"));
        Ok(slot)
    }

    fn destroy(&self, device: &ash::Device) {
        unsafe {
            for p in &self.parts {
                device.destroy_fence(p.fence, None);
            }
            // Destroying the pool frees its command buffers.
            device.destroy_command_pool(self.pool, None);
        }
    }
}

impl Drop for FrameRing {
    fn drop(&mut self) {
        // No progress display while tearing down.
        self.progress = None;
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
