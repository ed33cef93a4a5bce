//! Sorting the ready list by (patch, node) on the GPU (`glsl/sort.comp`), so
//! that a frame's draw order, and with it every equal-depth tie, does not
//! depend on how a producer's threads happened to interleave: a block pass
//! (blocks of `SORT_BLOCK` entries sorted in shared memory), then merge
//! passes doubling the sorted runs, all sized by the list's actual length
//! (the producer writes each pass's dispatch arguments; passes the length
//! does not need get no workgroups). Recorded between the producer and the
//! draw, for the producer that needs it (`subdiv --kernel queue`): the
//! level kernels write the list in a canonical order already.

use super::ReadyStage;
use crate::constants::*;
use crate::frame::FrameRec;
use crate::gpu::{ListPush, Shaders};
use crate::vk::{Access, Context, Pass, Pipeline, PipelineLayout, Recorder, Res, VkResult};

const MODE_BLOCK: u32 = 0;
const MODE_MERGE: u32 = 1;

/// Merge passes a list of `capacity` entries needs: runs start at
/// `SORT_BLOCK` and double until one spans the list (`passes_needed` in
/// `glsl/sort.comp`), at most `SORT_MAX_MERGES`.
pub fn merge_passes(capacity: u32) -> u32 {
    let mut passes = 0;
    let mut run = SORT_BLOCK;
    while run < capacity {
        run *= 2;
        passes += 1;
    }
    passes
}

/// The merge sort of the ready list.
pub struct ReadySort {
    pipeline: Pipeline,
}

impl ReadySort {
    /// Creates the pipeline with the ready-list pass layout.
    pub fn new(
        ctx: &Context,
        shaders: &mut Shaders,
        layout: &PipelineLayout<ListPush>,
    ) -> VkResult<Self> {
        Ok(Self {
            pipeline: shaders.compute(ctx, layout, "sort ready list", "sort.comp")?,
        })
    }

    /// Records the block pass and every merge pass the list's capacity may
    /// need, with barriers. The producer's arguments give a pass no
    /// workgroups once the runs span the actual list, and the shader picks
    /// each pass's direction from the actual length, so the sorted list ends
    /// in `ready` whatever the count.
    pub fn record(&self, f: &mut FrameRec<'_>, stage: &ReadyStage) -> VkResult<()> {
        let cap = stage.list().caps.ready;
        let layout = stage.list_layout();
        let counters = &stage.list().counters;
        // The passes read and write the list, the count and each other's
        // runs, all through the sets they bind; the arguments they are
        // dispatched with are the producer's.
        let mut rec = Recorder::new(f.ctx, f.cmd);
        // The producer's writes (list, count, arguments) first.
        rec.after(Res::Memory, Access::ALL);
        let mut pass = |name: &str, mode: u32, k: u32, args: u32| -> VkResult<()> {
            let pc = ListPush {
                ready_capacity: cap,
                mode,
                k,
                j: 0,
            };
            layout.push(f.cmd, &pc);
            let pass = Pass::new(name)
                .pipeline(&self.pipeline)
                .read(Res::Buffer(counters), Access::INDIRECT_READ);
            let pass = stage.bind_to(f, pass);
            rec.dispatch_indirect(&pass, counters, u64::from(args) * 4);
            Ok(())
        };
        pass("sort blocks", MODE_BLOCK, 0, C_SORT_BLOCK_ARGS)?;
        for i in 0..merge_passes(cap) {
            pass(
                "sort merge",
                MODE_MERGE,
                SORT_BLOCK << i,
                C_SORT_MERGE_ARGS + 4 * i,
            )?;
        }
        rec.hand_off(Res::Memory, Access::ALL);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merge_passes_double_runs_up_to_the_capacity() {
        assert_eq!(merge_passes(SORT_BLOCK), 0);
        assert_eq!(merge_passes(SORT_BLOCK + 1), 1);
        assert_eq!(merge_passes(1 << 18), 8);
        // The largest ready list the methods grow to has its arguments.
        assert!(merge_passes(crate::draw::MAX_READY_CAPACITY) <= SORT_MAX_MERGES);
    }
}
