//! Method `subdiv`: the paper's recursive subdivision in one dispatch of
//! persistent workgroups (`glsl/subdivide.comp`), which also writes the
//! indirect arguments of the sort and the draw; then the shared ready-list
//! stage (sort, mesh or fallback draw). Rational patches (`PATCH_RATIONAL`)
//! are subdivided in homogeneous coordinates by the same kernel
//! (`oracle::process_rational`; docs/ARCHITECTURE.md, "Rational patches").

use ash::vk;
use serde_json::json;

use super::{Finished, Method, MethodInfo, MethodSetup, MethodStats, RenderError};
use crate::constants::*;
use crate::draw::{ReadyCaps, ReadyStage};
use crate::frame::{CopyRange, FrameOut, FrameRec, Retired};
use crate::gpu::SubdivPush;
use crate::vk::{
    buffer_barrier, memory_barrier, Access, Buffer, Context, DescriptorSet, MemoryLocation,
    Pipeline, PipelineLayout, SetLayout, VkError, VkResult,
};

/// The registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "subdiv",
    about: "recursive subdivision, one dispatch of persistent workgroups (this project's \
            stand-in for the paper's work graph)",
    rational: true,
    reads_lambda: true,
    build: |setup| Ok(Box::new(Subdiv::new(setup)?)),
};

/// Polls without observed progress before the kernel gives up. One idle
/// poll costs about 8 µs on this project's lavapipe (2 cores), so the cap
/// is about 2 s there and far less on a GPU; any item finishing anywhere
/// resets it, so only a truly stuck kernel reaches it.
pub const DEFAULT_IDLE_POLL_CAP: u32 = 1 << 18;

/// Largest ready list the method grows to (8 bytes per entry, plus the
/// fallback's 240 bytes of vertices per entry).
pub const MAX_READY_CAPACITY: u32 = 1 << 24;

/// How many workgroups to launch: about as many as the device keeps
/// resident. On a CPU device that is one per worker thread (lavapipe runs
/// each workgroup to completion on one thread); on a GPU a generous fixed
/// number, since a workgroup that starts late only finds the work taken.
pub fn default_groups(ctx: &Context) -> u32 {
    if ctx.info().is_cpu {
        let threads = std::env::var("LP_NUM_THREADS")
            .ok()
            .and_then(|s| s.parse::<u32>().ok())
            .filter(|&n| n > 0)
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get() as u32));
        threads.max(1)
    } else {
        512
    }
}

/// The work queue (set 2 of the kernel, `glsl/common/queue.glsl`): nodes,
/// a sequence number per slot, and the head and tail. It is put in its
/// empty state when made and after a frame that ended abnormally; a frame
/// that ends normally leaves it empty and valid for the next.
struct Queue {
    items: Buffer,
    seqs: Buffer,
    state: Buffer,
    capacity: u32,
    set: DescriptorSet,
    /// The next frame must reset it first.
    needs_reset: bool,
}

impl Queue {
    /// A queue of `capacity` entries, rounded up to a power of two.
    fn new(ctx: &Context, layout: &SetLayout, capacity: u32) -> VkResult<Self> {
        if capacity == 0 || capacity > 1 << 30 {
            return Err(VkError::Usage(format!(
                "a work queue of {capacity} entries (1 to 2^30)"
            )));
        }
        let capacity = capacity.next_power_of_two();
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let gpu = MemoryLocation::GpuOnly;
        let items = Buffer::new(ctx, "queue items", u64::from(capacity) * 8, storage, gpu)?;
        let seqs = Buffer::new(ctx, "queue seqs", u64::from(capacity) * 4, storage, gpu)?;
        let state = Buffer::new(
            ctx,
            "queue head and tail",
            u64::from(QUEUE_STATE_WORDS) * 4,
            storage,
            gpu,
        )?;
        let mut bound = [(&items).into(); QUEUE_BINDINGS as usize];
        bound[BIND_QUEUE_ITEMS as usize] = (&items).into();
        bound[BIND_QUEUE_SEQS as usize] = (&seqs).into();
        bound[BIND_QUEUE_STATE as usize] = (&state).into();
        let set = DescriptorSet::new(ctx, "queue set", layout, &bound)?;
        Ok(Self {
            items,
            seqs,
            state,
            capacity,
            set,
            needs_reset: true,
        })
    }

    fn bytes(&self) -> u64 {
        self.items.size() + self.seqs.size() + self.state.size()
    }
}

/// The persistent subdivision method.
pub struct Subdiv {
    stage: ReadyStage,
    queue: Queue,
    layout: PipelineLayout,
    pipeline: Pipeline,
    reset: Pipeline,
    groups: u32,
    idle_poll_cap: u32,
    plant_endless_loop: bool,
    sort: bool,
    counters: Option<CopyRange>,
    // Kept alive for the queue set's layout.
    _queue_layout: SetLayout,
}

impl Subdiv {
    /// Creates the ready stage, the queue and the kernel's pipeline.
    pub fn new(setup: &mut MethodSetup<'_>) -> Result<Self, RenderError> {
        let (ctx, o) = (setup.ctx, setup.options);
        let caps = ReadyCaps {
            ready: o.ready_capacity,
            vertices: false,
            capture: false,
        };
        let stage = ReadyStage::new(ctx, setup.shaders, setup.scene_layout, o.draw, caps)?;
        let queue_layout = SetLayout::storage(
            ctx,
            "queue set",
            QUEUE_BINDINGS as usize,
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let queue = Queue::new(ctx, &queue_layout, o.queue_capacity)?;
        let layout = setup.scene_layout.pipeline_layout::<SubdivPush>(
            ctx,
            "subdivide layout",
            &[stage.set_layout(), &queue_layout],
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let pipeline = setup
            .shaders
            .compute(ctx, &layout, "subdivide", "subdivide.comp")?;
        let reset = setup
            .shaders
            .compute(ctx, &layout, "queue reset", "queue_reset.comp")?;
        Ok(Self {
            stage,
            queue,
            layout,
            pipeline,
            reset,
            groups: o.groups.unwrap_or_else(|| default_groups(ctx)).max(1),
            idle_poll_cap: o.idle_poll_cap,
            plant_endless_loop: o.plant_endless_loop,
            sort: o.sort,
            counters: None,
            _queue_layout: queue_layout,
        })
    }

    /// Workgroups launched per dispatch.
    pub fn groups(&self) -> u32 {
        self.groups
    }

    /// Records the reset of the counters and the queue, the in-flight
    /// count, and the kernel's dispatch (scope "subdivide").
    fn record_subdivide(&self, f: &mut FrameRec<'_>) -> VkResult<()> {
        let count = f.scene.count;
        if count > IN_FLIGHT_MASK {
            return Err(VkError::Usage(format!(
                "{count} base patches: the subdivision kernel counts at most {IN_FLIGHT_MASK}"
            )));
        }
        let list = self.stage.list();
        self.stage.record_reset(f);
        let in_flight = count + self.plant_endless_loop as u32;
        unsafe {
            f.ctx.device().cmd_update_buffer(
                f.cmd,
                list.counters.handle(),
                u64::from(C_IN_FLIGHT) * 4,
                &in_flight.to_le_bytes(),
            )
        };
        buffer_barrier(
            f.ctx,
            f.cmd,
            &list.counters,
            Access::TRANSFER_WRITE,
            Access::ALL,
        );
        let pc = SubdivPush {
            ready_capacity: list.caps.ready,
            queue_capacity: self.queue.capacity,
            patch_count: count,
            idle_poll_cap: self.idle_poll_cap,
        };
        let bind = vk::PipelineBindPoint::COMPUTE;
        self.stage.bind_sets(f, bind, &self.layout);
        self.queue
            .set
            .bind(f.ctx, f.cmd, bind, &self.layout, SET_PRODUCER, &[]);
        self.layout.push_block(f.cmd, &pc)?;
        if self.queue.needs_reset {
            self.reset.bind(f.cmd);
            let groups = self.queue.capacity.div_ceil(64);
            unsafe { f.ctx.device().cmd_dispatch(f.cmd, groups, 1, 1) };
            memory_barrier(
                f.ctx,
                f.cmd,
                Access::COMPUTE_WRITE,
                Access::COMPUTE_READ_WRITE,
            );
        }
        self.pipeline.bind(f.cmd);
        let groups = self.groups;
        f.scoped("subdivide", |f| {
            unsafe { f.ctx.device().cmd_dispatch(f.cmd, groups, 1, 1) };
            Ok(())
        })?;
        buffer_barrier(
            f.ctx,
            f.cmd,
            &list.counters,
            Access::COMPUTE_READ_WRITE,
            Access::ALL,
        );
        buffer_barrier(
            f.ctx,
            f.cmd,
            &list.ready,
            Access::COMPUTE_READ_WRITE,
            Access::ALL,
        );
        Ok(())
    }
}

impl Method for Subdiv {
    fn name(&self) -> &'static str {
        INFO.name
    }

    fn draw_path(&self) -> &'static str {
        self.stage.path().name()
    }

    fn record(&mut self, f: &mut FrameRec<'_>) -> Result<(), RenderError> {
        self.stage.ensure_capture(f.ctx, f.capture, f.retired)?;
        self.record_subdivide(f)?;
        self.stage.record_draw(f, self.sort)?;
        self.counters = Some(f.copy_out(&self.stage.list().counters, COUNTER_WORDS)?);
        Ok(())
    }

    fn finish(&mut self, out: &mut FrameOut<'_>) -> Result<Finished, RenderError> {
        let range = self
            .counters
            .ok_or_else(|| RenderError::Request("finish() before any frame was recorded".into()))?;
        let words = out.words(range);
        let stats = GpuSubdivStats::from_counters(words);
        // This frame's reset (if any) is done; an abnormal end leaves the
        // queue in an unknown state.
        self.queue.needs_reset = stats.errors != 0 || stats.in_flight_left != 0;
        if let Some(reason) =
            self.stage
                .grow_if_full(out.ctx, words, MAX_READY_CAPACITY, out.retired)?
        {
            return Ok(Finished::Redo { reason });
        }
        if let Some(message) = stats.error_message() {
            return Err(RenderError::Method {
                method: INFO.name,
                message,
            });
        }
        let mut m = stats.method_stats(self.stage.list().caps.ready);
        m.own
            .push(("queue_capacity_items", json!(self.queue.capacity)));
        m.own.push(("workgroups", json!(self.groups)));
        Ok(Finished::Done(m))
    }

    fn reconfigure(
        &mut self,
        setup: &mut MethodSetup<'_>,
        _retired: &mut Retired,
    ) -> Result<bool, RenderError> {
        let o = setup.options;
        // Buffer sizes and the draw path need a new method; the rest are
        // values recorded per frame.
        if o.draw != self.stage.path()
            || o.queue_capacity.next_power_of_two() != self.queue.capacity
            || o.ready_capacity > self.stage.list().caps.ready
        {
            return Ok(false);
        }
        self.groups = o.groups.unwrap_or_else(|| default_groups(setup.ctx)).max(1);
        self.idle_poll_cap = o.idle_poll_cap;
        self.plant_endless_loop = o.plant_endless_loop;
        self.sort = o.sort;
        Ok(true)
    }

    fn memory(&self) -> Vec<(&'static str, u64)> {
        let mut v = vec![("queue", self.queue.bytes())];
        v.extend(self.stage.memory_bytes());
        v
    }

    fn ready(&self) -> Option<&ReadyStage> {
        Some(&self.stage)
    }

    fn has_wedges(&self) -> bool {
        true
    }
}

/// What the subdivision pass reported through its counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GpuSubdivStats {
    /// Ready nodes appended (may exceed the capacity: see `errors`).
    pub ready_quads: u32,
    /// Work items processed.
    pub nodes_processed: u32,
    /// Nodes dropped by the frustum test.
    pub culled_patches: u32,
    /// Ready nodes dropped as back-facing.
    pub backface_culled: u32,
    /// Deepest ready node.
    pub max_depth: u32,
    /// Ready nodes at l_max.
    pub nodes_at_lmax: u32,
    /// Triangles of the ready nodes (2 per quad + wedges).
    pub triangles: u32,
    /// Wedge triangles.
    pub wedge_triangles: u32,
    /// Items a full queue refused (they stayed in their workgroup).
    pub queue_spills: u32,
    /// Queue operations that lost a compare-and-swap (retried later).
    pub queue_retries: u32,
    /// Polls of the in-flight count by idle workgroups.
    pub idle_polls: u32,
    /// Atomic read-modify-write operations on global memory.
    pub global_atomics: u32,
    /// Items that went through the queue.
    pub queue_pushed: u32,
    /// Most items in the queue at once (sampled at pushes).
    pub queue_peak_items: u32,
    /// Most outer iterations of one invocation.
    pub iterations_max: u32,
    /// `ERR_*` bits.
    pub errors: u32,
    /// Items still counted in flight at the end (0 unless stuck).
    pub in_flight_left: u32,
}

impl GpuSubdivStats {
    /// Reads the counters words.
    pub fn from_counters(c: &[u32]) -> Self {
        let at = |i: u32| c[i as usize];
        GpuSubdivStats {
            ready_quads: at(C_READY_COUNT),
            nodes_processed: at(C_PROCESSED),
            culled_patches: at(C_CULLED),
            backface_culled: at(C_BACKFACE),
            max_depth: at(C_MAX_DEPTH),
            nodes_at_lmax: at(C_AT_LMAX),
            triangles: at(C_TRIANGLES),
            wedge_triangles: at(C_WEDGES),
            queue_spills: at(C_SPILLS),
            queue_retries: at(C_QUEUE_RETRIES),
            idle_polls: at(C_IDLE_POLLS),
            global_atomics: at(C_GLOBAL_ATOMICS),
            queue_pushed: at(C_QUEUE_PUSHED),
            queue_peak_items: at(C_QUEUE_PEAK),
            iterations_max: at(C_ITERATIONS_MAX),
            errors: at(C_ERROR),
            in_flight_left: at(C_IN_FLIGHT) & IN_FLIGHT_MASK,
        }
    }

    /// The common keys plus the method's own section.
    pub fn method_stats(&self, ready_capacity: u32) -> MethodStats {
        MethodStats {
            triangles: u64::from(self.triangles),
            culled_patches: u64::from(self.culled_patches),
            own: vec![
                ("ready_quads", json!(self.ready_quads)),
                ("wedge_triangles", json!(self.wedge_triangles)),
                ("backface_culled", json!(self.backface_culled)),
                ("max_depth", json!(self.max_depth)),
                ("nodes_at_lmax", json!(self.nodes_at_lmax)),
                ("nodes_processed", json!(self.nodes_processed)),
                ("queue_peak_items", json!(self.queue_peak_items)),
                ("queue_spills", json!(self.queue_spills)),
                ("queue_pushed", json!(self.queue_pushed)),
                ("queue_retries", json!(self.queue_retries)),
                ("iterations_max", json!(self.iterations_max)),
                ("idle_polls", json!(self.idle_polls)),
                ("global_atomics", json!(self.global_atomics)),
                (
                    "global_atomics_per_node",
                    json!(f64::from(self.global_atomics) / f64::from(self.nodes_processed.max(1))),
                ),
                ("ready_capacity_items", json!(ready_capacity)),
            ],
        }
    }

    /// The error bits as a sentence, or `None`.
    pub fn error_message(&self) -> Option<String> {
        if self.errors == 0 {
            return None;
        }
        let mut parts = Vec::new();
        if self.errors & ERR_ITERATION_CAP != 0 {
            parts.push(format!(
                "the subdivision kernel made no progress for its whole iteration cap and gave up \
                 ({} items still in flight)",
                self.in_flight_left
            ));
        }
        if self.errors & ERR_READY_FULL != 0 {
            parts.push(format!(
                "the ready list overflowed ({} ready nodes) and cannot grow further",
                self.ready_quads
            ));
        }
        if self.errors & ERR_STACK_OVERFLOW != 0 {
            parts.push("an invocation's depth-first stack overflowed".into());
        }
        Some(parts.join("; "))
    }
}
