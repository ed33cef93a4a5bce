//! Method `subdiv-indirect`: the paper's execute-indirect variant (§4.1,
//! §4.3), the baseline the persistent kernel is measured against and the
//! path for devices where persistent threads misbehave.
//!
//! One compute dispatch per depth (`glsl/subdivide_level.comp`) through
//! `vkCmdDispatchIndirect`: depth 0 is the base patches, depth d reads one
//! node buffer and appends the children to the other (ping-pong), ready
//! nodes go to the shared [`ReadyStage`]. Between depths one invocation
//! (`glsl/level_args.comp`) turns the appended count into the next
//! dispatch's arguments. The same `process()` as the persistent kernel and
//! the oracle (rational patches included), so the ready set equals the
//! oracle's at this method's depth limit (`max_depth`, default 6 as in the paper: the worst case of every
//! deeper level grows fourfold).
//!
//! The node buffers are sized for the worst case of `max_depth`
//! (`patches × 4^d` nodes of depth d) where the device's storage-buffer
//! range allows it; otherwise to that range, the documented budget. A depth
//! that overflows its buffer sets `ERR_LEVEL_FULL`: the frame is refused
//! with the count it needed, never drawn with nodes missing.

use ash::vk;
use serde_json::json;

use super::subdiv::GpuSubdivStats;
use super::{Finished, Method, MethodInfo, MethodSetup, RenderError};
use crate::constants::*;
use crate::draw::{ReadyCaps, ReadyStage};
use crate::frame::{CopyRange, FrameOut, FrameRec, Retired};
use crate::gpu::LevelPush;
use crate::patch::view::ViewParams;
use crate::vk::{
    fill_buffer, memory_barrier, Access, Buffer, Context, DescriptorSet, MemoryLocation, Pipeline,
    PipelineLayout, SetLayout, VkError, VkResult,
};

/// The registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "subdiv-indirect",
    about: "recursive subdivision, one indirect dispatch per depth (the paper's \
            execute-indirect variant)",
    rational: true,
    reads_lambda: true,
    build: |setup| Ok(Box::new(SubdivIndirect::new(setup)?)),
};

/// The paper's depth limit for this variant.
pub const DEFAULT_MAX_DEPTH: u32 = 6;

/// Worst-case node counts of the two buffers for `patches` base patches and
/// depth limit `max_depth`: (odd depths, even depths ≥ 2), i.e. the largest
/// depth of each parity, `patches × 4^d`.
pub fn worst_case_nodes(patches: u32, max_depth: u32) -> (u64, u64) {
    let deepest = |parity: u32| {
        (1..=max_depth)
            .filter(|d| d % 2 == parity)
            .max()
            .map_or(0, |d| u64::from(patches) << (2 * d))
    };
    (deepest(1), deepest(0))
}

/// The node buffers and set 2.
struct Nodes {
    odd: Buffer,
    even: Buffer,
    levels: Buffer,
    /// Entries of the two node buffers.
    odd_capacity: u32,
    even_capacity: u32,
    /// Whether both hold the worst case (else the device's budget).
    worst_case: bool,
    set: DescriptorSet,
}

impl Nodes {
    /// Buffers for the worst case of `max_depth`, or at most `budget`
    /// entries each (the device's storage-buffer range when not given).
    fn new(
        ctx: &Context,
        layout: &SetLayout,
        patches: u32,
        max_depth: u32,
        budget: Option<u32>,
    ) -> VkResult<Self> {
        let (odd_worst, even_worst) = worst_case_nodes(patches, max_depth);
        let device = u64::from(ctx.info().limits.max_storage_buffer_range) / 8;
        let budget = budget.map_or(device, |b| u64::from(b).min(device));
        let odd_capacity = odd_worst.clamp(1, budget) as u32;
        let even_capacity = even_worst.clamp(1, budget) as u32;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let gpu = MemoryLocation::GpuOnly;
        let bytes = |n: u32| u64::from(n) * 8;
        let odd = Buffer::new(
            ctx,
            "nodes of odd depths",
            bytes(odd_capacity),
            storage,
            gpu,
        )?;
        let even = Buffer::new(
            ctx,
            "nodes of even depths",
            bytes(even_capacity),
            storage,
            gpu,
        )?;
        let levels = Buffer::new(
            ctx,
            "levels",
            u64::from(LEVEL_WORDS) * 4,
            storage | vk::BufferUsageFlags::INDIRECT_BUFFER,
            gpu,
        )?;
        let mut bound = [(&odd).into(); LEVEL_BINDINGS as usize];
        bound[BIND_NODES_ODD as usize] = (&odd).into();
        bound[BIND_NODES_EVEN as usize] = (&even).into();
        bound[BIND_LEVELS as usize] = (&levels).into();
        let set = DescriptorSet::new(ctx, "level set", layout, &bound)?;
        Ok(Self {
            odd,
            even,
            levels,
            odd_capacity,
            even_capacity,
            worst_case: odd_worst.max(even_worst) <= budget,
            set,
        })
    }

    fn bytes(&self) -> u64 {
        self.odd.size() + self.even.size() + self.levels.size()
    }
}

/// The per-depth method.
pub struct SubdivIndirect {
    stage: ReadyStage,
    set_layout: SetLayout,
    nodes: Option<(u32, Nodes)>,
    layout: PipelineLayout,
    level: Pipeline,
    args: Pipeline,
    max_depth: u32,
    node_budget: Option<u32>,
    sort: bool,
    counters: Option<CopyRange>,
    level_counts: Option<CopyRange>,
}

impl SubdivIndirect {
    /// Creates the ready stage and both pipelines; the node buffers are
    /// made for the scene at the first frame.
    pub fn new(setup: &mut MethodSetup<'_>) -> Result<Self, RenderError> {
        let (ctx, o) = (setup.ctx, setup.options);
        if o.max_depth > L_MAX {
            return Err(RenderError::Request(format!(
                "--max-depth {} is beyond l_max = {L_MAX}",
                o.max_depth
            )));
        }
        let caps = ReadyCaps {
            ready: o.ready_capacity,
            vertices: false,
            capture: false,
        };
        let stage = ReadyStage::new(ctx, setup.shaders, setup.scene_layout, o.draw, caps)?;
        let set_layout = SetLayout::storage(
            ctx,
            "level set",
            LEVEL_BINDINGS as usize,
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let layout = setup.scene_layout.pipeline_layout::<LevelPush>(
            ctx,
            "per-depth layout",
            &[stage.set_layout(), &set_layout],
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let level =
            setup
                .shaders
                .compute(ctx, &layout, "subdivide one depth", "subdivide_level.comp")?;
        let args = setup
            .shaders
            .compute(ctx, &layout, "depth arguments", "level_args.comp")?;
        Ok(Self {
            stage,
            set_layout,
            nodes: None,
            layout,
            level,
            args,
            max_depth: o.max_depth,
            node_budget: o.node_capacity,
            sort: o.sort,
            counters: None,
            level_counts: None,
        })
    }

    /// The node buffers for `patches` base patches, made (or remade for a
    /// new scene size) on demand; replaced ones are retired.
    fn ensure_nodes(&mut self, f: &mut FrameRec<'_>) -> VkResult<()> {
        let patches = f.scene.count;
        if self.nodes.as_ref().is_some_and(|(p, _)| *p == patches) {
            return Ok(());
        }
        let nodes = Nodes::new(
            f.ctx,
            &self.set_layout,
            patches,
            self.max_depth,
            self.node_budget,
        )?;
        if let Some(old) = self.nodes.replace((patches, nodes)) {
            f.retired.push(old);
        }
        Ok(())
    }

    fn push(&self, f: &FrameRec<'_>, nodes: &Nodes, level: u32) -> VkResult<()> {
        let pc = LevelPush {
            level,
            patch_count: f.scene.count,
            odd_capacity: nodes.odd_capacity,
            even_capacity: nodes.even_capacity,
            ready_capacity: self.stage.list().caps.ready,
            max_groups: f.ctx.info().limits.max_compute_work_group_count[0],
            pad: [0; 2],
        };
        self.layout.push_block(f.cmd, &pc)
    }

    /// Records every depth: the resets, depth 0 directly, then per depth
    /// the argument pass and the indirect dispatch, with barriers between.
    fn record_depths(&self, f: &mut FrameRec<'_>, nodes: &Nodes) -> VkResult<()> {
        self.stage.record_reset(f);
        fill_buffer(f.ctx, f.cmd, &nodes.levels, 0);
        let bind = vk::PipelineBindPoint::COMPUTE;
        self.stage.bind_sets(f, bind, &self.layout);
        nodes
            .set
            .bind(f.ctx, f.cmd, bind, &self.layout, SET_PRODUCER, &[]);
        let compute = Access::COMPUTE_READ_WRITE;
        let to_indirect = Access::new(
            vk::PipelineStageFlags2::DRAW_INDIRECT | vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::INDIRECT_COMMAND_READ
                | vk::AccessFlags2::SHADER_STORAGE_READ
                | vk::AccessFlags2::SHADER_STORAGE_WRITE,
        );
        let max_groups = f.ctx.info().limits.max_compute_work_group_count[0];
        let groups0 = f
            .scene
            .count
            .div_ceil(LEVEL_GROUP_SIZE)
            .clamp(1, max_groups);
        let levels = nodes.levels.handle();
        let max_depth = self.max_depth;
        f.scoped("subdivide", |f| {
            self.level.bind(f.cmd);
            self.push(f, nodes, 0)?;
            unsafe { f.ctx.device().cmd_dispatch(f.cmd, groups0, 1, 1) };
            for d in 1..=max_depth + 1 {
                memory_barrier(f.ctx, f.cmd, compute, compute);
                self.args.bind(f.cmd);
                self.push(f, nodes, d)?;
                unsafe { f.ctx.device().cmd_dispatch(f.cmd, 1, 1, 1) };
                if d > max_depth {
                    break;
                }
                memory_barrier(f.ctx, f.cmd, compute, to_indirect);
                self.level.bind(f.cmd);
                self.push(f, nodes, d)?;
                let offset = u64::from(L_ARGS + 4 * d) * 4;
                unsafe { f.ctx.device().cmd_dispatch_indirect(f.cmd, levels, offset) };
            }
            Ok(())
        })?;
        memory_barrier(f.ctx, f.cmd, compute, Access::ALL);
        Ok(())
    }
}

impl Method for SubdivIndirect {
    fn name(&self) -> &'static str {
        INFO.name
    }

    fn draw_path(&self) -> &'static str {
        self.stage.path().name()
    }

    fn adjust_view(&self, params: &mut ViewParams) {
        params.l_max = params.l_max.min(self.max_depth);
    }

    fn record(&mut self, f: &mut FrameRec<'_>) -> Result<(), RenderError> {
        self.stage.ensure_capture(f.ctx, f.capture, f.retired)?;
        self.ensure_nodes(f)?;
        let (_, nodes) = self
            .nodes
            .as_ref()
            .ok_or_else(|| VkError::Usage("no node buffers".into()))?;
        self.record_depths(f, nodes)?;
        self.stage.record_draw(f, self.sort)?;
        self.counters = Some(f.copy_out(&self.stage.list().counters, COUNTER_WORDS)?);
        self.level_counts = Some(f.copy_out(&nodes.levels, L_MAX + 2)?);
        Ok(())
    }

    fn finish(&mut self, out: &mut FrameOut<'_>) -> Result<Finished, RenderError> {
        let (Some(c), Some(l)) = (self.counters, self.level_counts) else {
            return Err(RenderError::Request(
                "finish() before any frame was recorded".into(),
            ));
        };
        let words = out.words(c);
        let per_depth = out.words(l);
        let stats = GpuSubdivStats::from_counters(words);
        if let Some(reason) = self.stage.grow_if_full(
            out.ctx,
            words,
            super::subdiv::MAX_READY_CAPACITY,
            out.retired,
        )? {
            return Ok(Finished::Redo { reason });
        }
        let caps = self
            .nodes
            .as_ref()
            .map_or((0, 0), |(_, n)| (n.odd_capacity, n.even_capacity));
        if stats.errors & ERR_LEVEL_FULL != 0 {
            let full = per_depth
                .iter()
                .enumerate()
                .skip(1)
                .find(|&(d, &n)| n > if d % 2 == 1 { caps.0 } else { caps.1 });
            let (d, need) = full.map_or((0, 0), |(d, &n)| (d, n));
            let held = if d % 2 == 1 { caps.0 } else { caps.1 };
            return Err(RenderError::Method {
                method: INFO.name,
                message: format!(
                    "depth {d} needs {need} nodes but its node buffer holds {held} \
                     (the budget, or this device's storage-buffer range); raise ε or \
                     lower --max-depth"
                ),
            });
        }
        if let Some(message) = stats.error_message() {
            return Err(RenderError::Method {
                method: INFO.name,
                message,
            });
        }
        let mut m = stats.method_stats(self.stage.list().caps.ready);
        // The persistent kernel's own figures mean nothing here.
        let persistent_only = ["iterations_max", "idle_polls", "global_atomics"];
        m.own.retain(|(k, _)| {
            !k.starts_with("queue") && !persistent_only.iter().any(|p| k.starts_with(p))
        });
        let nodes_per_depth: Vec<u32> = per_depth[..=(self.max_depth as usize + 1)].to_vec();
        m.own.push(("max_depth_limit", json!(self.max_depth)));
        m.own.push(("nodes_per_depth", json!(nodes_per_depth)));
        m.own.push(("node_capacity_items", json!([caps.0, caps.1])));
        let worst = self.nodes.as_ref().is_some_and(|(_, n)| n.worst_case);
        m.own.push(("node_buffers_worst_case", json!(worst)));
        Ok(Finished::Done(m))
    }

    fn reconfigure(
        &mut self,
        setup: &mut MethodSetup<'_>,
        _retired: &mut Retired,
    ) -> Result<bool, RenderError> {
        let o = setup.options;
        if o.draw != self.stage.path()
            || o.max_depth != self.max_depth
            || o.node_capacity != self.node_budget
            || o.ready_capacity > self.stage.list().caps.ready
        {
            return Ok(false);
        }
        self.sort = o.sort;
        Ok(true)
    }

    fn memory(&self) -> Vec<(&'static str, u64)> {
        let mut v = Vec::new();
        if let Some((_, n)) = &self.nodes {
            v.push(("node_buffers", n.bytes()));
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn worst_case_is_the_deepest_level_of_each_parity() {
        // The paper's kitchen at depth 6: 35,940 × (4^5 + 4^6) nodes.
        let (odd, even) = worst_case_nodes(35_940, 6);
        assert_eq!((odd, even), (35_940 * 1024, 35_940 * 4096));
        assert_eq!(worst_case_nodes(1, 1), (4, 0));
        assert_eq!(worst_case_nodes(2, 0), (0, 0));
    }
}
