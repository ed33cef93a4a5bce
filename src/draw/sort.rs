//! Sorting the ready list by (patch, node) on the GPU (`glsl/sort.comp`), so
//! that a frame's draw order, and with it every equal-depth tie, does not
//! depend on how a producer's threads happened to interleave. Recorded
//! between the producer and the draw; the dispatch sizes come from the
//! arguments the producer wrote.

use ash::vk;

use super::ReadyStage;
use crate::constants::*;
use crate::frame::FrameRec;
use crate::gpu::{ListPush, Shaders};
use crate::vk::{memory_barrier, Access, Context, Pipeline, PipelineLayout, VkError, VkResult};

const MODE_FILL: u32 = 0;
const MODE_BLOCK: u32 = 1;
const MODE_GLOBAL: u32 = 2;

/// The bitonic sort of the ready list.
pub struct ReadySort {
    pipeline: Pipeline,
}

impl ReadySort {
    /// Creates the pipeline with the ready-list pass layout.
    pub fn new(ctx: &Context, shaders: &mut Shaders, layout: &PipelineLayout) -> VkResult<Self> {
        Ok(Self {
            pipeline: shaders.compute(ctx, layout, "sort ready list", "sort.comp")?,
        })
    }

    /// Records every pass needed for the list's capacity (the passes beyond
    /// the actual length do nothing on the GPU), with barriers.
    pub fn record(&self, f: &mut FrameRec<'_>, stage: &ReadyStage) -> VkResult<()> {
        let cap = stage.list().caps.ready;
        if !cap.is_power_of_two() || cap < SORT_BLOCK {
            return Err(VkError::Usage(format!(
                "sorting needs a power-of-two ready capacity of at least {SORT_BLOCK} (got {cap})"
            )));
        }
        let layout = stage.list_layout();
        self.pipeline.bind(f.cmd);
        stage.bind_sets(f, vk::PipelineBindPoint::COMPUTE, layout);
        let counters = stage.list().counters.handle();
        let compute = Access::COMPUTE_READ_WRITE;
        let pass = |mode: u32, k: u32, j: u32, args: u32| -> VkResult<()> {
            let pc = ListPush {
                ready_capacity: cap,
                mode,
                k,
                j,
            };
            layout.push_block(f.cmd, &pc)?;
            unsafe {
                f.ctx
                    .device()
                    .cmd_dispatch_indirect(f.cmd, counters, u64::from(args) * 4)
            };
            memory_barrier(f.ctx, f.cmd, compute, compute);
            Ok(())
        };
        // The producer's writes (list, count, arguments) first.
        memory_barrier(f.ctx, f.cmd, Access::ALL, Access::ALL);
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
        memory_barrier(f.ctx, f.cmd, Access::ALL, Access::ALL);
        Ok(())
    }
}
