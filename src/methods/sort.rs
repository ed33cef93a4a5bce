//! Sorting the ready list by (patch, node) on the GPU (`glsl/sort.comp`), so
//! that a frame's draw order, and with it every equal-depth tie, does not
//! depend on how the persistent kernel's threads happened to interleave.
//! Recorded between the subdivision pass and the draw; the dispatch sizes
//! come from the arguments the subdivision pass wrote.

use ash::vk;

use crate::constants::*;
use crate::gpu::{FrameGpu, PushConstants, SceneLayout};
use crate::vk::{
    memory_barrier, Access, Context, GpuTimer, Pipeline, ShaderModule, VkError, VkResult,
};

const MODE_FILL: u32 = 0;
const MODE_BLOCK: u32 = 1;
const MODE_GLOBAL: u32 = 2;

/// The bitonic sort of the ready list.
pub struct ReadySort {
    pipeline: Pipeline,
}

impl ReadySort {
    /// Creates the pipeline.
    pub fn new(ctx: &Context, layout: &SceneLayout) -> VkResult<Self> {
        let shader = ShaderModule::load(ctx, "sort.comp")?;
        Ok(Self {
            pipeline: Pipeline::compute(ctx, "sort ready list", &layout.layout, &shader, &[])?,
        })
    }

    /// Records every pass needed for the frame's ready-list capacity (the
    /// passes beyond the actual length do nothing on the GPU), with
    /// barriers, under the timestamp scope "sort".
    pub fn record(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        layout: &SceneLayout,
        frame: &FrameGpu,
        timer: Option<&mut GpuTimer>,
    ) -> VkResult<()> {
        let cap = frame.caps.ready;
        if !cap.is_power_of_two() || cap < SORT_BLOCK {
            return Err(VkError::Usage(format!(
                "sorting needs a power-of-two ready capacity of at least {SORT_BLOCK} (got {cap})"
            )));
        }
        let mut timer = timer;
        if let Some(t) = timer.as_deref_mut() {
            t.begin(cmd, "sort")?;
        }
        self.pipeline.bind(cmd);
        frame.bind(ctx, cmd, layout, vk::PipelineBindPoint::COMPUTE);
        let compute = Access::COMPUTE_READ_WRITE;
        let pass = |mode: u32, k: u32, j: u32, args: u32| -> VkResult<()> {
            let pc = PushConstants {
                ready_capacity: cap,
                sort_mode: mode,
                sort_k: k,
                sort_j: j,
                ..bytemuck::Zeroable::zeroed()
            };
            layout.push(cmd, &pc)?;
            unsafe {
                ctx.device().cmd_dispatch_indirect(
                    cmd,
                    frame.counters.handle(),
                    u64::from(args) * 4,
                )
            };
            memory_barrier(ctx, cmd, compute, compute);
            Ok(())
        };
        // The subdivision pass's writes (list, count, arguments) first.
        memory_barrier(ctx, cmd, Access::ALL, Access::ALL);
        pass(MODE_FILL, 0, 0, C_SORT_FILL_ARGS)?;
        pass(MODE_BLOCK, 0, 0, C_SORT_BLOCK_ARGS)?;
        let mut k = 2 * SORT_BLOCK;
        while k <= cap {
            let mut j = k / 2;
            while j >= SORT_BLOCK {
                pass(MODE_GLOBAL, k, j, C_SORT_GLOBAL_ARGS)?;
                j /= 2;
            }
            pass(MODE_BLOCK, k, 0, C_SORT_BLOCK_ARGS)?;
            k *= 2;
        }
        if let Some(t) = timer {
            t.end(cmd, "sort")?;
        }
        memory_barrier(ctx, cmd, Access::ALL, Access::ALL);
        Ok(())
    }
}
