//! `cudatess`'s compute passes of one frame: the patches' and the PN
//! triangles' stages, each reading what the last wrote.

use super::constants::*;
use super::push::CtPush;
use super::{CudaTess, SceneBuffers};
use crate::frame::FrameRec;
use crate::vk::{Access, DescriptorSet, Pass, Pipeline, Recorder, Res, VkResult};

/// What every compute pass of one frame records with: the method (its
/// pipelines and layout), set 1 and the frame's push block.
pub(super) struct ComputePasses<'a> {
    pub(super) method: &'a CudaTess,
    pub(super) set: &'a DescriptorSet,
    pub(super) push: CtPush,
    /// PN triangles: their passes are recorded only where there are some.
    pub(super) tris: u32,
}

/// A compute stage of the frame: its passes (patches, PN triangles) read
/// and write the method's buffers all over, each stage what the last wrote.
fn compute_stage(name: &str) -> Pass<'_> {
    Pass::new(name).write(Res::Memory, Access::COMPUTE_READ_WRITE)
}

impl ComputePasses<'_> {
    /// Records the four compute stages over `s` (factors, scan, vertices,
    /// indices), each in its timing scope, with a barrier after the first
    /// two.
    pub(super) fn record(
        &self,
        f: &mut FrameRec<'_>,
        rec: &mut Recorder<'_>,
        s: &SceneBuffers,
    ) -> VkResult<()> {
        let ctx = f.ctx;
        let m = self.method;
        let per_patch = CudaTess::groups(ctx, s.patches, CT_GROUP_SIZE);
        let per_tri = CudaTess::groups(ctx, s.tris, CT_GROUP_SIZE);
        f.scoped("factors", |f| {
            rec.run(&compute_stage("factors"), |_| {
                self.both(f, [&m.factors, &m.pn.factors], [per_patch, per_tri])
            })
        })?;
        f.scoped("scan", |f| self.record_scan(f, rec, s, per_patch, per_tri))?;
        let vertex_groups = CudaTess::groups(ctx, s.patches, CT_GROUP_SIZE / CT_VERTEX_THREADS);
        let tri_vertex_groups = CudaTess::groups(ctx, s.tris, CT_GROUP_SIZE / CT_VERTEX_THREADS);
        // Neither stage reads what the other writes: one pass, so no
        // barrier between them.
        rec.run(&compute_stage("vertices and indices"), |_| {
            f.scoped("vertices", |f| {
                let groups = [vertex_groups, tri_vertex_groups];
                self.both(f, [&m.vertices, &m.pn.vertices], groups)
            })?;
            f.scoped("indices", |f| {
                self.both(f, [&m.indices, &m.pn.indices], [per_patch, per_tri])
            })
        })
    }

    /// The scan stage: the counts (patches, then PN triangles), the
    /// multi-level scan of `s.plan`, then the draw's arguments.
    fn record_scan(
        &self,
        f: &mut FrameRec<'_>,
        rec: &mut Recorder<'_>,
        s: &SceneBuffers,
        per_patch: u32,
        per_tri: u32,
    ) -> VkResult<()> {
        let m = self.method;
        rec.run(&compute_stage("counts"), |_| {
            self.both(f, [&m.counts, &m.pn.counts], [per_patch, per_tri])
        })?;
        m.bind_compute(f, &m.scan, self.set)?;
        s.plan.record(rec, &m.compute_layout, self.push)?;
        rec.run(&compute_stage("draw arguments"), |_| {
            self.dispatch(f, &m.args, 1)
        })
    }

    /// Binds `pipeline` with sets 0 and 1, pushes the frame's block and
    /// dispatches `groups` workgroups.
    fn dispatch(&self, f: &FrameRec<'_>, pipeline: &Pipeline, groups: u32) -> VkResult<()> {
        self.method.bind_compute(f, pipeline, self.set)?;
        self.method.compute_layout.push(f.cmd, &self.push);
        unsafe { f.ctx.device().cmd_dispatch(f.cmd, groups, 1, 1) };
        Ok(())
    }

    /// A stage's patch pass then its PN-triangle pass (`groups` each),
    /// the latter only where there are triangles (a scene without them
    /// records exactly what it did before PN triangles).
    fn both(&self, f: &FrameRec<'_>, pipelines: [&Pipeline; 2], groups: [u32; 2]) -> VkResult<()> {
        self.dispatch(f, pipelines[0], groups[0])?;
        if self.tris > 0 {
            self.dispatch(f, pipelines[1], groups[1])?;
        }
        Ok(())
    }
}
