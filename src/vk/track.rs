//! What a [`Recorder`](super::pass::Recorder) remembers between passes,
//! and the barriers it derives: the resources uses name ([`Res`]), the
//! state of each (writes not yet visible, reads since), and the rules that
//! turn a pass's uses into one `vkCmdPipelineBarrier2` (see
//! `super::pass`'s module comment). Knows no device beyond recording the
//! barriers, so its rules are tested alone.

use super::barrier::{buffer_barrier_info, image_barrier_info, memory_barrier_info, Access};
use super::context::Context;
use super::memory::{Buffer, Image};
use ash::vk;

/// A resource a pass uses.
#[derive(Clone, Copy)]
pub enum Res<'a> {
    /// Every resource: the barrier is a global memory barrier. For passes
    /// whose buffers are too many or too dynamic to list (a kernel that
    /// reads and writes the whole node pool), as the code before the pass
    /// layer deliberately did.
    Memory,
    /// A whole buffer.
    Buffer(&'a Buffer),
    /// A whole buffer a set bound by the pass points at
    /// ([`Pass::bind`](super::Pass::bind)).
    Bound(vk::Buffer),
    /// A whole image, used in this layout.
    Image(&'a Image, vk::ImageLayout),
    /// A swapchain image (owned by the swapchain, one mip and layer of
    /// colour), used in this layout.
    Swapchain(vk::Image, vk::ImageLayout),
}

/// What identifies a resource's tracked state.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Key {
    Memory,
    Buffer(vk::Buffer),
    Image(vk::Image),
}

impl Res<'_> {
    pub(super) fn key(&self) -> Key {
        match self {
            Res::Memory => Key::Memory,
            Res::Buffer(b) => Key::Buffer(b.handle()),
            Res::Bound(b) => Key::Buffer(*b),
            Res::Image(i, _) => Key::Image(i.handle()),
            Res::Swapchain(i, _) => Key::Image(*i),
        }
    }

    /// The layout an image is used in.
    pub(super) fn layout(&self) -> Option<vk::ImageLayout> {
        match self {
            Res::Image(_, layout) | Res::Swapchain(_, layout) => Some(*layout),
            _ => None,
        }
    }
}

/// One declared use.
#[derive(Clone, Copy)]
pub(super) struct Use<'a> {
    pub(super) res: Res<'a>,
    pub(super) access: Access,
    pub(super) write: bool,
}

/// The tracked state of one resource.
#[derive(Clone, Copy, Debug)]
struct State {
    key: Key,
    /// The last writes, not yet visible to everything.
    writes: Access,
    /// The scope the last writes were made visible to.
    visible: Access,
    /// Reads since the last write (a later write waits for them).
    reads: Access,
    /// Writes before the last ones: already available, kept so that a
    /// hand-off to undeclared work names them in its source too.
    carried: Access,
    layout: vk::ImageLayout,
}

impl State {
    fn new(key: Key) -> Self {
        Self {
            key,
            writes: Access::NONE,
            visible: Access::NONE,
            reads: Access::NONE,
            carried: Access::NONE,
            layout: vk::ImageLayout::UNDEFINED,
        }
    }

    /// The source scope `u` must wait for, if any: the last writes unless
    /// a barrier already made them visible to `u`'s scope (which also
    /// orders a write after them), and for a write the reads since.
    fn source(&self, u: &Use<'_>) -> Access {
        let writes = if self.visible.covers(u.access) {
            Access::NONE
        } else {
            self.writes
        };
        if u.write {
            writes.union(self.reads)
        } else {
            writes
        }
    }

    /// The state after a pass that wrote `w` and read `r` of it, behind
    /// a barrier from [`State::source`] of each use. The pass's own reads
    /// stay in `reads` so that a later write waits for them, but are not
    /// made visible: its writes are not visible to anything yet.
    fn apply(&mut self, w: Access, r: Access) {
        if !w.is_none() {
            self.carried = self.carried.union(self.writes);
            self.writes = w;
            self.visible = Access::NONE;
            self.reads = r;
        } else {
            if !self.writes.is_none() {
                self.visible = self.visible.union(r);
            }
            self.reads = self.reads.union(r);
        }
    }
}

/// The barriers of one pass, gathered so they go in one call.
#[derive(Default)]
pub(super) struct Barriers {
    pub(super) memory: Option<(Access, Access)>,
    pub(super) buffers: Vec<vk::BufferMemoryBarrier2<'static>>,
    pub(super) images: Vec<vk::ImageMemoryBarrier2<'static>>,
}

impl Barriers {
    pub(super) fn is_empty(&self) -> bool {
        self.memory.is_none() && self.buffers.is_empty() && self.images.is_empty()
    }

    fn global(&mut self, src: Access, dst: Access) {
        let (s, d) = self.memory.unwrap_or((Access::NONE, Access::NONE));
        self.memory = Some((s.union(src), d.union(dst)));
    }

    /// Adds the barrier for one use of `res`: global, buffer or image (with
    /// the transition from `old_layout`).
    fn push(&mut self, res: Res<'_>, old_layout: vk::ImageLayout, src: Access, dst: Access) {
        match res {
            Res::Memory => self.global(src, dst),
            Res::Buffer(buffer) => {
                self.buffers
                    .push(buffer_barrier_info(buffer.handle(), src, dst))
            }
            Res::Bound(buffer) => self.buffers.push(buffer_barrier_info(buffer, src, dst)),
            Res::Image(image, layout) => self.images.push(
                image_barrier_info(src, dst, old_layout, layout)
                    .image(image.handle())
                    .subresource_range(image.full_range()),
            ),
            Res::Swapchain(image, layout) => self.images.push(
                image_barrier_info(src, dst, old_layout, layout)
                    .image(image)
                    .subresource_range(super::swapchain::color_range()),
            ),
        }
    }

    pub(super) fn record(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        let memory: Vec<vk::MemoryBarrier2> = self
            .memory
            .iter()
            .map(|&(src, dst)| memory_barrier_info(src, dst))
            .collect();
        let dep = vk::DependencyInfo::default()
            .memory_barriers(&memory)
            .buffer_memory_barriers(&self.buffers)
            .image_memory_barriers(&self.images);
        unsafe { ctx.device().cmd_pipeline_barrier2(cmd, &dep) };
    }
}

/// The tracked state of every resource one recorder has seen, and the
/// barriers it calls for. Knows no device, so its rules are tested alone.
///
/// The first state is all memory's. A resource seen for the first time
/// starts as a copy of it (every global use so far touched it too), and
/// from then on every global use moves it on along with its own uses; so
/// a use of one resource looks at that resource's state only, and a
/// barrier on one resource makes nothing else visible.
pub(super) struct Tracker {
    states: Vec<State>,
}

impl Tracker {
    pub(super) fn new() -> Self {
        Self {
            states: vec![State::new(Key::Memory)],
        }
    }

    fn state(&mut self, key: Key) -> &mut State {
        let i = match self.states.iter().position(|s| s.key == key) {
            Some(i) => i,
            None => {
                let global = self.states[0];
                self.states.push(State {
                    key,
                    layout: vk::ImageLayout::UNDEFINED,
                    ..global
                });
                self.states.len() - 1
            }
        };
        &mut self.states[i]
    }

    /// The states a use of `key` looks at and moves on: its own, or for
    /// all memory every one.
    fn moved_by(&mut self, key: Key) -> impl Iterator<Item = &mut State> {
        self.state(key);
        self.states
            .iter_mut()
            .filter(move |s| key == Key::Memory || s.key == key)
    }

    /// See [`Recorder::after`](super::Recorder::after).
    pub(super) fn after(&mut self, res: Res<'_>, access: Access) {
        for s in self.moved_by(res.key()) {
            s.carried = s.carried.union(s.writes);
            s.writes = access;
            s.visible = Access::NONE;
            s.reads = Access::NONE;
        }
        if let Some(layout) = res.layout() {
            self.state(res.key()).layout = layout;
        }
    }

    /// The barriers `pass` needs, and the states after it. Every use is
    /// checked against the state before the pass (a pass's uses are not
    /// ordered among themselves), then the state is moved on.
    pub(super) fn derive(&mut self, uses: &[Use<'_>]) -> Barriers {
        let mut barriers = Barriers::default();
        for u in uses {
            let key = u.res.key();
            let mut src = self
                .moved_by(key)
                .fold(Access::NONE, |a, s| a.union(s.source(u)));
            let s = self.state(key);
            let old_layout = s.layout;
            let transition = u.res.layout().is_some_and(|layout| layout != old_layout);
            if transition {
                // A layout transition writes the image: it waits for every
                // earlier use.
                src = src.union(s.writes).union(s.reads).union(s.carried);
            }
            if !src.is_none() || transition {
                barriers.push(u.res, old_layout, src, u.access);
            }
        }
        let touched = |key: Key, write: bool| {
            uses.iter()
                .filter(|u| u.write == write && (u.res.key() == key || u.res.key() == Key::Memory))
                .fold(Access::NONE, |a, u| a.union(u.access))
        };
        for s in &mut self.states {
            let (w, r) = (touched(s.key, true), touched(s.key, false));
            if !w.is_none() || !r.is_none() {
                s.apply(w, r);
            }
        }
        for u in uses {
            if let Some(layout) = u.res.layout() {
                self.state(u.res.key()).layout = layout;
            }
        }
        barriers
    }

    /// The barrier of [`Recorder::hand_off`](super::Recorder::hand_off), and
    /// the states after it.
    pub(super) fn hand_off(&mut self, res: Res<'_>, dst: Access) -> Barriers {
        let key = res.key();
        let src = self.moved_by(key).fold(Access::NONE, |a, s| {
            a.union(s.writes).union(s.reads).union(s.carried)
        });
        let mut barriers = Barriers::default();
        if src.is_none() {
            return barriers;
        }
        let layout = self.state(key).layout;
        barriers.push(res, layout, src, dst);
        if let Some(new_layout) = res.layout() {
            self.state(key).layout = new_layout;
        }
        for s in self.moved_by(key) {
            s.visible = s.visible.union(dst);
            if dst.covers(Access::ALL) {
                // Everything before is now ordered before everything after.
                s.reads = Access::NONE;
                s.carried = Access::NONE;
            }
        }
        barriers
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ash::vk::Handle;

    fn write(access: Access) -> Use<'static> {
        Use {
            res: Res::Memory,
            access,
            write: true,
        }
    }

    fn read(access: Access) -> Use<'static> {
        Use {
            res: Res::Memory,
            access,
            write: false,
        }
    }

    #[test]
    fn a_read_after_a_write_waits_once_and_a_second_read_does_not() {
        let mut s = State::new(Key::Memory);
        s.apply(Access::COMPUTE_WRITE, Access::NONE);
        let r = read(Access::INDIRECT_READ);
        assert_eq!(s.source(&r), Access::COMPUTE_WRITE);
        s.apply(Access::NONE, r.access);
        assert!(s.source(&r).is_none());
    }

    #[test]
    fn a_write_waits_for_the_reads_and_writes_before_it() {
        let mut s = State::new(Key::Memory);
        s.apply(Access::COMPUTE_WRITE, Access::NONE);
        s.apply(Access::NONE, Access::TRANSFER_READ);
        let w = write(Access::COMPUTE_READ_WRITE);
        // The write was made visible to transfers only: the compute write
        // still waits for it, and for the copy's read.
        assert_eq!(
            s.source(&w),
            Access::COMPUTE_WRITE.union(Access::TRANSFER_READ)
        );
    }

    #[test]
    fn nothing_before_means_no_barrier() {
        let s = State::new(Key::Memory);
        assert!(s.source(&write(Access::ALL)).is_none());
        assert!(s.source(&read(Access::ALL)).is_none());
    }

    #[test]
    fn a_pass_s_own_reads_are_not_visible_to_the_next() {
        let mut s = State::new(Key::Memory);
        s.apply(Access::COMPUTE_WRITE, Access::INDIRECT_READ);
        assert_eq!(
            s.source(&read(Access::INDIRECT_READ)),
            Access::COMPUTE_WRITE
        );
    }

    #[test]
    fn all_commands_and_memory_access_cover_any_scope() {
        assert!(Access::ALL.covers(Access::COMPUTE_READ_WRITE));
        assert!(Access::ALL.covers(Access::HOST_READ));
        assert!(!Access::COMPUTE_READ.covers(Access::COMPUTE_WRITE));
        assert!(!Access::COMPUTE_WRITE.covers(Access::INDIRECT_READ));
    }

    /// A swapchain image in the general layout: a per-resource key the
    /// tracker can be tested with without a device.
    fn image(raw: u64) -> Res<'static> {
        Res::Swapchain(vk::Image::from_raw(raw), vk::ImageLayout::GENERAL)
    }

    /// One use of `res` as a pass declares it.
    fn uses(res: Res<'static>, access: Access, write: bool) -> [Use<'static>; 1] {
        [Use { res, access, write }]
    }

    fn global_write() -> [Use<'static>; 1] {
        uses(Res::Memory, Access::COMPUTE_READ_WRITE, true)
    }

    #[test]
    fn a_second_read_of_one_resource_after_a_global_write_waits_no_more() {
        // Whether the resource was seen before the global write or not.
        for seen_before in [true, false] {
            let mut t = Tracker::new();
            if seen_before {
                t.after(image(1), Access::NONE);
            }
            assert!(t.derive(&global_write()).is_empty());
            if !seen_before {
                t.after(image(1), Access::NONE);
                t.derive(&global_write());
            }
            let read = uses(image(1), Access::COMPUTE_READ, false);
            let first = t.derive(&read);
            assert_eq!(first.images.len(), 1, "seen before: {seen_before}");
            assert!(first.memory.is_none());
            assert!(t.derive(&read).is_empty(), "seen before: {seen_before}");
        }
    }

    #[test]
    fn a_hand_off_of_one_resource_makes_no_other_visible() {
        let mut t = Tracker::new();
        t.derive(&global_write());
        assert_eq!(t.hand_off(image(1), Access::ALL).images.len(), 1);
        // Image 2, first seen now, was written by the global write too.
        let read = t.derive(&uses(image(2), Access::COMPUTE_READ, false));
        assert_eq!(read.images.len(), 1);
        let src = read.images[0].src_access_mask;
        assert!(
            src.contains(vk::AccessFlags2::SHADER_STORAGE_WRITE),
            "{src:?}"
        );
    }

    #[test]
    fn a_global_read_waits_for_a_write_of_one_resource() {
        let mut t = Tracker::new();
        t.after(image(1), Access::NONE);
        t.derive(&uses(image(1), Access::TRANSFER_WRITE, true));
        let read = t.derive(&uses(Res::Memory, Access::COMPUTE_READ, false));
        let (src, _) = read.memory.expect("a global barrier");
        assert_eq!(src, Access::TRANSFER_WRITE);
    }
}
