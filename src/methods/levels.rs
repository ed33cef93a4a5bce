//! The level schedule both subdivision methods run (`glsl/common/level.glsl`):
//! `subdiv` in one dispatch of persistent workgroups with a grid barrier
//! between rounds (`glsl/subdivide.comp`), `subdiv-indirect` as one indirect
//! dispatch per round (`glsl/subdivide_level.comp`), and `subdiv` again when
//! its watchdog sends it back to the per-depth rounds.
//!
//! A round processes a chunk of at most [`LevelPlan::chunk`] nodes of one
//! depth; the next round takes the deepest depth that still holds nodes
//! (depth first over chunks), so each depth's region only ever holds the
//! children of one chunk of the depth above: the node memory is bounded by
//! the plan whatever the depth, and a depth too large for one chunk is
//! simply taken in several. Within a depth nodes keep their parents' order,
//! so the ready list comes out in a canonical order ([`canonical_ready`] is
//! the CPU twin) and no sort is needed.

use ash::vk;
use serde_json::{json, Value};

use super::RenderError;
use crate::constants::*;
use crate::draw::hiz::Hiz;
use crate::draw::ReadyStage;
use crate::frame::{CopyRange, FrameRec, Retired};
use crate::gpu::{LevelPush, SceneLayout, Shaders};
use crate::patch::bezier::BezierPatch;
use crate::patch::cull::outside_frustum;
use crate::patch::oracle::{process_any, Outcome};
use crate::patch::quadnode::QuadNode;
use crate::patch::rational::Weights;
use crate::patch::view::ViewParams;
use crate::scene::instances::Instance;
use crate::vk::{
    Access, Buffer, Context, DescriptorSet, MemoryLocation, Pass, Pipeline, PipelineLayout,
    Recorder, Res, SetLayout, VkResult,
};

/// Node memory of the level kernels unless asked otherwise: under the
/// 26.39 MiB of backing memory the paper's work graph needs at depth 10,
/// and enough that no kitchen keyframe at ε = 1 needs a depth in parts.
pub const DEFAULT_NODE_MEMORY: u64 = 24 << 20;

/// The level schedule's knob, which `subdiv` and `subdiv-indirect` share
/// ([`super::PerMethod::levels`]), and its flag, under their heading in
/// `--help`.
#[derive(Clone, Debug, PartialEq, Eq, clap::Args)]
#[command(next_help_heading = "subdiv and subdiv-indirect")]
pub struct Options {
    /// subdiv and subdiv-indirect: node memory of the level schedule in MiB
    /// (default 24); a depth that does not fit is taken in parts.
    // In bytes once parsed; "24" is DEFAULT_NODE_MEMORY in MiB (a test
    // holds them together).
    #[arg(long, value_name = "MIB", value_parser = parse_mib,
          default_value = "24", hide_default_value = true)]
    pub node_memory: u64,
    /// Test-only, a planted fault: regions for this many depths whatever
    /// the split (fewer than aniso reaches must be caught by the kernels'
    /// ERR_LEVEL_REGION, not written past the regions).
    #[arg(skip)]
    pub planted_levels: Option<u32>,
}

impl Default for Options {
    fn default() -> Self {
        super::cli_defaults()
    }
}

impl Options {
    /// Refuses a budget with no room for a node.
    pub fn check(&self) -> Result<(), String> {
        if self.node_memory == 0 {
            return Err("--node-memory must be positive".into());
        }
        Ok(())
    }
}

/// A number of MiB (fractions too) as bytes; a negative one is 0, which
/// [`Options::check`] refuses in its own words.
fn parse_mib(s: &str) -> Result<u64, String> {
    let mib: f64 = s
        .parse()
        .map_err(|e: std::num::ParseFloatError| e.to_string())?;
    Ok((mib * f64::from(1u32 << 20)) as u64)
}

/// Depths with a region under split mode `aniso`: every depth of the
/// schedule a node can reach. A 1:4 split deepens both directions in one
/// round, so iso nodes are done after `L_MAX` rounds; a 1:2 split deepens
/// one, so under aniso a node can take `L_MAX` rounds per direction,
/// `LEVEL_DEPTHS_MAX` = 2 `L_MAX` in all.
pub const fn levels_for(aniso: bool) -> u32 {
    if aniso {
        LEVEL_DEPTHS_MAX
    } else {
        L_MAX
    }
}

// The state's per-depth arrays hold a word for every depth the schedule
// reaches and one past it (a depth's children are booked at d + 1).
const _: () = {
    assert!(levels_for(true) <= LEVEL_DEPTHS_MAX);
    assert!(S_LEVEL_NEXT - S_LEVEL_COUNT >= LEVEL_DEPTHS_MAX + 2);
    assert!(S_LEVEL_BLOCKS - S_LEVEL_NEXT >= LEVEL_DEPTHS_MAX + 2);
    assert!(S_DEPTH_NODES - S_LEVEL_BLOCKS >= LEVEL_DEPTHS_MAX + 2);
    assert!(S_READY - S_DEPTH_NODES > LEVEL_DEPTHS_MAX);
    assert!(S_VISIBILITY_ATOMICS < LEVEL_STATE_WORDS);
    // S_PENDING holds a bit per depth.
    assert!(LEVEL_DEPTHS_MAX < 32);
};

/// Polls of a barrier without progress before the persistent kernel's
/// watchdog trips: about a second of polling with its back-off, far beyond
/// any round (a kitchen round at ε = 0.25 is tens of milliseconds on a
/// 2-core lavapipe).
pub const DEFAULT_WATCHDOG_POLLS: u32 = 1 << 20;

/// Polls of an unchanged join count before the occupancy window closes: a
/// GPU starts its resident workgroups within microseconds; lavapipe's
/// worker threads can start milliseconds apart on a loaded machine.
pub fn default_join_polls(ctx: &Context) -> u32 {
    if ctx.info().is_cpu {
        4096
    } else {
        16
    }
}

/// Blocks per workgroup of a per-depth round: one on a GPU, where a
/// workgroup's barriers cost cycles and more workgroups hide latency; 16
/// on a CPU device, where lavapipe pays about 5 µs per workgroup barrier
/// (it switches between the workgroup's subgroups) and a workgroup that
/// takes 16 blocks shares its arrival's two barriers among them.
pub fn group_blocks(ctx: &Context) -> u32 {
    if ctx.info().is_cpu {
        16
    } else {
        1
    }
}

/// How a node-memory budget is spent: rounds of at most `chunk` nodes,
/// regions for depths 1..=`levels`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LevelPlan {
    /// Nodes per round at most (a multiple of `LEVEL_GROUP_SIZE`).
    pub chunk: u32,
    /// Depths with a region of child slots.
    pub levels: u32,
}

impl LevelPlan {
    /// Entries (8 bytes) of the node buffer: a region of `chunk ×
    /// SPLIT_MAX_CHILDREN` child slots per depth, two ready scratches.
    pub fn node_entries(self) -> u64 {
        let chunk = u64::from(self.chunk);
        u64::from(self.levels) * chunk * u64::from(SPLIT_MAX_CHILDREN) + 2 * chunk
    }

    /// Words of the scan buffer: a block scan per depth 1..=levels+1, two
    /// ready scans, and the round's block statistics.
    pub fn scan_words(self) -> u64 {
        let blocks = u64::from(self.chunk / LEVEL_GROUP_SIZE);
        u64::from(self.levels + 3) * (blocks + 1) + u64::from(LEVEL_BLOCK_STATS) * blocks
    }

    /// Bytes of the three buffers together.
    pub fn bytes(self) -> u64 {
        8 * self.node_entries() + 4 * self.scan_words() + 4 * u64::from(LEVEL_STATE_WORDS)
    }

    /// The largest plan with regions for depths 1..=`levels` within
    /// `budget` bytes whose buffers each fit `max_buffer` bytes (one
    /// storage-buffer binding), and whose chunk is at most
    /// `LEVEL_MAX_CHUNK` nodes (a round's finish walks at most 64 block
    /// totals per invocation; beyond it a budget buys nothing).
    pub fn for_budget(budget: u64, max_buffer: u64, levels: u32) -> Result<Self, String> {
        let fits = |chunk: u32| {
            let p = LevelPlan { chunk, levels };
            p.bytes() <= budget && 8 * p.node_entries() <= max_buffer
        };
        let smallest = LevelPlan {
            chunk: LEVEL_GROUP_SIZE,
            levels,
        };
        if !fits(LEVEL_GROUP_SIZE) {
            return Err(format!(
                "a node memory of {budget} bytes is below the smallest the level kernels \
                 can work in ({} bytes: one block of {LEVEL_GROUP_SIZE} nodes per round)",
                smallest.bytes()
            ));
        }
        // Blocks per round: the largest count that fits (a binary search;
        // the cost grows with the chunk), at most LEVEL_MAX_CHUNK nodes.
        let (mut lo, mut hi) = (1u32, LEVEL_MAX_CHUNK / LEVEL_GROUP_SIZE + 1);
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if fits(mid * LEVEL_GROUP_SIZE) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Ok(LevelPlan {
            chunk: lo * LEVEL_GROUP_SIZE,
            levels,
        })
    }
}

/// The node memory and set 2 of the level kernels.
struct LevelMemory {
    nodes: Buffer,
    scans: Buffer,
    state: Buffer,
    plan: LevelPlan,
    set: DescriptorSet,
}

impl LevelMemory {
    fn new(ctx: &Context, layout: &SetLayout, plan: LevelPlan) -> VkResult<Self> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let gpu = MemoryLocation::GpuOnly;
        let nodes = Buffer::new(ctx, "level nodes", 8 * plan.node_entries(), storage, gpu)?;
        let scans = Buffer::new(ctx, "level scans", 4 * plan.scan_words(), storage, gpu)?;
        let state = Buffer::new(
            ctx,
            "level state",
            4 * u64::from(LEVEL_STATE_WORDS),
            storage | vk::BufferUsageFlags::INDIRECT_BUFFER,
            gpu,
        )?;
        let set = Self::set(ctx, layout, [&nodes, &scans, &state], None)?;
        Ok(Self {
            nodes,
            scans,
            state,
            plan,
            set,
        })
    }

    /// Set 2: the node memory and the depth pyramid (before there is one,
    /// the state stands in: only the late phase of occlusion culling reads
    /// the pyramid).
    fn set(
        ctx: &Context,
        layout: &SetLayout,
        [nodes, scans, state]: [&Buffer; 3],
        hiz: Option<&Buffer>,
    ) -> VkResult<DescriptorSet> {
        let mut bound = [nodes.into(); LEVEL_BINDINGS as usize];
        bound[BIND_LEVEL_NODES as usize] = nodes.into();
        bound[BIND_LEVEL_SCANS as usize] = scans.into();
        bound[BIND_LEVEL_STATE as usize] = state.into();
        bound[BIND_LEVEL_HIZ as usize] = hiz.unwrap_or(state).into();
        DescriptorSet::new(ctx, "level set", layout, &bound)
    }

    fn bytes(&self) -> u64 {
        self.nodes.size() + self.scans.size() + self.state.size()
    }
}

/// How the persistent kernel is launched.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PersistentRun {
    /// Workgroups launched (those beyond what the device keeps resident
    /// leave at once).
    pub groups: u32,
    /// Polls without progress before the watchdog trips.
    pub watchdog_polls: u32,
    /// Polls of an unchanged join count before the window closes.
    pub join_polls: u32,
    /// `FAULT_*` bits (tests).
    pub faults: u32,
}

/// The level kernels' shaders, which share set 2.
pub const LEVEL_SHADERS: &[&str] = &[
    "level_init.comp",
    "level_clusters.comp",
    "subdivide_level.comp",
    "subdivide.comp",
];

/// The level kernels' memory, set 2 and pipelines.
pub struct Levels {
    memory: LevelMemory,
    /// The node-memory budget and the device's largest storage buffer,
    /// which every plan is made for (the plan's depths follow the split),
    /// and the test-only depths that replace the split's.
    budget: u64,
    max_buffer: u64,
    planted_levels: Option<u32>,
    /// The depth pyramid set 2 binds, when occlusion culling bound one.
    hiz_bound: bool,
    layout: PipelineLayout<LevelPush>,
    init: Pipeline,
    /// Occlusion culling's cluster filter (`level_clusters.comp`).
    filter: Pipeline,
    round: Pipeline,
    persistent: Option<Pipeline>,
    group_blocks: u32,
    set_layout: SetLayout,
}

impl Levels {
    /// Node memory for the budget `options` give (regions for iso splits
    /// until a frame asks for aniso), the init and round pipelines, and
    /// the persistent kernel's when `persistent`.
    pub fn new(
        ctx: &Context,
        shaders: &mut Shaders,
        scene_layout: &SceneLayout,
        stage: &ReadyStage,
        options: &Options,
        persistent: bool,
    ) -> Result<Self, RenderError> {
        let budget = options.node_memory;
        let planted_levels = options.planted_levels;
        if !ctx.info().features.vulkan_memory_model {
            return Err(RenderError::Request(format!(
                "the subdivision kernels need the Vulkan memory model with device scope \
                 (vulkanMemoryModel, vulkanMemoryModelDeviceScope) for their acquire/release \
                 atomics, and {} does not offer it",
                ctx.info().name
            )));
        }
        if !ctx.info().compute_subgroup_ops {
            return Err(RenderError::Request(format!(
                "the subdivision kernels scan, search and count with subgroup operations \
                 (basic, arithmetic, ballot) in compute shaders, and {} does not offer them",
                ctx.info().name
            )));
        }
        let max_buffer = u64::from(ctx.info().limits.max_storage_buffer_range);
        let levels = planted_levels.unwrap_or(levels_for(false));
        let plan =
            LevelPlan::for_budget(budget, max_buffer, levels).map_err(RenderError::Request)?;
        let set_layout = SetLayout::reflect(ctx, "level set", SET_PRODUCER, LEVEL_SHADERS)?;
        let memory = LevelMemory::new(ctx, &set_layout, plan)?;
        let layout = scene_layout.pipeline_layout::<LevelPush>(
            ctx,
            "level layout",
            &[stage.set_layout(), &set_layout],
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let init = shaders.compute(ctx, &layout, "level init", "level_init.comp")?;
        let filter = shaders.compute(ctx, &layout, "cluster filter", "level_clusters.comp")?;
        let round = shaders.compute(ctx, &layout, "level round", "subdivide_level.comp")?;
        let persistent = if persistent {
            Some(shaders.compute(ctx, &layout, "subdivide (persistent)", "subdivide.comp")?)
        } else {
            None
        };
        Ok(Self {
            memory,
            budget,
            max_buffer,
            planted_levels,
            hiz_bound: false,
            layout,
            init,
            filter,
            round,
            persistent,
            group_blocks: group_blocks(ctx),
            set_layout,
        })
    }

    /// The plan the memory was made for.
    pub fn plan(&self) -> LevelPlan {
        self.memory.plan
    }

    /// Bytes of node memory (nodes, scans, state).
    pub fn bytes(&self) -> u64 {
        self.memory.bytes()
    }

    /// Points set 2 at the depth pyramid `hiz` (a new one: the old set is
    /// retired).
    pub fn bind_hiz(&mut self, ctx: &Context, hiz: &Buffer, retired: &mut Retired) -> VkResult<()> {
        let m = &self.memory;
        let set = LevelMemory::set(
            ctx,
            &self.set_layout,
            [&m.nodes, &m.scans, &m.state],
            Some(hiz),
        )?;
        retired.push(std::mem::replace(&mut self.memory.set, set));
        self.hiz_bound = true;
        Ok(())
    }

    /// Makes the node memory again, within the same budget, where its
    /// regions are not those of split mode `aniso` ([`levels_for`]); true
    /// when it did (the old memory is retired, and a depth pyramid must
    /// be bound again). The plan is a function of the budget and the split
    /// alone, so the ready list's order (which follows the chunk) is too.
    pub fn ensure_split(
        &mut self,
        ctx: &Context,
        aniso: bool,
        retired: &mut Retired,
    ) -> Result<bool, RenderError> {
        let levels = self.planted_levels.unwrap_or(levels_for(aniso));
        if self.memory.plan.levels == levels {
            return Ok(false);
        }
        let plan = LevelPlan::for_budget(self.budget, self.max_buffer, levels)
            .map_err(RenderError::Request)?;
        let memory = LevelMemory::new(ctx, &self.set_layout, plan)?;
        retired.push(std::mem::replace(&mut self.memory, memory));
        self.hiz_bound = false;
        Ok(true)
    }

    fn push(
        &self,
        f: &FrameRec<'_>,
        stage: &ReadyStage,
        run: Option<PersistentRun>,
        phase: u32,
    ) -> VkResult<()> {
        let run = run.unwrap_or(PersistentRun {
            groups: 0,
            watchdog_polls: 0,
            join_polls: 0,
            faults: 0,
        });
        let pc = LevelPush {
            patch_count: f.scene.count,
            chunk: self.memory.plan.chunk,
            ready_capacity: stage.list().caps.ready,
            levels: self.memory.plan.levels,
            watchdog_polls: run.watchdog_polls,
            join_polls: run.join_polls,
            launched: run.groups,
            faults: run.faults,
            group_blocks: self.group_blocks,
            phase,
            cluster_blocks: f.scene.cluster_blocks,
            pad: 0,
        };
        self.layout.push(f.cmd, &pc);
        Ok(())
    }

    /// Records the counters' reset (not for the late phase, which adds to
    /// the early one's), binding sets 0-2 and the push block.
    fn record_start(
        &self,
        f: &FrameRec<'_>,
        stage: &ReadyStage,
        run: Option<PersistentRun>,
        phase: u32,
    ) -> VkResult<()> {
        if phase != PHASE_LATE {
            stage.record_reset(f);
        }
        let bind = vk::PipelineBindPoint::COMPUTE;
        stage.bind_sets(f, bind, &self.layout);
        self.memory
            .set
            .bind(f.ctx, f.cmd, bind, &self.layout, SET_PRODUCER, &[]);
        self.push(f, stage, run, phase)
    }

    /// Records a pass's first step, after the previous frame's rounds and
    /// copy-out are done with the memory, in a new recorder that the
    /// rounds continue: the state for the first round, or under occlusion
    /// culling (`phase` early or late) the arguments of the cluster filter,
    /// and the filter, which makes depth 0 and schedules the first round.
    fn first_steps<'c>(&self, f: &FrameRec<'c>, phase: u32) -> Recorder<'c> {
        let mut rec = Recorder::new(f.ctx, f.cmd);
        rec.after(Res::Memory, Access::ALL);
        self.init.bind(f.cmd);
        let init = Pass::new("level init").write(Res::Memory, Access::COMPUTE_READ_WRITE);
        rec.dispatch(&init, [1, 1, 1]);
        if phase != PHASE_ALL {
            self.filter.bind(f.cmd);
            let offset = u64::from(S_ARGS) * 4;
            rec.dispatch_indirect(&round_pass("cluster filter"), &self.memory.state, offset);
        }
        rec
    }

    /// Dispatches of a pass's first steps: the first step, and the cluster
    /// filter under occlusion culling.
    pub fn first_dispatches(phase: u32) -> u32 {
        if phase == PHASE_ALL {
            1
        } else {
            2
        }
    }

    /// Records `rounds` per-depth rounds of pass `phase` (`PHASE_*`; scope
    /// "subdivide"): the first step, then one indirect dispatch per round,
    /// each after a barrier from the last. Rounds past the end of the
    /// schedule dispatch nothing.
    pub fn record_rounds(
        &self,
        f: &mut FrameRec<'_>,
        stage: &ReadyStage,
        rounds: u32,
        phase: u32,
    ) -> VkResult<()> {
        self.record_start(f, stage, None, phase)?;
        let state = &self.memory.state;
        let mut rec = f.scoped("subdivide", |f| {
            let mut rec = self.first_steps(f, phase);
            self.round.bind(f.cmd);
            for _ in 0..rounds {
                let offset = u64::from(S_ARGS) * 4;
                rec.dispatch_indirect(&round_pass("level round"), state, offset);
            }
            Ok(rec)
        })?;
        rec.hand_off(Res::Memory, Access::ALL);
        Ok(())
    }

    /// Records the persistent kernel's pass `phase` (`PHASE_*`; scope
    /// "subdivide"): the first step and one dispatch of `run.groups`
    /// workgroups.
    pub fn record_persistent(
        &self,
        f: &mut FrameRec<'_>,
        stage: &ReadyStage,
        run: PersistentRun,
        phase: u32,
    ) -> VkResult<()> {
        let Some(pipeline) = &self.persistent else {
            return Err(crate::vk::VkError::Usage(
                "the persistent level kernel was not made for this method".into(),
            ));
        };
        self.record_start(f, stage, Some(run), phase)?;
        let mut rec = f.scoped("subdivide", |f| {
            let mut rec = self.first_steps(f, phase);
            pipeline.bind(f.cmd);
            rec.dispatch(&round_pass("level kernel"), [run.groups, 1, 1]);
            Ok(rec)
        })?;
        rec.hand_off(Res::Memory, Access::ALL);
        Ok(())
    }

    /// Records copying the state words out of the frame.
    pub fn copy_out_state(&self, f: &mut FrameRec<'_>) -> VkResult<CopyRange> {
        f.copy_out(&self.memory.state, LEVEL_STATE_WORDS)
    }
}

/// Records a level method's frame: its subdivision `subdivide` (one pass
/// of the level schedule, `PHASE_*` given) and the draw of its ready list.
/// Without `occlusion`, one pass and one draw. With it, occlusion culling
/// in two phases: the instances the last frame found visible are
/// subdivided and drawn, the depth pyramid is built from what they drew,
/// and the late phase tests every other instance in view (and each of its
/// nodes) against it, subdividing and drawing what is not hidden, into the
/// same target after the early draw.
pub fn record_phases(
    f: &mut FrameRec<'_>,
    stage: &ReadyStage,
    levels: &mut Levels,
    occlusion: Option<&mut Hiz>,
    mut subdivide: impl FnMut(&mut FrameRec<'_>, &Levels, u32) -> VkResult<()>,
) -> Result<(), RenderError> {
    let aniso = f.view.params.flags & FLAG_ANISO != 0;
    levels.ensure_split(f.ctx, aniso, f.retired)?;
    let Some(hiz) = occlusion else {
        subdivide(f, levels, PHASE_ALL)?;
        return Ok(stage.record_draw(f, false)?);
    };
    let new_pyramid = hiz.ensure(f.ctx, f.target, f.retired)?;
    if new_pyramid || !levels.hiz_bound {
        if let Some(pyramid) = hiz.buffer() {
            levels.bind_hiz(f.ctx, pyramid, f.retired)?;
        }
    }
    subdivide(f, levels, PHASE_EARLY)?;
    stage.record_draw_part(f, false, true, false)?;
    hiz.record_build(f)?;
    subdivide(f, levels, PHASE_LATE)?;
    Ok(stage.record_draw_part(f, false, false, true)?)
}

/// A round (or the persistent kernel): it reads and writes the node pool,
/// queues and state all over, so all memory, and the state's arguments of
/// the next round (the kernel declares them too, as the barrier before the
/// pass layer did).
fn round_pass(name: &str) -> Pass<'_> {
    Pass::new(name)
        .write(Res::Memory, Access::COMPUTE_READ_WRITE)
        .read(Res::Memory, Access::INDIRECT_READ)
}

/// The schedule's state at the end of a frame (the state words).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LevelState {
    /// Rounds run.
    pub rounds: u32,
    /// Whether the schedule ran out of work (else it ran out of rounds).
    pub done: bool,
    /// Occlusion culling: whether the early phase ran out of rounds.
    pub early_unfinished: bool,
    /// Persistent kernel: workgroups that joined (0 for the per-depth rounds).
    pub participants: u32,
    /// Persistent kernel: a watchdog tripped.
    pub aborted: bool,
    /// Rounds that took part of a depth too large for one chunk.
    pub split_rounds: u32,
    /// Most nodes one depth held at once.
    pub peak_nodes: u32,
    /// Nodes processed per depth 0..=LEVEL_DEPTHS_MAX.
    pub nodes_per_depth: Vec<u32>,
    /// Instances whose patches were depth 0.
    pub root_instances: u32,
    /// Instances culled whole by their boxes, and their patches (counted
    /// among the culled patches, never processed).
    pub culled_instances: u32,
    /// See `culled_instances`.
    pub culled_instance_patches: u32,
    /// Occlusion culling: instances drawn in the early phase, and those the
    /// late phase found hidden (and their patches, never processed).
    pub early_instances: u32,
    /// See `early_instances`.
    pub occluded_instances: u32,
    /// See `early_instances`.
    pub occluded_instance_patches: u32,
    /// Instances the last pass listed that the early phase did not (all
    /// of a frame of one pass).
    pub new_instances: u32,
    /// Occlusion culling: rounds of the early phase (the rest of `rounds`
    /// are the late phase's).
    pub early_rounds: u32,
    /// Occlusion culling's cluster filters: clusters the early phase drew,
    /// clusters the late phase took, the early phase's clusters the late
    /// phase left (their boxes tested against the pyramid) and those found
    /// hidden there.
    pub clusters_early: u32,
    /// See `clusters_early`.
    pub clusters_late: u32,
    /// See `clusters_early`.
    pub clusters_tested: u32,
    /// See `clusters_early`.
    pub clusters_hidden: u32,
    /// Read-modify-writes of the visibility bits (among the global atomics).
    pub visibility_atomics: u32,
}

impl LevelState {
    /// Reads the copied-out state words.
    pub fn from_words(w: &[u32]) -> Self {
        let at = |i: u32| w[i as usize];
        let depths = (0..=LEVEL_DEPTHS_MAX)
            .map(|d| at(S_DEPTH_NODES + d))
            .collect();
        LevelState {
            rounds: at(S_ROUND),
            done: at(S_DONE) != 0 && at(S_EARLY_UNFINISHED) == 0,
            early_unfinished: at(S_EARLY_UNFINISHED) != 0,
            participants: at(S_PARTICIPANTS),
            aborted: at(S_SYNC) & SYNC_ABORT != 0,
            split_rounds: at(S_SPLIT_ROUNDS),
            peak_nodes: at(S_PEAK_NODES),
            nodes_per_depth: depths,
            root_instances: at(S_ROOT_INSTANCES),
            culled_instances: at(S_CULLED_INSTANCES),
            culled_instance_patches: at(S_CULLED_INSTANCE_PATCHES),
            early_instances: at(S_EARLY_INSTANCES),
            occluded_instances: at(S_OCCLUDED_INSTANCES),
            occluded_instance_patches: at(S_OCCLUDED_INSTANCE_PATCHES),
            new_instances: at(S_NEW_INSTANCES),
            early_rounds: at(S_EARLY_ROUNDS),
            clusters_early: at(S_CLUSTERS_EARLY),
            clusters_late: at(S_CLUSTERS_LATE),
            clusters_tested: at(S_CLUSTERS_TESTED),
            clusters_hidden: at(S_CLUSTERS_HIDDEN),
            visibility_atomics: at(S_VISIBILITY_ATOMICS),
        }
    }

    /// The schedule's figures for `method_stats`.
    pub fn stats(&self, plan: LevelPlan) -> Vec<(&'static str, Value)> {
        vec![
            ("rounds", json!(self.rounds)),
            ("rounds_split", json!(self.split_rounds)),
            ("chunk_nodes", json!(plan.chunk)),
            ("peak_depth_nodes", json!(self.peak_nodes)),
            (
                "nodes_per_depth",
                json!(self.nodes_per_depth[..=plan.levels as usize]),
            ),
            ("node_memory_bytes", json!(plan.bytes())),
            (
                "instances_drawn",
                json!(self.early_instances + self.new_instances),
            ),
            ("instances_culled", json!(self.culled_instances)),
            (
                "instance_culled_patches",
                json!(self.culled_instance_patches),
            ),
            ("instances_early", json!(self.early_instances)),
            ("instances_occluded", json!(self.occluded_instances)),
            (
                "instance_occluded_patches",
                json!(self.occluded_instance_patches),
            ),
            ("rounds_early", json!(self.early_rounds)),
            ("clusters_early", json!(self.clusters_early)),
            ("clusters_late", json!(self.clusters_late)),
            ("clusters_retested", json!(self.clusters_tested)),
            ("clusters_found_hidden", json!(self.clusters_hidden)),
            ("visibility_atomics", json!(self.visibility_atomics)),
        ]
    }

    /// Rounds of the early and the late phase (of a frame of one pass: the
    /// pass, and 0).
    pub fn phase_rounds(&self, phases: bool) -> (u32, u32) {
        if phases {
            (self.early_rounds, self.rounds - self.early_rounds)
        } else {
            (self.rounds, 0)
        }
    }
}

/// The level schedule on the CPU: the ready list the level kernels write,
/// in their order, and the rounds it takes.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CanonicalRun {
    /// Ready nodes in list order.
    pub ready: Vec<QuadNode>,
    /// Rounds (processing and the final copy).
    pub rounds: u32,
    /// Rounds that took part of a depth too large for one chunk.
    pub split_rounds: u32,
    /// Nodes processed per depth 0..=`plan.levels`.
    pub nodes_per_depth: Vec<u32>,
    /// Most nodes one depth held at once.
    pub peak_nodes: u32,
    /// Children of nodes at the deepest depth with a region, dropped as
    /// the kernels drop them (`ERR_LEVEL_REGION`): 0 for a plan made for
    /// the view's split.
    pub dropped: u32,
}

/// Runs the schedule of `glsl/common/level.glsl` (`schedule`,
/// `finish_round`) with the oracle's `process` on the CPU: what the GPU's
/// ready list must equal, entry for entry. `weights` is parallel to
/// `patches` or empty; `instances` are the records the scene was uploaded
/// with (`SceneGpu::instance_records`), whose boxes decide depth 0 as
/// `level_init.comp` does.
pub fn canonical_ready(
    patches: &[BezierPatch],
    weights: &[Weights],
    flags: &[u32],
    instances: &[Instance],
    vp: &ViewParams,
    plan: LevelPlan,
) -> CanonicalRun {
    let depths = plan.levels as usize + 1;
    let mut held: Vec<Vec<QuadNode>> = vec![Vec::new(); depths];
    held[0] = root_patches(instances, vp)
        .into_iter()
        .map(QuadNode::root)
        .collect();
    let mut next = vec![0usize; depths];
    let mut out = CanonicalRun {
        nodes_per_depth: vec![0; depths],
        ..CanonicalRun::default()
    };
    let chunk = plan.chunk as usize;
    let mut copy_blocks = 0;
    loop {
        // `schedule`: the deepest depth with nodes left.
        let pick = (0..=plan.levels as usize)
            .rev()
            .find(|&d| next[d] < held[d].len());
        let Some(d) = pick else {
            if copy_blocks > 0 {
                out.rounds += 1; // the final copy
            }
            return out;
        };
        let (first, n) = (next[d], chunk.min(held[d].len() - next[d]));
        next[d] += n;
        out.split_rounds += (held[d].len() > chunk) as u32;
        out.rounds += 1;
        out.nodes_per_depth[d] += n as u32;
        let mut children = Vec::new();
        let mut readies = 0;
        for &q in &held[d][first..first + n] {
            let id = q.patch() as usize;
            match process_any(&patches[id], weights.get(id), flags[id], q, vp) {
                Outcome::Ready => {
                    out.ready.push(q);
                    readies += 1;
                }
                Outcome::Split(kids) => children.extend(kids),
                Outcome::Culled | Outcome::BackFacing => {}
            }
        }
        if d + 1 == depths {
            out.dropped += children.len() as u32;
        } else if !children.is_empty() {
            out.peak_nodes = out.peak_nodes.max(children.len() as u32);
            held[d + 1] = children;
            next[d + 1] = 0;
        }
        copy_blocks = if readies > 0 {
            n.div_ceil(LEVEL_GROUP_SIZE as usize)
        } else {
            0
        };
    }
}

/// Depth 0 of the level schedule, as `level_init.comp` lists it: the
/// patches of every instance whose box is not outside the frustum (when
/// the view culls by it), in instance order.
pub fn root_patches(instances: &[Instance], vp: &ViewParams) -> Vec<u32> {
    let frustum = vp.flags & FLAG_FRUSTUM_CULL != 0;
    instances
        .iter()
        .filter(|t| {
            let (lo, hi) = t.bounds();
            !(frustum && outside_frustum(lo, hi, vp))
        })
        .flat_map(|t| t.first..t.first + t.count)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plans_fill_the_budget_in_whole_blocks() {
        let range = 128 << 20;
        let p = LevelPlan::for_budget(DEFAULT_NODE_MEMORY, range, L_MAX).unwrap();
        assert_eq!(p.chunk % LEVEL_GROUP_SIZE, 0);
        assert!(p.bytes() <= DEFAULT_NODE_MEMORY);
        let bigger = LevelPlan {
            chunk: p.chunk + LEVEL_GROUP_SIZE,
            ..p
        };
        assert!(
            bigger.bytes() > DEFAULT_NODE_MEMORY,
            "{p:?} is not the largest"
        );
        // A budget that is not a multiple of anything still gives whole blocks.
        let odd = LevelPlan::for_budget(1_000_003, range, L_MAX).unwrap();
        assert_eq!(odd.chunk % LEVEL_GROUP_SIZE, 0);
        assert!(odd.bytes() <= 1_000_003);
        // One block is the least; below that, a sentence.
        let least = LevelPlan::for_budget(p.bytes().min(30_000), range, L_MAX).unwrap();
        assert_eq!(least.chunk, LEVEL_GROUP_SIZE);
        let e = LevelPlan::for_budget(1000, range, L_MAX).unwrap_err();
        assert!(e.contains("below the smallest"), "{e}");
        // The buffer range caps the chunk too.
        let capped = LevelPlan::for_budget(1 << 40, 1 << 20, L_MAX).unwrap();
        assert!(8 * capped.node_entries() <= 1 << 20);
        // And LEVEL_MAX_CHUNK: a round's finish walks at most 64 block
        // totals per invocation.
        let huge = LevelPlan::for_budget(1 << 40, 1 << 40, L_MAX).unwrap();
        assert_eq!(huge.chunk, LEVEL_MAX_CHUNK);
        assert_eq!(LEVEL_MAX_CHUNK, LEVEL_GROUP_SIZE.pow(3));
    }

    #[test]
    fn the_state_holds_every_depth_aniso_reaches() {
        // A 1:2 split deepens one direction: L_MAX rounds per direction.
        assert_eq!(levels_for(true), 2 * L_MAX);
        assert_eq!(levels_for(false), L_MAX);
        // Twice the regions at the same budget: half the chunk, or about.
        let range = 128 << 20;
        let iso = LevelPlan::for_budget(DEFAULT_NODE_MEMORY, range, levels_for(false)).unwrap();
        let aniso = LevelPlan::for_budget(DEFAULT_NODE_MEMORY, range, levels_for(true)).unwrap();
        assert!(aniso.bytes() <= DEFAULT_NODE_MEMORY && aniso.chunk < iso.chunk);
    }
}
