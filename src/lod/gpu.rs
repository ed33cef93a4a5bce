//! The levels on the GPU, their cull and their draw: one vertex and one
//! index buffer for every level of every model, a compute pass that turns
//! the host's choice per instance into indexed indirect draws (culling the
//! instances hidden behind what the method drew, with occlusion culling
//! on), and a vertex + fragment pipeline that places a level by its
//! instance's record and shades it as the patches are shaded. The renderer
//! asks [`Lod::prepare`] before the method and [`Lod::record`] after it.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::constants::{
    BIND_LOD_HIZ, LOD_BINDINGS, LOD_BY_LEVEL, LOD_COUNTER_WORDS, LOD_CULL_GROUP, LOD_DRAWN,
    LOD_MAX_LEVELS, LOD_NONE, LOD_OCCLUDED, LOD_RANGE_WORDS, LOD_TRIANGLES,
};
use super::select::{self, Draw};
use super::SceneLevels;
use crate::constants::{INSTANCE_LOD, LOD_VERTEX_WORDS, SET_PASS};
use crate::draw::hiz::Hiz;
use crate::frame::{CopyRange, FrameRec};
use crate::gpu::blocks::{gpu_block, DrawPush};
use crate::gpu::{SceneGpu, SceneLayout, SceneSpec, Shaders};
use crate::patch::view::ViewParams;
use crate::scene::instances::{Instance, INSTANCE_BYTES};
use crate::vk::{
    Access, Binding, Buffer, Context, DescriptorSet, MemoryLocation, Pass, Pipeline,
    PipelineLayout, Recorder, Res, SetLayout, VkResult,
};

/// The level passes' shaders (their set layout is reflected from them).
const SHADERS: &[&str] = &["lod/draw.vert", "lod/draw.frag", "lod/cull.comp"];

/// Byte offset of the flags word in an instance record.
const FLAGS_OFFSET: u64 = 60;

/// Bytes of a `VkDrawIndexedIndirectCommand`.
const DRAW_BYTES: u32 = 20;

/// Push constants of the level cull (`LodCullPush` in
/// `glsl/lod/cull.comp`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct LodCullPush {
    /// Instance records.
    pub instance_count: u32,
    /// 1: test each box against the depth pyramid.
    pub occlusion: u32,
    /// Padding to 16 bytes.
    pub pad: [u32; 2],
}
gpu_block!(LodCullPush, "LodCullPush", [instance_count, occlusion, pad]);

/// A unit vector as two snorm16 of its octahedral projection (decoded by
/// `oct_decode` in `glsl/lod/draw.vert`).
pub fn oct_encode(n: Vec3) -> u32 {
    let n = n / (n.x.abs() + n.y.abs() + n.z.abs()).max(1e-30);
    let (mut x, mut y) = (n.x, n.y);
    if n.z < 0.0 {
        let sx = if n.x >= 0.0 { 1.0 } else { -1.0 };
        let sy = if n.y >= 0.0 { 1.0 } else { -1.0 };
        (x, y) = ((1.0 - n.y.abs()) * sx, (1.0 - n.x.abs()) * sy);
    }
    let q = |v: f32| ((v.clamp(-1.0, 1.0) * 32767.0).round() as i16) as u16 as u32;
    q(x) | (q(y) << 16)
}

/// What the levels drew in a frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LodFrame {
    /// Instances drawn from a level (inside the view, not hidden).
    pub instances: u64,
    /// Their triangles.
    pub triangles: u64,
    /// Instances chosen for a level but hidden behind what the method drew
    /// (occlusion culling), so not drawn.
    pub occluded: u64,
    /// Per level index (0 the finest of each model): instances, triangles.
    pub by_level: Vec<(u64, u64)>,
    /// Bytes of every level on the GPU.
    pub bytes: u64,
}

impl LodFrame {
    /// The figures from the cull's counters (`LOD_COUNTER_WORDS` words).
    pub fn from_counters(words: &[u32], bytes: u64) -> Self {
        let w = |k: u32| u64::from(words[k as usize]);
        let mut by_level: Vec<(u64, u64)> = (0..LOD_MAX_LEVELS)
            .map(|l| (w(LOD_BY_LEVEL + 2 * l), w(LOD_BY_LEVEL + 2 * l + 1)))
            .collect();
        while by_level.last().is_some_and(|&(n, _)| n == 0) {
            by_level.pop();
        }
        Self {
            instances: w(LOD_DRAWN),
            triangles: w(LOD_TRIANGLES),
            occluded: w(LOD_OCCLUDED),
            by_level,
            bytes,
        }
    }
}

/// The buffers the level passes share (set 1) and the set that binds them.
struct Buffers {
    vertices: Buffer,
    indices: Buffer,
    /// The level table: `LOD_RANGE_WORDS` per level of every model.
    table: Buffer,
    /// Per instance its `BIND_LOD_CHOICE` word.
    choice: Buffer,
    /// Per instance a `VkDrawIndexedIndirectCommand`, written by the cull.
    draws: Buffer,
    counters: Buffer,
}

/// The levels packed for the GPU: the vertices (`LOD_VERTEX_WORDS` each),
/// the indices, and the level table (`LOD_RANGE_WORDS` a level, the rows
/// model by model, level by level).
fn pack(levels: &SceneLevels) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
    let mut words: Vec<u32> = Vec::new();
    let mut indices: Vec<u32> = Vec::new();
    let mut table: Vec<u32> = Vec::new();
    for m in &levels.models {
        for (k, l) in m.levels.iter().enumerate() {
            let base = (words.len() / LOD_VERTEX_WORDS as usize) as u32;
            for (v, p) in l.mesh.positions.iter().enumerate() {
                let st = l.mesh.st[v];
                words.extend([
                    p.x.to_bits(),
                    p.y.to_bits(),
                    p.z.to_bits(),
                    oct_encode(l.mesh.normals[v][0]),
                    st[0].to_bits(),
                    st[1].to_bits(),
                ]);
            }
            let first = indices.len() as u32;
            table.extend([first, l.mesh.indices.len() as u32, base, k as u32]);
            indices.extend_from_slice(&l.mesh.indices);
        }
    }
    (words, indices, table)
}

impl Buffers {
    /// The buffers for `levels` and `instances` instance records, and the
    /// level table they hold (for direct draws on the host).
    fn new(ctx: &Context, levels: &SceneLevels, instances: usize) -> VkResult<(Self, Vec<u32>)> {
        let (mut words, mut indices, mut table) = pack(levels);
        // Never empty: a scene whose models all lack levels binds a word.
        words.resize(words.len().max(LOD_VERTEX_WORDS as usize), 0);
        indices.resize(indices.len().max(3), 0);
        table.resize(table.len().max(LOD_RANGE_WORDS as usize), 0);
        let n = instances.max(1) as u64;
        let gpu = MemoryLocation::GpuOnly;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let written = storage | vk::BufferUsageFlags::TRANSFER_DST;
        let buffers = Self {
            vertices: Buffer::with_data(ctx, "level-of-detail vertices", &words, storage, gpu)?,
            indices: Buffer::with_data(
                ctx,
                "level-of-detail indices",
                &indices,
                vk::BufferUsageFlags::INDEX_BUFFER,
                gpu,
            )?,
            table: Buffer::with_data(ctx, "level-of-detail table", &table, storage, gpu)?,
            choice: Buffer::with_data(
                ctx,
                "level-of-detail choice",
                &vec![LOD_NONE; n as usize],
                written,
                gpu,
            )?,
            draws: Buffer::new(
                ctx,
                "level-of-detail draws",
                n * u64::from(DRAW_BYTES),
                storage | vk::BufferUsageFlags::INDIRECT_BUFFER,
                gpu,
            )?,
            counters: Buffer::new(
                ctx,
                "level-of-detail counters",
                u64::from(LOD_COUNTER_WORDS) * 4,
                written | vk::BufferUsageFlags::TRANSFER_SRC,
                gpu,
            )?,
        };
        Ok((buffers, table))
    }

    /// The set binding them, and the pyramid `hiz` (the counters stand in
    /// for it without occlusion culling: the cull then never reads it).
    fn set(
        &self,
        ctx: &Context,
        layout: &SetLayout,
        hiz: Option<&Buffer>,
    ) -> VkResult<DescriptorSet> {
        let mut bound = [
            Binding::from(&self.vertices),
            Binding::from(&self.choice),
            Binding::from(&self.table),
            Binding::from(&self.draws),
            Binding::from(&self.counters),
            Binding::from(&self.counters),
        ];
        debug_assert_eq!(bound.len(), LOD_BINDINGS as usize);
        bound[BIND_LOD_HIZ as usize] = Binding::from(hiz.unwrap_or(&self.counters));
        DescriptorSet::with_bindings(ctx, "level-of-detail set", layout, &bound)
    }

    /// Bytes of the levels themselves (vertices and indices).
    fn level_bytes(&self) -> u64 {
        self.vertices.size() + self.indices.size()
    }

    /// Bytes of every buffer.
    fn bytes(&self) -> u64 {
        self.level_bytes()
            + [&self.table, &self.choice, &self.draws, &self.counters]
                .iter()
                .map(|b| b.size())
                .sum::<u64>()
    }
}

/// The levels of a scene on the GPU and what draws each instance.
pub struct Lod {
    levels: SceneLevels,
    /// Per model, per level: its row of the level table.
    rows: Vec<Vec<u32>>,
    /// The level table, as on the GPU (for direct draws).
    table: Vec<u32>,
    buffers: Buffers,
    set_layout: SetLayout,
    layout: PipelineLayout<DrawPush>,
    cull_layout: PipelineLayout<LodCullPush>,
    set: DescriptorSet,
    /// The pyramid buffer `set` binds, if any.
    set_hiz: Option<vk::Buffer>,
    /// The draw pipeline and what it was made for (sample count, scene).
    pipeline: Option<(Pipeline, vk::SampleCountFlags, SceneSpec)>,
    /// The cull pipeline and the scene it was made for.
    cull: Option<(Pipeline, SceneSpec)>,
    /// The depth pyramid of what the method drew (made at the first frame
    /// with occlusion culling on).
    hiz: Option<Hiz>,
    /// Whether indirect draws may name their first instance
    /// (`drawIndirectFirstInstance`): without it the level draws are
    /// direct, and never occlusion-culled.
    indirect: bool,
    /// Whether one indirect call may draw many (`multiDrawIndirect`).
    multi: bool,
    /// Per instance: what drew it last frame (`None`: nothing yet, or ε
    /// changed since).
    choice: Vec<Option<Draw>>,
    /// The ε × pixel size of the last frame's view (`ViewParams::eps_k`).
    eps_k: f32,
    /// Per instance: whether its record on the GPU has `INSTANCE_LOD` set.
    flagged: Vec<bool>,
    /// Per instance: its `BIND_LOD_CHOICE` word on the GPU.
    words: Vec<u32>,
    /// Levels on ([`Lod::set_enabled`]).
    enabled: bool,
    /// `flagged` and `words` as the frame being recorded leaves them, kept
    /// until it is submitted ([`Lod::submitted`]).
    pending: Option<(Vec<bool>, Vec<u32>)>,
    /// The instances this frame draws from a level (in view), in instance
    /// order: (instance, model, level).
    draws: Vec<(u32, usize, usize)>,
    /// Every instance with levels drawn from this one (the model's
    /// coarsest where it has fewer), whatever its distance: the hole test
    /// of a level.
    force: Option<usize>,
}

impl Lod {
    /// Uploads `levels` for the scene `scene` holds.
    pub fn new(
        ctx: &Context,
        scene: &SceneGpu,
        scene_layout: &SceneLayout,
        levels: SceneLevels,
    ) -> VkResult<Self> {
        let n = scene.instance_records.len();
        let (buffers, table) = Buffers::new(ctx, &levels, n)?;
        let mut rows = Vec::new();
        let mut row = 0;
        for m in &levels.models {
            rows.push((row..row + m.levels.len() as u32).collect());
            row += m.levels.len() as u32;
        }
        let set_layout = SetLayout::reflect(ctx, "level-of-detail set", SET_PASS, SHADERS)?;
        let layout = scene_layout.pipeline_layout::<DrawPush>(
            ctx,
            "level-of-detail draw layout",
            &[&set_layout],
            scene_layout.stages(),
        )?;
        let cull_layout = scene_layout.pipeline_layout::<LodCullPush>(
            ctx,
            "level-of-detail cull layout",
            &[&set_layout],
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let set = buffers.set(ctx, &set_layout, None)?;
        let features = ctx.info().features;
        Ok(Self {
            levels,
            rows,
            table,
            buffers,
            set_layout,
            layout,
            cull_layout,
            set,
            set_hiz: None,
            pipeline: None,
            cull: None,
            hiz: None,
            indirect: features.draw_indirect_first_instance,
            multi: features.multi_draw_indirect,
            choice: vec![None; n],
            eps_k: 0.0,
            force: None,
            flagged: vec![false; n],
            words: vec![LOD_NONE; n],
            enabled: true,
            pending: None,
            draws: Vec::new(),
        })
    }

    /// Levels on (the default) or off: off, every instance is drawn from
    /// its patches, as without levels, and the levels stay made.
    pub fn set_enabled(&mut self, on: bool) {
        self.enabled = on;
    }

    /// Draws every instance with levels from level `level` (see
    /// [`Lod::force`]'s field), or, with `None`, as its distance says.
    pub fn set_force(&mut self, level: Option<usize>) {
        self.force = level;
    }

    /// The levels.
    pub fn levels(&self) -> &SceneLevels {
        &self.levels
    }

    /// Bytes the levels take on the GPU (vertices and indices).
    pub fn bytes(&self) -> u64 {
        self.buffers.level_bytes()
    }

    /// Bytes of everything the levels keep on the GPU: the levels, the
    /// per-instance choice and draws, the depth pyramid.
    pub fn memory(&self) -> u64 {
        self.buffers.bytes() + self.hiz.as_ref().map_or(0, Hiz::bytes)
    }

    /// Chooses what draws each instance in `params` (`enabled` false: the
    /// patches, everywhere) and records the changes into the instance
    /// records, so the method leaves the level-drawn instances alone, and
    /// into the choice the cull reads. Call before the method records.
    pub fn prepare(
        &mut self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        scene: &SceneGpu,
        params: &ViewParams,
        enabled: bool,
    ) {
        self.choose(scene, params, enabled && self.enabled);
        let mut flags = Vec::new();
        let mut words = Vec::new();
        let mut next = vec![LOD_NONE; self.words.len()];
        for &(i, m, l) in &self.draws {
            next[i as usize] = self.rows[m][l] + 1;
        }
        let mut flagged = self.flagged.clone();
        for (i, inst) in scene.instance_records.iter().enumerate() {
            let lod = matches!(self.choice[i], Some(Draw::Level(..)));
            if lod != flagged[i] {
                flagged[i] = lod;
                let f = inst.flags | if lod { INSTANCE_LOD } else { 0 };
                flags.push((i as u64 * INSTANCE_BYTES + FLAGS_OFFSET, f));
            }
            if next[i] != self.words[i] {
                words.push((i as u64 * 4, next[i]));
            }
        }
        // What the GPU will hold once this frame is submitted; until then
        // (a frame whose recording fails is never submitted) the mirrors
        // keep what it holds now, so the next frame writes the changes.
        self.pending = Some((flagged, next));
        if flags.is_empty() && words.is_empty() {
            return;
        }
        let mut rec = Recorder::new(ctx, cmd);
        // The frames before may still read the records and the choice.
        rec.after(Res::Memory, Access::ALL);
        let pass = Pass::new("level-of-detail choice")
            .write(Res::Buffer(&scene.instances), Access::TRANSFER_WRITE)
            .write(Res::Buffer(&self.buffers.choice), Access::TRANSFER_WRITE);
        let updates = [
            (scene.instances.handle(), flags),
            (self.buffers.choice.handle(), words),
        ];
        rec.run(&pass, |cmd| {
            for (buffer, writes) in &updates {
                for &(offset, word) in writes {
                    unsafe {
                        ctx.device()
                            .cmd_update_buffer(cmd, *buffer, offset, &word.to_ne_bytes())
                    };
                }
            }
        });
        rec.hand_off(Res::Memory, Access::ALL);
    }

    /// The frame [`Lod::prepare`] recorded was submitted: the GPU's flag
    /// and choice words are what it wrote.
    pub fn submitted(&mut self) {
        if let Some((flagged, words)) = self.pending.take() {
            self.flagged = flagged;
            self.words = words;
        }
    }

    /// Each instance's choice this frame and the level-drawn ones in view.
    fn choose(&mut self, scene: &SceneGpu, params: &ViewParams, enabled: bool) {
        self.draws.clear();
        if params.eps_k != self.eps_k {
            // A new tolerance (or image height, or field of view): the
            // hysteresis band was the old one's.
            self.choice.fill(None);
            self.eps_k = params.eps_k;
        }
        for (i, inst) in scene.instance_records.iter().enumerate() {
            let forced = self.levels.model_of(inst.source).and_then(|m| {
                let n = self.levels.models[m].levels.len();
                let l = self.force?;
                (n > 0).then(|| Draw::Level(m, l.min(n - 1)))
            });
            let draw = match (enabled, forced) {
                (false, _) => Draw::Patches,
                (true, Some(d)) => d,
                (true, None) => select::choose(&self.levels, params, inst, self.choice[i]),
            };
            self.choice[i] = Some(draw);
            if let Draw::Level(m, l) = draw {
                if !outside(params, inst) {
                    self.draws.push((i as u32, m, l));
                }
            }
        }
    }

    /// Whether this frame draws anything from a level.
    pub fn draws_any(&self) -> bool {
        !self.draws.is_empty()
    }

    /// Records this frame's level draws after the method (whose image and
    /// depth the target holds): the cull (with `occlusion`, against the
    /// depth pyramid of what the method drew), then the draws into the
    /// target, loading what the method drew. Returns where the cull's
    /// counters land in the copy-out area ([`LodFrame::from_counters`]).
    pub fn record(
        &mut self,
        f: &mut FrameRec<'_>,
        shaders: &mut Shaders,
        scene_layout: &SceneLayout,
        occlusion: bool,
    ) -> VkResult<CopyRange> {
        // Without named first instances the draws are direct: nothing the
        // cull decides reaches them.
        let occlusion = occlusion && self.indirect;
        if occlusion {
            self.build_pyramid(f, shaders, scene_layout)?;
        }
        self.record_cull(f, shaders, occlusion)?;
        let counters = f.copy_out(&self.buffers.counters, LOD_COUNTER_WORDS)?;
        self.record_draw(f, shaders)?;
        Ok(counters)
    }

    /// The depth pyramid of what the frame drew so far, and the set
    /// pointed at it when it is new.
    fn build_pyramid(
        &mut self,
        f: &mut FrameRec<'_>,
        shaders: &mut Shaders,
        scene_layout: &SceneLayout,
    ) -> VkResult<()> {
        if self.hiz.is_none() {
            self.hiz = Some(Hiz::new(f.ctx, shaders, scene_layout)?);
        }
        let Some(hiz) = &mut self.hiz else {
            return Ok(());
        };
        hiz.ensure(f.ctx, f.target, f.retired)?;
        let buffer = hiz.buffer();
        if buffer.map(Buffer::handle) != self.set_hiz {
            let set = self.buffers.set(f.ctx, &self.set_layout, buffer)?;
            // Frames in flight may still cull with the old set.
            f.retired.push(std::mem::replace(&mut self.set, set));
            self.set_hiz = buffer.map(Buffer::handle);
        }
        hiz.record_build(f)
    }

    /// Records the cull: the counters zeroed, one invocation per instance.
    fn record_cull(
        &mut self,
        f: &mut FrameRec<'_>,
        shaders: &mut Shaders,
        occlusion: bool,
    ) -> VkResult<()> {
        if self
            .cull
            .as_ref()
            .is_none_or(|(_, spec)| *spec != shaders.scene)
        {
            let p =
                shaders.compute(f.ctx, &self.cull_layout, "level-of-detail cull", SHADERS[2])?;
            if let Some(old) = self.cull.replace((p, shaders.scene)) {
                f.retired.push(old);
            }
        }
        let Some((pipeline, _)) = &self.cull else {
            return Ok(());
        };
        let (ctx, cmd) = (f.ctx, f.cmd);
        let b = &self.buffers;
        let mut rec = Recorder::new(ctx, cmd);
        // The last frame's draw and copy-out read them.
        rec.after(Res::Buffer(&b.counters), Access::ALL);
        rec.after(Res::Buffer(&b.draws), Access::ALL);
        let reset = Pass::new("level-of-detail counters")
            .write(Res::Buffer(&b.counters), Access::TRANSFER_WRITE);
        rec.run(&reset, |cmd| unsafe {
            ctx.device()
                .cmd_fill_buffer(cmd, b.counters.handle(), 0, vk::WHOLE_SIZE, 0)
        });
        let n = f.scene.instance_records.len() as u32;
        self.cull_layout.push(
            cmd,
            &LodCullPush {
                instance_count: n,
                occlusion: u32::from(occlusion),
                pad: [0; 2],
            },
        );
        let pass = Pass::new("level-of-detail cull")
            .pipeline(pipeline)
            .bind(SET_PASS, &self.set);
        let pass = f.with_scene(pass);
        rec.dispatch(&pass, [n.div_ceil(LOD_CULL_GROUP), 1, 1]);
        // The draw reads the commands, its vertex shader the vertices.
        let draw = Access::new(
            vk::PipelineStageFlags2::DRAW_INDIRECT | vk::PipelineStageFlags2::VERTEX_SHADER,
            vk::AccessFlags2::INDIRECT_COMMAND_READ | vk::AccessFlags2::SHADER_STORAGE_READ,
        );
        rec.hand_off_set(&self.set, draw);
        Ok(())
    }

    /// Records the level draws into the target, in instance order: one
    /// indirect draw per run of consecutive level-drawn instances (one per
    /// instance without `multiDrawIndirect`), or direct draws without
    /// `drawIndirectFirstInstance`.
    fn record_draw(&mut self, f: &mut FrameRec<'_>, shaders: &mut Shaders) -> VkResult<()> {
        let key = (shaders.samples, shaders.scene);
        let stale = self
            .pipeline
            .as_ref()
            .is_none_or(|(_, s, spec)| (*s, *spec) != key);
        if stale {
            let stages = [
                (vk::ShaderStageFlags::VERTEX, SHADERS[0]),
                (vk::ShaderStageFlags::FRAGMENT, SHADERS[1]),
            ];
            let p =
                shaders.draw_pipeline(f.ctx, &self.layout, "draw (levels of detail)", &stages)?;
            // Frames in flight may still draw with the old one.
            if let Some(old) = self.pipeline.replace((p, key.0, key.1)) {
                f.retired.push(old);
            }
        }
        let Some((pipeline, ..)) = &self.pipeline else {
            return Ok(());
        };
        let (ctx, cmd) = (f.ctx, f.cmd);
        let bind = vk::PipelineBindPoint::GRAPHICS;
        f.target.begin_part(ctx, cmd, false, true);
        pipeline.bind(cmd);
        f.bind_scene(bind, &self.layout);
        self.set.bind(ctx, cmd, bind, &self.layout, SET_PASS, &[]);
        self.layout.push(cmd, &f.view.draw_push(0, false, 0));
        let dev = ctx.device();
        let b = &self.buffers;
        unsafe {
            dev.cmd_bind_index_buffer(cmd, b.indices.handle(), 0, vk::IndexType::UINT32);
            if self.indirect {
                for (first, count) in runs(&self.draws, self.multi) {
                    let offset = u64::from(first) * u64::from(DRAW_BYTES);
                    dev.cmd_draw_indexed_indirect(cmd, b.draws.handle(), offset, count, DRAW_BYTES);
                }
            } else {
                for &(i, m, l) in &self.draws {
                    let at = (self.rows[m][l] * LOD_RANGE_WORDS) as usize;
                    let r = &self.table[at..at + 3];
                    dev.cmd_draw_indexed(cmd, r[1], 1, r[0], r[2] as i32, i);
                }
            }
        }
        f.target.end(ctx, cmd);
        Ok(())
    }
}

/// The runs of consecutive instances in `draws` (instance order) as (first
/// instance, count); each instance alone unless `multi`.
fn runs(draws: &[(u32, usize, usize)], multi: bool) -> Vec<(u32, u32)> {
    let mut out: Vec<(u32, u32)> = Vec::new();
    for &(i, ..) in draws {
        match out.last_mut() {
            Some((first, count)) if multi && *first + *count == i => *count += 1,
            _ => out.push((i, 1)),
        }
    }
    out
}

/// Whether `inst`'s box lies wholly outside one of the view's planes.
fn outside(params: &ViewParams, inst: &Instance) -> bool {
    let (lo, hi) = (Vec3::from_slice(&inst.lo), Vec3::from_slice(&inst.hi));
    params.planes.iter().any(|p| {
        let far = |a: f32, l: f32, h: f32| (a * l).max(a * h);
        far(p.x, lo.x, hi.x) + far(p.y, lo.y, hi.y) + far(p.z, lo.z, hi.z) + p.w < 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn consecutive_instances_share_one_indirect_call_only_with_multi_draw() {
        let draws = [
            (3, 0, 0),
            (4, 0, 1),
            (5, 1, 0),
            (9, 0, 0),
            (11, 0, 0),
            (12, 0, 0),
        ];
        assert_eq!(runs(&draws, true), vec![(3, 3), (9, 1), (11, 2)]);
        let single: Vec<_> = draws.iter().map(|d| (d.0, 1)).collect();
        assert_eq!(runs(&draws, false), single);
        assert!(runs(&[], true).is_empty());
    }

    #[test]
    fn counters_give_the_frame_and_its_levels() {
        let mut w = vec![0u32; LOD_COUNTER_WORDS as usize];
        w[LOD_DRAWN as usize] = 5;
        w[LOD_TRIANGLES as usize] = 700;
        w[LOD_OCCLUDED as usize] = 2;
        // Level 0: 1 instance of 100 triangles; level 2: 4 of 150.
        w[LOD_BY_LEVEL as usize] = 1;
        w[LOD_BY_LEVEL as usize + 1] = 100;
        w[LOD_BY_LEVEL as usize + 4] = 4;
        w[LOD_BY_LEVEL as usize + 5] = 600;
        let f = LodFrame::from_counters(&w, 64);
        assert_eq!(
            (f.instances, f.triangles, f.occluded, f.bytes),
            (5, 700, 2, 64)
        );
        assert_eq!(f.by_level, vec![(1, 100), (0, 0), (4, 600)]);
        assert_eq!(LOD_BY_LEVEL + 2 * LOD_MAX_LEVELS, LOD_COUNTER_WORDS);
    }

    #[test]
    fn octahedral_codes_keep_unit_vectors_within_a_thousandth() {
        for k in 0..500 {
            let s = k as f32 * 0.61;
            let n = Vec3::new(
                s.sin() * (s * 0.3).cos(),
                (s * 1.7).cos(),
                (s * 0.9).sin() - 0.2,
            )
            .normalize();
            let w = oct_encode(n);
            let e = glam::Vec2::new(
                (w as u16 as i16) as f32 / 32767.0,
                ((w >> 16) as u16 as i16) as f32 / 32767.0,
            );
            let mut d = Vec3::new(e.x, e.y, 1.0 - e.x.abs() - e.y.abs());
            if d.z < 0.0 {
                let sx = if e.x >= 0.0 { 1.0 } else { -1.0 };
                let sy = if e.y >= 0.0 { 1.0 } else { -1.0 };
                d = Vec3::new((1.0 - e.y.abs()) * sx, (1.0 - e.x.abs()) * sy, d.z);
            }
            assert!(d.normalize().distance(n) < 1e-3, "{n} -> {d}");
        }
    }
}
