//! Passes that declare what they read and write; a [`Recorder`] per command
//! buffer derives the barriers between them.
//!
//! A pass names each resource it touches ([`Res`]: a buffer, an image in a
//! layout, or all memory where a global barrier is meant) with the
//! [`Access`] of the use. The recorder remembers, per resource, the writes
//! not yet made visible and the reads since the last write, and before each
//! pass records one `vkCmdPipelineBarrier2` holding what the pass needs: a
//! write waits for earlier reads and writes, a read waits for an earlier
//! write it has not been made visible to, an image in another layout is
//! transitioned. Two reads never get a barrier between them.
//!
//! A compute pass names its pipeline and binds its descriptor sets through
//! the pass ([`Pass::pipeline`], [`Pass::bind`]): the recorder binds them,
//! and declares each buffer they point at that the pipeline's shaders use,
//! as a write where the SPIR-V may write it and a read elsewhere. What a
//! pass binds is thus what it declares, and a shader cannot touch a buffer
//! its pass did not declare (a set the pipeline uses but the pass does not
//! bind is refused). Other uses (indirect arguments, images sampled through
//! a set, transfers) are declared with [`Pass::read`] and [`Pass::write`].
//!
//! What happened before the recorder (earlier in the command buffer, or in
//! an earlier submission) is declared with [`Recorder::after`]; what later,
//! undeclared work needs is given with [`Recorder::hand_off`].

use super::barrier::Access;
use super::context::Context;
use super::layout::DescriptorSet;
use super::memory::Buffer;
use super::pipeline::Pipeline;
pub use super::track::Res;
use super::track::{Barriers, Tracker, Use};
use ash::vk;
use std::collections::BTreeMap;
use std::ffi::CString;

/// A descriptor set a pass binds: its index, the set, its dynamic offsets.
struct BoundSet<'a> {
    index: u32,
    handle: vk::DescriptorSet,
    /// The buffer of each binding (`None`: an image).
    buffers: &'a [Option<vk::Buffer>],
    offsets: Vec<u32>,
}

/// A pass: a name (its debug label), the uses it declares, and for a compute
/// pass its pipelines and the sets it binds.
pub struct Pass<'a> {
    name: &'a str,
    uses: Vec<Use<'a>>,
    /// The compute pipelines it runs, of one layout; the first is bound
    /// with the sets, the others by [`Pass::dispatch`].
    pipelines: Vec<&'a Pipeline>,
    sets: Vec<BoundSet<'a>>,
}

impl<'a> Pass<'a> {
    /// A pass with no uses yet.
    pub fn new(name: &'a str) -> Self {
        Self {
            name,
            uses: Vec::new(),
            pipelines: Vec::new(),
            sets: Vec::new(),
        }
    }

    /// Declares that the pass reads `res` with `access`.
    pub fn read(mut self, res: Res<'a>, access: Access) -> Self {
        self.uses.push(Use {
            res,
            access,
            write: false,
        });
        self
    }

    /// Declares that the pass writes `res` (and may read it) with `access`.
    pub fn write(mut self, res: Res<'a>, access: Access) -> Self {
        self.uses.push(Use {
            res,
            access,
            write: true,
        });
        self
    }

    /// A compute pipeline the pass runs. The recorder binds the first, and
    /// the sets the pass binds, before the pass's work; a pass that runs
    /// several (in turn, no barrier between them: their writes must not
    /// meet) names each and dispatches them with [`Pass::dispatch`].
    pub fn pipeline(mut self, pipeline: &'a Pipeline) -> Self {
        self.pipelines.push(pipeline);
        self
    }

    /// Records binding `pipeline`, one the pass names, and a dispatch of
    /// `groups` workgroups: for the work of a pass that runs several
    /// pipelines. The sets stay bound (the pipelines share a layout).
    ///
    /// # Panics
    ///
    /// If the pass does not name `pipeline`.
    pub fn dispatch(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        pipeline: &Pipeline,
        groups: [u32; 3],
    ) {
        assert!(
            self.pipelines.iter().any(|p| std::ptr::eq(*p, pipeline)),
            "pass `{}` dispatches a pipeline it does not name",
            self.name
        );
        pipeline.bind(cmd);
        unsafe {
            ctx.device()
                .cmd_dispatch(cmd, groups[0], groups[1], groups[2])
        };
    }

    /// Binds `set` as set `index` of the pipeline's layout, declaring every
    /// buffer of it the pipeline's shaders use (see the module's comment).
    pub fn bind(self, index: u32, set: &'a DescriptorSet) -> Self {
        self.bind_dynamic(index, set, &[])
    }

    /// [`Pass::bind`] with one dynamic offset per dynamic descriptor.
    pub fn bind_dynamic(mut self, index: u32, set: &'a DescriptorSet, offsets: &[u32]) -> Self {
        self.sets.push(BoundSet {
            index,
            handle: set.handle(),
            buffers: set.buffers(),
            offsets: offsets.to_vec(),
        });
        self
    }

    /// The uses the pass declares and those of the sets it binds. Refuses
    /// a set the pipeline uses that the pass does not bind (its buffers
    /// would be used undeclared), sets bound without a compute pipeline,
    /// and one index bound twice.
    fn all_uses(&self) -> Result<Vec<Use<'a>>, String> {
        let mut uses = self.uses.clone();
        let Some(first) = self.pipelines.first() else {
            return match self.sets.is_empty() {
                true => Ok(uses),
                false => Err("binds sets but names no pipeline".into()),
            };
        };
        for p in &self.pipelines {
            if p.bind_point() != vk::PipelineBindPoint::COMPUTE {
                return Err("names a pipeline that is not a compute pipeline".into());
            }
            if p.layout() != first.layout() {
                return Err("names pipelines of different layouts".into());
            }
            uses.extend(set_uses(p.uses(), &self.sets)?);
        }
        Ok(uses)
    }

    /// Records binding the first pipeline and the sets, if the pass names
    /// any.
    fn bind_all(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        let Some(pipeline) = self.pipelines.first() else {
            return;
        };
        pipeline.bind(cmd);
        for b in &self.sets {
            unsafe {
                ctx.device().cmd_bind_descriptor_sets(
                    cmd,
                    pipeline.bind_point(),
                    pipeline.layout(),
                    b.index,
                    &[b.handle],
                    &b.offsets,
                )
            };
        }
    }
}

/// The uses of the buffers in `sets` that a compute pipeline using
/// `pipeline_uses` ((set, binding) → may write) touches: a write where it
/// may write, a read elsewhere. Refuses a set index bound twice and a set
/// the pipeline uses that is not bound.
fn set_uses<'a>(
    pipeline_uses: &BTreeMap<(u32, u32), bool>,
    sets: &[BoundSet<'a>],
) -> Result<Vec<Use<'a>>, String> {
    for (k, b) in sets.iter().enumerate() {
        if sets[..k].iter().any(|a| a.index == b.index) {
            return Err(format!("binds set {} twice", b.index));
        }
    }
    let mut uses = Vec::new();
    for (&(set, binding), &written) in pipeline_uses {
        let Some(bound) = sets.iter().find(|b| b.index == set) else {
            return Err(format!(
                "runs a pipeline that uses set {set} (binding {binding}), which the pass does not bind"
            ));
        };
        // An image binding is declared by the pass itself.
        if let Some(&Some(buffer)) = bound.buffers.get(binding as usize) {
            let access = if written {
                Access::COMPUTE_READ_WRITE
            } else {
                Access::COMPUTE_READ
            };
            uses.push(Use {
                res: Res::Bound(buffer),
                access,
                write: written,
            });
        }
    }
    Ok(uses)
}

/// Records passes into one command buffer, with the barriers their
/// declarations call for.
pub struct Recorder<'c> {
    ctx: &'c Context,
    cmd: vk::CommandBuffer,
    tracker: Tracker,
}

impl<'c> Recorder<'c> {
    /// A recorder that knows of no earlier use of anything.
    pub fn new(ctx: &'c Context, cmd: vk::CommandBuffer) -> Self {
        Self {
            ctx,
            cmd,
            tracker: Tracker::new(),
        }
    }

    /// The command buffer recorded into.
    pub fn cmd(&self) -> vk::CommandBuffer {
        self.cmd
    }

    /// Continues in another command buffer of the same queue (a frame
    /// split into parts): the tracked state still holds, since only a
    /// barrier, not a submission boundary, makes writes visible.
    pub fn set_cmd(&mut self, cmd: vk::CommandBuffer) {
        self.cmd = cmd;
    }

    /// Declares that work before the recorder (earlier in the command
    /// buffer or an earlier submission) may have written `res` with
    /// `access`, leaving an image in the layout `res` names.
    pub fn after(&mut self, res: Res<'_>, access: Access) -> &mut Self {
        self.tracker.after(res, access);
        self
    }

    /// Records `pass`: its barriers, its pipeline and sets if it names them,
    /// then `work`, inside its debug label.
    ///
    /// # Panics
    ///
    /// If the pass binds sets its pipeline does not account for, or its
    /// pipeline uses a set the pass does not bind ([`Pass::bind`]): a
    /// mistake in the code recording it, which every test that runs the
    /// pass finds.
    pub fn run<R>(&mut self, pass: &Pass<'_>, work: impl FnOnce(vk::CommandBuffer) -> R) -> R {
        begin_label(self.ctx, self.cmd, pass.name);
        let uses = pass
            .all_uses()
            .unwrap_or_else(|e| panic!("pass `{}` {e}", pass.name));
        let barriers = self.tracker.derive(&uses);
        self.record(barriers);
        pass.bind_all(self.ctx, self.cmd);
        let out = work(self.cmd);
        end_label(self.ctx, self.cmd);
        out
    }

    fn record(&self, barriers: Barriers) {
        if !barriers.is_empty() {
            barriers.record(self.ctx, self.cmd);
        }
    }

    /// Records `pass` with a dispatch of `groups` workgroups as its work.
    pub fn dispatch(&mut self, pass: &Pass<'_>, groups: [u32; 3]) {
        let device = self.ctx.device();
        self.run(pass, |cmd| unsafe {
            device.cmd_dispatch(cmd, groups[0], groups[1], groups[2])
        });
    }

    /// Records `pass` with an indirect dispatch whose arguments are at
    /// `offset` in `args` (the pass should declare reading them).
    pub fn dispatch_indirect(&mut self, pass: &Pass<'_>, args: &Buffer, offset: u64) {
        let device = self.ctx.device();
        self.run(pass, |cmd| unsafe {
            device.cmd_dispatch_indirect(cmd, args.handle(), offset)
        });
    }

    /// Records filling the whole of `buffer` with `value`, as a pass that
    /// writes it in the transfer stage.
    pub fn fill(&mut self, name: &str, buffer: &Buffer, value: u32) {
        let pass = Pass::new(name).write(Res::Buffer(buffer), Access::TRANSFER_WRITE);
        let device = self.ctx.device();
        self.run(&pass, |cmd| unsafe {
            device.cmd_fill_buffer(cmd, buffer.handle(), 0, vk::WHOLE_SIZE, value)
        });
    }

    /// Records the barrier that lets later work the recorder does not see
    /// (another recorder, the host after the fence, the next frame) use
    /// `res` with `dst`: from every tracked write and read of it. That
    /// work's own accesses are not tracked: a pass after a hand-off that
    /// may race with it declares them with [`Recorder::after`].
    pub fn hand_off(&mut self, res: Res<'_>, dst: Access) {
        let barriers = self.tracker.hand_off(res, dst);
        self.record(barriers);
    }

    /// [`Recorder::hand_off`] of every buffer `set` points at: for
    /// undeclared work that reads the set (a draw).
    pub fn hand_off_set(&mut self, set: &DescriptorSet, dst: Access) {
        for &buffer in set.buffers().iter().flatten() {
            self.hand_off(Res::Bound(buffer), dst);
        }
    }

    /// Makes every device write visible to host reads after the fence.
    pub fn host_read(&mut self) {
        self.hand_off(Res::Memory, Access::HOST_READ);
    }
}

/// Opens a debug label named `name` (no-op without debug utils), so
/// captures and validation messages show which pass a command is in.
fn begin_label(ctx: &Context, cmd: vk::CommandBuffer, name: &str) {
    let Some(loader) = ctx.debug_utils() else {
        return;
    };
    let name = CString::new(name.replace('\0', " ")).unwrap_or_default();
    let label = vk::DebugUtilsLabelEXT::default().label_name(&name);
    unsafe { loader.cmd_begin_debug_utils_label(cmd, &label) };
}

/// Closes the label [`begin_label`] opened.
fn end_label(ctx: &Context, cmd: vk::CommandBuffer) {
    if let Some(loader) = ctx.debug_utils() {
        unsafe { loader.cmd_end_debug_utils_label(cmd) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vk::track::Key;
    use ash::vk::Handle;

    fn buffer(raw: u64) -> vk::Buffer {
        vk::Buffer::from_raw(raw)
    }

    fn bound(index: u32, buffers: &[Option<vk::Buffer>]) -> BoundSet<'_> {
        BoundSet {
            index,
            handle: vk::DescriptorSet::null(),
            buffers,
            offsets: Vec::new(),
        }
    }

    #[test]
    fn a_bound_set_declares_what_the_pipeline_uses_of_it() {
        // Set 0: buffers 10, 11 and an image; set 1: buffers 20, 21.
        let (scene, list) = (
            [Some(buffer(10)), Some(buffer(11)), None],
            [Some(buffer(20)), Some(buffer(21))],
        );
        let sets = [bound(0, &scene), bound(1, &list)];
        // The pipeline reads 0.0 and the image 0.2, writes 1.1; it never
        // touches 0.1 or 1.0.
        let uses = BTreeMap::from([((0, 0), false), ((0, 2), false), ((1, 1), true)]);
        let derived = set_uses(&uses, &sets).unwrap();
        let got: Vec<(Key, bool)> = derived.iter().map(|u| (u.res.key(), u.write)).collect();
        assert_eq!(
            got,
            [
                (Key::Buffer(buffer(10)), false),
                (Key::Buffer(buffer(21)), true)
            ]
        );
        assert!(derived[0].access == Access::COMPUTE_READ);
        assert!(derived[1].access == Access::COMPUTE_READ_WRITE);

        // A write through a set, then a read of the same buffer through
        // another pass's set: one buffer barrier, on that buffer.
        let mut t = Tracker::new();
        t.derive(&derived);
        let reader = BTreeMap::from([((1, 1), false)]);
        let read = t.derive(&set_uses(&reader, &sets).unwrap());
        assert!(read.memory.is_none());
        assert_eq!(read.buffers.len(), 1);
        assert_eq!(read.buffers[0].buffer, buffer(21));
        assert_eq!(
            read.buffers[0].src_access_mask,
            Access::COMPUTE_READ_WRITE.access
        );
    }

    #[test]
    fn a_set_the_pipeline_uses_must_be_bound_by_the_pass() {
        let list = [Some(buffer(20))];
        let uses = BTreeMap::from([((0, 0), false), ((1, 0), true)]);
        let err = set_uses(&uses, &[bound(1, &list)]).err().unwrap();
        assert!(
            err.contains("uses set 0") && err.contains("does not bind"),
            "{err}"
        );
        let err = set_uses(&uses, &[bound(1, &list), bound(1, &list)])
            .err()
            .unwrap();
        assert!(err.contains("binds set 1 twice"), "{err}");
        let mut pass = Pass::new("lost");
        pass.sets.push(bound(1, &list));
        assert!(pass.all_uses().err().unwrap().contains("no pipeline"));
    }
}
