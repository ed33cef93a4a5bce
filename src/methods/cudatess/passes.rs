//! `cudatess`'s compute passes of one frame: the patches' and the PN
//! triangles' stages, each reading what the last wrote.

use super::constants::*;
use super::push::CtPush;
use super::{CudaTess, SceneBuffers};
use crate::frame::FrameRec;
use ash::vk;

use crate::constants::SET_PASS;
use crate::vk::{DescriptorSet, Pass, Pipeline, Recorder, VkResult};

/// What every compute pass of one frame records with: the method (its
/// pipelines and layout), set 1 and the frame's push block.
pub(super) struct ComputePasses<'a> {
    pub(super) method: &'a CudaTess,
    pub(super) set: &'a DescriptorSet,
    pub(super) push: CtPush,
    /// PN triangles: their passes are recorded only where there are some.
    pub(super) tris: u32,
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
            let runs = self.runs([&m.factors, &m.pn.factors], [per_patch, per_tri]);
            let pass = self.stage(f, "factors", &runs);
            rec.run(&pass, |cmd| self.dispatch_all(f, &pass, cmd, &runs));
            Ok(())
        })?;
        f.scoped("scan", |f| self.record_scan(f, rec, s, per_patch, per_tri))?;
        let vertex_groups = CudaTess::groups(ctx, s.patches, CT_GROUP_SIZE / CT_VERTEX_THREADS);
        let tri_vertex_groups = CudaTess::groups(ctx, s.tris, CT_GROUP_SIZE / CT_VERTEX_THREADS);
        // Neither stage reads what the other writes: one pass, so no
        // barrier between them.
        let vertices = self.runs(
            [&m.vertices, &m.pn.vertices],
            [vertex_groups, tri_vertex_groups],
        );
        let indices = self.runs([&m.indices, &m.pn.indices], [per_patch, per_tri]);
        let all: Vec<_> = vertices.iter().chain(&indices).copied().collect();
        let pass = self.stage(f, "vertices and indices", &all);
        rec.run(&pass, |cmd| {
            f.scoped("vertices", |f| {
                self.dispatch_all(f, &pass, cmd, &vertices);
                Ok(())
            })?;
            f.scoped("indices", |f| {
                self.dispatch_all(f, &pass, cmd, &indices);
                Ok(())
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
        let runs = self.runs([&m.counts, &m.pn.counts], [per_patch, per_tri]);
        let pass = self.stage(f, "counts", &runs);
        rec.run(&pass, |cmd| self.dispatch_all(f, &pass, cmd, &runs));
        let layout = &m.compute_layout;
        s.plan.record(rec, &m.scan, self.set, layout, self.push)?;
        let runs = [(&m.args, 1)];
        let pass = self.stage(f, "draw arguments", &runs);
        rec.run(&pass, |cmd| self.dispatch_all(f, &pass, cmd, &runs));
        Ok(())
    }

    /// A stage's patch pipeline with `groups[0]` workgroups, then its
    /// PN-triangle pipeline with `groups[1]` where there are triangles (a
    /// scene without them records exactly what it did before PN
    /// triangles).
    fn runs<'p>(&self, pipelines: [&'p Pipeline; 2], groups: [u32; 2]) -> Vec<(&'p Pipeline, u32)> {
        let n = if self.tris > 0 { 2 } else { 1 };
        (0..n).map(|k| (pipelines[k], groups[k])).collect()
    }

    /// The pass of a compute stage that runs `runs`' pipelines in turn:
    /// sets 0 and 1 bound through it, so it declares what its shaders use
    /// of them (the stage reads what the last wrote).
    fn stage<'p>(
        &'p self,
        f: &FrameRec<'p>,
        name: &'p str,
        runs: &[(&'p Pipeline, u32)],
    ) -> Pass<'p> {
        let pass = runs
            .iter()
            .fold(Pass::new(name), |pass, (p, _)| pass.pipeline(p));
        f.with_scene(pass.bind(SET_PASS, self.set))
    }

    /// The work of `pass`: the frame's push block, then each run's
    /// dispatch.
    fn dispatch_all(
        &self,
        f: &FrameRec<'_>,
        pass: &Pass<'_>,
        cmd: vk::CommandBuffer,
        runs: &[(&Pipeline, u32)],
    ) {
        self.method.compute_layout.push(cmd, &self.push);
        for &(pipeline, groups) in runs {
            pass.dispatch(f.ctx, cmd, pipeline, [groups, 1, 1]);
        }
    }
}
