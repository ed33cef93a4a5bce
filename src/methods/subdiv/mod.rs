//! Method `subdiv`: the paper's recursive subdivision in one dispatch of
//! persistent workgroups, then the shared ready-list stage (mesh or
//! fallback draw). Rational patches (`PATCH_RATIONAL`) are subdivided in
//! homogeneous coordinates by the same kernels (`oracle::process_rational`;
//! docs/ARCHITECTURE.md, "Rational patches").
//!
//! Two kernels, `--kernel`:
//! - `levels` (the default): the depth-synchronous persistent kernel
//!   (`glsl/levels/persistent.comp`), the level schedule of `subdiv-indirect`
//!   ([`super::levels`]) looped inside one dispatch with a grid barrier
//!   between rounds, among the workgroups its occupancy discovery found
//!   resident. Its ready list is in the canonical order: no sort, and the
//!   image of `subdiv-indirect`.
//! - `queue`: the work-queue kernel of commit a7d19dc
//!   (`glsl/subdiv/queue.comp`), kept until a GPU run shows whether it
//!   wins anywhere; its order depends on timing, so its list is sorted.
//!
//! Where a kernel's watchdog trips (a workgroup that stopped running, a
//! device that does not keep its promises), the frame is drawn again with
//! the per-depth rounds of `subdiv-indirect`, and so is every later frame
//! of this method; the stats say so (`kernel`, `fallback`).

pub mod constants;
pub mod push;
use std::fmt;
use std::str::FromStr;

use ash::vk;
use serde_json::json;

use self::constants::*;
use self::push::SubdivPush;
use super::levels::{self, LevelState, Levels, PersistentRun};
use super::levels::{
    finish_rounds, level_memory, level_parts, must_remake, recorded, GpuSubdivStats, RoundBudget,
};
use super::targets::{Against, Figure, Target};
use super::{tess, Finished, Method, MethodInfo, MethodSetup, Reads, RenderError, Role};
use crate::constants::*;
use crate::draw::hiz::Hiz;
use crate::draw::{ReadyStage, MAX_READY_CAPACITY};
use crate::frame::{CopyRange, FrameOut, FrameRec, Retired};
use crate::gpu::blocks::block;
use crate::vk::{
    Access, Buffer, Context, DescriptorSet, MemoryLocation, Pass, Pipeline, PipelineLayout,
    Recorder, Res, SetLayout, VkError, VkResult,
};

/// The registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "subdiv",
    about: "recursive subdivision, one dispatch of persistent workgroups (this project's \
            stand-in for the paper's work graph)",
    rational: true,
    pn: false,
    reads: Reads::SUBDIVIDES,
    role: Role::Compared,
    targets: SUBDIV_TARGETS,
    heat_map: "subdivision depth",
    seams: "wedges (crack-closing triangles)",
    checks: None,
    blocks: &[
        block::<push::SubdivPush>,
        block::<crate::methods::levels::push::LevelPush>,
    ],
    build: |setup| Ok(Box::new(Subdiv::new(setup)?)),
};

/// What `bench`'s report judges `subdiv` by: the paper's triangle ratios
/// against `tess` at ε = 1 (0.45× at λ = 0.5, 0.12× at λ = 0, and λ = 0
/// 0.3× of λ = 0.5), its image error within 10 % of `tess`'s at ε 0.5, 1
/// and 2, at equal FLIP 0.6× `tess`'s triangles on the kitchen and 0.9×
/// on the teapot; its subdivision pass 0.9× `subdiv-indirect`'s at ε = 1;
/// its node memory within 32 MiB (the paper's work graph needs 26.39).
const SUBDIV_TARGETS: &[Target] = &[
    Target::Ratio {
        eps: 1.0,
        figure: Figure::Triangles,
        lambda: Some(0.5),
        against: Against::Method(tess::INFO.name),
        limit: 0.45,
    },
    Target::Ratio {
        eps: 1.0,
        figure: Figure::Triangles,
        lambda: Some(0.0),
        against: Against::Method(tess::INFO.name),
        limit: 0.12,
    },
    Target::Ratio {
        eps: 1.0,
        figure: Figure::Triangles,
        lambda: Some(0.0),
        against: Against::Lambda(0.5),
        limit: 0.3,
    },
    Target::Ratio {
        eps: 0.5,
        figure: Figure::Flip,
        lambda: Some(0.5),
        against: Against::Method(tess::INFO.name),
        limit: 1.1,
    },
    Target::Ratio {
        eps: 1.0,
        figure: Figure::Flip,
        lambda: Some(0.5),
        against: Against::Method(tess::INFO.name),
        limit: 1.1,
    },
    Target::Ratio {
        eps: 2.0,
        figure: Figure::Flip,
        lambda: Some(0.5),
        against: Against::Method(tess::INFO.name),
        limit: 1.1,
    },
    Target::EqualFlip {
        lambda: 0.5,
        limits: &[("kitchen", 0.6), ("teapot", 0.9)],
    },
    Target::Ratio {
        eps: 1.0,
        figure: Figure::SubdividePass,
        lambda: None,
        against: Against::Method(super::subdiv_indirect::INFO.name),
        limit: 0.9,
    },
    levels::NODE_MEMORY_TARGET,
];

/// Polls without observed progress before the queue kernel gives up. One
/// idle poll costs about 8 µs on this project's lavapipe (2 cores), so the
/// cap is about 2 s there and far less on a GPU; any item finishing
/// anywhere resets it, so only a truly stuck kernel reaches it.
pub const DEFAULT_IDLE_POLL_CAP: u32 = 1 << 18;

/// Which persistent kernel `subdiv` runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Kernel {
    /// The depth-synchronous level kernel (`glsl/levels/persistent.comp`).
    #[default]
    Levels,
    /// The work-queue kernel (`glsl/subdiv/queue.comp`).
    Queue,
}

impl Kernel {
    /// The name the command line uses.
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Levels => "levels",
            Kernel::Queue => "queue",
        }
    }
}

impl fmt::Display for Kernel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Kernel {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "levels" => Ok(Kernel::Levels),
            "queue" => Ok(Kernel::Queue),
            other => Err(format!(
                "unknown kernel `{other}`: expected levels (depth-synchronous) or queue"
            )),
        }
    }
}

/// `subdiv`'s knobs ([`super::PerMethod::subdiv`]): its flags, under their
/// own heading in `--help`, and the tuning and test faults that have none.
#[derive(Clone, Debug, PartialEq, Eq, clap::Args)]
#[command(next_help_heading = "subdiv")]
pub struct Options {
    /// subdiv: the persistent kernel, levels (depth-synchronous: the
    /// per-depth schedule in one dispatch, a grid barrier between rounds;
    /// the default) or queue (the work-queue kernel, kept for comparison).
    #[arg(long, value_name = "K", default_value = "levels")]
    pub kernel: Kernel,
    /// subdiv: persistent workgroups to launch (default: about what the
    /// device keeps resident), for profiling.
    #[arg(long, value_name = "N")]
    pub groups: Option<u32>,
    /// Polls without progress before the level kernel's watchdog sends the
    /// frame to the per-depth rounds.
    #[arg(skip = levels::DEFAULT_WATCHDOG_POLLS)]
    pub watchdog_polls: u32,
    /// Polls of an unchanged join count before the occupancy window closes
    /// (`None`: the device's default).
    #[arg(skip)]
    pub join_polls: Option<u32>,
    /// Test-only faults of the persistent level kernel (`FAULT_*`).
    #[arg(skip)]
    pub level_faults: u32,
    /// `--kernel queue`: work-queue entries.
    #[arg(skip = 1u32 << 19)]
    pub queue_capacity: u32,
    /// `--kernel queue`: polls without progress before it gives up.
    #[arg(skip = DEFAULT_IDLE_POLL_CAP)]
    pub idle_poll_cap: u32,
    /// `--kernel queue`: deque entries per workgroup (tests lower it).
    #[arg(skip = SUBDIV_LOCAL_CAP)]
    pub deque_capacity: u32,
    /// `--kernel queue`: base patches per claim (0: spread over the
    /// workgroups; tests fill the deque with it).
    #[arg(skip)]
    pub base_batch: u32,
    /// `--kernel queue`: sort the ready list before drawing (deterministic
    /// images; the level kernels need no sort).
    #[arg(skip = true)]
    pub sort: bool,
    /// Test-only fault for `--kernel queue`: one phantom item in flight
    /// that never completes, so the kernel can only end through its
    /// iteration cap.
    #[arg(skip)]
    pub plant_endless_loop: bool,
}

impl Default for Options {
    fn default() -> Self {
        super::cli_defaults()
    }
}

impl Options {
    /// Refuses what no device could run: no workgroups, a deque the
    /// kernel's workgroups cannot hold. (How many workgroups one dispatch
    /// may launch depends on the device: [`check_groups`].)
    pub fn check(&self) -> Result<(), String> {
        if self.groups == Some(0) {
            return Err("--groups must be at least 1".into());
        }
        if self.deque_capacity == 0 || self.deque_capacity > SUBDIV_LOCAL_CAP {
            return Err(format!(
                "a deque of {} entries: the queue kernel's workgroups hold 1 to {SUBDIV_LOCAL_CAP}",
                self.deque_capacity
            ));
        }
        Ok(())
    }
}

/// Workgroups of the level kernel per SM or compute unit by default: 8
/// warps of 32 (two per scheduler of an NVIDIA SM) or 4 waves of 64 (one
/// per SIMD of an AMD CU), enough that one waiting on memory leaves
/// another to run, few enough that a barrier's arrivals stay cheap.
/// `tools/gpu/kernel.txt` sweeps around it.
pub const LEVEL_GROUPS_PER_UNIT: u32 = 4;

/// How many workgroups to launch. On a GPU: the level kernel
/// [`LEVEL_GROUPS_PER_UNIT`] per SM or compute unit where the driver says
/// how many it has (else 256; its discovery keeps only the resident ones),
/// the queue kernel a generous 512 (late starters find the work taken). On
/// a CPU device (lavapipe runs each workgroup to completion on one worker
/// thread) the queue kernel takes one per thread; the level kernel takes
/// one, because a barrier among lavapipe's threads costs a scheduler time
/// slice whenever other processes share the cores (the teapot at 1920x1080
/// on this project's 2-core machine: 5 ms with 1 workgroup, 55 ms with 2),
/// and a CPU gains nothing from one dispatch over several. `--groups` and
/// the tests run it with many.
pub fn default_groups(ctx: &Context, kernel: Kernel) -> u32 {
    if ctx.info().is_cpu {
        if kernel == Kernel::Levels {
            return 1;
        }
        let threads = std::env::var("LP_NUM_THREADS")
            .ok()
            .and_then(|s| s.parse::<u32>().ok())
            .filter(|&n| n > 0)
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get() as u32));
        threads.max(1)
    } else {
        match kernel {
            Kernel::Levels => ctx.info().compute_units.map_or(256, |units| {
                (units * LEVEL_GROUPS_PER_UNIT).clamp(1, SYNC_ARRIVALS)
            }),
            Kernel::Queue => 512,
        }
    }
}

/// `groups` (or the default), refused with a sentence beyond what one
/// dispatch may launch on this device.
pub fn check_groups(
    ctx: &Context,
    groups: Option<u32>,
    kernel: Kernel,
) -> Result<u32, RenderError> {
    let n = groups.unwrap_or_else(|| default_groups(ctx, kernel));
    let max = ctx.info().limits.max_compute_work_group_count[0];
    if n == 0 || n > max {
        return Err(RenderError::Request(format!(
            "--groups {n}: a dispatch on {} launches 1 to {max} workgroups \
             (maxComputeWorkGroupCount[0])",
            ctx.info().name
        )));
    }
    if kernel == Kernel::Levels && n > SYNC_ARRIVALS {
        return Err(RenderError::Request(format!(
            "--groups {n}: the level kernel's barrier counts at most {SYNC_ARRIVALS} workgroups"
        )));
    }
    Ok(n)
}

/// Refuses a queue-kernel launch whose items in flight could pass the 24
/// bits of its in-flight count: at most every unclaimed base patch, a full
/// queue and a full deque per workgroup are in flight at once.
pub fn check_in_flight(patches: u32, queue: u32, groups: u32, deque: u32) -> Result<(), String> {
    let most = u64::from(patches) + u64::from(queue) + u64::from(groups) * u64::from(deque);
    if most > u64::from(IN_FLIGHT_MASK) {
        return Err(format!(
            "the queue kernel counts at most {IN_FLIGHT_MASK} items in flight, and {patches} base \
             patches + a {queue}-entry queue + {groups} workgroups x {deque} deque entries could \
             hold {most}; use fewer --groups (or the levels kernel)"
        ));
    }
    Ok(())
}

/// The queue kernel's shaders, which share set 2.
pub const QUEUE_SHADERS: &[&str] = &["subdiv/queue.comp", "subdiv/queue_reset.comp"];

/// The work queue (set 2 of the queue kernel, `glsl/subdiv/queue.glsl`):
/// nodes, a sequence number per slot, and the head and tail. It is put in
/// its empty state when made and after a frame that ended abnormally; a
/// frame that ends normally leaves it empty and valid for the next.
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

/// The queue kernel: its queue, pipelines and knobs.
struct QueueKernel {
    queue: Queue,
    layout: PipelineLayout<SubdivPush>,
    pipeline: Pipeline,
    reset: Pipeline,
    idle_poll_cap: u32,
    plant_endless_loop: bool,
    deque: u32,
    base_batch: u32,
    // Kept alive for the queue set's layout.
    _queue_layout: SetLayout,
}

impl QueueKernel {
    fn new(setup: &mut MethodSetup<'_>, stage: &ReadyStage) -> Result<Self, RenderError> {
        let (ctx, o) = (setup.ctx, &setup.options.per_method.subdiv);
        let queue_layout = SetLayout::reflect(ctx, "queue set", SET_PRODUCER, QUEUE_SHADERS)?;
        let queue = Queue::new(ctx, &queue_layout, o.queue_capacity)?;
        let layout = setup.scene_layout.pipeline_layout::<SubdivPush>(
            ctx,
            "queue kernel layout",
            &[stage.set_layout(), &queue_layout],
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let pipeline =
            setup
                .shaders
                .compute(ctx, &layout, "subdivide (queue)", "subdiv/queue.comp")?;
        let reset =
            setup
                .shaders
                .compute(ctx, &layout, "queue reset", "subdiv/queue_reset.comp")?;
        Ok(Self {
            queue,
            layout,
            pipeline,
            reset,
            idle_poll_cap: o.idle_poll_cap,
            plant_endless_loop: o.plant_endless_loop,
            deque: o.deque_capacity,
            base_batch: o.base_batch,
            _queue_layout: queue_layout,
        })
    }

    /// Records the reset of the counters and the queue, the in-flight
    /// count, and the kernel's dispatch (scope "subdivide").
    fn record(
        &self,
        f: &mut FrameRec<'_>,
        stage: &ReadyStage,
        groups: u32,
    ) -> Result<(), RenderError> {
        let count = f.scene.count;
        check_in_flight(count, self.queue.capacity, groups, self.deque)
            .map_err(RenderError::Request)?;
        let list = stage.list();
        stage.record_reset(f);
        let in_flight = count + self.plant_endless_loop as u32;
        let counters = Res::Buffer(&list.counters);
        let mut rec = Recorder::new(f.ctx, f.cmd);
        let update = Pass::new("in-flight count").write(counters, Access::TRANSFER_WRITE);
        rec.run(&update, |cmd| unsafe {
            f.ctx.device().cmd_update_buffer(
                cmd,
                list.counters.handle(),
                u64::from(C_IN_FLIGHT) * 4,
                &in_flight.to_le_bytes(),
            )
        });
        rec.hand_off(counters, Access::ALL);
        let pc = SubdivPush {
            ready_capacity: list.caps.ready,
            queue_capacity: self.queue.capacity,
            patch_count: count,
            idle_poll_cap: self.idle_poll_cap,
            local_cap: self.deque,
            base_batch: self.base_batch,
            pad: [0; 2],
        };
        self.layout.push(f.cmd, &pc);
        // Both passes bind the ready list's sets and the queue's: the
        // kernel reads and writes the queue, the node pool and the list.
        let pass = |name, pipeline| {
            let pass = Pass::new(name)
                .pipeline(pipeline)
                .bind(SET_PRODUCER, &self.queue.set);
            stage.bind_to(f, pass)
        };
        if self.queue.needs_reset {
            let groups = self.queue.capacity.div_ceil(64);
            rec.dispatch(&pass("queue reset", &self.reset), [groups, 1, 1]);
        }
        let kernel = pass("queue kernel", &self.pipeline);
        f.scoped("subdivide", |_| {
            rec.dispatch(&kernel, [groups, 1, 1]);
            Ok(())
        })?;
        rec.hand_off(counters, Access::ALL);
        rec.hand_off(Res::Buffer(&list.ready), Access::ALL);
        Ok(())
    }
}

/// The persistent subdivision method.
pub struct Subdiv {
    stage: ReadyStage,
    levels: Levels,
    /// The depth pyramid, when occlusion culling is on (level kernels only).
    occlusion: Option<Hiz>,
    queue: Option<QueueKernel>,
    kernel: Kernel,
    groups: u32,
    watchdog_polls: u32,
    join_polls: u32,
    faults: u32,
    node_memory: u64,
    sort: bool,
    /// Why this method now runs the per-depth rounds, once a watchdog
    /// tripped.
    fallback: Option<String>,
    /// Rounds recorded for the per-depth fallback.
    budget: RoundBudget,
    counters: Option<CopyRange>,
    state: Option<CopyRange>,
}

impl Subdiv {
    /// Creates the ready stage, the node memory, the kernel's pipelines
    /// (and the queue, for the queue kernel).
    pub fn new(setup: &mut MethodSetup<'_>) -> Result<Self, RenderError> {
        let (ctx, o) = (setup.ctx, setup.options);
        let s = &o.per_method.subdiv;
        let groups = check_groups(ctx, s.groups, s.kernel)?;
        let sort = s.kernel == Kernel::Queue && s.sort;
        // The queue kernel has no phases: it draws everything it keeps.
        let culls = o.occlusion && s.kernel == Kernel::Levels;
        let (stage, levels, occlusion) = level_parts(setup, sort, true, culls)?;
        let queue = match s.kernel {
            Kernel::Queue => Some(QueueKernel::new(setup, &stage)?),
            Kernel::Levels => None,
        };
        Ok(Self {
            stage,
            levels,
            occlusion,
            queue,
            kernel: s.kernel,
            groups,
            watchdog_polls: s.watchdog_polls,
            join_polls: s
                .join_polls
                .unwrap_or_else(|| levels::default_join_polls(setup.ctx)),
            faults: s.level_faults,
            node_memory: o.per_method.levels.node_memory,
            sort,
            fallback: None,
            budget: RoundBudget::new(L_MAX),
            counters: None,
            state: None,
        })
    }

    /// Workgroups launched per dispatch.
    pub fn groups(&self) -> u32 {
        self.groups
    }

    /// Why the method runs the per-depth rounds, once it does.
    pub fn fallback(&self) -> Option<&str> {
        self.fallback.as_deref()
    }

    fn persistent_run(&self) -> PersistentRun {
        PersistentRun {
            groups: self.groups,
            watchdog_polls: self.watchdog_polls,
            join_polls: self.join_polls,
            faults: self.faults,
        }
    }

    /// After a watchdog: every frame from now on takes the per-depth rounds.
    fn fall_back(&mut self, reason: String) -> Finished {
        log::warn!("subdiv: {reason}; this and every later frame takes the per-depth rounds");
        self.fallback = Some(reason.clone());
        Finished::Redo { reason }
    }

    /// The persistent level kernel's frame.
    fn finish_levels(&mut self, words: &[u32], state: &[u32]) -> Result<Finished, RenderError> {
        let stats = GpuSubdivStats::from_counters(words);
        let st = LevelState::from_words(state);
        if stats.errors & ERR_WATCHDOG != 0 {
            return Ok(self.fall_back(format!(
                "the persistent kernel's watchdog tripped ({} of {} launched workgroups had \
                 joined; a barrier or the occupancy discovery saw no progress for {} polls)",
                st.participants, self.groups, self.watchdog_polls
            )));
        }
        if let Some(message) = stats.error_message() {
            return Err(RenderError::Method {
                method: INFO.name,
                message,
            });
        }
        if !st.done {
            return Err(RenderError::Method {
                method: INFO.name,
                message: format!(
                    "the persistent kernel stopped after {} rounds with work left",
                    st.rounds
                ),
            });
        }
        let mut m = stats.method_stats(&self.stage);
        m.own.retain(|(k, _)| {
            !k.starts_with("queue") && !["iterations_max", "idle_polls"].contains(k)
        });
        m.own.extend(st.stats(self.levels.plan()));
        m.own.push(("workgroups", json!(self.groups)));
        m.own.push(("workgroups_joined", json!(st.participants)));
        m.own.push(("barrier_polls", json!(stats.idle_polls)));
        // Each pass's first steps and its kernel.
        let dispatches = if self.occlusion.is_some() {
            2 * (Levels::first_dispatches(PHASE_EARLY) + 1)
        } else {
            Levels::first_dispatches(PHASE_ALL) + 1
        };
        m.own.push(("dispatches", json!(dispatches)));
        Ok(Finished::Done(m))
    }

    /// The queue kernel's frame.
    fn finish_queue(&mut self, words: &[u32]) -> Result<Finished, RenderError> {
        let stats = GpuSubdivStats::from_counters(words);
        let Some(q) = self.queue.as_mut() else {
            return Err(RenderError::Request("the queue kernel has no queue".into()));
        };
        // An abnormal end leaves the queue in an unknown state.
        q.queue.needs_reset = stats.errors != 0 || stats.in_flight_left != 0;
        let capacity = q.queue.capacity;
        if stats.errors & ERR_ITERATION_CAP != 0 {
            return Ok(self.fall_back(format!(
                "the queue kernel made no progress for its whole iteration cap ({} items \
                 still in flight)",
                stats.in_flight_left
            )));
        }
        if let Some(message) = stats.error_message() {
            return Err(RenderError::Method {
                method: INFO.name,
                message,
            });
        }
        let mut m = stats.method_stats(&self.stage);
        m.own.push(("queue_capacity_items", json!(capacity)));
        m.own.push(("workgroups", json!(self.groups)));
        m.own.push(("dispatches", json!(1)));
        Ok(Finished::Done(m))
    }
}

impl Method for Subdiv {
    fn name(&self) -> &'static str {
        INFO.name
    }

    fn record(&mut self, f: &mut FrameRec<'_>) -> Result<(), RenderError> {
        self.stage.ensure_capture(f.ctx, f.capture, f.retired)?;
        let stage = &self.stage;
        if self.fallback.is_some() {
            let budget = self.budget;
            levels::record_phases(
                f,
                stage,
                &mut self.levels,
                self.occlusion.as_mut(),
                |f, l, phase| l.record_rounds(f, stage, budget.for_phase(phase), phase),
            )?;
        } else if let Some(q) = &self.queue {
            q.record(f, stage, self.groups)?;
            stage.record_draw(f, self.sort)?;
        } else {
            let run = self.persistent_run();
            levels::record_phases(
                f,
                stage,
                &mut self.levels,
                self.occlusion.as_mut(),
                |f, l, phase| l.record_persistent(f, stage, run, phase),
            )?;
        }
        self.counters = Some(f.copy_out(&self.stage.list().counters, COUNTER_WORDS)?);
        self.state = Some(self.levels.copy_out_state(f)?);
        Ok(())
    }

    fn finish(&mut self, out: &mut FrameOut<'_>) -> Result<Finished, RenderError> {
        let (c, s) = recorded(self.counters, self.state)?;
        let mut finished = if let Some(reason) = self.fallback.clone() {
            let mut m = finish_rounds(
                &mut self.stage,
                &self.levels,
                &mut self.budget,
                self.occlusion.is_some(),
                out,
                (c, s),
                INFO.name,
            )?;
            if let Finished::Done(m) = &mut m {
                m.own.push(("fallback", json!(reason)));
            }
            m
        } else {
            let words = out.words(c);
            if let Some(reason) =
                self.stage
                    .grow_if_full(out.ctx, words, MAX_READY_CAPACITY, out.retired)?
            {
                if let Some(q) = self.queue.as_mut() {
                    q.queue.needs_reset = true;
                }
                return Ok(Finished::Redo { reason });
            }
            match self.kernel {
                Kernel::Levels => self.finish_levels(words, out.words(s))?,
                Kernel::Queue => self.finish_queue(words)?,
            }
        };
        if let Finished::Done(m) = &mut finished {
            m.own.push(("occlusion", json!(self.occlusion.is_some())));
            let kernel = if self.fallback.is_some() {
                "per-depth (fallback)"
            } else {
                self.kernel.name()
            };
            m.own.insert(0, ("kernel", json!(kernel)));
        }
        Ok(finished)
    }

    fn reconfigure(
        &mut self,
        setup: &mut MethodSetup<'_>,
        _retired: &mut Retired,
    ) -> Result<bool, RenderError> {
        let (o, s) = (setup.options, &setup.options.per_method.subdiv);
        // Buffer sizes, the kernel and the draw path need a new method; the
        // rest are values recorded per frame.
        let queue_changed = self.queue.as_ref().is_some_and(|q| {
            s.queue_capacity.next_power_of_two() != q.queue.capacity
                || s.deque_capacity != q.deque
                || s.base_batch != q.base_batch
        });
        let culls = (
            o.occlusion && s.kernel == Kernel::Levels,
            self.occlusion.is_some(),
        );
        if must_remake(o, &self.stage, self.node_memory, culls)
            || s.kernel != self.kernel
            || queue_changed
            || (s.kernel == Kernel::Queue && s.sort) != self.sort
        {
            return Ok(false);
        }
        self.groups = check_groups(setup.ctx, s.groups, s.kernel)?;
        self.watchdog_polls = s.watchdog_polls;
        self.join_polls = s
            .join_polls
            .unwrap_or_else(|| levels::default_join_polls(setup.ctx));
        self.faults = s.level_faults;
        if let Some(q) = self.queue.as_mut() {
            q.idle_poll_cap = s.idle_poll_cap;
            q.plant_endless_loop = s.plant_endless_loop;
        }
        Ok(true)
    }

    fn memory(&self) -> Vec<(&'static str, u64)> {
        let queue = self.queue.as_ref().map(|q| ("queue", q.queue.bytes()));
        level_memory(&self.levels, self.occlusion.as_ref(), queue, &self.stage)
    }

    fn ready(&self) -> Option<&ReadyStage> {
        Some(&self.stage)
    }

    /// The level kernels cull by occlusion (in both phases of
    /// `levels::record_phases`); the queue kernel does not.
    fn culls_occluded(&self) -> bool {
        self.kernel == Kernel::Levels
    }
}
