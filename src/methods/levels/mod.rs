//! The level schedule both subdivision methods run (`glsl/levels/level.glsl`):
//! `subdiv` in one dispatch of persistent workgroups with a grid barrier
//! between rounds (`glsl/levels/persistent.comp`), `subdiv-indirect` as one indirect
//! dispatch per round (`glsl/levels/round.comp`), and `subdiv` again when
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

mod canonical;
mod frame;
mod plan;
pub mod push;
mod state;
mod stats;

pub use canonical::{canonical_ready, root_patches, CanonicalRun};
pub use frame::{
    base_rounds, finish_rounds, level_memory, level_parts, must_remake, recorded, RoundBudget,
    MAX_ROUNDS,
};
pub use plan::{levels_for, LevelPlan, Options, DEFAULT_NODE_MEMORY, NODE_MEMORY_TARGET};
pub use state::LevelState;
pub use stats::GpuSubdivStats;

use ash::vk;

use self::push::LevelPush;
use super::RenderError;
use crate::constants::*;
use crate::draw::hiz::Hiz;
use crate::draw::ReadyStage;
use crate::frame::{CopyRange, FrameRec, Retired};
use crate::gpu::{SceneLayout, Shaders};
use crate::vk::{
    Access, Buffer, Context, DescriptorSet, MemoryLocation, Pass, Pipeline, PipelineLayout,
    Recorder, Res, SetLayout, VkResult,
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
    "levels/init.comp",
    "levels/clusters.comp",
    "levels/round.comp",
    "levels/persistent.comp",
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
    /// Occlusion culling's cluster filter (`levels/clusters.comp`).
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
        let init = shaders.compute(ctx, &layout, "level init", "levels/init.comp")?;
        let filter = shaders.compute(ctx, &layout, "cluster filter", "levels/clusters.comp")?;
        let round = shaders.compute(ctx, &layout, "level round", "levels/round.comp")?;
        let persistent = if persistent {
            Some(shaders.compute(
                ctx,
                &layout,
                "subdivide (persistent)",
                "levels/persistent.comp",
            )?)
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
    /// the early one's) and the push block.
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
        self.push(f, stage, run, phase)
    }

    /// A pass of the level schedule running `pipeline`, with sets 0-2 (the
    /// scene, the ready list, the node memory) bound through it: it
    /// declares what its shader uses of them.
    fn level_pass<'p>(
        &'p self,
        f: &FrameRec<'p>,
        stage: &'p ReadyStage,
        name: &'p str,
        pipeline: &'p Pipeline,
    ) -> Pass<'p> {
        let pass = Pass::new(name)
            .pipeline(pipeline)
            .bind(SET_PRODUCER, &self.memory.set);
        stage.bind_to(f, pass)
    }

    /// [`Levels::level_pass`] for an indirect dispatch: it also reads the
    /// arguments the step before wrote into the state.
    fn indirect_pass<'p>(
        &'p self,
        f: &FrameRec<'p>,
        stage: &'p ReadyStage,
        name: &'p str,
        pipeline: &'p Pipeline,
    ) -> Pass<'p> {
        self.level_pass(f, stage, name, pipeline)
            .read(Res::Buffer(&self.memory.state), Access::INDIRECT_READ)
    }

    /// Records a pass's first step, after the previous frame's rounds and
    /// copy-out are done with the memory, in a new recorder that the
    /// rounds continue: the state for the first round, or under occlusion
    /// culling (`phase` early or late) the arguments of the cluster filter,
    /// and the filter, which makes depth 0 and schedules the first round.
    fn first_steps<'c>(&self, f: &FrameRec<'c>, stage: &ReadyStage, phase: u32) -> Recorder<'c> {
        let mut rec = Recorder::new(f.ctx, f.cmd);
        rec.after(Res::Memory, Access::ALL);
        let init = self.level_pass(f, stage, "level init", &self.init);
        rec.dispatch(&init, [1, 1, 1]);
        if phase != PHASE_ALL {
            let filter = self.indirect_pass(f, stage, "cluster filter", &self.filter);
            let offset = u64::from(S_ARGS) * 4;
            rec.dispatch_indirect(&filter, &self.memory.state, offset);
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
            let mut rec = self.first_steps(f, stage, phase);
            let round = self.indirect_pass(f, stage, "level round", &self.round);
            for _ in 0..rounds {
                let offset = u64::from(S_ARGS) * 4;
                rec.dispatch_indirect(&round, state, offset);
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
            let mut rec = self.first_steps(f, stage, phase);
            // It reads the state's words, not as arguments: the state is in
            // set 2 like the rest of what it touches.
            let kernel = self.level_pass(f, stage, "level kernel", pipeline);
            rec.dispatch(&kernel, [run.groups, 1, 1]);
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
