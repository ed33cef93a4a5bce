//! The exclusive scan of cudatess (`glsl/cudatess/scan.comp`): its plan of levels,
//! the commands that run it, and a stand-alone run for the tests.
//!
//! Level 0 is the input, `len` pairs; while a level is longer than one block
//! ([`CT_SCAN_BLOCK`] entries), its block sums form the next level, stored
//! right after it in the same buffer. Every level is scanned block by block
//! (the top one in a single block), then from the top down each level's
//! blocks get the scanned sum of the blocks before them. Any length works:
//! 0 entries dispatch nothing, one block needs one pass.

use ash::vk;

use super::constants::*;
use super::push::CtPush;
use crate::constants::*;
use crate::gpu::SceneLayout;
use crate::vk::{
    Access, Buffer, BufferBinding, Context, DescriptorSet, MemoryLocation, Pass, Pipeline,
    PipelineLayout, Recorder, Res, SetLayout, ShaderModule, VkResult,
};

/// "No next level" in `CtPush::scan_sums`.
pub const NO_SUMS: u32 = u32::MAX;

/// One level of the scan: where its entries start, how many there are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Level {
    /// First entry in the scan buffer.
    pub offset: u32,
    /// Entries.
    pub count: u32,
}

/// The levels of a scan of `len` entries.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScanPlan {
    /// Level 0 is the input; each further level holds the block sums of the
    /// one before; the last fits one block.
    pub levels: Vec<Level>,
}

impl ScanPlan {
    /// The plan for `len` entries.
    pub fn new(len: u32) -> Self {
        let mut levels = vec![Level {
            offset: 0,
            count: len,
        }];
        while let Some(&last) = levels.last() {
            if last.count <= CT_SCAN_BLOCK {
                break;
            }
            levels.push(Level {
                offset: last.offset + last.count,
                count: last.count.div_ceil(CT_SCAN_BLOCK),
            });
        }
        Self { levels }
    }

    /// Entries the scan buffer needs (at least one).
    pub fn entries(&self) -> u32 {
        self.levels
            .last()
            .map_or(1, |l| (l.offset + l.count).max(1))
    }

    /// Records the scan with `pipeline` (the scan shader, of `layout`) and
    /// `set` (cudatess's set 1, bound through each pass), pushing `push`
    /// with the scan fields filled in per pass; every pass waits for the
    /// one before (and the first for earlier writes of the scan buffer).
    pub fn record(
        &self,
        rec: &mut Recorder<'_>,
        pipeline: &Pipeline,
        set: &DescriptorSet,
        layout: &PipelineLayout<CtPush>,
        push: CtPush,
    ) -> VkResult<()> {
        let n = self.levels.len();
        // Each pass reads the sums the one before wrote, in place.
        let scan = Pass::new("scan level")
            .pipeline(pipeline)
            .bind(SET_PASS, set);
        let mut pass = |level: Level, sums: u32, kind: u32| -> VkResult<()> {
            if level.count == 0 {
                return Ok(());
            }
            layout.push(
                rec.cmd(),
                &CtPush {
                    scan_offset: level.offset,
                    scan_count: level.count,
                    scan_sums: sums,
                    pass: kind,
                    ..push
                },
            );
            let groups = level.count.div_ceil(CT_SCAN_BLOCK);
            rec.dispatch(&scan, [groups, 1, 1]);
            Ok(())
        };
        for k in 0..n {
            let sums = self.levels.get(k + 1).map_or(NO_SUMS, |l| l.offset);
            pass(self.levels[k], sums, CT_SCAN_PASS_BLOCKS)?;
        }
        for k in (0..n.saturating_sub(1)).rev() {
            pass(self.levels[k], self.levels[k + 1].offset, CT_SCAN_PASS_ADD)?;
        }
        Ok(())
    }
}

/// Every shader whose pipelines bind cudatess's set 1: its passes, its
/// draw, and ground truth's PN draw, which reads the PN buffers.
pub const CT_SHADERS: &[&str] = &[
    "cudatess/factors.comp",
    "cudatess/counts.comp",
    "cudatess/scan.comp",
    "cudatess/args.comp",
    "cudatess/vertices.comp",
    "cudatess/indices.comp",
    "cudatess/pn_factors.comp",
    "cudatess/pn_counts.comp",
    "cudatess/pn_vertices.comp",
    "cudatess/pn_indices.comp",
    "cudatess/draw.vert",
    "cudatess/draw.frag",
    "ground_truth/pn.vert",
];

/// The set layout of cudatess's set 1 (storage buffers), as
/// [`CT_SHADERS`] declare it.
pub fn set_layout(ctx: &Context) -> VkResult<SetLayout> {
    SetLayout::reflect(ctx, "cudatess set", SET_PASS, CT_SHADERS)
}

/// The exclusive scan of `input` on the GPU with the method's own shader
/// and commands (a test entry point: the scan alone, on any length).
pub fn scan_on_gpu(ctx: &Context, input: &[[u32; 2]]) -> VkResult<Vec<[u32; 2]>> {
    let scene = SceneLayout::new(ctx)?;
    let set_layout = set_layout(ctx)?;
    let layout = scene.pipeline_layout::<CtPush>(
        ctx,
        "cudatess scan test layout",
        &[&set_layout],
        vk::ShaderStageFlags::COMPUTE,
    )?;
    let module = ShaderModule::load(ctx, "cudatess/scan.comp")?;
    let pipeline = Pipeline::compute(ctx, "cudatess scan (test)", &layout, &module, &[])?;
    let plan = ScanPlan::new(input.len() as u32);
    let mut data = vec![[0u32; 2]; plan.entries() as usize];
    data[..input.len()].copy_from_slice(input);
    let buffer = Buffer::with_data(
        ctx,
        "cudatess scan (test)",
        &data,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )?;
    let bound = [BufferBinding::from(&buffer); CT_BINDINGS as usize];
    let set = DescriptorSet::new(ctx, "cudatess scan (test)", &set_layout, &bound)?;
    ctx.one_shot(|cmd| {
        // The upload was an earlier submission: order it before the scan.
        let mut rec = Recorder::new(ctx, cmd);
        rec.after(Res::Buffer(&buffer), Access::TRANSFER_WRITE);
        let push = bytemuck::Zeroable::zeroed();
        plan.record(&mut rec, &pipeline, &set, &layout, push)?;
        // For the read-back copy.
        rec.hand_off(Res::Buffer(&buffer), Access::TRANSFER_READ);
        Ok(())
    })?;
    let out: Vec<[u32; 2]> = buffer.read(ctx)?;
    Ok(out[..input.len()].to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plans_have_levels_until_one_block() {
        let b = CT_SCAN_BLOCK;
        assert_eq!(ScanPlan::new(0).levels.len(), 1);
        assert_eq!(ScanPlan::new(0).entries(), 1);
        assert_eq!(ScanPlan::new(b).levels.len(), 1);
        let p = ScanPlan::new(b + 1);
        assert_eq!(
            p.levels[1],
            Level {
                offset: b + 1,
                count: 2
            }
        );
        // b * b entries fill b blocks exactly: their b sums fit one block.
        let p = ScanPlan::new(b * b);
        assert_eq!(p.levels.len(), 2);
        assert_eq!(p.levels[1].count, b);
        // Three more spill into a (b + 1)-th block, whose b + 1 sums need
        // two blocks of their own, whose 2 sums make the top level.
        let p = ScanPlan::new(b * b + 3);
        assert_eq!(p.levels.len(), 3);
        assert_eq!(p.levels[1].count, b + 1);
        assert_eq!(p.levels[2].count, 2);
        assert_eq!(p.entries(), p.levels[2].offset + 2);
    }
}
